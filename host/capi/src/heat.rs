//! The batch call of the heat kind (sdk 0.4): the heat each contact conducts between its two
//! temperatures. (Creating, binding and freeing: `kinds.rs`, `dashpot_heat_*`.)
//!
//! Per contact: the temperatures `[T_i, T_j]` (K; the partner's, or a wall's, second: `2 n`
//! doubles), the normal force F_n (N), the overlap δ (m), the effective radius R_eff (m; R_i
//! against a flat wall), optionally the normal law's context (3 doubles: contact radius m, cap
//! force N, damping N·s/m, from `dashpot_contact_model_force_batch_context`; null for the
//! default a = √(R_eff max(δ, 0)); `dashpot_heat_model_reads_context` says whether the law
//! reads it), and the history (`n × slots`, kept by the caller as for every kind). Outputs: the
//! heat flow Q into particle i (W); add Q to i's heat rate and −Q to j's (Q_ji = −Q_ij exactly),
//! then T += dt Q / (m c) as LAMMPS's `fix heat/flow`; and, if non-null, each contact's
//! conductance H (W/K), whose sum per particle bounds the stable step dt < m c / Σ H.

use crate::error::{arg, guard, slice, slice_mut, CError, DashpotStatus};
use crate::handle::{contexts, history_width};
use crate::kinds::DashpotHeatModel;
use dashpot_core::laws::HeatConduction;
use dashpot_sdk::{HeatBatch, HeatFlow};

/// The heat flow through each of `n` contacts: `out_heat[i]` (W) into particle i, and
/// `out_conductance[i]` (W/K) if `out_conductance` is not null. `temperature` holds `2 n`
/// values `[T_i, T_j]` (K); `normal_force` (N), `delta` (m) and `radius` (m) `n` each;
/// `context` `3 n` values or null (the defaults); `history` `n_history = n × slots` values,
/// updated in place. A non-finite temperature, force or overlap, a radius ≤ 0 or a bad context
/// gives `DASHPOT_ERR_NON_FINITE` naming the contact, before the law runs.
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or the
/// inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_heat_model_heat_batch(
    model: *const DashpotHeatModel,
    n: usize,
    dt: f64,
    temperature: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    radius: *const f64,
    context: *const f64,
    history: *mut f64,
    n_history: usize,
    out_heat: *mut f64,
    out_conductance: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let what = "dashpot_heat_model_heat_batch";
        let m = unsafe { arg(model, "model") }?;
        let slots = history_width(what, m, n, n_history)?;
        let two_n = n.checked_mul(2).ok_or_else(|| {
            CError::new(
                DashpotStatus::DASHPOT_ERR_BAD_LENGTH,
                format!("n = {n} contacts is too many"),
            )
        })?;
        let t = unsafe { slice(temperature, two_n, "temperature") }?;
        // SAFETY: [f64; 2] has the alignment of f64 and no padding; n whole pairs.
        let t: &[[f64; 2]] =
            unsafe { std::slice::from_raw_parts(t.as_ptr().cast::<[f64; 2]>(), t.len() / 2) };
        let normal_force = unsafe { slice(normal_force, n, "normal_force") }?;
        let delta = unsafe { slice(delta, n, "delta") }?;
        let radius = unsafe { slice(radius, n, "radius") }?;
        let context = unsafe { contexts(context, n) }?;
        let history = unsafe { slice_mut(history, n_history, "history") }?;
        let heat = unsafe { slice_mut(out_heat, n, "out_heat") }?;
        let conductance = if out_conductance.is_null() {
            None
        } else {
            Some(unsafe { slice_mut(out_conductance, n, "out_conductance") }?)
        };
        let mut flow = vec![HeatFlow::default(); n];
        m.model.heat_batch(HeatBatch {
            dt,
            temperature: t,
            normal_force,
            delta,
            radius,
            context,
            slots,
            history,
            flow: &mut flow,
        })?;
        for (h, f) in heat.iter_mut().zip(&flow) {
            *h = f.heat;
        }
        if let Some(c) = conductance {
            for (c, f) in c.iter_mut().zip(&flow) {
                *c = f.conductance;
            }
        }
        Ok(())
    })
}
