//! Spring–dashpot–slider twisting resistance with the semantics of LAMMPS `twisting sds`.

use dashpot_sdk::physics::TwistSpring as Sds;
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
    const DOC: &'static str = "Spring–dashpot–slider twisting resistance with the semantics of LAMMPS \
        `pair_style granular ... twisting sds k_twist gamma_twist mu_twist` (Marshall 2009, J. Comput. Phys. 228, \
        1541, eqs. 30, 34, 44). Input: the twisting rate ω = (ω_i − ω_j)·n̂ (rad/s), the normal force F_n (N), \
        the step dt (s). History: the twist angle θ (rad), 0 at first touch. Each call: θ += ω dt; \
        M = −k θ − γ ω (N·m, about n̂, on the particle; its opposite on the partner); if |M| > μ|F_n|: \
        θ = (μ|F_n| sgn ω − γ ω)/k and M = −μ|F_n| sgn ω. Parameters: k (N·m/rad, > 0), gamma (N·m·s/rad), \
        mu (m: the critical torque is μ|F_n|). Energy: elastic = k θ²/2 (J); power = γ ω² while the spring holds, −M ω \
        plus the change of the stored energy while it slides (W).";
    const HISTORY: &'static [History] = &[History::new("theta", "rad", "twist angle θ of the spring")];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl TwistingSds {
    fn sds(&self, c: &TwistingContact) -> Sds {
        Sds {
            k: self.k,
            gamma: self.gamma,
            mcrit: self.mu * c.normal_force.abs(),
        }
    }
}

impl BoundTwisting for TwistingSds {
    fn torque(&self, c: &TwistingContact, h: &mut [f64]) -> f64 {
        self.sds(c).torque(c.rate, c.dt, h)
    }

    /// The torque with the step's energy: elastic k θ²/2 (J); power (W) γ ω² while the spring
    /// holds, −M ω plus the change of the stored energy while it slides.
    fn torque_energy(&self, c: &TwistingContact, h: &mut [f64]) -> (f64, Option<Energy>) {
        let (m, e) = self.sds(c).torque_energy(self.k, c.rate, c.dt, h);
        (m, Some(e))
    }
}

dashpot_sdk::export_laws!(twisting: [TwistingSds]);
