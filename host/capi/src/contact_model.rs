//! Contact laws bound to materials (sdk 0.2, 0.3): per-contact geometry and history in the batch
//! call, and sdk 0.3's reach and energy outputs. (Creating, binding and freeing: `kinds.rs`.)
//!
//! Sign convention as for the pair-bound functions: δ ≥ 0 is the overlap (m), δ̇ its rate
//! (m/s, positive while approaching), the force (N) is positive when repulsive, and a law
//! that is not adhesive returns 0 for δ < 0.
//!
//! History: a law may keep per-contact state (`dashpot_contact_model_history_slots` values of
//! type double per contact, e.g. the largest overlap of a plastic law). The caller stores it:
//! zero at a contact's first touch, passed to every batch call (the law reads it and writes the
//! updated value in place), kept when the step is accepted, dropped when the contact ends. For a
//! trial evaluation (an integrator stage) pass a scratch copy.

use crate::error::{arg, guard, slice, slice_mut, DashpotStatus};
use crate::handle::{energy, history_width, optional, report_written};
use crate::kinds::DashpotContactModel;
use dashpot_sdk::NormalBatch;
use std::ffi::c_int;

/// The body of both batch functions: the checks, then the law.
///
/// # Safety
/// As their contracts.
#[allow(clippy::too_many_arguments)]
unsafe fn batch(
    what: &str,
    model: *const DashpotContactModel,
    n: usize,
    [delta, rate, mass, radius]: [*const f64; 4],
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
    [out_reach, out_power, out_elastic]: [*mut f64; 3],
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = history_width(what, m, n, n_history)?;
        let b = NormalBatch {
            delta: unsafe { slice(delta, n, "delta") }?,
            rate: unsafe { slice(rate, n, "rate") }?,
            mass: unsafe { slice(mass, n, "mass") }?,
            radius: unsafe { slice(radius, n, "radius") }?,
            slots,
            history: unsafe { slice_mut(history, n_history, "history") }?,
            force: unsafe { slice_mut(out_force, n, "out_force") }?,
        };
        let reach = unsafe { optional(out_reach, n, "out_reach") }?;
        let written = m
            .model
            .force_batch_with(b, reach, unsafe { energy(out_power, out_elastic, n) }?)?;
        unsafe { report_written(out_energy_written, written) };
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
    let what = "dashpot_contact_model_force_batch";
    let null = std::ptr::null_mut();
    unsafe {
        batch(
            what,
            model,
            n,
            [delta, rate, mass, radius],
            history,
            n_history,
            out_force,
            [null; 3],
            null.cast(),
        )
    }
}

/// `dashpot_contact_model_force_batch` with sdk 0.3's outputs, each null or `n` values:
/// `out_reach[i]` how far beyond touching the contact still acts (m: it ends once δ < −reach;
/// 0 for a non-adhesive law), `out_power[i]` the dissipated power (W), `out_elastic[i]` the
/// stored elastic energy (J); `*out_energy_written` (may be null) whether the law reported the
/// energy.
///
/// Errors: as `dashpot_contact_model_force_batch`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_model_force_batch_energy(
    model: *const DashpotContactModel,
    n: usize,
    delta: *const f64,
    rate: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
    out_reach: *mut f64,
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    let what = "dashpot_contact_model_force_batch_energy";
    let outs = [out_reach, out_power, out_elastic];
    unsafe {
        batch(
            what,
            model,
            n,
            [delta, rate, mass, radius],
            history,
            n_history,
            out_force,
            outs,
            out_energy_written,
        )
    }
}
