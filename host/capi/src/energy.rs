//! The batch calls of the tangential, rolling and twisting kinds (sdk 0.2, 0.3), with sdk 0.3's
//! energy outputs where the function has them (the tangential kind's `_force_batch_energy`, the
//! rolling and twisting batches), from one body (`handle::energy_batch`) and one line per
//! function, declared in the header by `DASHPOT_MOTION_BATCH` lines. (Creating, binding and
//! freeing: `kinds.rs`.)
//!
//! Vectors are `[x, y, z]` triples stored one after the other (`3 n` doubles for `n` contacts;
//! a 2D code sets z = 0). Per contact: the unit normal n̂ (from the partner j to the particle i);
//! the input, a triple for the vector kinds (tangential: the velocity of i's contact point
//! relative to j's, ω × r included, of which the law uses the part in the tangent plane;
//! rolling: v_roll = R_eff (ω_i − ω_j) × n̂, m/s), the twisting rate (ω_i − ω_j)·n̂ (rad/s) for
//! twisting; the normal force F_n (N), overlap δ (m), effective mass (kg) and radius (m); the
//! history (a spring's displacement, for example), `n × slots` values stored by the caller
//! exactly as for contact laws: zero at first touch, updated in place by each call, kept when
//! the step is accepted, dropped when the contact ends. The output: the tangential force on i
//! (N, capped by Coulomb's μ F_n), the rolling force F_r (N; its torque on i is R_eff n̂ × F_r,
//! on j the opposite; F_r itself is not applied to the centres), or the torque about n̂ on i
//! (N·m; on j the opposite). Energy outputs, where given (non-null): each contact's dissipated
//! power (W, ≥ 0) and stored elastic energy (J); `*out_energy_written` says whether the law
//! reported them (a law of an older sdk does not). The `_context` forms (sdk 0.4) also take the
//! normal law's context of each contact (3 values: contact radius m, cap force N, damping
//! N·s/m; from `dashpot_contact_model_force_batch_context`), or null for the defaults; a host
//! asks `dashpot_KIND_model_reads_context` whether the law reads it.

use crate::handle::{motion_batch_functions, EnergyBatch, Raw};
use crate::kinds::{DashpotRollingModel, DashpotTangentialModel, DashpotTwistingModel};
use dashpot_sdk::abi::EnergyOut;
use dashpot_sdk::{LawError, TwistingBatch};

impl EnergyBatch for DashpotTangentialModel {
    const WIDTH: usize = 3;
    #[inline(always)]
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.model.force_batch_with(b.vector(), energy)
    }
}

impl EnergyBatch for DashpotRollingModel {
    const WIDTH: usize = 3;
    #[inline(always)]
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.model.batch(b.vector(), energy)
    }
}

impl EnergyBatch for DashpotTwistingModel {
    const WIDTH: usize = 1;
    #[inline(always)]
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        let [normal_force, delta, mass, radius] = b.scalars;
        let (dt, normal, context, slots) = (b.dt, b.normal, b.context, b.slots);
        let (rate, history, torque) = (b.input, b.history, b.out);
        let twisting = TwistingBatch {
            dt,
            normal,
            rate,
            normal_force,
            delta,
            mass,
            radius,
            context,
            slots,
            history,
            torque,
        };
        self.model.batch(twisting, energy)
    }
}

motion_batch_functions! {
    DashpotTangentialModel: dashpot_tangential_model_force_batch(velocity, out_force);
    DashpotTangentialModel:
        dashpot_tangential_model_force_batch_energy(velocity, out_force, out_power, out_elastic, out_energy_written);
    DashpotRollingModel: dashpot_rolling_model_force_batch(velocity, out_force, out_power, out_elastic, out_energy_written);
    DashpotTwistingModel: dashpot_twisting_model_torque_batch(rate, out_torque, out_power, out_elastic, out_energy_written);
    DashpotTangentialModel:
        dashpot_tangential_model_force_batch_context(velocity, out_force [context], out_power, out_elastic, out_energy_written);
    DashpotRollingModel:
        dashpot_rolling_model_force_batch_context(velocity, out_force [context], out_power, out_elastic, out_energy_written);
    DashpotTwistingModel:
        dashpot_twisting_model_torque_batch_context(rate, out_torque [context], out_power, out_elastic, out_energy_written);
}
