//! The tangential sub-models of LAMMPS's `pair_style granular` and of its classic styles, as
//! pure functions in LAMMPS's order of operations.
//!
//! Inputs of every kernel: the unit normal n̂ (from the partner j to the particle i), the
//! tangential relative velocity of the contact points v_t (m/s; the kernel takes the part of
//! the given velocity normal to n̂, LAMMPS's `vtr`), the time step dt (s), the contact's
//! history, and the normal law's context ([`Ctx`]): the tangential dashpot is
//! η_t = x_t η_n (η_n the normal damping prefactor) and the Coulomb cap μ F_c.
//! Output: the tangential force on i (N) and what the step's energy needs.

use crate::normal::lmin;
use crate::spring::{add, dot, len, rotate_rescale, scale, sub, tangential, vec3, Ctx, SpringStep};

/// LAMMPS's `EPSILON`: a spring is turned into the tangent plane only when its normal part,
/// as a force, exceeds 10⁻¹⁰ of the cap.
pub const FRAME_EPS: f64 = 1e-10;

/// A tangential spring's constants: stiffness k (N/m; N/m² for the per-radius Mindlin and
/// classic Hertzian ones), x_t (the dashpot over the normal damping prefactor) and μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Stiffness k.
    pub k: f64,
    /// x_t.
    pub xt: f64,
    /// Friction coefficient μ.
    pub mu: f64,
}

/// The motion of a contact over a step: unit normal n̂ (from the partner to the particle), the
/// relative velocity v (m/s; of the contact points for tangential laws, v_roll for rolling) and
/// the step dt (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// n̂.
    pub n: [f64; 3],
    /// v.
    pub v: [f64; 3],
    /// dt.
    pub dt: f64,
}

/// LAMMPS `tangential linear_nohistory x_t μ` (classic `gran/hooke`): F_t = −min(μ F_c, η_t |v_t|)
/// v_t/|v_t|, η_t = x_t η_n.
/// No spring: the step's energy is the dashpot-or-cap's power F_t |v_t| (`SpringStep` with
/// k = 0 and η = F_t/|v_t|).
#[inline(always)]
pub fn linear_nohistory(s: &Spring, ctx: &Ctx, m: &Motion) -> SpringStep {
    let vtr = tangential(m.v, m.n);
    let vrel = len(vtr);
    let damp = s.xt * ctx.damping;
    let fscrit = s.mu * ctx.cap_force;
    let fsmag = damp * vrel;
    let ft = if vrel != 0.0 {
        lmin(fscrit, fsmag) / vrel
    } else {
        0.0
    };
    let f = scale(-ft, vtr);
    SpringStep::new([0.0, 0.0], [[0.0; 3], [0.0; 3], [0.0; 3]], ft, vtr, f, false)
}

/// What every history spring reads first: the tangential velocity v_t, the dashpot
/// η_t = x_t η_n and the cap μ F_c (LAMMPS's operations).
#[inline(always)]
fn dashpot_and_cap(s: &Spring, ctx: &Ctx, m: &Motion) -> ([f64; 3], f64, f64) {
    (tangential(m.v, m.n), s.xt * ctx.damping, ctx.cap_force * s.mu)
}

/// LAMMPS's frame update, then the advance: the spring `xi` turned into the tangent plane of
/// `n` at its length when its normal part, as a force (stiffness `k`), exceeds 10⁻¹⁰ of `cap`,
/// then advanced by `step` `v`: (the turned spring, the advanced one).
#[inline(always)]
pub(crate) fn turn_advance(
    xi: [f64; 3],
    n: [f64; 3],
    k: f64,
    cap: f64,
    step: f64,
    v: [f64; 3],
) -> ([f64; 3], [f64; 3]) {
    let start = if dot(xi, n).abs() * k > FRAME_EPS * cap {
        rotate_rescale(xi, n)
    } else {
        xi
    };
    (start, add(start, scale(step, v)))
}

/// LAMMPS's Coulomb cap of a tangential force `f` at `cap`: past it the force is scaled to the
/// cap and, if the spring held anything (`held`), the spring `xi` reset to the capped force plus
/// the dashpot's share `eta` `v`, divided by −`k` (a displacement spring; `None`: a force
/// history, kept as it is); a spring that held nothing gives no force. Returns the force, the
/// spring and whether the cap acted.
#[inline(always)]
fn coulomb(
    f: [f64; 3],
    xi: [f64; 3],
    held: bool,
    cap: f64,
    eta: f64,
    v: [f64; 3],
    k: Option<f64>,
) -> ([f64; 3], [f64; 3], bool) {
    let magfs = len(f);
    if magfs <= cap {
        return (f, xi, false);
    }
    if !held {
        return ([0.0; 3], xi, true);
    }
    let inv = 1.0 / magfs;
    let mut reset = add(scale(cap * inv, f), scale(eta, v));
    if let Some(k) = k {
        reset = scale(-1.0 / k, reset);
    }
    (scale(cap * inv, f), reset, true)
}

/// LAMMPS `tangential linear_history k_t x_t μ`: history ξ (m, slots 0..3). Turn ξ into the
/// tangent plane (when its normal part matters), ξ += v_t dt, F = −k_t ξ − η_t v_t; if
/// |F| > μ F_c and ξ ≠ 0: F scaled to μ F_c and ξ = −(F + η_t v_t)/k_t; if ξ = 0, F = 0.
#[inline(always)]
pub fn linear_history(s: &Spring, ctx: &Ctx, m: &Motion, h: &mut [f64]) -> SpringStep {
    let (kt, n, dt) = (s.k, m.n, m.dt);
    let (vtr, damp, fscrit) = dashpot_and_cap(s, ctx, m);
    let before = vec3(h);
    let (start, xi) = turn_advance(before, n, kt, fscrit, dt, vtr);
    let f = sub(scale(-kt, xi), scale(damp, vtr));
    let (f, xi, slid) = coulomb(f, xi, len(xi) != 0.0, fscrit, damp, vtr, Some(kt));
    h[..3].copy_from_slice(&xi);
    SpringStep::new([kt, kt], [before, start, xi], damp, vtr, f, slid)
}

/// LAMMPS `tangential mindlin k x_t μ` and its variants: stiffness k a (k in N/m², a the
/// contact radius of the context). `FORCE` (`mindlin/force`, `mindlin_rescale/force`): the
/// history is the elastic force (N), advanced by −k a v_t dt; else the displacement ξ (m).
/// `RESCALE` (`mindlin_rescale*`): on unloading (a below the a of the last step, slot 3) the
/// history is first scaled by a/a_last. Slot 3 holds a of this step for every variant (LAMMPS
/// keeps it for the rescaling ones only; the others use it for their energy).
#[inline(always)]
pub fn mindlin<const FORCE: bool, const RESCALE: bool>(
    s: &Spring,
    ctx: &Ctx,
    m: &Motion,
    h: &mut [f64],
) -> SpringStep {
    let (k, n, dt) = (s.k, m.n, m.dt);
    let (vtr, damp, fscrit) = dashpot_and_cap(s, ctx, m);
    let a = ctx.contact_radius;
    let k_scaled = k * a;
    let (before, a_last) = (vec3(h), h[3]);
    let mut hist = before;
    if RESCALE && a < a_last {
        hist = scale(a / a_last, hist);
    }
    // a force history turns when its normal part exceeds 10⁻¹⁰ of the cap, and advances by
    // −k a v_t dt
    let (start, hist) = if FORCE {
        turn_advance(hist, n, 1.0, fscrit, -k_scaled * dt, vtr)
    } else {
        turn_advance(hist, n, k_scaled, fscrit, dt, vtr)
    };
    let f = scale(-damp, vtr);
    let f = if FORCE {
        add(f, hist)
    } else {
        sub(f, scale(k_scaled, hist))
    };
    let k_reset = (!FORCE).then_some(k_scaled);
    let (f, hist, slid) = coulomb(f, hist, len(hist) != 0.0, fscrit, damp, vtr, k_reset);
    h[..3].copy_from_slice(&hist);
    h[3] = a;
    // the force history as the displacement it stands for, ξ = −F_el/(k a)
    let k_before = k * a_last;
    let as_xi = |x: [f64; 3], kk: f64| {
        if !FORCE {
            x
        } else if kk > 0.0 {
            scale(-1.0 / kk, x)
        } else {
            [0.0; 3]
        }
    };
    let xi = [
        as_xi(before, k_before),
        as_xi(start, k_scaled),
        as_xi(hist, k_scaled),
    ];
    SpringStep::new([k_before, k_scaled], xi, damp, vtr, f, slid)
}

/// The classic history springs: ξ += v_t dt first, then ξ is projected onto the tangent plane
/// (no rescaling), F = −k_s ξ − η_t v_t, and past the cap ξ = −(F + η_t v_t)/k_r.
/// `gran/hooke/history`: k_s = k_r = k_t; `gran/hertz/history`: k_s = k_r = k_t a; LAMMPS
/// 22 Jul 2025's granular `linear_history_classic`/`mindlin_classic` (and `fix wall/gran`
/// `hooke/history`, `hertz/history`): k_s = k_t a, k_r = k_t. The spring `s` has k = k_s;
/// `k_before` is the spring stiffness of the previous step (for the energy only).
#[inline(always)]
pub fn classic(s: &Spring, k_reset: f64, ctx: &Ctx, m: &Motion, h: &mut [f64], k_before: f64) -> SpringStep {
    let (k_spring, n, dt) = (s.k, m.n, m.dt);
    let (vtr, damp, fscrit) = dashpot_and_cap(s, ctx, m);
    let before = vec3(h);
    let xi = add(before, scale(dt, vtr));
    let shrmag = len(xi);
    let xi = sub(xi, scale(dot(xi, n), n));
    let f = sub(scale(-k_spring, xi), scale(damp, vtr));
    let (f, xi, slid) = coulomb(f, xi, shrmag != 0.0, fscrit, damp, vtr, Some(k_reset));
    h[..3].copy_from_slice(&xi);
    SpringStep::new(
        [k_before, k_spring],
        [before, sub(xi, scale(dt, vtr)), xi],
        damp,
        vtr,
        f,
        slid,
    )
}
