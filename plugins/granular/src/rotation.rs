//! The rolling and twisting sub-models of LAMMPS's `pair_style granular`, as pure functions in
//! LAMMPS's order of operations.
//!
//! Rolling: the rolling velocity v_roll = R_eff (ω_i − ω_j) × n̂ (m/s) advances a spring ξ_r (m);
//! the law returns the rolling force F_r (N), whose torque on i is R_eff n̂ × F_r. Twisting:
//! the twist rate ω_t = (ω_i − ω_j)·n̂ (rad/s) advances an angle θ (rad); the law returns the
//! torque M_t (N·m) about n̂ on i. Both are capped by the normal law's F_c (LAMMPS's `Fncrit`).

use crate::spring::{add, len, scale, vec3, Ctx, SpringStep};
use crate::tangential::{turn_advance, Motion};

/// LAMMPS `rolling sds k γ μ`: ξ turned into the tangent plane when its normal part matters,
/// ξ += v_roll dt, F = −k ξ − γ v_roll; past μ F_c, with ξ ≠ 0: ξ = −(μ F_c F/|F| + γ v)/k and
/// F scaled to μ F_c; with ξ = 0, F = 0. History ξ (m), slots 0..3.
/// `s` holds k (N/m), γ (N·s/m) and μ; `m` the normal, v_roll and dt; `cap` is F_c (N).
#[inline(always)]
pub fn rolling_sds(s: &Sds, cap: f64, m: &Motion, h: &mut [f64]) -> SpringStep {
    let (k, gamma, mu, n, vrl, dt) = (s.k, s.gamma, s.mu, m.n, m.v, m.dt);
    let frcrit = mu * cap;
    let before = vec3(h);
    let (start, mut xi) = turn_advance(before, n, k, frcrit, dt, vrl);
    let mut f = add(scale(-k, xi), scale(-gamma, vrl));
    let magfr = len(f);
    let slid = magfr > frcrit;
    if slid {
        if len(xi) != 0.0 {
            let k_inv = 1.0 / k;
            let magfr_inv = 1.0 / magfr;
            xi = add(scale(-frcrit * k_inv * magfr_inv, f), scale(-gamma * k_inv, vrl));
            f = scale(frcrit * magfr_inv, f);
        } else {
            f = [0.0; 3];
        }
    }
    h[..3].copy_from_slice(&xi);
    SpringStep::new([k, k], [before, start, xi], gamma, vrl, f, slid)
}

/// The constants of a spring–dashpot–slider law (`rolling sds`, `twisting sds`): stiffness,
/// damping and friction coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sds {
    /// Stiffness.
    pub k: f64,
    /// Damping.
    pub gamma: f64,
    /// Friction coefficient.
    pub mu: f64,
}

/// The constants of a twisting spring–dashpot–slider: stiffness (N·m/rad), damping
/// (N·m·s/rad) and the coefficient of the critical torque M_c = `mu` F_c (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Twist {
    /// Stiffness k_t (N·m/rad).
    pub k: f64,
    /// Damping γ_t (N·m·s/rad).
    pub damp: f64,
    /// Critical-torque coefficient μ_t (m).
    pub mu: f64,
}

impl Twist {
    /// LAMMPS `twisting marshall` (Marshall 2009, eq. 32): from the tangential model's stiffness
    /// `k_tang` (as LAMMPS keeps it: N/m for `linear_history`, N/m² for `mindlin`), its dashpot
    /// `damp_tang` = x_t η_n (N·s/m) and its friction coefficient `mu_tang`, at contact radius
    /// `a` (m): k = k_tang a²/2, γ = damp_tang a²/2, μ = (2/3) μ_tang a.
    #[inline(always)]
    pub fn marshall(k_tang: f64, damp_tang: f64, mu_tang: f64, a: f64) -> Twist {
        Twist {
            k: 0.5 * k_tang * a * a,
            damp: 0.5 * damp_tang * a * a,
            mu: TWOTHIRDS * mu_tang * a,
        }
    }

    /// One step: θ += ω dt, M = −k θ − γ ω; past M_c = μ F_c: θ = (M_c sgn ω − γ ω)/k and
    /// M = −M_c sgn ω. `theta` is the angle (rad), read and updated; `k_before` the stiffness
    /// of the previous step (for the energy).
    #[inline(always)]
    pub fn step(&self, cap: f64, rate: f64, dt: f64, theta: &mut f64, k_before: f64) -> (f64, SpringStep) {
        let before = *theta;
        *theta += rate * dt;
        let mut m = -self.k * *theta - self.damp * rate;
        let sign = f64::from(u8::from(rate > 0.0)) - f64::from(u8::from(rate < 0.0));
        let mtcrit = self.mu * cap;
        let slid = m.abs() > mtcrit;
        if slid {
            *theta = (mtcrit * sign - self.damp * rate) / self.k;
            m = -mtcrit * sign;
        }
        let xi = [[before, 0.0, 0.0], [before, 0.0, 0.0], [*theta, 0.0, 0.0]];
        let spring = SpringStep::new(
            [k_before, self.k],
            xi,
            self.damp,
            [rate, 0.0, 0.0],
            [m, 0.0, 0.0],
            slid,
        );
        (m, spring)
    }
}

/// 2/3 as LAMMPS writes it (`TWOTHIRDS`).
pub(crate) const TWOTHIRDS: f64 = 0.6666666666666666;

/// The Marshall twist of a contact from the tangential law's k_t, x_t and μ and the normal
/// law's context (contact radius, damping prefactor η_n: the tangential dashpot is x_t η_n).
pub fn marshall_twist(kt: f64, xt: f64, mu: f64, ctx: &Ctx) -> Twist {
    Twist::marshall(kt, xt * ctx.damping, mu, ctx.contact_radius)
}
