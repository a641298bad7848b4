//! Tangential (friction) laws (sdk 0.2): create by name, bind to a pair of materials, evaluate
//! the tangential force on every contact with its history.
//!
//! Vectors are `[x, y, z]` triples stored one after the other (`3 n` doubles for `n` contacts;
//! a 2D code sets z = 0). `normal[i]` is the unit normal from the partner j to the particle i the
//! force acts on; `velocity[i]` the relative velocity of i's contact point with respect to j's
//! (ω × r terms included; the law uses its part in the tangent plane); the result is the
//! tangential force on i (N), capped by Coulomb's μ F_n. History (a spring's displacement, for
//! example) is stored by the caller exactly as for contact laws: zero at first touch, updated in
//! place by each call, kept when the step is accepted, dropped when the contact ends.

use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::materials::DashpotMaterials;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::{TangentialLawHandle, TangentialModelHandle};
use dashpot_sdk::TangentialBatch;
use std::ffi::c_char;

/// A configured tangential law (opaque).
pub struct DashpotTangentialLaw {
    pub(crate) law: TangentialLawHandle,
}

/// A tangential law bound to a pair of materials (opaque): the hot path.
pub struct DashpotTangentialModel {
    pub(crate) model: TangentialModelHandle,
}

/// Creates tangential law `name` (e.g. `"mindlin"`) from `n_params` named values (parameters
/// left out take their defaults; the values are validated against the law's schema).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW` (also for a law of another kind),
/// `DASHPOT_ERR_UNKNOWN_PARAMETER`, `DASHPOT_ERR_INVALID_PARAMETER`, `DASHPOT_ERR_PANIC`.
/// Ownership: inputs are copied; `*out_law` is owned by the caller (free with
/// `dashpot_tangential_free`) and may outlive the registry. Thread-safe.
///
/// # Safety
/// `param_names`/`param_values` must be null (only if `n_params` is 0) or hold `n_params`
/// elements; strings NUL-terminated; other non-null pointers valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotTangentialLaw,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        let law = r.reg.tangential(name, &p)?;
        *o = Box::into_raw(Box::new(DashpotTangentialLaw { law }));
        Ok(())
    })
}

/// Frees a tangential law (null is ignored). Models bound from it stay valid.
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_tangential_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_free(law: *mut DashpotTangentialLaw) {
    if !law.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(law) })
        }));
    }
}

/// Binds a tangential law to a pair of materials (see `dashpot_materials_spheres`, `_wall`).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR` (a modulus not finite and > 0),
/// `DASHPOT_ERR_INVALID_PARAMETER` (the law rejects these materials), `DASHPOT_ERR_PANIC`.
/// Ownership: `*out_model` is owned by the caller (free with `dashpot_tangential_model_free`)
/// and may outlive the law. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_bind_materials(
    law: *const DashpotTangentialLaw,
    materials: *const DashpotMaterials,
    out_model: *mut *mut DashpotTangentialModel,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let m = unsafe { arg(materials, "materials") }?.to_materials()?;
        let o = unsafe { out(out_model, "out_model") }?;
        let model = l.law.bind(&m)?;
        *o = Box::into_raw(Box::new(DashpotTangentialModel { model }));
        Ok(())
    })
}

/// Frees a bound tangential law (null is ignored).
///
/// # Safety
/// `model` must be null or a live handle from `dashpot_tangential_bind_materials`, not used
/// concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_model_free(model: *mut DashpotTangentialModel) {
    if !model.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(model) })
        }));
    }
}

/// The number of history values (doubles) the law keeps per contact (3 for a tangential
/// spring).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_model_history_slots(
    model: *const DashpotTangentialModel,
    out_slots: *mut usize,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let o = unsafe { out(out_slots, "out_slots") }?;
        *o = m.model.history_slots();
        Ok(())
    })
}

/// The tangential force on `n` contacts, history advanced by the time step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal (from partner to particle),
/// `velocity[3i..3i+3]` the relative contact-point velocity (m/s), `normal_force[i]` the normal
/// force this step (N, > 0 repulsive; from the normal law), `delta[i]` the overlap (m),
/// `mass[i]`, `radius[i]` the effective mass (kg) and radius (m), `history[i*slots ..]` its
/// history (`n_history = n × slots` values, read and updated in place) and
/// `out_force[3i..3i+3]` the tangential force on the particle (N).
///
/// Every input is checked inside the plugin: a non-finite vector, normal force, overlap or
/// `dt`, or a mass or radius not finite and > 0, is refused with `DASHPOT_ERR_NON_FINITE`
/// naming the array, the index and the value; so is a non-finite force.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (the handle, or an array when `n` > 0),
/// `DASHPOT_ERR_BAD_LENGTH` (`n_history` ≠ `n × slots`), `DASHPOT_ERR_NON_FINITE` (outputs
/// then partly written), `DASHPOT_ERR_PANIC` (the handle stays usable).
/// Ownership: the arrays stay the caller's. Thread-safe (distinct output and history arrays
/// per thread).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; `out_force` and `history` must not overlap
/// each other or the inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_model_force_batch(
    model: *const DashpotTangentialModel,
    n: usize,
    dt: f64,
    normal: *const f64,
    velocity: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = m.model.history_slots();
        let n3 = n
            .checked_mul(3)
            .ok_or_else(|| CError::new(DASHPOT_ERR_BAD_LENGTH, format!("n = {n} contacts is too many")))?;
        if Some(n_history) != n.checked_mul(slots) {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_tangential_model_force_batch: history must hold n × slots = {n} × {slots} \
                     values (law '{}'), got n_history = {n_history}",
                    m.model.name()
                ),
            ));
        }
        let normal = unsafe { slice(normal, n3, "normal") }?;
        let velocity = unsafe { slice(velocity, n3, "velocity") }?;
        let normal_force = unsafe { slice(normal_force, n, "normal_force") }?;
        let delta = unsafe { slice(delta, n, "delta") }?;
        let mass = unsafe { slice(mass, n, "mass") }?;
        let radius = unsafe { slice(radius, n, "radius") }?;
        let history = unsafe { slice_mut(history, n_history, "history") }?;
        let force = unsafe { slice_mut(out_force, n3, "out_force") }?;
        m.model.force_batch(TangentialBatch {
            dt,
            normal: triples(normal),
            velocity: triples(velocity),
            normal_force,
            delta,
            mass,
            radius,
            slots,
            history,
            force: triples_mut(force),
        })?;
        Ok(())
    })
}

fn triples(v: &[f64]) -> &[[f64; 3]] {
    // SAFETY: [f64; 3] has the alignment of f64 and no padding; len / 3 whole triples.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}

fn triples_mut(v: &mut [f64]) -> &mut [[f64; 3]] {
    // SAFETY: as `triples`, with the unique borrow of `v` moved into the result.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}
