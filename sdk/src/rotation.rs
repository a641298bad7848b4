//! The two rotational law kinds of sdk 0.3: rolling resistance and twisting resistance.
//!
//! Conventions (those of LAMMPS `pair_style granular`): n̂ is the unit contact normal from the
//! partner j to the particle i; R_eff the contact's effective radius; ω_i, ω_j the angular
//! velocities (rad/s).
//! - **Rolling**: the relative rolling velocity is v_roll = R_eff (ω_i − ω_j) × n̂ (m/s, in the
//!   tangent plane; for a sphere rolling without slip on a still wall, its centre's velocity).
//!   The law returns a rolling-resistance force F_roll (N) in the tangent plane; it is never
//!   applied to the centres: the torque on i is M_i = R_eff n̂ × F_roll (N·m), on j −M_i.
//! - **Twisting**: the relative twisting rate is ω_tw = (ω_i − ω_j) · n̂ (rad/s); the law
//!   returns the twisting torque M_tw (N·m) about n̂ on i (the torque vector M_tw n̂ on i,
//!   −M_tw n̂ on j).
//!
//! Both kinds keep a per-contact history (zero at first touch), which the caller stores as for
//! tangential laws, and both receive the contact's normal force, overlap, effective mass and
//! radius and the time step.

use crate::error::LawError;
use crate::law::history_mut;
use crate::law::{
    history_law, law_info, law_trait, Coefficient, Energy, EnergyBatch, History, LawInfo, LawKind,
};
use crate::motion::{motion_kind, motion_law_methods, vector_law};
use crate::pair::MaterialPair;
use crate::params::{LawParams, ParamValue};

vector_law!(
    /// The state of one contact as a rolling law sees it ([`VectorContact`](crate::VectorContact);
    /// its `velocity` is the relative rolling velocity v_roll = R_eff (ω_i − ω_j) × n̂, m/s, and
    /// its `radius` R_eff the torque arm).
    RollingContact,
    /// Every contact of one material pair for a rolling law ([`VectorBatch`](crate::VectorBatch);
    /// its `force` is the rolling-resistance force F_roll (N), whose torque on i is
    /// R_eff n̂ × F_roll).
    RollingBatch,
    /// A rolling-resistance law bound to a material pair.
    BoundRolling: "rolling-resistance force (N)" {
        /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
        fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
            Vec::new()
        }
    }
);

motion_kind!(
    /// The state of one contact as a twisting law sees it.
    TwistingContact,
    /// Every contact of one material pair for a twisting law, structure of arrays; `history` is
    /// `n × slots` as in [`NormalBatch`](crate::NormalBatch).
    TwistingBatch,
    /// Relative twisting rate ω_tw = (ω_i − ω_j) · n̂ (rad/s).
    rate: f64,
    /// Output: the twisting torque M_tw about n̂ on particle i (N·m).
    torque: f64
);

/// A twisting-resistance law bound to a material pair.
pub trait BoundTwisting: Send + Sync + 'static {
    motion_law_methods!(
        "twisting torque (N·m) about n̂",
        TwistingContact,
        TwistingBatch<'_>,
        f64,
        torque,
        torque_batch,
        torque_energy,
        torque_batch_energy
    );

    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        Vec::new()
    }
}

history_law!(
    /// A configurable rolling-resistance law (sdk 0.3). Declare its parameters with
    /// [`law_params!`](crate::law_params), implement this, then export with
    /// [`export_laws!`](crate::export_laws) under `rolling: [...]`.
    RollingLaw: BoundRolling, LawKind::Rolling
);

history_law!(
    /// A configurable twisting-resistance law (sdk 0.3). Declare its parameters with
    /// [`law_params!`](crate::law_params), implement this, then export with
    /// [`export_laws!`](crate::export_laws) under `twisting: [...]`.
    TwistingLaw: BoundTwisting, LawKind::Twisting
);
