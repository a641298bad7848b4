//! Elastic–plastic spring–dashpot (EPSD) rolling resistance of Ai et al. (2011).

use dashpot_sdk::physics::dot;
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
        coefficient: the limit torque is μ_r R |F_n|), eta (damping ratio, Ai et al. use 0.3). History: ξ, and \
        the dashpot's share of the last force (N; 0 mobilized). Energy: elastic k_t |ξ|²/2 (J); power (W) the \
        work of the force averaged over the step less the change of the stored energy: γ |v_roll|² while the \
        spring holds, −F_r·v_roll plus the change of the stored energy while mobilized.";
    const HISTORY: &'static [History] = &{
        let [fx, fy, fz] = History::DASHPOT_FORCE;
        [
            History::new("xi_x", "m", "rolling displacement ξ = R θ_r, x component"),
            History::new("xi_y", "m", "rolling displacement ξ = R θ_r, y component"),
            History::new("xi_z", "m", "rolling displacement ξ = R θ_r, z component"),
            fx,
            fy,
            fz,
        ]
    };

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl RollingEpsd {
    /// One call (see [`RollingEpsd::DOC`]): the force, and the step's energy when `ENERGY`.
    fn step<const ENERGY: bool>(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let n = c.normal;
        let read = [h[0], h[1], h[2]];
        let mut xi = read;
        let xn = dot(xi, n);
        if xn != 0.0 {
            let len = dot(xi, xi).sqrt();
            let p = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
            let plen = dot(p, p).sqrt();
            let s = if plen > 0.0 { len / plen } else { 0.0 };
            xi = [p[0] * s, p[1] * s, p[2] * s];
        }
        for (x, v) in xi.iter_mut().zip(c.velocity) {
            *x += v * c.dt;
        }
        let cap = self.mu_r * c.normal_force.abs();
        let spring = self.kt * dot(xi, xi).sqrt();
        let gamma = self.gamma(c.mass);
        let v = c.velocity;
        let (f, fd) = if spring > cap {
            // mobilized: the spring holds the limit force alone, the dashpot off
            let s = cap / spring;
            let f = [-self.kt * xi[0] * s, -self.kt * xi[1] * s, -self.kt * xi[2] * s];
            xi = [-f[0] / self.kt, -f[1] / self.kt, -f[2] / self.kt];
            (f, [0.0; 3])
        } else {
            let fd = [-gamma * v[0], -gamma * v[1], -gamma * v[2]];
            let f = [
                -self.kt * xi[0] + fd[0],
                -self.kt * xi[1] + fd[1],
                -self.kt * xi[2] + fd[2],
            ];
            (f, fd)
        };
        let energy = ENERGY.then(|| {
            // the work of the force averaged over the step, the force before it as the last
            // step left it (its spring and its dashpot's share), less what the spring stored
            let (k, dt) = (self.kt, c.dt);
            let mut mean = [0.0; 3];
            for q in 0..3 {
                mean[q] = 0.5 * (f[q] - k * read[q] + h[3 + q]);
            }
            let stored = 0.5 * k * (dot(read, read) - dot(xi, xi));
            Energy {
                power: if dt > 0.0 {
                    -dot(mean, v) + stored / dt
                } else {
                    0.0
                },
                elastic: 0.5 * k * dot(xi, xi),
            }
        });
        h[..3].copy_from_slice(&xi);
        h[3..6].copy_from_slice(&fd);
        (f, energy)
    }
}

impl BoundRolling for RollingEpsd {
    fn force(&self, c: &RollingContact, h: &mut [f64]) -> [f64; 3] {
        self.step::<false>(c, h).0
    }

    /// The force with the step's energy: elastic k_t |ξ|²/2 (J); power (W): the work of the
    /// force averaged over the step (the force before it rebuilt from the history: the spring's
    /// and the dashpot's shares, so the balance closes as velocity Verlet integrates it) less
    /// the change of the stored energy.
    fn force_energy(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        self.step::<true>(c, h)
    }
}

dashpot_sdk::export_laws!(rolling: [RollingEpsd]);

#[cfg(test)]
mod tests {
    use super::*;

    /// The law never gives back more energy than the rolling put into it, and its books close
    /// ([`dashpot_sdk::testkit`]: random materials, random paths).
    #[test]
    fn never_gives_back_more_than_it_was_given() {
        for (kt, mu_r, eta) in [
            (1e5, 0.1, 0.3),
            (1e5, 0.1, 0.0),
            (1e3, 0.01, 1.0),
            (1e8, 1.0, 0.3),
        ] {
            dashpot_sdk::testkit::assert_dissipative_rolling(&RollingEpsd { kt, mu_r, eta });
        }
    }
}
