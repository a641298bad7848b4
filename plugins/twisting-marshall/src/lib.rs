//! Marshall's twisting resistance (LAMMPS `twisting marshall`), its constants from explicit
//! tangential-law parameters.

use dashpot_sdk::physics::TwistSpring;
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
        eqs. 30, 32, 34, 44), as LAMMPS `twisting marshall`: a twisting spring–dashpot–slider whose constants \
        come from the tangential law's and the contact radius a = √(R_eff δ) (m, Hertz): stiffness \
        k = k_t a²/2 (N·m/rad), damping γ = γ_t a²/2 (N·m·s/rad), critical torque M_c = (2/3) μ_t a |F_n| (N·m). \
        LAMMPS reads k_t, γ_t and μ_t from the tangential model; a dashpot twisting law does not see the \
        tangential law, so they are this law's parameters: kt (N/m, the tangential spring stiffness, e.g. \
        Mindlin's 8 G_eff a), gammat (N·s/m, the tangential damping coefficient), mu_t (the tangential friction \
        coefficient). Each call, with ω = (ω_i − ω_j)·n̂ (rad/s) and the step dt (s): θ += ω dt; \
        M = −k θ − γ ω (N·m, about n̂, on the particle); if |M| > M_c: θ = (M_c sgn ω − γ ω)/k and \
        M = −M_c sgn ω. For δ ≤ 0 (a = 0) the torque is 0 and θ is reset. History: the twist angle θ (rad). \
        Energy: elastic = k θ²/2 (J); power = γ ω² while the spring holds, −M ω plus the change of the stored \
        energy while it slides (W; k taken as unchanged over the step, the twisting contact carrying no normal \
        rate).";
    const HISTORY: &'static [History] = &[History::new("theta", "rad", "twist angle θ of the spring")];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl TwistingMarshall {
    /// The spring of a contact of radius a (m) > 0.
    fn spring(&self, c: &TwistingContact, a: f64) -> TwistSpring {
        TwistSpring {
            k: 0.5 * self.kt * a * a,
            gamma: 0.5 * self.gammat * a * a,
            mcrit: 2.0 / 3.0 * self.mu_t * a * c.normal_force.abs(),
        }
    }
}

impl BoundTwisting for TwistingMarshall {
    fn torque(&self, c: &TwistingContact, h: &mut [f64]) -> f64 {
        let a = dashpot_sdk::physics::contact_radius(c.radius, c.delta);
        if a == 0.0 {
            h[0] = 0.0;
            return 0.0;
        }
        self.spring(c, a).torque(c.rate, c.dt, h)
    }

    /// The torque with the step's energy (the stiffness taken as unchanged over the step: the
    /// twisting contact carries no normal rate).
    fn torque_energy(&self, c: &TwistingContact, h: &mut [f64]) -> (f64, Option<Energy>) {
        let a = dashpot_sdk::physics::contact_radius(c.radius, c.delta);
        if a == 0.0 {
            h[0] = 0.0;
            return (0.0, Some(Energy::default()));
        }
        let spring = self.spring(c, a);
        let (m, e) = spring.torque_energy(spring.k, c.rate, c.dt, h);
        (m, Some(e))
    }
}

dashpot_sdk::export_laws!(twisting: [TwistingMarshall]);
