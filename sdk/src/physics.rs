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

    /// The energy of a step of `dt` (s) at twisting rate `rate` (rad/s) that left the angle
    /// `theta` (rad) and returned `torque` (N·m), the spring's stiffness, damping and critical
    /// torque taken as the same one step before: [`SliderStep::energy`] with θ, ω and M as
    /// vectors along n̂ (elastic k θ²/2, no more than M_c²/(2k), J; power W).
    pub fn step_energy(&self, rate: f64, dt: f64, theta: f64, torque: f64) -> crate::Energy {
        let step = SliderStep {
            k: self.k,
            k_before: self.k,
            eta: self.gamma,
            eta_before: self.gamma,
            cap: self.mcrit,
            cap_before: self.mcrit,
            dt,
        };
        let m = [torque, 0.0, 0.0];
        step.energy(
            torque.abs() >= self.mcrit && rate != 0.0,
            [theta, 0.0, 0.0],
            [rate, 0.0, 0.0],
            m,
        )
    }

    /// Elastic energy k θ²/2 (J) and dissipated power (W): γ ω² while the spring holds, |M ω|
    /// while it slides (the steady form; [`TwistSpring::step_energy`] books the energy the
    /// spring stores or loses under a changing critical torque).
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
/// This steady form misses the energy the spring stores or loses while it slides under a
/// changing cap; [`SliderStep::energy`] books it.
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

/// The energy of [`spring_friction`] with a constant stiffness `kt` (N/m) and dashpot `eta`
/// (N·s/m) after a step that returned `force` and left `history`: see
/// [`spring_friction_energy_varying`].
pub fn spring_friction_energy(
    kt: f64,
    eta: f64,
    mu: f64,
    c: &crate::TangentialContact,
    history: &[f64],
    force: [f64; 3],
) -> crate::Energy {
    spring_friction_energy_varying([kt, kt], [eta, eta], mu, c, history, force)
}

/// The energy of [`spring_friction`] after a step that returned `force` and left `history`,
/// for a stiffness `kt` = [before, after] the step (N/m) and a dashpot `eta` = [before, after]
/// (N·s/m): elastic k_t |ξ|²/2, no more than (μ F_n)²/(2 k_t) (J), and the power of
/// [`SliderStep::energy`] (W) with v the tangential velocity, the cap μ max(F_n, 0) now and,
/// one step before, the cap that leaves the most a sliding spring can hold, cap²/(2 k_t),
/// unchanged: μ F_n √(k_before/k_t). (The normal force of the previous step is not part of
/// the contact, so the energy a changing cap puts into or truncates from a sliding spring is
/// booked only as far as it follows from the stiffness; with a constant k_t it is not booked.)
/// 0 out of contact (δ ≤ 0).
pub fn spring_friction_energy_varying(
    kt: [f64; 2],
    eta: [f64; 2],
    mu: f64,
    c: &crate::TangentialContact,
    history: &[f64],
    force: [f64; 3],
) -> crate::Energy {
    if c.delta <= 0.0 {
        return crate::Energy::default();
    }
    let cap = mu * c.normal_force.max(0.0);
    let step = SliderStep {
        k: kt[1],
        k_before: kt[0],
        eta: eta[1],
        eta_before: eta[0],
        cap,
        cap_before: if kt[1] > 0.0 {
            cap * (kt[0] / kt[1]).sqrt()
        } else {
            cap
        },
        dt: c.dt,
    };
    step.energy(
        SliderStep::at_cap(force, cap),
        [history[0], history[1], history[2]],
        tangential_part(c.velocity, c.normal),
        force,
    )
}

/// The overlap one step before (m), δ − δ̇ dt with δ̇ = −v·n̂ the approach rate, for a contact
/// of overlap `delta` (m), unit normal `normal` (from partner to particle) and relative
/// velocity `velocity` (m/s, of the particle's contact point w.r.t. the partner's) over a step
/// `dt` (s); 0 when the contact had not formed.
#[inline]
pub fn overlap_before(delta: f64, normal: [f64; 3], velocity: [f64; 3], dt: f64) -> f64 {
    (delta + dot(velocity, normal) * dt).max(0.0)
}

/// One step of a spring–dashpot–slider (a tangential, rolling or twisting spring capped by
/// Coulomb, its spring reset to the capped force) as its energy accounting sees it: the
/// stiffness, dashpot and cap after the step and one step before. Units: N/m, N·s/m and N for
/// a displacement spring; N·m/rad, N·m·s/rad and N·m for a twist.
///
/// [`SliderStep::energy`] recovers what the step did from its end state only (the law's
/// energy call sees the history after the step) and closes the balance step by step:
/// power × dt = W − (E_after − E_before), with W the work the bodies did on the contact over
/// the step and E the stored energy [`SliderStep::stored`]:
/// - stuck (|F| below the cap): the spring advanced by v dt, so ξ_before = ξ − v dt exactly;
///   W = η |v|² dt + k (|ξ|² − |ξ_before|²)/2 (the dashpot at the end of the step, the spring
///   force averaged over it), and power = η |v|² − (E(k, ξ_before) − E(k_before, ξ_before))/dt:
///   the dashpot, less the energy a changing stiffness puts into the spring at fixed ξ (Mindlin's
///   k_t ∝ √δ grows on loading), which no force paid for;
/// - sliding (|F| at the cap): the reset erased ξ_before; the spring is taken to have held the
///   capped force at the previous cap, F cap_before/cap, plus the dashpot share η_before v it
///   holds under LAMMPS's reset, so W = −F·v dt and the stored energy's change between the two
///   caps, the truncation of the spring when the cap falls and its loading when it rises, is
///   booked as far as `cap_before` is known.
///
/// The power is therefore the energy the contact takes out of the bodies' motion and out of its
/// spring per second: ≥ 0 where the law is passive, negative on a step where a growing stiffness
/// (or a rising spring under a sliding dashpot) stores energy no force paid for. Summed over the
/// steps with the elastic energy at the end it equals the work the bodies lost, to first order in
/// dt, as far as `cap_before` and `k_before` are exact: a stuck spring's accounting is exact, a
/// sliding one's misses whatever error `cap_before` carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliderStep {
    /// Stiffness k after the step.
    pub k: f64,
    /// Stiffness one step before (`k` for a constant stiffness).
    pub k_before: f64,
    /// Dashpot η acting over the step.
    pub eta: f64,
    /// The dashpot whose share η v the spring held before the step while sliding (the dashpot
    /// one step before for LAMMPS's reset ξ = −(F + η v)/k; 0 for a spring reset to the capped
    /// force alone).
    pub eta_before: f64,
    /// The Coulomb cap after the step.
    pub cap: f64,
    /// The cap one step before (`cap` when it is not known).
    pub cap_before: f64,
    /// Time step (s).
    pub dt: f64,
}

impl SliderStep {
    /// The energy stored in a spring of stiffness `k` holding a displacement of squared length
    /// `xi2` under a cap `cap`: k ξ²/2, but no more than cap²/(2k), what the spring can give
    /// back through the slider (the rest of a spring that holds a dashpot's share beyond the cap
    /// is truncated as soon as the slip stops); 0 for k = 0 (J).
    #[inline]
    pub fn stored(k: f64, xi2: f64, cap: f64) -> f64 {
        if k > 0.0 {
            (0.5 * k * xi2).min(0.5 * cap * cap / k)
        } else {
            0.0
        }
    }

    /// Whether a force `force` sits at the cap `cap` (to rounding): the step slid.
    #[inline]
    pub fn at_cap(force: [f64; 3], cap: f64) -> bool {
        dot(force, force) >= cap * cap * (1.0 - 1e-12)
    }

    /// The energy of a step that left the spring at `xi`, advanced it with velocity `v` (the
    /// tangential, rolling or twisting velocity; a twist as `[θ, 0, 0]`, `[ω, 0, 0]`) and
    /// returned `force`; `sliding` says whether the force was capped (see the type's doc).
    pub fn energy(&self, sliding: bool, xi: [f64; 3], v: [f64; 3], force: [f64; 3]) -> crate::Energy {
        let elastic = Self::stored(self.k, dot(xi, xi), self.cap);
        if self.dt.is_nan() || self.dt <= 0.0 {
            return crate::Energy { power: 0.0, elastic };
        }
        let dt = self.dt;
        // the spring energy beyond what the slider lets it give back
        let excess = |k: f64, x2: f64, cap: f64| 0.5 * k * x2 - Self::stored(k, x2, cap);
        let power = if sliding {
            let s = if self.cap > 0.0 {
                self.cap_before / self.cap
            } else {
                1.0
            };
            let held = [
                s * force[0] + self.eta_before * v[0],
                s * force[1] + self.eta_before * v[1],
                s * force[2] + self.eta_before * v[2],
            ];
            let xo2 = if self.k_before > 0.0 {
                dot(held, held) / (self.k_before * self.k_before)
            } else {
                0.0
            };
            -dot(force, v) + (Self::stored(self.k_before, xo2, self.cap_before) - elastic) / dt
        } else {
            // W − E_after + E_before with W = η |v|² dt + k (|ξ|² − |ξ_before|²)/2, arranged so
            // that a constant stiffness below the cap gives η |v|² to the bit
            let xo = [xi[0] - v[0] * dt, xi[1] - v[1] * dt, xi[2] - v[2] * dt];
            let (x2, xo2) = (dot(xi, xi), dot(xo, xo));
            let stiffening = 0.5 * (self.k_before - self.k) * xo2;
            let clipped = excess(self.k, x2, self.cap) - excess(self.k_before, xo2, self.cap_before);
            self.eta * dot(v, v) + (stiffening + clipped) / dt
        };
        crate::Energy { power, elastic }
    }
}
