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
use crate::law::{
    history_law, history_mut, law_info, law_trait, Coefficient, Energy, EnergyBatch, History, LawInfo,
    LawKind,
};
use crate::law::{motion_kind, VectorBatch, VectorContact};
use crate::pair::MaterialPair;
use crate::params::{LawParams, ParamValue};

/// The state of one contact as a rolling law sees it ([`VectorContact`]; its `velocity` is the
/// relative rolling velocity v_roll = R_eff (ω_i − ω_j) × n̂, m/s, and its `radius` R_eff the
/// torque arm).
pub type RollingContact = VectorContact;

/// Every contact of one material pair for a rolling law ([`VectorBatch`]; its `force` is the
/// rolling-resistance force F_roll (N), whose torque on i is R_eff n̂ × F_roll).
pub type RollingBatch<'a> = VectorBatch<'a>;

/// A rolling-resistance law bound to a material pair.
pub trait BoundRolling: Send + Sync + 'static {
    /// The rolling-resistance force (N) on contact `c`, updating `history` in place.
    fn force(&self, c: &RollingContact, history: &mut [f64]) -> [f64; 3];

    /// `b.force[i]` for every contact of the batch.
    #[inline(always)]
    fn force_batch(&self, b: RollingBatch<'_>) {
        b.each(|c, h| self.force(c, h));
    }

    /// The energy of contact `c` after a call that returned `force` and left `history`;
    /// `None` (the default) when the law does not account for it.
    fn energy(&self, _c: &RollingContact, _history: &[f64], _force: [f64; 3]) -> Option<Energy> {
        None
    }

    /// The force (N) on contact `c`, `history` updated as by [`BoundRolling::force`], with the
    /// contact's energy over the step (sdk 0.3), the history before the step in view. The
    /// default is [`BoundRolling::force`] then [`BoundRolling::energy`].
    #[inline(always)]
    fn force_energy(&self, c: &RollingContact, history: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let f = self.force(c, history);
        (f, self.energy(c, history, f))
    }

    /// [`BoundRolling::force_batch`] with each contact's energy written to `out`; whether every
    /// contact reported one. The default loops over [`BoundRolling::force_energy`]: a law that
    /// overrides `force_batch` for speed overrides this too.
    #[inline(always)]
    fn force_batch_energy(&self, b: RollingBatch<'_>, out: EnergyBatch<'_>) -> bool {
        b.each_energy(out, |c, h| self.force_energy(c, h))
    }

    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        Vec::new()
    }
}

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
    /// The twisting torque (N·m) about n̂ on contact `c`, updating `history` in place.
    fn torque(&self, c: &TwistingContact, history: &mut [f64]) -> f64;

    /// `b.torque[i]` for every contact of the batch.
    #[inline(always)]
    fn torque_batch(&self, b: TwistingBatch<'_>) {
        b.each(|c, h| self.torque(c, h));
    }

    /// The energy of contact `c` after a call that returned `torque` and left `history`;
    /// `None` (the default) when the law does not account for it.
    fn energy(&self, _c: &TwistingContact, _history: &[f64], _torque: f64) -> Option<Energy> {
        None
    }

    /// The torque (N·m) on contact `c`, `history` updated as by [`BoundTwisting::torque`], with
    /// the contact's energy over the step (sdk 0.3), the history before the step in view. The
    /// default is [`BoundTwisting::torque`] then [`BoundTwisting::energy`].
    #[inline(always)]
    fn torque_energy(&self, c: &TwistingContact, history: &mut [f64]) -> (f64, Option<Energy>) {
        let m = self.torque(c, history);
        (m, self.energy(c, history, m))
    }

    /// [`BoundTwisting::torque_batch`] with each contact's energy written to `out`; whether
    /// every contact reported one. The default loops over [`BoundTwisting::torque_energy`].
    #[inline(always)]
    fn torque_batch_energy(&self, b: TwistingBatch<'_>, out: EnergyBatch<'_>) -> bool {
        b.each_energy(out, |c, h| self.torque_energy(c, h))
    }

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
