//! Spring–dashpot–slider twisting resistance with the parameters and order of LAMMPS `twisting
//! sds`, its spring reset passive ([`dashpot_sdk::physics::Slider`]).

use dashpot_sdk::physics::Slider;
use dashpot_sdk::{
    BoundTwisting, Energy, History, LawError, MaterialPair, Range, TwistingContact, TwistingLaw,
};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct TwistingSds {
        /// twisting stiffness k_twist
        k: f64 { unit: "N·m/rad", default: 1e-3, range: Range::positive() },
        /// twisting damping γ_twist
        gamma: f64 { unit: "N·m·s/rad", default: 0.0, range: Range::non_negative() },
        /// twisting friction μ_twist (torque per newton)
        mu: f64 { unit: "m", default: 1e-4, range: Range::non_negative() },
    }
}

impl TwistingLaw for TwistingSds {
    type Bound = TwistingSds;
    const NAME: &'static str = "twisting-sds";
    const SUMMARY: &'static str =
        "Twisting spring–dashpot–slider (LAMMPS `twisting sds k gamma mu`): M = −k θ − γ ω, |M| ≤ μ |F_n|";
    const DOC: &'static str = "Spring–dashpot–slider twisting resistance with the parameters and order of \
        LAMMPS `pair_style granular ... twisting sds k_twist gamma_twist mu_twist` (Marshall 2009, J. Comput. \
        Phys. 228, 1541, eqs. 30, 34, 44). Input: the twisting rate ω = (ω_i − ω_j)·n̂ (rad/s), the normal \
        force F_n (N), the step dt (s). History: the twist angle θ (rad), 0 at first touch, and the dashpot's share of the last torque \
        (N·m), which the energy books read. Each call: \
        θ_t = θ + ω dt; M = −k θ_t − γ ω (N·m, about n̂, on the particle; its opposite on the partner); \
        if |M| > μ|F_n|: M = μ|F_n| sgn M and θ = ((γ/dt) θ − M)/(k + γ/dt) (a spring ∥ dashpot in series \
        with the slider: the dashpot acts on the spring's rate, not on the slip), else θ = θ_t. Unlike \
        LAMMPS's reset θ = (μ|F_n| sgn ω − γ ω)/k, the spring never holds the dashpot's share: the law \
        never does positive work on the twist it resists (gran-twisting-sds keeps LAMMPS's reset). \
        Parameters: k (N·m/rad, > 0), gamma (N·m·s/rad), mu (m: the critical torque is μ|F_n|). Energy: \
        elastic = k θ²/2 (J); power (W) = the work of the torque over the step less the change of the \
        stored energy: γ ω² while the spring holds, the slip's work while it slides.";
    const HISTORY: &'static [History] = &[
        History::new("theta", "rad", "twist angle θ of the spring"),
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

impl TwistingSds {
    /// The slider of contact `c`: k, γ, the critical torque μ |F_n|.
    fn slider(&self, c: &TwistingContact) -> Slider {
        Slider::new(self.k, self.k, self.gamma, self.mu * c.normal_force.abs(), c.dt)
    }
}

impl BoundTwisting for TwistingSds {
    fn torque(&self, c: &TwistingContact, h: &mut [f64]) -> f64 {
        let s = self.slider(c).advance([h[0]], [c.rate]);
        (h[0], h[1]) = (s.spring[0], s.dashpot[0]);
        s.force[0]
    }

    /// The torque with the step's energy: elastic k θ²/2 (J); power (W) the work of the torque
    /// of the last call and this one over the step's rate less the change of the stored energy
    /// ([`Slider::energy`]).
    fn torque_energy(&self, c: &TwistingContact, h: &mut [f64]) -> (f64, Option<Energy>) {
        let sl = self.slider(c);
        let s = sl.advance([h[0]], [c.rate]);
        let e = sl.energy([h[0]], [h[1]], &s, [c.rate]);
        (h[0], h[1]) = (s.spring[0], s.dashpot[0]);
        (s.force[0], Some(e))
    }
}

dashpot_sdk::export_laws!(twisting: [TwistingSds]);

#[cfg(test)]
mod tests {
    use super::*;

    /// The law never gives back more energy than the twist put into it, and its books close
    /// ([`dashpot_sdk::testkit`]: random materials, random paths).
    #[test]
    fn never_gives_back_more_than_it_was_given() {
        for (k, gamma, mu) in [
            (1e-3, 0.0, 1e-4),
            (1e-3, 1e-6, 1e-4),
            (1e-5, 1e-4, 1e-6),
            (1.0, 1e-3, 1e-2),
        ] {
            dashpot_sdk::testkit::assert_dissipative_twisting(&TwistingSds { k, gamma, mu });
        }
    }
}
