//! Contact laws bound to materials (sdk 0.2): per-contact geometry and history in the batch call.
//!
//! Sign convention as for the pair-bound functions: δ ≥ 0 is the overlap (m), δ̇ its rate
//! (m/s, positive while approaching), the force (N) is positive when repulsive, and a law
//! returns 0 for δ < 0.
//!
//! History: a law may keep per-contact state (`dashpot_contact_model_history_slots` values of
//! type double per contact, e.g. the largest overlap of a plastic law). The caller stores it:
//! zero at a contact's first touch, passed to every batch call (the law reads it and writes the
//! updated value in place), kept when the step is accepted, dropped when the contact ends. For a
//! trial evaluation (an integrator stage) pass a scratch copy.

use crate::contact::DashpotContactLaw;
use crate::error::{arg, guard, out, slice, slice_mut, CError, DashpotStatus, DashpotStatus::*};
use crate::materials::DashpotMaterials;
use dashpot_sdk::abi::ContactModelHandle;
use dashpot_sdk::NormalBatch;

/// A contact law bound to a pair of materials (opaque): the hot path of a polydisperse DEM code.
pub struct DashpotContactModel {
    pub(crate) model: ContactModelHandle,
}

/// Binds a contact law to a pair of materials: every constant that depends only on the
/// materials and the parameters is computed here, once. Any law may be bound this way, with
/// or without history.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR` (a modulus not finite and > 0),
/// `DASHPOT_ERR_INVALID_PARAMETER` (the law rejects these materials), `DASHPOT_ERR_PANIC`.
/// Ownership: `*out_model` is owned by the caller (free with `dashpot_contact_model_free`) and
/// may outlive the law. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_bind_materials(
    law: *const DashpotContactLaw,
    materials: *const DashpotMaterials,
    out_model: *mut *mut DashpotContactModel,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let m = unsafe { arg(materials, "materials") }?.to_materials()?;
        let o = unsafe { out(out_model, "out_model") }?;
        let model = l.law.bind(&m)?;
        *o = Box::into_raw(Box::new(DashpotContactModel { model }));
        Ok(())
    })
}

/// Frees a material-bound contact law (null is ignored).
///
/// # Safety
/// `model` must be null or a live handle from `dashpot_contact_bind_materials`, not used
/// concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_model_free(model: *mut DashpotContactModel) {
    if !model.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(model) })
        }));
    }
}

/// The number of history values (doubles) the law keeps per contact (0 for a memoryless law).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_model_history_slots(
    model: *const DashpotContactModel,
    out_slots: *mut usize,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let o = unsafe { out(out_slots, "out_slots") }?;
        *o = m.model.history_slots();
        Ok(())
    })
}

/// The normal force on `n` contacts, each with its own geometry and history:
/// `out_force[i] = F(delta[i], rate[i]; mass[i], radius[i], history[i*slots .. (i+1)*slots])`.
///
/// `delta` (m), `rate` (m/s), `mass` (effective mass m1 m2/(m1 + m2), kg; the particle's mass
/// against a wall), `radius` (effective radius r1 r2/(r1 + r2), m; the particle's radius against
/// a flat wall) and `out_force` (N) hold `n` values each; `history` holds `n_history = n × slots`
/// values (see `dashpot_contact_model_history_slots`; null with 0 for a memoryless law), read
/// and updated in place.
///
/// Every input is checked inside the plugin, fused with the computation: a NaN or infinite
/// overlap or rate, or a mass or radius not finite and > 0, is refused with
/// `DASHPOT_ERR_NON_FINITE` naming the array, the index and the value; so is a non-finite force.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (the handle, or an array when `n` > 0),
/// `DASHPOT_ERR_BAD_LENGTH` (`n_history` ≠ `n × slots`), `DASHPOT_ERR_NON_FINITE` (`out_force`
/// and `history` are then partly written), `DASHPOT_ERR_PANIC` (the handle stays usable).
/// Ownership: the arrays stay the caller's. Thread-safe (distinct output and history arrays
/// per thread).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; `out_force` and `history` must not overlap
/// each other or the inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_model_force_batch(
    model: *const DashpotContactModel,
    n: usize,
    delta: *const f64,
    rate: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = m.model.history_slots();
        if Some(n_history) != n.checked_mul(slots) {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_contact_model_force_batch: history must hold n × slots = {n} × {slots} \
                     values (law '{}'), got n_history = {n_history}",
                    m.model.name()
                ),
            ));
        }
        let delta = unsafe { slice(delta, n, "delta") }?;
        let rate = unsafe { slice(rate, n, "rate") }?;
        let mass = unsafe { slice(mass, n, "mass") }?;
        let radius = unsafe { slice(radius, n, "radius") }?;
        let history = unsafe { slice_mut(history, n_history, "history") }?;
        let force = unsafe { slice_mut(out_force, n, "out_force") }?;
        m.model.force_batch(NormalBatch {
            delta,
            rate,
            mass,
            radius,
            slots,
            history,
            force,
        })?;
        Ok(())
    })
}
