//! Rolling and twisting resistance (sdk 0.3): the batch call on every contact with its history.
//! (Creating, binding and freeing: `kinds.rs`.)
//!
//! Rolling: per contact the unit normal n̂ (from the partner j to the particle i) and the rolling
//! velocity v_roll = R_eff (ω_i − ω_j) × n̂ (m/s), as `[x, y, z]` triples; the result is the
//! rolling-resistance force F_r (N), whose torque on i is R_eff n̂ × F_r (on j its opposite; F_r
//! itself is not applied to the centres). Twisting: the twisting rate (ω_i − ω_j)·n̂ (rad/s);
//! the result is the torque about n̂ on i (N·m; on j its opposite). History is kept by the caller
//! as for the other kinds: zero at first touch, updated in place, dropped when the contact ends.
//! Energy outputs, where given (non-null): each contact's dissipated power (W, ≥ 0) and stored
//! elastic energy (J); `*out_energy_written` says whether the law reported them (a law of an
//! older sdk does not).

use crate::error::{arg, guard, slice, slice_mut, DashpotStatus};
use crate::handle::{energy, history_width, report_written, vector_batch, vectors};
use crate::kinds::{DashpotRollingModel, DashpotTwistingModel};
use dashpot_sdk::TwistingBatch;
use std::ffi::c_int;

/// The rolling-resistance force on `n` contacts, history advanced by the step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal (partner to particle), `velocity[3i..3i+3]`
/// the rolling velocity R_eff (ω_i − ω_j) × n̂ (m/s), `normal_force[i]` (N), `delta[i]` (m),
/// `mass[i]` (kg), `radius[i]` (m, R_eff), `history` (`n × slots` values, in place),
/// `out_force[3i..3i+3]` the rolling force F_r (N; torque on i: R_eff n̂ × F_r); `out_power`,
/// `out_elastic` (null, or `n` values each) the energy outputs, `*out_energy_written` (may be
/// null) whether the law wrote them.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE`
/// (naming the array, index and value), `DASHPOT_ERR_PANIC`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_model_force_batch(
    model: *const DashpotRollingModel,
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
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let scalars = [normal_force, delta, mass, radius];
        let what = "dashpot_rolling_model_force_batch";
        let b = unsafe {
            vector_batch(
                what, m, n, dt, normal, velocity, scalars, history, n_history, out_force,
            )
        }?;
        let written = m.model.batch(b, unsafe { energy(out_power, out_elastic, n) }?)?;
        unsafe { report_written(out_energy_written, written) };
        Ok(())
    })
}

/// The twisting torque on `n` contacts, history advanced by the step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal, `rate[i]` the twisting rate
/// (ω_i − ω_j)·n̂ (rad/s), `normal_force[i]` (N), `delta[i]` (m), `mass[i]` (kg), `radius[i]`
/// (m), `history` (`n × slots` values, in place), `out_torque[i]` the torque about n̂ on i (N·m);
/// energy outputs as in `dashpot_rolling_model_force_batch`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE`,
/// `DASHPOT_ERR_PANIC`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_model_torque_batch(
    model: *const DashpotTwistingModel,
    n: usize,
    dt: f64,
    normal: *const f64,
    rate: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_torque: *mut f64,
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = history_width("dashpot_twisting_model_torque_batch", m, n, n_history)?;
        let b = TwistingBatch {
            dt,
            normal: unsafe { vectors(normal, n, "normal") }?,
            rate: unsafe { slice(rate, n, "rate") }?,
            normal_force: unsafe { slice(normal_force, n, "normal_force") }?,
            delta: unsafe { slice(delta, n, "delta") }?,
            mass: unsafe { slice(mass, n, "mass") }?,
            radius: unsafe { slice(radius, n, "radius") }?,
            slots,
            history: unsafe { slice_mut(history, n_history, "history") }?,
            torque: unsafe { slice_mut(out_torque, n, "out_torque") }?,
        };
        let written = m.model.batch(b, unsafe { energy(out_power, out_elastic, n) }?)?;
        unsafe { report_written(out_energy_written, written) };
        Ok(())
    })
}
