//! Cundall–Strack tangential spring with Coulomb friction: a constant stiffness k_t and a history
//! spring (Cundall & Strack, Géotechnique 29, 47, 1979; bookkeeping of LAMMPS `pair_style
//! granular` `tangential linear_history` and Luding 2008).
//!
//! # Formula
//! Per contact of overlap δ (m) and effective mass m (kg):
//!
//! - stiffness k_t (N/m), the parameter `kt`, the same for every contact;
//! - dashpot η_t = 2 ζ_t √(m k_t) (N·s/m), ζ_t the parameter `damping` (relative to the
//!   contact's effective mass m, not to the tangential effective mass 2m/7 of a rolling sphere);
//! - history: the spring displacement ξ (m, 3 slots `xi_x`, `xi_y`, `xi_z`), zero at first
//!   touch.
//!
//! # Conventions
//! `normal` n̂ is the unit normal from the partner j to the particle i the force acts on;
//! `velocity` v is the velocity of i's contact point relative to j's, ω × r terms included
//! (for a sphere of radius R on a wall: v + ω × (−R n̂)); the result is the tangential force on
//! i (the partner receives its opposite). `normal_force` F_n is this step's normal force
//! (N, > 0 repulsive). To make ξ the tangential displacement of the contact points accumulated
//! over the step, pass the velocity over the step (in velocity Verlet the half-step velocity,
//! (x_{n+1} − x_n)/dt), and the normal force at the end of the step.
//!
//! # Order of one call (time step dt)
//! 1. δ ≤ 0: no contact; the force is 0 and ξ is reset to 0 (what it stored is dissipated).
//! 2. Rotate: ξ ← ξ − (ξ·n̂) n̂, rescaled to its previous length (the contact frame turned).
//! 3. Tangential relative velocity v_t = v − (v·n̂) n̂; advance ξ_t = ξ + v_t dt; trial force
//!    F_t = −k_t ξ_t − η_t v_t.
//! 4. Coulomb: if |F_t| > μ max(F_n, 0), F_t is scaled to length μ max(F_n, 0), and the spring
//!    is the one that force leaves in a spring ∥ dashpot element in series with the slider:
//!    ξ = ((η_t/dt) ξ_before − F_t)/(k_t + η_t/dt), the rest of v_t dt being slip
//!    ([`dashpot_sdk::physics::Slider`]); with η_t = 0 this is Cundall–Strack's ξ = −F_t/k_t.
//!
//! Capping after advancing makes a sliding contact carry exactly μ F_n from its first step, and
//! leaves the spring holding the sliding force's spring share when the slip stops. With this
//! order a sphere launched sliding without spin on a plane ends rolling at 5/7 of its launch
//! speed and an oblique impact in gross sliding changes the tangential velocity by μ (1 + e) v_n
//! (both tested). There is no friction in tension (F_n ≤ 0). The dashpot acts on the spring's
//! own rate, never on the slip, so the law never does positive work on the motion it resists
//! (LAMMPS's reset ξ = −(F_t + η_t v_t)/k_t stores the dashpot's share in the spring, which can
//! push along the slip when the slip slows; the LAMMPS-compatible `gran-linear-history` keeps
//! it).
//!
//! # Parameters
//! - `kt` (N/m, > 0, default 1e5, illustrative): tangential stiffness k_t;
//! - `mu` (1, ≥ 0, default 0.5): Coulomb friction coefficient μ;
//! - `damping` (1, ≥ 0, default 0): tangential damping ratio ζ_t.
//!
//! References: P. A. Cundall & O. D. L. Strack, Géotechnique 29, 47 (1979); S. Luding, Granular
//! Matter 10, 235 (2008); LAMMPS `pair_style granular`.

#![warn(missing_docs)]

use dashpot_sdk::physics::{slider_friction, Slider};
use dashpot_sdk::{
    BoundTangential, Energy, History, LawError, MaterialPair, Range, TangentialContact, TangentialLaw,
};

dashpot_sdk::law_params! {
    /// The configured law: stiffness `kt` (N/m), friction coefficient `mu`, damping ratio `damping`.
    #[derive(Debug, Clone)]
    pub struct LinearHistory {
        /// tangential stiffness k_t; the default is illustrative, not a material value
        pub kt: f64 { unit: "N/m", default: 1.0e5, range: Range::positive() },
        /// Coulomb friction coefficient μ
        pub mu: f64 { unit: "1", default: 0.5, range: Range::non_negative() },
        /// tangential damping ratio ζ_t: η_t = 2 ζ_t √(m k_t)
        pub damping: f64 { unit: "1", default: 0.0, range: Range::non_negative() },
    }
}

impl LinearHistory {
    /// The law with stiffness `kt` > 0 (N/m), friction coefficient `mu` ≥ 0 and damping ratio
    /// `damping` ≥ 0.
    pub fn with(kt: f64, mu: f64, damping: f64) -> LinearHistory {
        LinearHistory { kt, mu, damping }
    }
}

/// The law does not depend on the materials: bound, it is itself.
impl TangentialLaw for LinearHistory {
    type Bound = LinearHistory;
    const NAME: &'static str = "linear-history";
    const SUMMARY: &'static str =
        "Cundall–Strack tangential spring of constant k_t with history, Coulomb cap μ F_n, optional damping";
    const DOC: &'static str = "Cundall–Strack tangential spring with Coulomb friction (Cundall & Strack \
        1979; Luding 2008; the order of LAMMPS pair granular 'tangential linear_history'). Constant \
        stiffness k_t; dashpot η_t = 2 ζ_t √(m k_t), m the effective mass. History: the spring \
        displacement ξ (m; slots xi_x, xi_y, xi_z), 0 at first touch, and the dashpot's share of the \
        last force (N; fd_x, fd_y, fd_z), which the energy books read. Conventions: normal n from \
        the partner to the particle; velocity = relative velocity of the particle's contact point \
        w.r.t. the partner's (ω × r included; pass the velocity over the step, e.g. the half-step \
        velocity of velocity Verlet); the result is the tangential force on the particle. Each \
        call: if δ ≤ 0 the force is 0 and ξ = 0; otherwise (1) rotate ξ into the tangent plane \
        keeping its length, (2) v_t = v − (v·n) n, ξ_t = ξ + v_t dt, F_t = −k_t ξ_t − η_t v_t, \
        (3) if |F_t| > μ max(F_n, 0) scale F_t to μ max(F_n, 0) and set \
        ξ = ((η_t/dt) ξ − F_t)/(k_t + η_t/dt) (a spring ∥ dashpot in series with the slider: the \
        dashpot acts on the spring's rate, not on the slip), else ξ = ξ_t. No friction in \
        tension; the law never does positive work on the motion it resists (see \
        gran-linear-history for LAMMPS's reset ξ = −(F + η v)/k). Parameters: kt (N/m, > 0, \
        default 1e5, illustrative), mu (≥ 0, default 0.5), damping ζ_t (≥ 0, default 0). A sphere \
        launched sliding on a plane ends rolling at 5/7 of its launch speed; an oblique impact in \
        gross sliding changes the tangential velocity by μ (1 + e) v_n.";
    const HISTORY: &'static [History] = &{
        let [x, y, z] = History::TANGENTIAL_SPRING;
        let [fx, fy, fz] = History::DASHPOT_FORCE;
        [x, y, z, fx, fy, fz]
    };

    fn bind(&self, _materials: &MaterialPair) -> Result<LinearHistory, LawError> {
        Ok(self.clone())
    }
}

impl LinearHistory {
    /// The slider of contact `c`: k_t, η_t = 2 ζ_t √(m k_t), the cap μ max(F_n, 0).
    #[inline(always)]
    fn slider(&self, c: &TangentialContact) -> Slider {
        Slider::new(
            self.kt,
            self.kt,
            2.0 * self.damping * (c.mass * self.kt).sqrt(),
            self.mu * c.normal_force.max(0.0),
            c.dt,
        )
    }
}

impl BoundTangential for LinearHistory {
    #[inline]
    fn force(&self, c: &TangentialContact, history: &mut [f64]) -> [f64; 3] {
        let (xi, fd) = history.split_at_mut(3);
        slider_friction::<false>(&self.slider(c), c, xi, fd).0
    }

    /// The force with the step's energy: elastic k_t |ξ|²/2 (J); power (W) as
    /// [`dashpot_sdk::physics::Slider::energy`] books it: the work of the force of the last call
    /// and this one over the step's velocity, less the change of the stored energy (the
    /// velocity Verlet balance, exactly).
    #[inline]
    fn force_energy(&self, c: &TangentialContact, history: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let (xi, fd) = history.split_at_mut(3);
        slider_friction::<true>(&self.slider(c), c, xi, fd)
    }
}

dashpot_sdk::export_laws!(tangential: [LinearHistory]);

#[cfg(test)]
mod tests {
    //! The law's schema; its closed forms (a sliding sphere, an oblique impact, the spring's
    //! rotation and cap) are tested with Mindlin's in `tests/tests/tangential_springs.rs`.
    use super::*;
    use dashpot_sdk::ParamValue;

    #[test]
    fn schema_and_history_slots() {
        dashpot_testkit::assert_spring_history(&LinearHistory::info());
        let l = LinearHistory::from_values(&[]).unwrap();
        assert_eq!((l.kt, l.mu, l.damping), (1e5, 0.5, 0.0));
        for bad in [("kt", 0.0), ("mu", -0.1), ("damping", -1.0)] {
            assert!(LinearHistory::from_values(&[ParamValue::new(bad.0, bad.1)]).is_err());
        }
    }

    /// The law never gives back more energy than the slip put into it, and its books close
    /// ([`dashpot_sdk::testkit`]: random materials, random paths).
    #[test]
    fn never_gives_back_more_than_it_was_given() {
        for (kt, mu, damping) in [(1e5, 0.5, 0.0), (1e5, 0.4, 2.0), (1e3, 0.1, 5.0), (1e8, 1.0, 0.3)] {
            dashpot_sdk::testkit::assert_dissipative_tangential(&LinearHistory::with(kt, mu, damping));
        }
    }
}
