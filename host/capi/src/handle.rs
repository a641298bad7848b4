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
use dashpot_sdk::{LawError, MaterialPair, NormalContext, Pair, ParamValue};
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

/// A bound model: its history width, its law's name (for messages) and whether it reads the
/// normal law's context (sdk 0.4).
pub(crate) trait Model {
    fn slots(&self) -> usize;
    fn law_name(&self) -> &str;
    fn reads_context(&self) -> bool;
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

/// The body of every binding: `law` bound by `bind` to what `with` points to (checked by
/// `convert`), the new handle written to `*out` (`names`: the two pointers, for messages).
///
/// # Safety
/// Non-null pointers must be valid.
unsafe fn bind_with<L, A, T, R>(
    law: *const L,
    with: *const A,
    out: *mut *mut R,
    names: [&str; 2],
    convert: impl FnOnce(&A) -> Result<T, LawError>,
    bind: impl FnOnce(&L, &T) -> Result<R, CError>,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let w = convert(unsafe { arg(with, names[0]) }?)?;
        let o = unsafe { self::out(out, names[1]) }?;
        *o = Box::into_raw(Box::new(bind(l, &w)?));
        Ok(())
    })
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
    let names = ["materials", "out_model"];
    unsafe {
        bind_with(
            law,
            materials,
            out_model,
            names,
            DashpotMaterials::to_materials,
            L::bind_materials,
        )
    }
}

/// The body of every `*_model_history_slots`.
///
/// # Safety
/// Non-null pointers must be valid.
pub(crate) unsafe fn history_slots<M: Model>(model: *const M, out_slots: *mut usize) -> DashpotStatus {
    crate::error::output!(arg model => out_slots = model.slots())
}

/// The body of every `*_model_reads_context`.
///
/// # Safety
/// Non-null pointers must be valid.
pub(crate) unsafe fn reads_context<M: Model>(model: *const M, out_reads: *mut c_int) -> DashpotStatus {
    crate::error::output!(arg model => out_reads = c_int::from(model.reads_context()))
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
    unsafe {
        bind_with(
            law,
            pair,
            out_bound,
            ["pair", "out_bound"],
            DashpotPair::to_pair,
            L::bind_pair,
        )
    }
}

/// A `*_free` entry point for handle type `$ty`: `DASHPOT_*_FUNCTIONS` in dashpot.h.
macro_rules! free_function {
    ($free:ident($arg:ident: $ty:ty)) => {
        /// Frees a handle (null is ignored): `DASHPOT_*_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// The handle must be null or live, not used concurrently.
        #[no_mangle]
        pub unsafe extern "C" fn $free($arg: *mut $ty) {
            unsafe { $crate::handle::free($arg) }
        }
    };
}

/// A binding entry point: law type `$law` bound to what `$with` points to, by the body `$body`
/// (`bind_materials` or `bind_pair`): `DASHPOT_MODEL_FUNCTIONS` and `DASHPOT_PAIR_FUNCTIONS`.
macro_rules! bind_function {
    ($bind:ident($law:ty, $with:ident: $with_ty:ty, $out:ident: $out_ty:ty) => $body:ident) => {
        /// Binds a law: `DASHPOT_MODEL_FUNCTIONS` / `DASHPOT_PAIR_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $bind(
            law: *const $law,
            $with: *const $with_ty,
            $out: *mut *mut $out_ty,
        ) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::$body(law, $with, $out) }
        }
    };
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

        $crate::handle::free_function!($free(law: $law));
    )*};
}

/// `dashpot_<kind>_bind_materials`, `_model_free`, `_model_history_slots` and
/// `_model_reads_context` for each law type (the header's `DASHPOT_MODEL_FUNCTIONS`).
macro_rules! model_functions {
    ($($law:ty => $model:ty: $bind:ident, $free:ident, $slots:ident, $reads:ident;)*) => {$(
        $crate::handle::bind_function!(
            $bind($law, materials: $crate::materials::DashpotMaterials, out_model: $model) => bind_materials
        );

        $crate::handle::free_function!($free(model: $model));

        /// The history values per contact: `DASHPOT_MODEL_FUNCTIONS` in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $slots(model: *const $model, out_slots: *mut usize) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::history_slots(model, out_slots) }
        }

        /// Whether the law reads the normal law's context (sdk 0.4): `DASHPOT_MODEL_FUNCTIONS`
        /// in dashpot.h.
        ///
        /// # Safety
        /// Non-null pointers must be valid.
        #[no_mangle]
        pub unsafe extern "C" fn $reads(model: *const $model, out_reads: *mut std::ffi::c_int) -> $crate::error::DashpotStatus {
            unsafe { $crate::handle::reads_context(model, out_reads) }
        }
    )*};
}

/// `dashpot_<kind>_bind` and `dashpot_bound_<kind>_free` for each law type bound to a pair (the
/// header's `DASHPOT_PAIR_FUNCTIONS`).
macro_rules! pair_functions {
    ($($law:ty => $bound:ty: $bind:ident, $free:ident;)*) => {$(
        $crate::handle::bind_function!($bind($law, pair: $crate::pair::DashpotPair, out_bound: $bound) => bind_pair);

        $crate::handle::free_function!($free(bound: $bound));
    )*};
}

pub(crate) use {bind_function, free_function, law_functions, model_functions, pair_functions};

// ---- the argument checks every batch call shares ----

/// The history width of `model`, after checking that `n_history` = `n × slots` (`what` names
/// the function in the message).
#[inline(always)]
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
    Err(bad_history(what, model.law_name(), n, slots, n_history))
}

#[cold]
#[inline(never)]
fn bad_history(what: &str, law: &str, n: usize, slots: usize, n_history: usize) -> CError {
    CError::new(
        DASHPOT_ERR_BAD_LENGTH,
        format!("{what}: history must hold n × slots = {n} × {slots} values (law '{law}'), got n_history = {n_history}"),
    )
}

/// `n` contacts' `[x, y, z]` vectors: 3n values, null only when n = 0.
///
/// # Safety
/// A non-null `p` must point to 3n valid values for `'a`.
#[inline(always)]
pub(crate) unsafe fn vectors<'a>(p: *const f64, n: usize, what: &str) -> Result<&'a [[f64; 3]], CError> {
    let v = unsafe { slice(p, triple_len(n)?, what) }?;
    // SAFETY: [f64; 3] has the alignment of f64 and no padding; n whole triples.
    Ok(unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<[f64; 3]>(), n) })
}

#[inline(always)]
fn triple_len(n: usize) -> Result<usize, CError> {
    n.checked_mul(3).ok_or_else(|| too_many(n))
}

#[cold]
#[inline(never)]
fn too_many(n: usize) -> CError {
    CError::new(DASHPOT_ERR_BAD_LENGTH, format!("n = {n} contacts is too many"))
}

/// An optional output of `n` values (null: not wanted).
///
/// # Safety
/// A non-null `p` must point to `n` writable values for `'a`, not aliasing other arguments.
#[inline(always)]
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
#[inline(always)]
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

/// The normal contexts a batch is given (sdk 0.4): null for none (every contact's default), or
/// `n` contexts of 3 values each (contact radius m, cap force N, damping N·s/m).
///
/// # Safety
/// A non-null `p` must point to 3n valid values for `'a`.
#[inline(always)]
pub(crate) unsafe fn contexts<'a>(p: *const f64, n: usize) -> Result<&'a [NormalContext], CError> {
    if p.is_null() {
        return Ok(&[]);
    }
    let v = unsafe { slice(p, triple_len(n)?, "context") }?;
    // SAFETY: NormalContext is three f64 (repr(C)): the alignment of f64, no padding.
    Ok(unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<NormalContext>(), n) })
}

/// The output of `n` normal contexts (sdk 0.4), 3 values each.
///
/// # Safety
/// A non-null `p` must point to 3n writable values for `'a`, not aliasing other arguments.
#[inline(always)]
pub(crate) unsafe fn contexts_out<'a>(p: *mut f64, n: usize) -> Result<&'a mut [NormalContext], CError> {
    let v = unsafe { slice_mut(p, triple_len(n)?, "out_context") }?;
    // SAFETY: as `contexts`, with the unique borrow of the values moved into the result.
    Ok(unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<NormalContext>(), n) })
}

/// Writes whether the law reported its energy, if the caller asked (`p` non-null).
///
/// # Safety
/// A non-null `p` must be valid for writing.
#[inline(always)]
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
        context: &'a [NormalContext],
        slots: usize,
        history: &'a mut [f64],
        force: &'a mut [[f64; 3]],
    ) -> Self;
}

macro_rules! vector_batch {
    ($($batch:ident),*) => {$(
        impl<'a> VectorBatch<'a> for dashpot_sdk::$batch<'a> {
            #[inline(always)]
            fn of(
                dt: f64,
                normal: &'a [[f64; 3]],
                velocity: &'a [[f64; 3]],
                [normal_force, delta, mass, radius]: [&'a [f64]; 4],
                context: &'a [NormalContext],
                slots: usize,
                history: &'a mut [f64],
                force: &'a mut [[f64; 3]],
            ) -> Self {
                dashpot_sdk::$batch { dt, normal, velocity, normal_force, delta, mass, radius, context, slots, history, force }
            }
        }
    )*};
}

// (the tangential and rolling batches are one type, dashpot_sdk::VectorBatch)
vector_batch!(VectorBatch);

/// A model whose batch takes, per contact, a unit normal, an input (a vector, or the twisting
/// rate), the normal force, overlap, effective mass and radius and its history, and gives an
/// output of the input's shape, with sdk 0.3's energy outputs: the tangential (its
/// `_force_batch_energy`), rolling and twisting kinds (`DASHPOT_ENERGY_BATCH` in the header).
pub(crate) trait EnergyBatch: Model {
    /// Values per contact of the input and the output: 3 (a vector) or 1.
    const WIDTH: usize;
    /// The law on the checked batch: `Ok(true)` when it wrote the energy outputs.
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, dashpot_sdk::LawError>;
}

/// An energy batch's checked arrays: `input` and `out` hold `WIDTH` values per contact,
/// `scalars` the normal force, overlap, effective mass and radius.
pub(crate) struct Raw<'a> {
    pub dt: f64,
    pub normal: &'a [[f64; 3]],
    pub input: &'a [f64],
    pub scalars: [&'a [f64]; 4],
    pub context: &'a [NormalContext],
    pub slots: usize,
    pub history: &'a mut [f64],
    pub out: &'a mut [f64],
}

impl<'a> Raw<'a> {
    /// The batch of a vector kind (`input` and `out` as triples).
    #[inline(always)]
    pub fn vector<B: VectorBatch<'a>>(self) -> B {
        let velocity = triples(self.input);
        B::of(
            self.dt,
            self.normal,
            velocity,
            self.scalars,
            self.context,
            self.slots,
            self.history,
            triples_mut(self.out),
        )
    }
}

/// `[x, y, z]` triples of a slice of 3n values.
pub(crate) fn triples(v: &[f64]) -> &[[f64; 3]] {
    // SAFETY: [f64; 3] has the alignment of f64 and no padding; len / 3 whole triples.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}

/// As [`triples`], mutable.
pub(crate) fn triples_mut(v: &mut [f64]) -> &mut [[f64; 3]] {
    // SAFETY: as `triples`, with the unique borrow of `v` moved into the result.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}

/// The body of every energy batch (`what` names the function, `[input, out]` its two arrays
/// whose shape depends on the kind, in messages).
///
/// # Safety
/// Non-null arrays must hold the lengths the header states; outputs must not overlap inputs.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn energy_batch<M: EnergyBatch>(
    what: &str,
    [input_name, out_name]: [&str; 2],
    model: *const M,
    n: usize,
    dt: f64,
    normal: *const f64,
    input: *const f64,
    [normal_force, delta, mass, radius]: [*const f64; 4],
    context: *const f64,
    history: *mut f64,
    n_history: usize,
    out: *mut f64,
    [power, elastic]: [*mut f64; 2],
    written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = history_width(what, m, n, n_history)?;
        let w = if M::WIDTH == 3 { triple_len(n)? } else { n };
        let normal = unsafe { vectors(normal, n, "normal") }?;
        dashpot_core::checks::unit_normals(normal)
            .map_err(|m| CError::new(DASHPOT_ERR_INVALID_ARGUMENT, m))?;
        let input = unsafe { slice(input, w, input_name) }?;
        let scalars = [
            unsafe { slice(normal_force, n, "normal_force") }?,
            unsafe { slice(delta, n, "delta") }?,
            unsafe { slice(mass, n, "mass") }?,
            unsafe { slice(radius, n, "radius") }?,
        ];
        let context = unsafe { contexts(context, n) }?;
        let history = unsafe { slice_mut(history, n_history, "history") }?;
        let out = unsafe { slice_mut(out, w, out_name) }?;
        let e = unsafe { energy(power, elastic, n) }?;
        let raw = Raw {
            dt,
            normal,
            input,
            scalars,
            context,
            slots,
            history,
            out,
        };
        let done = m.run(raw, e)?;
        unsafe { report_written(written, done) };
        Ok(())
    })
}

/// The energy outputs of a batch: those given, or none (null).
macro_rules! energy_outputs {
    () => {
        ([std::ptr::null_mut(); 2], std::ptr::null_mut())
    };
    ($power:ident, $elastic:ident, $written:ident) => {
        ([$power, $elastic], $written)
    };
}

/// The normal contexts of a batch: those given, or none (null).
macro_rules! context_input {
    () => {
        std::ptr::null()
    };
    ($context:ident) => {
        $context
    };
}

/// The batches of the tangential, rolling and twisting kinds, one line per function, with the
/// sdk 0.4 normal contexts (`[context]`, after the radii) and the sdk 0.3 energy outputs where
/// the line names them (the header's `DASHPOT_MOTION_BATCH` and `DASHPOT_MOTION_BATCH_CONTEXT`).
macro_rules! motion_batch_functions {
    ($($model:ty: $name:ident($input:ident, $out:ident $([$context:ident])? $(, $power:ident, $elastic:ident, $written:ident)?);)*) => {$(
        /// A batch call: `DASHPOT_MOTION_BATCH` or `DASHPOT_MOTION_BATCH_CONTEXT` in dashpot.h.
        ///
        /// # Safety
        /// Non-null arrays must hold the lengths the header states; outputs must not overlap
        /// each other or the inputs.
        #[allow(clippy::too_many_arguments)]
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            model: *const $model,
            n: usize,
            dt: f64,
            normal: *const f64,
            $input: *const f64,
            normal_force: *const f64,
            delta: *const f64,
            mass: *const f64,
            radius: *const f64,
            $($context: *const f64,)?
            history: *mut f64,
            n_history: usize,
            $out: *mut f64,
            $($power: *mut f64, $elastic: *mut f64, $written: *mut std::ffi::c_int,)?
        ) -> $crate::error::DashpotStatus {
            let names = [stringify!($input), stringify!($out)];
            let scalars = [normal_force, delta, mass, radius];
            let context = $crate::handle::context_input!($($context)?);
            let (energy, written) = $crate::handle::energy_outputs!($($power, $elastic, $written)?);
            unsafe {
                $crate::handle::energy_batch(
                    stringify!($name), names, model, n, dt, normal, $input, scalars, context, history, n_history,
                    $out, energy, written,
                )
            }
        }
    )*};
}

pub(crate) use {context_input, energy_outputs, motion_batch_functions};
