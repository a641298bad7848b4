//! Elastic–plastic spring–dashpot (EPSD) rolling resistance of Ai et al. (2011).

use dashpot_sdk::physics::dot;
use dashpot_sdk::physics::SliderStep;
use dashpot_sdk::{BoundRolling, Energy, History, LawError, MaterialPair, Range, RollingContact, RollingLaw};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct RollingEpsd {
        /// tangential stiffness k_t (k_r = k_t R²)
        kt: f64 { unit: "N/m", default: 1e5, range: Range::positive() },
        /// rolling friction coefficient μ_r
        mu_r: f64 { unit: "1", default: 0.1, range: Range::non_negative() },
        /// rolling damping ratio η_r
        eta: f64 { unit: "1", default: 0.3, range: Range::non_negative() },
    }
}

impl RollingEpsd {
    /// The dashpot γ = 2 η √((7/5) m k_t) (N·s/m) of a contact of effective mass m (kg).
    fn gamma(&self, mass: f64) -> f64 {
        2.0 * self.eta * (1.4 * mass * self.kt).sqrt()
    }
}

impl RollingLaw for RollingEpsd {
    type Bound = RollingEpsd;
    const NAME: &'static str = "rolling-epsd";
    const SUMMARY: &'static str =
        "Elastic–plastic spring–dashpot rolling resistance (Ai et al. 2011): k_r = k_t R², |M_r| ≤ μ_r R |F_n|";
    const DOC: &'static str = "Elastic–plastic spring–dashpot (EPSD, model C) rolling resistance of Ai, Chen, \
        Rotter & Ooi 2011 (Powder Technol. 206, 269), with the rolling stiffness from a tangential stiffness \
        (k_r = k_t R², as LIGGGHTS's epsd2). In torque form: M_r = −k_r θ_r − C_r ω_r, capped at \
        |M_r| ≤ μ_r R |F_n| (full mobilization: the spring holds the limit torque and the dashpot is off), \
        C_r = 2 η √(I_r k_r) with I_r = (7/5) m R² (a sphere of the effective mass m and radius R rolling on \
        its contact point). dashpot's rolling kind carries it as a force F_r with M = R n̂ × F_r: with \
        ξ = R θ_r (m, history xi_x, xi_y, xi_z) and v_roll = R (ω_i − ω_j) × n̂ (m/s), each call (1) rotates ξ \
        into the tangent plane keeping its length, (2) ξ += v_roll dt, (3) F_r = −k_t ξ − γ v_roll with \
        γ = C_r/R² = 2 η √((7/5) m k_t) (N·s/m); (4) if |k_t ξ| > μ_r |F_n|: F_r = −μ_r |F_n| ξ/|ξ| and \
        ξ = −F_r/k_t (no damping while mobilized). Parameters: kt (N/m), mu_r (the rolling friction \
        coefficient: the limit torque is μ_r R |F_n|), eta (damping ratio, Ai et al. use 0.3). Energy: elastic \
        k_t |ξ|²/2 (J); power γ |v_roll|² while the spring holds, −F_r·v_roll plus the change of the stored \
        energy while mobilized (W).";
    const HISTORY: &'static [History] = &[
        History::new("xi_x", "m", "rolling displacement ξ = R θ_r, x component"),
        History::new("xi_y", "m", "rolling displacement ξ = R θ_r, y component"),
        History::new("xi_z", "m", "rolling displacement ξ = R θ_r, z component"),
    ];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl RollingEpsd {
    /// [`BoundRolling::force`], whether the spring was mobilized (capped), and the spring the
    /// step started from, turned into the tangent plane.
    fn step(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], bool, [f64; 3]) {
        let n = c.normal;
        let mut xi = [h[0], h[1], h[2]];
        let xn = dot(xi, n);
        if xn != 0.0 {
            let len = dot(xi, xi).sqrt();
            let p = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
            let plen = dot(p, p).sqrt();
            let s = if plen > 0.0 { len / plen } else { 0.0 };
            xi = [p[0] * s, p[1] * s, p[2] * s];
        }
        let turned = xi;
        for (x, v) in xi.iter_mut().zip(c.velocity) {
            *x += v * c.dt;
        }
        let cap = self.mu_r * c.normal_force.abs();
        let spring = self.kt * dot(xi, xi).sqrt();
        let mobilized = spring > cap;
        let f = if mobilized {
            let s = cap / spring;
            let f = [-self.kt * xi[0] * s, -self.kt * xi[1] * s, -self.kt * xi[2] * s];
            xi = [-f[0] / self.kt, -f[1] / self.kt, -f[2] / self.kt];
            f
        } else {
            let g = self.gamma(c.mass);
            [
                -self.kt * xi[0] - g * c.velocity[0],
                -self.kt * xi[1] - g * c.velocity[1],
                -self.kt * xi[2] - g * c.velocity[2],
            ]
        };
        h[..3].copy_from_slice(&xi);
        (f, mobilized, turned)
    }
}

impl BoundRolling for RollingEpsd {
    fn force(&self, c: &RollingContact, h: &mut [f64]) -> [f64; 3] {
        self.step(c, h).0
    }

    /// The force with the step's energy: elastic k_t |ξ|²/2 (J); power (W): γ |v_roll|² while
    /// the spring holds, −F_r·v_roll plus the change of the stored energy while mobilized (see
    /// [`SliderStep`]).
    fn force_energy(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let (f, mobilized, before) = self.step(c, h);
        // a mobilized spring holds the capped force alone: F = −k_t ξ
        let step = SliderStep {
            k: self.kt,
            k_before: self.kt,
            eta: self.gamma(c.mass),
            eta_held: 0.0,
            xi_before: before,
            dt: c.dt,
        };
        (f, Some(step.energy(mobilized, [h[0], h[1], h[2]], c.velocity, f)))
    }
}

dashpot_sdk::export_laws!(rolling: [RollingEpsd]);
