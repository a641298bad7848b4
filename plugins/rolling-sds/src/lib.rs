//! Spring–dashpot–slider rolling resistance with the semantics of LAMMPS `rolling sds`.

use dashpot_sdk::{BoundRolling, Energy, History, LawError, MaterialPair, Range, RollingContact, RollingLaw};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct RollingSds {
        /// rolling stiffness k_roll
        k: f64 { unit: "N/m", default: 1e3, range: Range::positive() },
        /// rolling damping γ_roll
        gamma: f64 { unit: "N·s/m", default: 0.0, range: Range::non_negative() },
        /// rolling friction coefficient μ_roll
        mu: f64 { unit: "1", default: 0.1, range: Range::non_negative() },
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Relative threshold below which ξ is not rotated into the tangent plane (LAMMPS's EPSILON).
const FRAME_EPS: f64 = 1e-10;

impl RollingLaw for RollingSds {
    type Bound = RollingSds;
    const NAME: &'static str = "rolling-sds";
    const SUMMARY: &'static str =
        "Rolling spring–dashpot–slider (LAMMPS `rolling sds k gamma mu`): F_r = −k ξ − γ v_roll, |F_r| ≤ μ |F_n|";
    const DOC: &'static str = "Spring–dashpot–slider rolling resistance with the semantics of LAMMPS \
        `pair_style granular ... rolling sds k_roll gamma_roll mu_roll` (Luding 2008; Wang et al. 2015, \
        Particuology 23, 49). Inputs: unit normal n̂ (from the partner to the particle), rolling velocity \
        v_roll = R_eff (ω_i − ω_j) × n̂ (m/s), the normal force F_n (N), the step dt (s). History: the rolling \
        displacement ξ (m; slots xi_x, xi_y, xi_z), 0 at first touch. Each call: (1) if |ξ·n̂| k > 10⁻¹⁰ μ|F_n|, \
        ξ is projected into the tangent plane and rescaled to its former length; (2) ξ += v_roll dt; (3) \
        F_r = −k ξ − γ v_roll (N); (4) if |F_r| > μ|F_n|: when ξ ≠ 0, ξ = −(μ|F_n| F_r/|F_r| + γ v_roll)/k and \
        F_r is scaled to length μ|F_n|; when ξ = 0, F_r = 0. The torque on the particle is R_eff n̂ × F_r (N·m), \
        on the partner its opposite; F_r itself is not applied to the centres. Parameters: k (N/m), gamma \
        (N·s/m), mu (dimensionless). Energy: elastic = k|ξ|²/2 (J); power (W) = γ|v_roll|² while the spring \
        holds, −F_r·v_roll (≥ 0, clamped) while it slides.";
    const HISTORY: &'static [History] = &[
        History::new("xi_x", "m", "rolling displacement ξ, x component"),
        History::new("xi_y", "m", "rolling displacement ξ, y component"),
        History::new("xi_z", "m", "rolling displacement ξ, z component"),
    ];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl BoundRolling for RollingSds {
    fn force(&self, c: &RollingContact, h: &mut [f64]) -> [f64; 3] {
        let n = c.normal;
        let fcrit = self.mu * c.normal_force.abs();
        let mut xi = [h[0], h[1], h[2]];
        let xn = dot(xi, n);
        if xn.abs() * self.k > FRAME_EPS * fcrit {
            let len = dot(xi, xi).sqrt();
            for (x, nk) in xi.iter_mut().zip(n) {
                *x -= xn * nk;
            }
            let prj = dot(xi, xi).sqrt();
            let s = if prj > 0.0 { len / prj } else { 0.0 };
            for x in &mut xi {
                *x *= s;
            }
        }
        for (x, v) in xi.iter_mut().zip(c.velocity) {
            *x += v * c.dt;
        }
        let mut f = [0.0; 3];
        for k in 0..3 {
            f[k] = -self.k * xi[k] - self.gamma * c.velocity[k];
        }
        let mag = dot(f, f).sqrt();
        if mag > fcrit {
            if dot(xi, xi) != 0.0 {
                for k in 0..3 {
                    xi[k] = -(fcrit * f[k] / mag + self.gamma * c.velocity[k]) / self.k;
                    f[k] *= fcrit / mag;
                }
            } else {
                f = [0.0; 3];
            }
        }
        h[..3].copy_from_slice(&xi);
        f
    }

    fn energy(&self, c: &RollingContact, h: &[f64], f: [f64; 3]) -> Option<Energy> {
        Some(dashpot_sdk::physics::spring_slider_energy(
            self.k,
            self.gamma,
            self.mu * c.normal_force.abs(),
            [h[0], h[1], h[2]],
            c.velocity,
            f,
        ))
    }
}

dashpot_sdk::export_laws!(rolling: [RollingSds]);
