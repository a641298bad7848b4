//! Formulas several laws share, each with its source.

use std::f64::consts::PI;

/// The damping factor α(ε) = −√5 ln ε / √(ln²ε + π²) of the Hertzian spring-dashpot in Tsuji's
/// form F_d = α √(m k) δ^{1/4} δ̇: the exact value (Antypov & Elliott 2011, eq. 17, not Tsuji's
/// 1992 fit) that realizes restitution ε at every impact speed when contact ends as δ returns to
/// 0. Dimensionless; α(1) = 0.
pub fn tsuji_alpha(eps: f64) -> f64 {
    let l = eps.ln();
    -(5.0f64).sqrt() * l / (l * l + PI * PI).sqrt()
}

/// The damping ratio ζ = −ln ε / √(ln²ε + π²) of the linear spring-dashpot with restitution ε
/// (Antypov & Elliott 2011, eq. 8: γ = ζ ω0). Dimensionless.
pub fn lsd_damping_ratio(eps: f64) -> f64 {
    let l = eps.ln();
    -l / (l * l + PI * PI).sqrt()
}

/// Hertz contact radius a = √(r δ) (m) at overlap δ (m) for effective radius r (m); 0 for δ ≤ 0.
#[inline]
pub fn contact_radius(radius: f64, delta: f64) -> f64 {
    (radius * delta.max(0.0)).sqrt()
}

/// Thornton's (1997) restitution of elastic–perfectly plastic spheres at x = V_y/v (V_y the
/// yield impact speed, v the normal impact speed): 1 for x ≥ 1 (an elastic impact), else
/// e = √(6√3/5) √(1 − x²/6) (x / (x + 2 √(6/5 − x²/5)))^{1/4}, which falls as v^{−1/4} far above
/// V_y. Dimensionless.
pub fn thornton_restitution(x: f64) -> f64 {
    if x >= 1.0 {
        return 1.0;
    }
    (6.0 * 3f64.sqrt() / 5.0).sqrt()
        * (1.0 - x * x / 6.0).sqrt()
        * (x / (x + 2.0 * (1.2 - 0.2 * x * x).sqrt())).powf(0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_factors_vanish_for_elastic_and_relate_by_sqrt5() {
        assert_eq!(tsuji_alpha(1.0), 0.0);
        assert_eq!(lsd_damping_ratio(1.0), 0.0);
        for eps in [0.1, 0.5, 0.9] {
            let r = tsuji_alpha(eps) / lsd_damping_ratio(eps);
            assert!((r - 5f64.sqrt()).abs() < 1e-14, "{eps}: {r}");
        }
    }
}

/// The spring–dashpot–slider of a twisting law: stiffness (N·m/rad), damping (N·m·s/rad) and
/// critical torque (N·m). Used by the `twisting-sds` and `twisting-marshall` laws (the latter's constants depend on
/// the contact radius).
#[derive(Debug, Clone, Copy)]
pub struct TwistSpring {
    /// Stiffness k (N·m/rad), > 0.
    pub k: f64,
    /// Damping γ (N·m·s/rad).
    pub gamma: f64,
    /// Critical torque M_c (N·m).
    pub mcrit: f64,
}

impl TwistSpring {
    /// Advances the twist angle θ = `h[0]` (rad) by ω dt and returns the torque (N·m):
    /// M = −k θ − γ ω; if |M| > M_c then θ = (M_c sgn ω − γ ω)/k and M = −M_c sgn ω.
    pub fn torque(&self, rate: f64, dt: f64, h: &mut [f64]) -> f64 {
        h[0] += rate * dt;
        let m = -self.k * h[0] - self.gamma * rate;
        if m.abs() > self.mcrit {
            let sign = if rate > 0.0 {
                1.0
            } else if rate < 0.0 {
                -1.0
            } else {
                0.0
            };
            h[0] = (self.mcrit * sign - self.gamma * rate) / self.k;
            return -self.mcrit * sign;
        }
        m
    }

    /// Elastic energy k θ²/2 (J) and dissipated power (W): γ ω² while the spring holds, |M ω|
    /// while it slides.
    pub fn energy(&self, rate: f64, theta: f64, torque: f64) -> crate::Energy {
        let sliding = torque.abs() >= self.mcrit && rate != 0.0;
        crate::Energy {
            power: if sliding {
                (-torque * rate).max(0.0)
            } else {
                self.gamma * rate * rate
            },
            elastic: 0.5 * self.k * theta * theta,
        }
    }
}

/// The energy of a tangential (or rolling) spring–dashpot–slider after a step: elastic
/// ½ k |ξ|² (J) with ξ the stored displacement `xi` (m) and k the stiffness `k` (N/m), and the
/// dissipated power (W): the dashpot's η |v|² while the spring holds (|F| below the cap
/// `cap`, N), the friction work rate −F·v (≥ 0, clamped) while it slides. `v` is the velocity
/// the spring advanced with (m/s), `force` the returned force (N), `eta` the dashpot (N·s/m).
pub fn spring_slider_energy(
    k: f64,
    eta: f64,
    cap: f64,
    xi: [f64; 3],
    v: [f64; 3],
    force: [f64; 3],
) -> crate::Energy {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let f2 = dot(force, force);
    let sliding = f2 > 0.0 && f2 >= cap * cap * (1.0 - 1e-12);
    crate::Energy {
        power: if sliding {
            (-dot(force, v)).max(0.0)
        } else {
            eta * dot(v, v)
        },
        elastic: 0.5 * k * dot(xi, xi),
    }
}

/// The tangential velocity v − (v·n̂) n̂ (m/s) of `v` for unit normal `n`.
#[inline(always)]
pub fn tangential_part(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    [v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]]
}

/// The dot product of two 3-vectors.
#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// One step of a tangential spring–dashpot with a Coulomb slider (the bookkeeping of Luding
/// 2008 and LAMMPS `pair granular`), for a spring of stiffness `kt` (N/m), a dashpot `eta`
/// (N·s/m) and a friction coefficient `mu`, on contact `c` whose history `h[..3]` is the spring
/// displacement ξ (m). Returns the tangential force (N). If δ ≤ 0 the force is 0 and ξ = 0;
/// otherwise (1) rotate ξ into the tangent plane keeping its length, (2) v_t = v − (v·n̂) n̂,
/// (3) ξ += v_t dt, (4) F_t = −k_t ξ − η_t v_t, (5) if |F_t| > μ max(F_n, 0) scale F_t to
/// μ max(F_n, 0) and reset ξ = −(F_t + η_t v_t)/k_t (0 when k_t = 0). Used by the
/// `linear-history` (constant k_t) and `mindlin` (k_t = 8 G a) laws.
#[inline(always)]
pub fn spring_friction(kt: f64, eta: f64, mu: f64, c: &crate::TangentialContact, h: &mut [f64]) -> [f64; 3] {
    if c.delta <= 0.0 {
        h[..3].fill(0.0);
        return [0.0; 3];
    }
    let n = c.normal;
    let mut xi = [h[0], h[1], h[2]];
    // Rotate into the current tangent plane, keeping the length.
    let xn = dot(xi, n);
    if xn != 0.0 {
        let len2 = dot(xi, xi);
        let p = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
        let plen2 = dot(p, p);
        let s = if plen2 > 0.0 { (len2 / plen2).sqrt() } else { 0.0 };
        xi = [p[0] * s, p[1] * s, p[2] * s];
    }
    // Tangential relative velocity, advance, trial force.
    let vt = tangential_part(c.velocity, n);
    let mut f = [0.0; 3];
    for i in 0..3 {
        xi[i] += vt[i] * c.dt;
        f[i] = -kt * xi[i] - eta * vt[i];
    }
    // Coulomb cap, with the spring reset to the capped force.
    let cap = mu * c.normal_force.max(0.0);
    let f2 = dot(f, f);
    if f2 > cap * cap {
        let s = cap / f2.sqrt();
        for i in 0..3 {
            f[i] *= s;
            xi[i] = if kt > 0.0 { -(f[i] + eta * vt[i]) / kt } else { 0.0 };
        }
    }
    h[..3].copy_from_slice(&xi);
    f
}

/// The energy of [`spring_friction`] after a step that returned `force` and left `history`:
/// elastic ½ k_t |ξ|² (J); power η_t |v_t|² while the spring holds, −F_t·v_t while it slides
/// (W); 0 out of contact (δ ≤ 0).
pub fn spring_friction_energy(
    kt: f64,
    eta: f64,
    mu: f64,
    c: &crate::TangentialContact,
    history: &[f64],
    force: [f64; 3],
) -> crate::Energy {
    if c.delta <= 0.0 {
        return crate::Energy::default();
    }
    spring_slider_energy(
        kt,
        eta,
        mu * c.normal_force.max(0.0),
        [history[0], history[1], history[2]],
        tangential_part(c.velocity, c.normal),
        force,
    )
}
