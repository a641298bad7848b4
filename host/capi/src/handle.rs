//! The shape every kind of law shares behind the C ABI, written once.
//!
//! A kind (contact, tangential, restitution, rolling, twisting) is a law handle made by name
//! from the registry, bound either to a pair of materials (a model that takes each contact's
//! geometry and history in its batch call) or to one pair (the sdk 0.1 hot path), and freed.
//! The kinds differ only in the sdk handle they wrap, so the C entry points of those steps come
//! from three macros over the traits below, one line per kind in `kinds.rs`; the header
//! declares them the same way (`DASHPOT_LAW_FUNCTIONS`, `DASHPOT_MODEL_FUNCTIONS`,
//! `DASHPOT_PAIR_FUNCTIONS`, cbindgen.toml's trailer). What differs per kind, the batch call,
//! is written per kind with the shared argument checks at the end of this module.

use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::materials::DashpotMaterials;
use crate::pair::DashpotPair;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::EnergyOut;
use dashpot_sdk::{MaterialPair, Pair, ParamValue};
use std::ffi::{c_char, c_int};

/// A law handle made by name from the registry.
pub(crate) trait NewLaw: Sized {
    fn make(reg: &dashpot_core::Registry, name: &str, params: &[ParamValue]) -> Result<Self, CError>;
}

/// A law bound to a pair of materials: a model with per-contact history.
pub(crate) trait BindMaterials {
    type Model: Model;
    fn bind_materials(&self, materials: &MaterialPair) -> Result<Self::Model, CError>;
}

/// A bound model: its history width and its law's name (for messages).
pub(crate) trait Model {
    fn slots(&self) -> usize;
    fn law_name(&self) -> &str;
}

/// A law bound to one pair (effective mass, radius and modulus).
pub(crate) trait BindPair {
    type Bound;
    fn bind_pair(&self, pair: &Pair) -> Result<Self::Bound, CError>;
}

/// The body of every `dashpot_*_new`.
///
/// # Safety
/// As the header states for `dashpot_*_new`.
pub(crate) unsafe fn new<L: NewLaw>(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut L,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        *o = Box::into_raw(Box::new(L::make(&r.reg, name, &p)?));
        Ok(())
    })
}

/// The body of every `*_free`: drops a boxed handle (null is ignored), catching a panic of its
/// destructor.
///
/// # Safety
/// `p` must be null or a live handle of this library, not used concurrently.
pub(crate) unsafe fn free<T>(p: *mut T) {
    if !p.is_null() {
        // SAFETY: a live handle from this library, by the caller's contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(unsafe { Box::from_raw(p) })));
    }
}

/// The body of every `*_bind_materials`.
///
/// # Safety
/// Non-null pointers must be valid.
pub(crate) unsafe fn bind_materials<L: BindMaterials>(
    law: *const L,
    materials: *const DashpotMaterials,
    out_model: *mut *mut L::Model,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let m = unsafe { arg(materials, "materials") }?.to_materials()?;
        let o = unsafe { out(out_model, "out_model") }?;
        *o = Box::into_raw(Box::new(l.bind_materials(&m)?));
        Ok(())
    })
}

/// The body of every `*_model_history_slots`.
///
/// # Safety
/// Non-null pointers must be valid.
pub(crate) unsafe fn history_slots<M: Model>(model: *const M, out_slots: *mut usize) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        *unsafe { out(out_slots, "out_slots") }? = m.slots();
        Ok(())
    })
}

/// The body of every `*_bind` (to a pair).
///
/// # Safety
/// Non-null pointers must be valid.
pub(crate) unsafe fn bind_pair<L: BindPair>(
    law: *const L,
    pair: *const DashpotPair,
    out_bound: *mut *mut L::Bound,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let p = unsafe { arg(pair, "pair") }?.to_pair()?;
        let o = unsafe { out(out_bound, "out_bound") }?;
        *o = Box::into_raw(Box::new(l.bind_pair(&p)?));
        Ok(())
    })
}

/// `dashpot_<kind>_new` and `dashpot_<kind>_free` for each law type (the header's
/// `DASHPOT_LAW_FUNCTIONS`).
macro_rules! law_functions {
    ($($law:ty: $new:ident, $free:ident;)*) => {$(
        /// Creates a law by name from named parameters: `DASHPOT_LAW_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// `param_names`/`param_values` null (only if `n_params` is 0) or `n_params` long;
        /// strings NUL-terminated; other non-null pointers valid.
        #[no_mangle]
        pub unsafe extern "C" fn $new(
            registry: *const $crate::registry::DashpotRegistry,
            name: *const std::ffi::c_char,
            param_names: *const *const std::ffi::c_char,
            param_values: *const f64,
            n_params: usize,
            out_law: *mut *mut $law,
        ) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::new(registry, name, param_names, param_values, n_params, out_law) }
        }

        /// Frees a law (null is ignored): `DASHPOT_LAW_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// `law` null or a live handle, not used concurrently.
        #[no_mangle]
        pub unsafe extern "C" fn $free(law: *mut $law) {
            unsafe { $crate::handle::free(law) }
        }
    )*};
}

/// `dashpot_<kind>_bind_materials`, `_model_free` and `_model_history_slots` for each law type
/// (the header's `DASHPOT_MODEL_FUNCTIONS`).
macro_rules! model_functions {
    ($($law:ty => $model:ty: $bind:ident, $free:ident, $slots:ident;)*) => {$(
        /// Binds a law to a pair of materials: `DASHPOT_MODEL_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $bind(
            law: *const $law,
            materials: *const $crate::materials::DashpotMaterials,
            out_model: *mut *mut $model,
        ) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::bind_materials(law, materials, out_model) }
        }

        /// Frees a bound law (null is ignored): `DASHPOT_MODEL_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// `model` null or a live handle, not used concurrently.
        #[no_mangle]
        pub unsafe extern "C" fn $free(model: *mut $model) {
            unsafe { $crate::handle::free(model) }
        }

        /// The history values per contact: `DASHPOT_MODEL_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $slots(model: *const $model, out_slots: *mut usize) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::history_slots(model, out_slots) }
        }
    )*};
}

/// `dashpot_<kind>_bind` and `dashpot_bound_<kind>_free` for each law type bound to a pair (the
/// header's `DASHPOT_PAIR_FUNCTIONS`).
macro_rules! pair_functions {
    ($($law:ty => $bound:ty: $bind:ident, $free:ident;)*) => {$(
        /// Binds a law to a pair: `DASHPOT_PAIR_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $bind(
            law: *const $law,
            pair: *const $crate::pair::DashpotPair,
            out_bound: *mut *mut $bound,
        ) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::bind_pair(law, pair, out_bound) }
        }

        /// Frees a bound law (null is ignored): `DASHPOT_PAIR_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// `bound` null or a live handle, not used concurrently.
        #[no_mangle]
        pub unsafe extern "C" fn $free(bound: *mut $bound) {
            unsafe { $crate::handle::free(bound) }
        }
    )*};
}

pub(crate) use {law_functions, model_functions, pair_functions};

// ---- the argument checks every batch call shares ----

/// The history width of `model`, after checking that `n_history` = `n × slots` (`what` names
/// the function in the message).
pub(crate) fn history_width(
    what: &str,
    model: &impl Model,
    n: usize,
    n_history: usize,
) -> Result<usize, CError> {
    let slots = model.slots();
    if Some(n_history) == n.checked_mul(slots) {
        return Ok(slots);
    }
    Err(CError::new(
        DASHPOT_ERR_BAD_LENGTH,
        format!(
            "{what}: history must hold n × slots = {n} × {slots} values (law '{}'), got n_history = {n_history}",
            model.law_name()
        ),
    ))
}

/// `n` contacts' `[x, y, z]` vectors: 3n values, null only when n = 0.
///
/// # Safety
/// A non-null `p` must point to 3n valid values for `'a`.
pub(crate) unsafe fn vectors<'a>(p: *const f64, n: usize, what: &str) -> Result<&'a [[f64; 3]], CError> {
    let v = unsafe { slice(p, triple_len(n)?, what) }?;
    // SAFETY: [f64; 3] has the alignment of f64 and no padding; n whole triples.
    Ok(unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<[f64; 3]>(), n) })
}

/// As [`vectors`], for an output.
///
/// # Safety
/// A non-null `p` must point to 3n writable values for `'a`, not aliasing other arguments.
pub(crate) unsafe fn vectors_mut<'a>(
    p: *mut f64,
    n: usize,
    what: &str,
) -> Result<&'a mut [[f64; 3]], CError> {
    let v = unsafe { slice_mut(p, triple_len(n)?, what) }?;
    // SAFETY: as `vectors`, with the unique borrow of `v` moved into the result.
    Ok(unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<[f64; 3]>(), n) })
}

fn triple_len(n: usize) -> Result<usize, CError> {
    n.checked_mul(3)
        .ok_or_else(|| CError::new(DASHPOT_ERR_BAD_LENGTH, format!("n = {n} contacts is too many")))
}

/// An optional output of `n` values (null: not wanted).
///
/// # Safety
/// A non-null `p` must point to `n` writable values for `'a`, not aliasing other arguments.
pub(crate) unsafe fn optional<'a>(
    p: *mut f64,
    n: usize,
    what: &str,
) -> Result<Option<&'a mut [f64]>, CError> {
    if p.is_null() {
        Ok(None)
    } else {
        unsafe { slice_mut(p, n, what) }.map(Some)
    }
}

/// The energy outputs: each of `power` and `elastic` null (not wanted) or `n` values.
///
/// # Safety
/// As [`optional`], for each.
pub(crate) unsafe fn energy<'a>(
    power: *mut f64,
    elastic: *mut f64,
    n: usize,
) -> Result<EnergyOut<'a>, CError> {
    Ok(EnergyOut {
        power: unsafe { optional(power, n, "out_power") }?,
        elastic: unsafe { optional(elastic, n, "out_elastic") }?,
    })
}

/// Writes whether the law reported its energy, if the caller asked (`p` non-null).
///
/// # Safety
/// A non-null `p` must be valid for writing.
pub(crate) unsafe fn report_written(p: *mut c_int, written: bool) {
    if let Some(w) = unsafe { p.as_mut() } {
        *w = c_int::from(written);
    }
}

/// A batch of the vector kinds (tangential, rolling): per contact a unit normal, a velocity and
/// a force vector, the normal force, overlap, effective mass and radius, and the history.
pub(crate) trait VectorBatch<'a>: Sized {
    #[allow(clippy::too_many_arguments)]
    fn of(
        dt: f64,
        normal: &'a [[f64; 3]],
        velocity: &'a [[f64; 3]],
        scalars: [&'a [f64]; 4],
        slots: usize,
        history: &'a mut [f64],
        force: &'a mut [[f64; 3]],
    ) -> Self;
}

macro_rules! vector_batch {
    ($($batch:ident),*) => {$(
        impl<'a> VectorBatch<'a> for dashpot_sdk::$batch<'a> {
            fn of(
                dt: f64,
                normal: &'a [[f64; 3]],
                velocity: &'a [[f64; 3]],
                [normal_force, delta, mass, radius]: [&'a [f64]; 4],
                slots: usize,
                history: &'a mut [f64],
                force: &'a mut [[f64; 3]],
            ) -> Self {
                dashpot_sdk::$batch { dt, normal, velocity, normal_force, delta, mass, radius, slots, history, force }
            }
        }
    )*};
}

vector_batch!(TangentialBatch, RollingBatch);

/// The checked batch of a vector kind's call (`what` names the function in messages).
///
/// # Safety
/// Non-null arrays must hold the lengths the functions state; outputs must not overlap inputs.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn vector_batch<'a, B: VectorBatch<'a>>(
    what: &str,
    model: &impl Model,
    n: usize,
    dt: f64,
    normal: *const f64,
    velocity: *const f64,
    [normal_force, delta, mass, radius]: [*const f64; 4],
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
) -> Result<B, CError> {
    let slots = history_width(what, model, n, n_history)?;
    Ok(B::of(
        dt,
        unsafe { vectors(normal, n, "normal") }?,
        unsafe { vectors(velocity, n, "velocity") }?,
        [
            unsafe { slice(normal_force, n, "normal_force") }?,
            unsafe { slice(delta, n, "delta") }?,
            unsafe { slice(mass, n, "mass") }?,
            unsafe { slice(radius, n, "radius") }?,
        ],
        slots,
        unsafe { slice_mut(history, n_history, "history") }?,
        unsafe { vectors_mut(out_force, n, "out_force") }?,
    ))
}
