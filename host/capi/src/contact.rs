//! Contact laws: create by name, bind to a pair, evaluate the normal force per pair or over
//! arrays.
//!
//! Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while the bodies approach),
//! and the force (N) is positive when repulsive. For δ < 0 a law returns 0.

use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::pair::DashpotPair;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::{BoundContactHandle, ContactLawHandle};
use std::ffi::c_char;

/// A configured contact law (opaque).
pub struct DashpotContactLaw {
    pub(crate) law: ContactLawHandle,
}

/// A contact law bound to a pair (opaque): the hot path.
pub struct DashpotBoundContact {
    pub(crate) bound: BoundContactHandle,
}

/// Creates contact law `name` from `n_params` named values (parameters left out take their
/// defaults; the values are validated against the law's schema).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW` (also for a restitution law's
/// name), `DASHPOT_ERR_UNKNOWN_PARAMETER`, `DASHPOT_ERR_INVALID_PARAMETER`, `DASHPOT_ERR_PANIC`.
/// Ownership: inputs are copied; `*out_law` is owned by the caller (free with
/// `dashpot_contact_free`) and may outlive the registry. Thread-safe.
///
/// # Safety
/// `param_names`/`param_values` must be null (only if `n_params` is 0) or hold `n_params`
/// elements; strings NUL-terminated; other non-null pointers valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotContactLaw,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        let law = r.reg.contact(name, &p)?;
        *o = Box::into_raw(Box::new(DashpotContactLaw { law }));
        Ok(())
    })
}

/// Frees a contact law (null is ignored). Bound laws made from it stay valid.
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_contact_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_free(law: *mut DashpotContactLaw) {
    if !law.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(law) })
        }));
    }
}

/// Binds a contact law to a pair: every constant of the force is computed here, once.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR` (a pair field not finite or not
/// positive), `DASHPOT_ERR_INVALID_PARAMETER` (the law rejects this pair), `DASHPOT_ERR_PANIC`.
/// Ownership: `*out_bound` is owned by the caller (free with `dashpot_bound_contact_free`) and
/// may outlive the law. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_bind(
    law: *const DashpotContactLaw,
    pair: *const DashpotPair,
    out_bound: *mut *mut DashpotBoundContact,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let p = unsafe { arg(pair, "pair") }?.to_pair()?;
        let o = unsafe { out(out_bound, "out_bound") }?;
        let bound = l.law.bind(&p)?;
        *o = Box::into_raw(Box::new(DashpotBoundContact { bound }));
        Ok(())
    })
}

/// Frees a bound contact law (null is ignored).
///
/// # Safety
/// `bound` must be null or a live handle from `dashpot_contact_bind`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_bound_contact_free(bound: *mut DashpotBoundContact) {
    if !bound.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(bound) })
        }));
    }
}

/// The normal force F(δ, δ̇) (N) at overlap `delta` (m) and overlap rate `rate` (m/s).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_NON_FINITE` (the law returned NaN or inf;
/// `*out_force` is not written), `DASHPOT_ERR_PANIC` (the law panicked; the handle stays
/// usable). Thread-safe: any number of threads may evaluate the same bound law at once.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_force(
    bound: *const DashpotBoundContact,
    delta: f64,
    rate: f64,
    out_force: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        let o = unsafe { out(out_force, "out_force") }?;
        *o = b.bound.force(delta, rate)?;
        Ok(())
    })
}

/// `out_force[i] = F(delta[i], rate[i])` (N) for every i: the call a DEM code makes once per
/// step (per kind of pair) with all its contacts. The three lengths must be equal. Every
/// output is checked for NaN and infinity inside the plugin, fused with the computation.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (a handle, or an array whose length is > 0),
/// `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE` (the message names the first bad
/// index's inputs; `out_force` is then partly written), `DASHPOT_ERR_PANIC`.
/// Ownership: the arrays stay the caller's. Thread-safe (distinct output arrays per thread).
///
/// # Safety
/// Non-null arrays must hold as many elements as their length says; `out_force` must not
/// overlap the inputs.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_force_batch(
    bound: *const DashpotBoundContact,
    delta: *const f64,
    n_delta: usize,
    rate: *const f64,
    n_rate: usize,
    out_force: *mut f64,
    n_out: usize,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        if n_delta != n_out || n_rate != n_out {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_contact_force_batch: delta, rate and out_force must have the same length, \
                     got {n_delta}, {n_rate} and {n_out}"
                ),
            ));
        }
        let d = unsafe { slice(delta, n_delta, "delta") }?;
        let r = unsafe { slice(rate, n_rate, "rate") }?;
        let o = unsafe { slice_mut(out_force, n_out, "out_force") }?;
        b.bound.force_batch(d, r, o)?;
        Ok(())
    })
}

/// A derived constant of the bound law by name (for HSD: `"K"`, `"c"`, `"alpha"`, ...).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_ARGUMENT` (no coefficient of that
/// name; the message lists those that exist), `DASHPOT_ERR_PANIC`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid; `name` NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_coefficient(
    bound: *const DashpotBoundContact,
    name: *const c_char,
    out_value: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_value, "out_value") }?;
        let all = b.bound.coefficients()?;
        match all.iter().find(|c| c.name == name) {
            Some(c) => {
                *o = c.value;
                Ok(())
            }
            None => Err(CError::new(
                DASHPOT_ERR_INVALID_ARGUMENT,
                format!(
                    "contact law '{}' has no coefficient '{name}'; it has: {}",
                    b.bound.name(),
                    all.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")
                ),
            )),
        }
    })
}
