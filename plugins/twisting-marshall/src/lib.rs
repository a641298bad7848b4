//! Marshall's twisting resistance (LAMMPS `twisting marshall`), its constants from explicit
//! tangential-law parameters.

use dashpot_sdk::physics::Slider;
use dashpot_sdk::{
    BoundTwisting, Energy, History, LawError, MaterialPair, Range, TwistingContact, TwistingLaw,
};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct TwistingMarshall {
        /// tangential spring stiffness k_t
        kt: f64 { unit: "N/m", default: 1e5, range: Range::positive() },
        /// tangential damping coefficient γ_t
        gammat: f64 { unit: "N·s/m", default: 0.0, range: Range::non_negative() },
        /// tangential friction coefficient μ_t
        mu_t: f64 { unit: "1", default: 0.5, range: Range::non_negative() },
    }
}

impl TwistingLaw for TwistingMarshall {
    type Bound = TwistingMarshall;
    const NAME: &'static str = "twisting-marshall";
    const SUMMARY: &'static str =
        "Marshall twisting (LAMMPS `twisting marshall`): k = k_t a²/2, γ = γ_t a²/2, M_c = (2/3) μ_t a |F_n|";
    const DOC: &'static str = "Marshall's twisting resistance (Marshall 2009, J. Comput. Phys. 228, 1541, \
        eqs. 30, 32, 34, 44), with the constants of LAMMPS `twisting marshall`: a twisting spring–dashpot–slider \
        whose constants come from the tangential law's and the contact radius a = √(R_eff δ) (m, Hertz): \
        stiffness k = k_t a²/2 (N·m/rad), damping γ = γ_t a²/2 (N·m·s/rad), critical torque \
        M_c = (2/3) μ_t a |F_n| (N·m). LAMMPS reads k_t, γ_t and μ_t from the tangential model; a dashpot \
        twisting law does not see the tangential law, so they are this law's parameters: kt (N/m, the \
        tangential spring stiffness, e.g. Mindlin's 8 G_eff a), gammat (N·s/m, the tangential damping \
        coefficient), mu_t (the tangential friction coefficient). Each call, with ω = (ω_i − ω_j)·n̂ (rad/s) \
        and the step dt (s): if k grew since the last call θ is scaled by k_before/k (the torque is kept: \
        incremental stiffness); θ_t = θ + ω dt; M = −k θ_t − γ ω (N·m, about n̂, on the particle); if \
        |M| > M_c: M = M_c sgn M and θ = ((γ/dt) θ − M)/(k + γ/dt) (a spring ∥ dashpot in series with the \
        slider), else θ = θ_t. For δ ≤ 0 (a = 0) the torque is 0 and θ is reset. The law never does \
        positive work on the twist it resists (gran-twisting-marshall keeps LAMMPS's reset \
        θ = (M_c sgn ω − γ ω)/k). History: the twist angle θ (rad), the stiffness k of the last call \
        (N·m/rad) and the dashpot's share of the last torque (N·m), which the energy books read. Energy: elastic = k θ²/2 (J); power = γ ω² while the spring holds, the slip's work and \
        the change of the stored energy while it slides (W).";
    const HISTORY: &'static [History] = &[
        History::new("theta", "rad", "twist angle θ of the spring"),
        History::new(
            "k",
            "N·m/rad",
            "the spring's stiffness k at the last call (its energy's)",
        ),
        History::new(
            "md",
            "N·m",
            "the dashpot's share of the last torque (its energy's)",
        ),
    ];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl TwistingMarshall {
    /// The slider of contact `c` (stiffness k_t a²/2 of its contact radius a, `k_before` from
    /// the history).
    fn slider(&self, c: &TwistingContact, k_before: f64) -> Slider {
        let a = dashpot_sdk::physics::contact_radius(c.radius, c.delta);
        Slider::new(
            0.5 * self.kt * a * a,
            k_before,
            0.5 * self.gammat * a * a,
            2.0 / 3.0 * self.mu_t * a * c.normal_force.abs(),
            c.dt,
        )
    }

    /// One call (see [`TwistingMarshall::DOC`]), with the step's energy.
    fn step(&self, c: &TwistingContact, h: &mut [f64]) -> (f64, Energy) {
        let (theta, md, sl) = ([h[0]], [h[2]], self.slider(c, h[1]));
        h[1] = sl.k;
        if c.delta <= 0.0 {
            (h[0], h[2]) = (0.0, 0.0);
            return (0.0, sl.dropped(theta, md, [c.rate]));
        }
        let s = sl.advance(theta, [c.rate]);
        (h[0], h[2]) = (s.spring[0], s.dashpot[0]);
        (s.force[0], sl.energy(theta, md, &s, [c.rate]))
    }
}

impl BoundTwisting for TwistingMarshall {
    fn torque(&self, c: &TwistingContact, h: &mut [f64]) -> f64 {
        self.step(c, h).0
    }

    /// The torque with the step's energy (see [`dashpot_sdk::physics::Slider::energy`]).
    fn torque_energy(&self, c: &TwistingContact, h: &mut [f64]) -> (f64, Option<Energy>) {
        let (m, e) = self.step(c, h);
        (m, Some(e))
    }
}

dashpot_sdk::export_laws!(twisting: [TwistingMarshall]);

#[cfg(test)]
mod tests {
    use super::*;

    /// The law never gives back more energy than the twist put into it, its stiffness growing
    /// or shrinking with the contact radius, and its books close ([`dashpot_sdk::testkit`]).
    #[test]
    fn never_gives_back_more_than_it_was_given() {
        for (kt, gammat, mu_t) in [
            (1e5, 0.0, 0.5),
            (1e5, 2e-2, 0.5),
            (1e3, 1.0, 0.1),
            (1e8, 1e-3, 1.0),
        ] {
            dashpot_sdk::testkit::assert_dissipative_twisting(&TwistingMarshall { kt, gammat, mu_t });
        }
    }
}
