//! Formulas several laws share, each with its source.

use std::f64::consts::PI;

/// The damping factor α(ε) = −√5 ln ε / √(ln²ε + π²) of the Hertzian spring-dashpot in Tsuji's
/// form F_d = α √(m k) δ^{1/4} δ̇: the exact value (Antypov & Elliott 2011, eq. 17, not Tsuji's
/// 1992 fit) that realizes restitution ε at every impact speed when contact ends as δ returns to
/// 0. Dimensionless; α(1) = 0.
pub fn tsuji_alpha(eps: f64) -> f64 {
    let l = eps.ln();
    // (0 − l, not −l: α(1) is +0, which prints as 0, not -0)
    (5.0f64).sqrt() * (0.0 - l) / (l * l + PI * PI).sqrt()
}

/// The damping ratio ζ = −ln ε / √(ln²ε + π²) of the linear spring-dashpot with restitution ε
/// (Antypov & Elliott 2011, eq. 8: γ = ζ ω0). Dimensionless.
pub fn lsd_damping_ratio(eps: f64) -> f64 {
    let l = eps.ln();
    (0.0 - l) / (l * l + PI * PI).sqrt()
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
        // +0, not -0: a report prints α(1) as 0.000000, not -0.000000
        assert!(tsuji_alpha(1.0).is_sign_positive() && lsd_damping_ratio(1.0).is_sign_positive());
        assert_eq!(format!("{:.6}", tsuji_alpha(1.0)), "0.000000");
        for eps in [0.1, 0.5, 0.9] {
            let r = tsuji_alpha(eps) / lsd_damping_ratio(eps);
            assert!((r - 5f64.sqrt()).abs() < 1e-14, "{eps}: {r}");
        }
    }
}

/// The spring–dashpot–slider of a twisting law with LAMMPS's reset (`twisting sds`, `twisting
/// marshall`): stiffness (N·m/rad), damping (N·m·s/rad) and critical torque (N·m). For laws that
/// mirror LAMMPS: its reset θ = (M_c sgn ω − γ ω)/k stores the dashpot's share in the spring;
/// dashpot's own twisting laws take the passive [`Slider`].
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
    #[inline]
    pub fn torque(&self, rate: f64, dt: f64, h: &mut [f64]) -> f64 {
        self.step(rate, dt, h).0
    }

    /// [`TwistSpring::torque`] and whether the torque was capped (the twist slid).
    #[inline]
    fn step(&self, rate: f64, dt: f64, h: &mut [f64]) -> (f64, bool) {
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
            return (-self.mcrit * sign, true);
        }
        (m, false)
    }

    /// [`TwistSpring::torque`] with the step's energy ([`SliderStep::energy`] with θ, ω and M as
    /// vectors along n̂: elastic k θ²/2, J; power, W), the stiffness taken as the same one step
    /// before (`k_before`, N·m/rad, for one that changes with the contact).
    #[inline]
    pub fn torque_energy(&self, k_before: f64, rate: f64, dt: f64, h: &mut [f64]) -> (f64, crate::Energy) {
        let before = h[0];
        let (m, sliding) = self.step(rate, dt, h);
        let step = SliderStep {
            k: self.k,
            k_before,
            eta: self.gamma,
            eta_held: self.gamma,
            xi_before: [before, 0.0, 0.0],
            dt,
        };
        (
            m,
            step.energy(sliding, [h[0], 0.0, 0.0], [rate, 0.0, 0.0], [m, 0.0, 0.0]),
        )
    }
}

/// The tangential velocity v − (v·n̂) n̂ (m/s) of `v` for unit normal `n`.
#[inline(always)]
pub fn tangential_part(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    [v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]]
}

/// The spring `xi` turned into the tangent plane of unit normal `n`, keeping its length (the
/// contact frame turned since the spring was stored): ξ − (ξ·n̂) n̂ rescaled to |ξ|; `xi` itself
/// when it lies in the plane, 0 when it lies along n̂.
#[inline(always)]
pub fn turn_into_plane(xi: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let xn = dot(xi, n);
    if xn == 0.0 {
        return xi;
    }
    let len2 = dot(xi, xi);
    let p = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
    let plen2 = dot(p, p);
    let s = if plen2 > 0.0 { (len2 / plen2).sqrt() } else { 0.0 };
    [p[0] * s, p[1] * s, p[2] * s]
}

/// The dot product of two 3-vectors.
#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// One step of a tangential spring–dashpot with a Coulomb slider with the bookkeeping of Luding
/// 2008 and LAMMPS `pair granular` (for laws that mirror LAMMPS; dashpot's own laws take the
/// passive [`Slider`]: this reset stores the dashpot's share in the spring, which can then push
/// along the slip and give the motion more energy than it took), for a spring of stiffness `kt`
/// (N/m), a dashpot `eta` (N·s/m) and a friction coefficient `mu`, on contact `c` whose history `h[..3]` is the spring
/// displacement ξ (m). Returns the tangential force (N). If δ ≤ 0 the force is 0 and ξ = 0;
/// otherwise (1) rotate ξ into the tangent plane keeping its length, (2) v_t = v − (v·n̂) n̂,
/// (3) ξ += v_t dt, (4) F_t = −k_t ξ − η_t v_t, (5) if |F_t| > μ max(F_n, 0) scale F_t to
/// μ max(F_n, 0) and reset ξ = −(F_t + η_t v_t)/k_t (0 when k_t = 0).
#[inline(always)]
pub fn spring_friction(kt: f64, eta: f64, mu: f64, c: &crate::TangentialContact, h: &mut [f64]) -> [f64; 3] {
    spring_friction_step(kt, eta, mu, c, h).0
}

/// [`spring_friction`], whether the spring slid or was dropped (δ ≤ 0), and the spring the step
/// started from, turned into the tangent plane.
#[inline(always)]
fn spring_friction_step(
    kt: f64,
    eta: f64,
    mu: f64,
    c: &crate::TangentialContact,
    h: &mut [f64],
) -> ([f64; 3], bool, [f64; 3]) {
    if c.delta <= 0.0 {
        let before = [h[0], h[1], h[2]];
        h[..3].fill(0.0);
        return ([0.0; 3], true, before);
    }
    let n = c.normal;
    let mut xi = turn_into_plane([h[0], h[1], h[2]], n);
    // Tangential relative velocity, advance, trial force.
    let vt = tangential_part(c.velocity, n);
    let turned = xi;
    let mut f = [0.0; 3];
    for i in 0..3 {
        xi[i] += vt[i] * c.dt;
        f[i] = -kt * xi[i] - eta * vt[i];
    }
    // Coulomb cap, with the spring reset to the capped force.
    let cap = mu * c.normal_force.max(0.0);
    let f2 = dot(f, f);
    let slid = f2 > cap * cap;
    if slid {
        let s = cap / f2.sqrt();
        for i in 0..3 {
            f[i] *= s;
            xi[i] = if kt > 0.0 { -(f[i] + eta * vt[i]) / kt } else { 0.0 };
        }
    }
    h[..3].copy_from_slice(&xi);
    (f, slid, turned)
}

/// [`spring_friction`] with the step's energy ([`SliderStep::energy`], v the tangential
/// velocity): for a stiffness `kt` = [at the previous call, now] (N/m; the same twice for a
/// constant one) and a dashpot `eta` (N·s/m). Elastic k_t |ξ|²/2 (J); a spring dropped out of contact
/// (δ ≤ 0) gives back nothing: its energy is dissipated at that step.
#[inline(always)]
pub fn spring_friction_energy(
    kt: [f64; 2],
    eta: f64,
    mu: f64,
    c: &crate::TangentialContact,
    h: &mut [f64],
) -> ([f64; 3], crate::Energy) {
    let (f, slid, before) = spring_friction_step(kt[1], eta, mu, c, h);
    let step = SliderStep {
        k: kt[1],
        k_before: kt[0],
        eta,
        eta_held: eta,
        xi_before: before,
        dt: c.dt,
    };
    let e = step.energy(slid, [h[0], h[1], h[2]], tangential_part(c.velocity, c.normal), f);
    (f, e)
}

/// One step of a spring–dashpot–slider with LAMMPS's reset (a tangential, rolling or twisting
/// spring capped by Coulomb, its spring reset to the capped force) as its energy accounting sees
/// it (for laws that mirror LAMMPS; [`Slider::energy`] is dashpot's own, exact), from both
/// ends: the stiffness after the step and one step before, the dashpot, and the spring the step
/// started from. Units: N/m, N·s/m and m for a displacement spring; N·m/rad, N·m·s/rad and rad
/// for a twist.
///
/// [`SliderStep::energy`] closes the balance step by step: power × dt = W − (E_after −
/// E_before), with E = k |ξ|²/2 the spring's energy (E_before from the stiffness and the spring
/// the step started from: what the previous step reported) and W the work the bodies did on
/// the contact over the step:
/// - stuck (the force below the cap): the spring advanced by v dt, W = η |v|² dt + k (|ξ|² −
///   |ξ_before|²)/2 (the dashpot at the end of the step, the spring force averaged over it), so
///   power = η |v|² − (E(k, ξ_before) − E(k_before, ξ_before))/dt: the dashpot, less the energy a
///   changing stiffness puts into the spring at fixed ξ (Mindlin's k_t ∝ √δ grows on loading),
///   which no force paid for;
/// - sliding, or dropped (the force capped, the spring reset): W = −(F_before + F)·v dt/2, the
///   force averaged over the step as velocity Verlet applies it, with F_before = −k_before
///   ξ_before − η_held v, or 0 from a spring at zero extension, a contact formed on the step
///   (the reset leaves a capped force −k ξ − η_held v: η_held = η under
///   LAMMPS's reset ξ = −(F + η v)/k, 0 for a spring reset to the capped force alone); and the
///   change of the stored energy, whether the cap truncated the spring or let it load, is booked
///   whole.
///   (Under LAMMPS's reset ξ = −(F + η v)/k a sliding spring also holds the dashpot's share:
///   that energy is stored until the spring gives it back or a later reset truncates it.)
///
/// The power is therefore the energy the contact takes out of the bodies' motion and out of its
/// spring per second: ≥ 0 where the law is passive, negative on a step where a growing stiffness
/// stores energy no force paid for. Summed over the steps with the elastic energy at the end it
/// equals the work the bodies lost, to the integrator's order in dt, as far as `k_before` is the
/// stiffness the previous step had (a constant one; Mindlin's, which its history keeps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliderStep {
    /// Stiffness k after the step.
    pub k: f64,
    /// Stiffness one step before (`k` for a constant stiffness).
    pub k_before: f64,
    /// Dashpot η acting over the step.
    pub eta: f64,
    /// The dashpot share a reset spring holds (`eta` under LAMMPS's reset ξ = −(F + η v)/k; 0 for
    /// a spring reset to the capped force alone).
    pub eta_held: f64,
    /// The spring the step started from (the history before the call, turned into the current
    /// tangent plane at its length; a twist as `[θ, 0, 0]`).
    pub xi_before: [f64; 3],
    /// Time step (s).
    pub dt: f64,
}

impl SliderStep {
    /// The energy of a step that left the spring at `xi`, advanced it with velocity `v` (the
    /// tangential, rolling or twisting velocity; a twist as `[θ, 0, 0]`, `[ω, 0, 0]`) and
    /// returned `force`; `sliding` says whether the force was capped or the spring dropped (see
    /// the type's doc). Elastic k |ξ|²/2 (J), power (W); a step of no length dissipates nothing.
    #[inline(always)]
    pub fn energy(&self, sliding: bool, xi: [f64; 3], v: [f64; 3], force: [f64; 3]) -> crate::Energy {
        // branch-free (both cases computed, one selected), so that a SIMD law's lanes keep
        // their vector form
        let elastic = 0.5 * self.k * dot(xi, xi);
        let (xo, x0) = (self.xi_before, dot(self.xi_before, self.xi_before));
        let before = 0.5 * self.k_before * x0;
        // sliding: a spring at zero extension held no force, the contact formed on this step
        let formed = x0 > 0.0;
        let kb = if formed { self.k_before } else { 0.0 };
        let held = if formed { self.eta_held } else { 0.0 };
        let mean = [
            0.5 * (force[0] - kb * xo[0] - held * v[0]),
            0.5 * (force[1] - kb * xo[1] - held * v[1]),
            0.5 * (force[2] - kb * xo[2] - held * v[2]),
        ];
        let slid = (-dot(mean, v), before - elastic);
        // stuck: arranged so that a constant stiffness below the cap gives η |v|² to the bit
        let stuck = (self.eta * dot(v, v), before - 0.5 * self.k * x0);
        let (work, stored) = if sliding { slid } else { stuck };
        // a step of no length (or a NaN one) dissipates nothing; 1/dt, the same for every
        // contact of a batch, is computed once outside a batch's loop
        let rate = 1.0 / self.dt;
        let power = if self.dt > 0.0 { work + stored * rate } else { 0.0 };
        crate::Energy { power, elastic }
    }
}

mod slider;
pub use slider::{slider_friction, Slid, Slider};

/// [`Slider`] on four contacts at once in AVX2 registers (x86-64).
#[cfg(target_arch = "x86_64")]
pub mod lanes;
