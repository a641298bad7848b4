//! Restitution laws r(v): create by name, bind to a pair, evaluate.

use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::pair::DashpotPair;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::{BoundRestitutionHandle, RestitutionLawHandle};
use std::ffi::c_char;

/// A configured restitution law (opaque).
pub struct DashpotRestitutionLaw {
    law: RestitutionLawHandle,
}

/// A restitution law bound to a pair (opaque).
pub struct DashpotBoundRestitution {
    bound: BoundRestitutionHandle,
}

/// Creates restitution law `name` from `n_params` named values.
///
/// Errors, ownership and thread safety as `dashpot_contact_new` (`DASHPOT_ERR_UNKNOWN_LAW` also
/// for a contact law's name). Free with `dashpot_restitution_free`.
///
/// # Safety
/// As `dashpot_contact_new`.
#[no_mangle]
pub unsafe extern "C" fn dashpot_restitution_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotRestitutionLaw,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        let law = r.reg.restitution(name, &p)?;
        *o = Box::into_raw(Box::new(DashpotRestitutionLaw { law }));
        Ok(())
    })
}

/// Frees a restitution law (null is ignored).
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_restitution_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_restitution_free(law: *mut DashpotRestitutionLaw) {
    if !law.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(law) })
        }));
    }
}

/// Binds a restitution law to a pair.
///
/// Errors, ownership and thread safety as `dashpot_contact_bind`. Free with
/// `dashpot_bound_restitution_free`.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_restitution_bind(
    law: *const DashpotRestitutionLaw,
    pair: *const DashpotPair,
    out_bound: *mut *mut DashpotBoundRestitution,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let p = unsafe { arg(pair, "pair") }?.to_pair()?;
        let o = unsafe { out(out_bound, "out_bound") }?;
        let bound = l.law.bind(&p)?;
        *o = Box::into_raw(Box::new(DashpotBoundRestitution { bound }));
        Ok(())
    })
}

/// Frees a bound restitution law (null is ignored).
///
/// # Safety
/// `bound` must be null or a live handle from `dashpot_restitution_bind`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_bound_restitution_free(bound: *mut DashpotBoundRestitution) {
    if !bound.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(bound) })
        }));
    }
}

/// r(v): the coefficient of restitution at normal impact speed `speed` (m/s).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_NON_FINITE`, `DASHPOT_ERR_PANIC`.
/// Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_restitution_eval(
    bound: *const DashpotBoundRestitution,
    speed: f64,
    out_restitution: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        let o = unsafe { out(out_restitution, "out_restitution") }?;
        *o = b.bound.restitution(speed)?;
        Ok(())
    })
}

/// `out_restitution[i] = r(speed[i])`; the two lengths must be equal.
///
/// Errors: as `dashpot_contact_force_batch`. Thread-safe.
///
/// # Safety
/// Non-null arrays must hold as many elements as their length says, without overlapping.
#[no_mangle]
pub unsafe extern "C" fn dashpot_restitution_batch(
    bound: *const DashpotBoundRestitution,
    speed: *const f64,
    n_speed: usize,
    out_restitution: *mut f64,
    n_out: usize,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        if n_speed != n_out {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_restitution_batch: speed and out_restitution must have the same length, \
                     got {n_speed} and {n_out}"
                ),
            ));
        }
        let s = unsafe { slice(speed, n_speed, "speed") }?;
        let o = unsafe { slice_mut(out_restitution, n_out, "out_restitution") }?;
        b.bound.restitution_batch(s, o)?;
        Ok(())
    })
}
