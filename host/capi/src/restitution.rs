//! Restitution laws r(v) bound to a pair: evaluate. (Creating, binding and freeing: `kinds.rs`.)

use crate::error::{arg, guard, output, same_lengths, slice, slice_mut, DashpotStatus};
use crate::kinds::DashpotBoundRestitution;

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
    output!(arg bound => out_restitution = bound.bound.restitution(speed)?)
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
        let lengths = [("speed", n_speed), ("out_restitution", n_out)];
        same_lengths("dashpot_restitution_batch", &lengths)?;
        let s = unsafe { slice(speed, n_speed, "speed") }?;
        let o = unsafe { slice_mut(out_restitution, n_out, "out_restitution") }?;
        b.bound.restitution_batch(s, o)?;
        Ok(())
    })
}
