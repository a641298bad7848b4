//! Contact laws bound to materials (sdk 0.2-0.4): per-contact geometry and history in the batch
//! call, sdk 0.3's reach and energy outputs, and sdk 0.4's normal contexts (what the contact's
//! other laws read). (Creating, binding and freeing: `kinds.rs`.)
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
use crate::handle::{contexts_out, energy, history_width, optional, report_written};
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
    out_context: Option<*mut f64>,
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
        let energy = unsafe { energy(out_power, out_elastic, n) }?;
        let written = match out_context {
            Some(p) => {
                let context = unsafe { contexts_out(p, n) }?;
                m.model.force_batch_context(b, reach, context, energy)?
            }
            None => m.model.force_batch_with(b, reach, energy)?,
        };
        unsafe { report_written(out_energy_written, written) };
        Ok(())
    })
}

/// The reach, energy and context outputs of a contact batch: those given, or none (null).
macro_rules! contact_outputs {
    () => {
        ([std::ptr::null_mut(); 3], std::ptr::null_mut(), None)
    };
    ($reach:ident, $power:ident, $elastic:ident, $written:ident) => {
        ([$reach, $power, $elastic], $written, None)
    };
    ($reach:ident, $power:ident, $elastic:ident, $written:ident, $context:ident) => {
        ([$reach, $power, $elastic], $written, Some($context))
    };
}

/// `dashpot_contact_model_force_batch`, its sdk 0.3 form with the reach and energy outputs and
/// its sdk 0.4 form with the contexts too, from one parameter list: the header's
/// `DASHPOT_CONTACT_BATCH`, whose comment is their contract.
macro_rules! contact_batch_functions {
    ($($name:ident($($reach:ident, $power:ident, $elastic:ident, $written:ident $(, $context:ident)?)?);)*) => {$(
        /// A contact batch: `DASHPOT_CONTACT_BATCH` in dashpot.h.
        ///
        /// # Safety
        /// Non-null arrays must hold the lengths the header states; outputs must not overlap
        /// each other or the inputs.
        #[allow(clippy::too_many_arguments)]
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            model: *const DashpotContactModel,
            n: usize,
            delta: *const f64,
            rate: *const f64,
            mass: *const f64,
            radius: *const f64,
            history: *mut f64,
            n_history: usize,
            out_force: *mut f64,
            $($reach: *mut f64, $power: *mut f64, $elastic: *mut f64, $written: *mut c_int, $($context: *mut f64,)?)?
        ) -> DashpotStatus {
            let (outs, written, context) = contact_outputs!($($reach, $power, $elastic, $written $(, $context)?)?);
            let inputs = [delta, rate, mass, radius];
            unsafe { batch(stringify!($name), model, n, inputs, history, n_history, out_force, outs, written, context) }
        }
    )*};
}

contact_batch_functions! {
    dashpot_contact_model_force_batch();
    dashpot_contact_model_force_batch_energy(out_reach, out_power, out_elastic, out_energy_written);
    dashpot_contact_model_force_batch_context(out_reach, out_power, out_elastic, out_energy_written, out_context);
}
