//! sdk 0.3's batch calls with energy outputs: the rolling and twisting kinds, and the tangential
//! kind's `_force_batch_energy`, from one body (`handle::energy_batch`) and one line per kind,
//! declared in the header by `DASHPOT_ENERGY_BATCH` lines. (Creating, binding and freeing:
//! `kinds.rs`.)
//!
//! Per contact: the unit normal n̂ (from the partner j to the particle i) as an `[x, y, z]`
//! triple; the input, a triple for the vector kinds (tangential: the velocity of i's contact
//! point relative to j's, ω × r included; rolling: v_roll = R_eff (ω_i − ω_j) × n̂, m/s), the
//! twisting rate (ω_i − ω_j)·n̂ (rad/s) for twisting; the normal force F_n (N), overlap δ (m),
//! effective mass (kg) and radius (m); the history, `n × slots` values updated in place. The
//! output: the tangential force on i (N), the rolling force F_r (N; its torque on i is
//! R_eff n̂ × F_r, on j the opposite; F_r itself is not applied to the centres), or the torque
//! about n̂ on i (N·m; on j the opposite). Energy outputs, where given (non-null): each contact's
//! dissipated power (W, ≥ 0) and stored elastic energy (J); `*out_energy_written` says whether
//! the law reported them (a law of an older sdk does not).

use crate::handle::{energy_batch_functions, EnergyBatch, Raw};
use crate::kinds::{DashpotRollingModel, DashpotTangentialModel, DashpotTwistingModel};
use dashpot_sdk::abi::EnergyOut;
use dashpot_sdk::{LawError, TwistingBatch};

impl EnergyBatch for DashpotTangentialModel {
    const WIDTH: usize = 3;
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.model.force_batch_with(b.vector(), energy)
    }
}

impl EnergyBatch for DashpotRollingModel {
    const WIDTH: usize = 3;
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.model.batch(b.vector(), energy)
    }
}

impl EnergyBatch for DashpotTwistingModel {
    const WIDTH: usize = 1;
    fn run(&self, b: Raw<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        let [normal_force, delta, mass, radius] = b.scalars;
        let (dt, normal, slots) = (b.dt, b.normal, b.slots);
        let (rate, history, torque) = (b.input, b.history, b.out);
        let twisting = TwistingBatch {
            dt,
            normal,
            rate,
            normal_force,
            delta,
            mass,
            radius,
            slots,
            history,
            torque,
        };
        self.model.batch(twisting, energy)
    }
}

energy_batch_functions! {
    DashpotTangentialModel: dashpot_tangential_model_force_batch_energy(velocity, out_force);
    DashpotRollingModel: dashpot_rolling_model_force_batch(velocity, out_force);
    DashpotTwistingModel: dashpot_twisting_model_torque_batch(rate, out_torque);
}
