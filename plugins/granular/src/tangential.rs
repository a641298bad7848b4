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
#[inline]
pub fn linear_nohistory(s: &Spring, ctx: &Ctx, m: &Motion) -> Step {
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
    Step {
        force: f,
        spring: SpringStep {
            k_before: 0.0,
            xi_before: [0.0; 3],
            k: 0.0,
            xi_start: [0.0; 3],
            xi_after: [0.0; 3],
            eta: ft,
            v: vtr,
            force: f,
            slid: false,
        },
    }
}

/// The outcome of one step of a history spring: the force and the step as its energy sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// The force on i (N).
    pub force: [f64; 3],
    /// The step for the energy accounting (displacement springs in m).
    pub spring: SpringStep,
}

/// LAMMPS `tangential linear_history k_t x_t μ`: history ξ (m, slots 0..3). Turn ξ into the
/// tangent plane (when its normal part matters), ξ += v_t dt, F = −k_t ξ − η_t v_t; if
/// |F| > μ F_c and ξ ≠ 0: F scaled to μ F_c and ξ = −(F + η_t v_t)/k_t; if ξ = 0, F = 0.
#[inline]
pub fn linear_history(s: &Spring, ctx: &Ctx, m: &Motion, h: &mut [f64]) -> Step {
    let (kt, xt, mu, n, dt) = (s.k, s.xt, s.mu, m.n, m.dt);
    let vtr = tangential(m.v, n);
    let damp = xt * ctx.damping;
    let fscrit = ctx.cap_force * mu;
    let before = vec3(h);
    let mut xi = before;
    if dot(xi, n).abs() * kt > FRAME_EPS * fscrit {
        xi = rotate_rescale(xi, n);
    }
    let start = xi;
    xi = add(xi, scale(dt, vtr));
    let mut f = sub(scale(-kt, xi), scale(damp, vtr));
    let magfs = len(f);
    let slid = magfs > fscrit;
    if slid {
        if len(xi) != 0.0 {
            let inv = 1.0 / magfs;
            xi = add(scale(fscrit * inv, f), scale(damp, vtr));
            xi = scale(-1.0 / kt, xi);
            f = scale(fscrit * inv, f);
        } else {
            f = [0.0; 3];
        }
    }
    h[..3].copy_from_slice(&xi);
    Step {
        force: f,
        spring: SpringStep {
            k_before: kt,
            xi_before: before,
            k: kt,
            xi_start: start,
            xi_after: xi,
            eta: damp,
            v: vtr,
            force: f,
            slid,
        },
    }
}

/// LAMMPS `tangential mindlin k x_t μ` and its variants: stiffness k a (k in N/m², a the
/// contact radius of the context). `FORCE` (`mindlin/force`, `mindlin_rescale/force`): the
/// history is the elastic force (N), advanced by −k a v_t dt; else the displacement ξ (m).
/// `RESCALE` (`mindlin_rescale*`): on unloading (a below the a of the last step, slot 3) the
/// history is first scaled by a/a_last. Slot 3 holds a of this step for every variant (LAMMPS
/// keeps it for the rescaling ones only; the others use it for their energy).
#[inline]
pub fn mindlin<const FORCE: bool, const RESCALE: bool>(
    s: &Spring,
    ctx: &Ctx,
    m: &Motion,
    h: &mut [f64],
) -> Step {
    let (k, xt, mu, n, dt) = (s.k, s.xt, s.mu, m.n, m.dt);
    let vtr = tangential(m.v, n);
    let a = ctx.contact_radius;
    let damp = xt * ctx.damping;
    let fscrit = ctx.cap_force * mu;
    let k_scaled = k * a;
    let (before, a_last) = (vec3(h), h[3]);
    let mut hist = before;
    if RESCALE && a < a_last {
        hist = scale(a / a_last, hist);
    }
    let rsht = dot(hist, n);
    let turn = if FORCE {
        rsht.abs() > FRAME_EPS * fscrit
    } else {
        rsht.abs() * k_scaled > FRAME_EPS * fscrit
    };
    if turn {
        hist = rotate_rescale(hist, n);
    }
    let start = hist;
    hist = if FORCE {
        add(hist, scale(-k_scaled * dt, vtr))
    } else {
        add(hist, scale(dt, vtr))
    };
    let mut f = scale(-damp, vtr);
    f = if FORCE {
        add(f, hist)
    } else {
        sub(f, scale(k_scaled, hist))
    };
    let magfs = len(f);
    let slid = magfs > fscrit;
    if slid {
        if len(hist) != 0.0 {
            let inv = 1.0 / magfs;
            hist = add(scale(fscrit * inv, f), scale(damp, vtr));
            if !FORCE {
                hist = scale(-1.0 / k_scaled, hist);
            }
            f = scale(fscrit * inv, f);
        } else {
            f = [0.0; 3];
        }
    }
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
    Step {
        force: f,
        spring: SpringStep {
            k_before,
            xi_before: as_xi(before, k_before),
            k: k_scaled,
            xi_start: as_xi(start, k_scaled),
            xi_after: as_xi(hist, k_scaled),
            eta: damp,
            v: vtr,
            force: f,
            slid,
        },
    }
}

/// The classic history springs: ξ += v_t dt first, then ξ is projected onto the tangent plane
/// (no rescaling), F = −k_s ξ − η_t v_t, and past the cap ξ = −(F + η_t v_t)/k_r.
/// `gran/hooke/history`: k_s = k_r = k_t; `gran/hertz/history`: k_s = k_r = k_t a; LAMMPS
/// 22 Jul 2025's granular `linear_history_classic`/`mindlin_classic` (and `fix wall/gran`
/// `hooke/history`, `hertz/history`): k_s = k_t a, k_r = k_t. The spring `s` has k = k_s;
/// `k_before` is the spring stiffness of the previous step (for the energy only).
#[inline]
pub fn classic(s: &Spring, k_reset: f64, ctx: &Ctx, m: &Motion, h: &mut [f64], k_before: f64) -> Step {
    let (k_spring, xt, mu, n, dt) = (s.k, s.xt, s.mu, m.n, m.dt);
    let vtr = tangential(m.v, n);
    let damp = xt * ctx.damping;
    let fscrit = ctx.cap_force * mu;
    let before = vec3(h);
    let mut xi = add(before, scale(dt, vtr));
    let shrmag = len(xi);
    xi = sub(xi, scale(dot(xi, n), n));
    let mut f = sub(scale(-k_spring, xi), scale(damp, vtr));
    let magfs = len(f);
    let slid = magfs > fscrit;
    if slid {
        if shrmag != 0.0 {
            let inv = 1.0 / magfs;
            xi = add(scale(fscrit * inv, f), scale(damp, vtr));
            xi = scale(-1.0 / k_reset, xi);
            f = scale(fscrit * inv, f);
        } else {
            f = [0.0; 3];
        }
    }
    h[..3].copy_from_slice(&xi);
    Step {
        force: f,
        spring: SpringStep {
            k_before,
            xi_before: before,
            k: k_spring,
            xi_start: sub(xi, scale(dt, vtr)),
            xi_after: xi,
            eta: damp,
            v: vtr,
            force: f,
            slid,
        },
    }
}
