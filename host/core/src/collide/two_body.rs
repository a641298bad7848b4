//! The head-on collision of two particles (or a particle and a wall) under any contact law:
//! m δ̈ = −F(δ, δ̇), δ(0) = 0, δ̇(0) = v0.
//!
//! # Why three phases
//! The contact laws of granular physics are not smooth at δ = 0 (δ^{1/4}, √δ, δ^{3/2} terms), so
//! near the start and the end of a contact the solution is not smooth in time and no
//! step-size control recovers the order of a Runge–Kutta method there. Near δ = 0 the speed is
//! far from zero, so the overlap itself can serve as the clock: with u = δ^{1/4} as independent
//! variable,
//!
//! dv/du = 4u³ a(u⁴, v)/v,   dt/du = 4u³/v,   a = −F/m,
//!
//! and every power δ^{k/4} becomes a polynomial in u: the system is smooth again. So:
//! 1. **compression start** in u, from u = 0 until the speed has fallen to half of v0;
//! 2. **around maximum compression** in t (smooth there, δ > 0), locating the maximum overlap
//!    (δ̇ = 0) and, under the force criterion, the instant the force returns to 0;
//! 3. **rebound end** in u again, from half the maximum overlap down to u = 0 exactly: the
//!    "overlap returns to 0" event is the end of the integration interval, not a root to find.
//!
//! Events inside a step are located by root finding on the step size with fresh steps, so the
//! located state has the method's full accuracy.

pub use super::outcome::*;
pub use super::pair_law::*;
use super::rk::{locate, RhsError, Step, System, Tolerance};
use dashpot_sdk::{EndCriterion, LawError};

/// The overlap scale δ* where F·δ* = m v0² (the kinetic energy in force × overlap), with
/// F = max(|F(δ*, 0)|, |F(δ*, v0)|) so that purely dissipative laws have a scale too. It sets
/// the collision's tolerances, first steps and time limit: a scale, found to a few per cent.
///
/// The law is only asked about overlaps the collision itself comes near: the search starts far
/// below any physical overlap ([`PROBE_START`]) and grows, never past the first overlap where
/// F·δ ≥ m v0² (and the collision's maximum overlap δ_max satisfies ∫F dδ = m v0²/2, so for any
/// force that does not decrease with δ, δ* ≤ 2 δ_max). Each growth step goes half-way (in log δ)
/// to where the power law through the last two points would cross, at least a factor 2 and at
/// most `MAX_GROWTH`, so the largest overlap probed stays below 2 δ* even where the law's
/// exponent doubles (a dashpot term δ^{1/4} δ̇ giving way to a Hertz spring δ^{3/2}). The first
/// call probes two overlaps a decade apart, so the first step is already aimed. A bracket wider
/// than `FINE_BRACKET` is narrowed by one geometric grid (one call of the law); the crossing
/// is then interpolated as a power law through the bracket's ends. About eight calls in all.
pub fn overlap_scale<C: ContactForce>(law: &C, mass: f64, v0: f64) -> Result<f64, CollideError> {
    let target = mass * v0 * v0;
    let mut w2 = [0.0; 2];
    works(law, v0, &[PROBE_START, 10.0 * PROBE_START], &mut w2)?;
    let (mut lo, mut w_lo) = (PROBE_START, w2[0]);
    if w_lo >= target {
        return Ok(lo);
    }
    let mut prev;
    let (mut hi, mut w_hi) = (10.0 * PROBE_START, w2[1]);
    while w_hi < target {
        (prev, lo, w_lo) = ((lo, w_lo), hi, w_hi);
        // the next overlap: half-way to the power-law estimate of the crossing
        let mut factor = 2.0f64;
        if let Some(p) = power_exponent(prev, (lo, w_lo)) {
            let to_cross = ((target / w_lo).ln() / p).exp();
            if to_cross.is_finite() {
                factor = to_cross.sqrt().clamp(2.0, MAX_GROWTH);
            }
        }
        hi = lo * factor;
        if hi > PROBE_LIMIT {
            return Err(CollideError::NoStop {
                v0,
                f_at_1m: law.force(lo, v0)?,
            });
        }
        let mut w = [0.0];
        works(law, v0, &[hi], &mut w)?;
        w_hi = w[0];
    }
    // one geometric grid inside a wide bracket [lo, hi], one call of the law
    if hi > FINE_BRACKET * lo {
        let step = (hi / lo).powf(1.0 / (GRID + 1) as f64);
        let mut ds = [0.0; GRID];
        let mut d = lo;
        for x in ds.iter_mut() {
            d *= step;
            *x = d;
        }
        let mut w = [0.0; GRID];
        works(law, v0, &ds, &mut w)?;
        match w.iter().position(|&w| w >= target) {
            Some(0) => (hi, w_hi) = (ds[0], w[0]),
            Some(i) => (lo, w_lo, hi, w_hi) = (ds[i - 1], w[i - 1], ds[i], w[i]),
            None => (lo, w_lo) = (ds[GRID - 1], w[GRID - 1]),
        }
    }
    // the crossing of the power law through the bracket's ends (hi if that is not defined)
    if let Some(p) = power_exponent((lo, w_lo), (hi, w_hi)) {
        let d = lo * ((target / w_lo).ln() / p).exp();
        if d.is_finite() && d > lo && d <= hi {
            return Ok(d);
        }
    }
    Ok(hi)
}

/// The exponent p of the power law w ∝ δ^p through the points `(d0, w0)` and `(d1, w1)` of the
/// scale search, if w is positive and grows between them.
fn power_exponent((d0, w0): (f64, f64), (d1, w1): (f64, f64)) -> Option<f64> {
    (w0 > 0.0 && w1 > w0).then(|| (w1 / w0).ln() / (d1 / d0).ln())
}

/// The largest growth factor of one step of the scale search.
const MAX_GROWTH: f64 = 1e6;

/// A bracket of the scale search wider than this factor is narrowed by a grid before the
/// crossing is interpolated.
const FINE_BRACKET: f64 = 1.2;

/// Interior overlaps of each grid of the scale search (two states each: one call of the law).
const GRID: usize = 7;

/// `w[i]` = F·δ at overlap `ds[i]` (the larger magnitude over δ̇ = 0 and `v0`), all in one call
/// of the law; a failure names the first overlap where the law fails.
fn works<C: ContactForce>(law: &C, v0: f64, ds: &[f64], w: &mut [f64]) -> Result<(), CollideError> {
    let n = ds.len();
    let (mut d, mut r, mut f) = ([0.0; 2 * GRID], [0.0; 2 * GRID], [0.0; 2 * GRID]);
    for (i, &x) in ds.iter().enumerate() {
        (d[2 * i], r[2 * i]) = (x, 0.0);
        (d[2 * i + 1], r[2 * i + 1]) = (x, v0);
    }
    if law
        .force_batch(&d[..2 * n], &r[..2 * n], &mut f[..2 * n])
        .is_err()
    {
        // one overlap at a time, to name the one where the law fails
        for (i, &x) in ds.iter().enumerate() {
            for (j, rate) in [0.0, v0].into_iter().enumerate() {
                f[2 * i + j] = law.force(x, rate).map_err(|e| CollideError::Probe {
                    delta: x,
                    v0,
                    source: e,
                })?;
            }
        }
    }
    for (i, (w, &x)) in w.iter_mut().zip(ds).enumerate() {
        *w = f[2 * i].abs().max(f[2 * i + 1].abs()) * x;
    }
    Ok(())
}

/// The smallest overlap the scale search asks a law about (m): far below any physical overlap
/// (10⁻⁴⁰ m), so that even the gentlest collision's scale lies above it.
pub const PROBE_START: f64 = 1e-40;

/// The largest overlap the scale search asks a law about (m): a law still too weak to stop the
/// particles there never will.
pub const PROBE_LIMIT: f64 = 1.0;

/// What a rebound that never ends suggests.
macro_rules! overdamped_hint {
    () => {
        "; the overlap creeps back towards 0 without reaching it: the law may be overdamped (the \
         particles come to rest before they separate). With --end force the contact ends when \
         the force returns to 0"
    };
}

/// A formulation of the collision as a first-order system y' = f(x, y) with f from the force:
/// what a step needs besides the law, so that the collisions of a restitution curve can take
/// their steps together ([`crate::collide::lanes`]). Each method is the arithmetic of
/// `Phase`'s right-hand sides, which use them, so both give the same bits.
#[derive(Debug, Clone, Copy)]
pub enum Formulation {
    /// Phases 1 and 3: u = δ^{1/4} (m^{1/4}) is the independent variable, the state is (v, t)
    /// (m/s, s); the speed must keep the sign `sign` and stay above `vmin` (m/s) in magnitude.
    U {
        /// 1 / the effective mass (1/kg).
        inv_m: f64,
        /// The sign the speed keeps.
        sign: f64,
        /// The smallest speed magnitude (m/s).
        vmin: f64,
    },
    /// Phase 2: time (s) is the independent variable, the state is (δ, v) (m, m/s).
    T {
        /// 1 / the effective mass (1/kg).
        inv_m: f64,
    },
}

impl Formulation {
    /// The contact state (δ m, δ̇ m/s) at point `(x, y)`, or [`RhsError::OutOfDomain`].
    #[inline]
    pub fn state(&self, x: f64, y: &[f64; 2]) -> Result<(f64, f64), RhsError> {
        match *self {
            Formulation::U { sign, vmin, .. } => {
                let v = y[0];
                if sign * v <= vmin || !v.is_finite() {
                    return Err(RhsError::OutOfDomain);
                }
                let u = x.max(0.0);
                let u2 = u * u;
                Ok((u2 * u2, v))
            }
            Formulation::T { .. } => Ok((y[0], y[1])),
        }
    }

    /// f(x, y) at a point of a batch, from the force `f` (N) at its [`state`](Self::state)
    /// with rate `v` (m/s).
    #[inline]
    pub fn rhs_of(&self, x: f64, v: f64, f: f64) -> [f64; 2] {
        match *self {
            Formulation::U { inv_m, .. } => {
                let u = x.max(0.0);
                let q = 4.0 * u * u * u / v;
                [-q * f * inv_m, q]
            }
            Formulation::T { inv_m } => [v, -f * inv_m],
        }
    }

    /// f(x, y) at a single point (the first and last of a step), from the force `f` (N) at its
    /// [`state`](Self::state) with rate `v` (m/s).
    #[inline]
    pub fn rhs_of_one(&self, x: f64, v: f64, f: f64) -> [f64; 2] {
        match *self {
            Formulation::U { inv_m, .. } => {
                let u = x.max(0.0);
                let u2 = u * u;
                let a = -f * inv_m;
                let q = 4.0 * u2 * u / v;
                [q * a, q]
            }
            Formulation::T { inv_m } => [v, -f * inv_m],
        }
    }
}

/// An extrapolation step to take: `k` columns, size `h` (either sign, in the formulation's
/// independent variable) from `(x, y)` with `f0 = f(x, y)`, of formulation `form`.
#[derive(Debug, Clone, Copy)]
pub struct StepAsk {
    /// The formulation.
    pub form: Formulation,
    /// The independent variable at the step's start (m^{1/4} or s).
    pub x: f64,
    /// The state there.
    pub y: [f64; 2],
    /// f(x, y).
    pub f0: [f64; 2],
    /// The step size.
    pub h: f64,
    /// The extrapolation's columns.
    pub k: usize,
}

/// A formulation with its law: the system a phase integrates, counting force evaluations.
pub(crate) struct Phase<'a, C> {
    pub(crate) law: &'a C,
    pub(crate) form: Formulation,
    pub(crate) evals: usize,
}

impl<'a, C> Phase<'a, C> {
    /// Phases 1 and 3 (in u).
    pub(crate) fn u(law: &'a C, inv_m: f64, sign: f64, vmin: f64) -> Self {
        let form = Formulation::U { inv_m, sign, vmin };
        Phase { law, form, evals: 0 }
    }

    /// Phase 2 (in time).
    pub(crate) fn t(law: &'a C, inv_m: f64) -> Self {
        let form = Formulation::T { inv_m };
        Phase { law, form, evals: 0 }
    }
}

impl<C: ContactForce> System<2> for Phase<'_, C> {
    #[inline]
    fn rhs(&mut self, x: f64, y: &[f64; 2]) -> Result<[f64; 2], RhsError> {
        let (d, v) = self.form.state(x, y)?;
        self.evals += 1;
        let f = self.law.force(d, v)?;
        Ok(self.form.rhs_of_one(x, v, f))
    }

    #[inline]
    fn rhs_many(&mut self, x: &[f64], y: &[[f64; 2]], out: &mut [[f64; 2]]) -> Result<(), RhsError> {
        let n = x.len();
        let (mut d, mut v, mut f) = ([0.0; MAX_BATCH], [0.0; MAX_BATCH], [0.0; MAX_BATCH]);
        for i in 0..n {
            (d[i], v[i]) = self.form.state(x[i], &y[i])?;
        }
        self.evals += n;
        self.law.force_batch(&d[..n], &v[..n], &mut f[..n])?;
        for i in 0..n {
            out[i] = self.form.rhs_of(x[i], v[i], f[i]);
        }
        Ok(())
    }

    #[inline]
    fn lockstep_step(
        &mut self,
        x: f64,
        y: &[f64; 2],
        f0: &[f64; 2],
        h: f64,
        k: usize,
    ) -> Option<Result<Step<2>, RhsError>> {
        let ask = StepAsk {
            form: self.form,
            x,
            y: *y,
            f0: *f0,
            h,
            k,
        };
        let (r, evals) = self.law.lockstep_step(&ask)?;
        self.evals += evals;
        Some(r)
    }
}

/// The most states evaluated together (the extrapolation method's columns).
const MAX_BATCH: usize = 10;

/// Locates δ̇ = 0 inside the accepted step `s` of length `h` from `(t, z)`: a cubic Hermite
/// guess, then Newton's method on fresh steps (the derivative of δ̇ is the acceleration, which
/// every trial step returns), with a regula-falsi fallback.
pub(crate) fn locate_speed_zero<S: System<2>>(
    opt: &Options,
    sys: &mut S,
    t: f64,
    z: &[f64; 2],
    kz: &[f64; 2],
    h: f64,
    s: &Step<2>,
) -> Result<(f64, [f64; 2]), RhsError> {
    let (v0, a0, v1, a1) = (z[1], kz[1], s.y[1], s.f[1]);
    if v1 == 0.0 {
        return Ok((h, s.y));
    }
    // cubic Hermite of v on [0, 1] (in units of h), root by bisection
    let herm = |x: f64| {
        let (x2, x3) = (x * x, x * x * x);
        (2.0 * x3 - 3.0 * x2 + 1.0) * v0
            + (x3 - 2.0 * x2 + x) * h * a0
            + (-2.0 * x3 + 3.0 * x2) * v1
            + (x3 - x2) * h * a1
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if herm(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let m = opt.method;
    let mut sv = 0.5 * (lo + hi) * h;
    for _ in 0..8 {
        let st = m.step(sys, t, z, kz, sv)?;
        let (v, a) = (st.y[1], st.f[1]);
        if v == 0.0 || a == 0.0 {
            return Ok((sv, st.y));
        }
        let next = sv - v / a;
        if !(next > 0.0 && next <= h) {
            break;
        }
        // Newton converges quadratically: `next` misses the zero by about (next − sv)²/T on the
        // contact's time scale T > h, and δ at `next` follows from the state at `sv` to third
        // order (δ̇ ≈ 0 there). Once that miss is below a tenth of the tolerance (of h), no
        // further step is needed: usually the first step from the Hermite guess.
        let c = (next - sv) / h;
        if c * c <= 0.1 * opt.rtol {
            let dt = next - sv;
            return Ok((next, [st.y[0] + v * dt + 0.5 * a * dt * dt, 0.0]));
        }
        sv = next;
    }
    locate::<_, RhsError, _>(0.0, v0, h, v1, |sv| {
        let st = m.step(sys, t, z, kz, sv)?;
        Ok((st.y[1], st.y))
    })
}

/// The head-on collision of `pair` at normal impact speed `v0` (m/s) under contact law `law` of
/// `reg` with `params`, both bodies of Poisson's ratio 0.3 (which only a shear modulus depends
/// on): what the reports and the tests run.
pub fn collide_named(
    reg: &crate::registry::Registry,
    law: &str,
    params: &[dashpot_sdk::ParamValue],
    pair: &dashpot_sdk::Pair,
    v0: f64,
    end: EndCriterion,
    opt: &Options,
) -> Result<Collision, CollideError> {
    let b = PairLaw::bind(&reg.contact(law, params)?, pair, 0.3)?;
    collide(&b, pair.mass, v0, end, opt)
}

/// Integrates one collision. `mass` is the effective mass (kg), `v0` the normal impact speed (m/s).
pub fn collide<C: ContactForce>(
    law: &C,
    mass: f64,
    v0: f64,
    end: EndCriterion,
    opt: &Options,
) -> Result<Collision, CollideError> {
    if !(v0.is_finite() && v0 > 0.0) {
        return Err(CollideError::BadSpeed(v0));
    }
    if !(mass.is_finite() && mass > 0.0) {
        return Err(CollideError::BadMass(mass));
    }
    let opt = &Options {
        method: opt.method.resolve(opt.rtol),
        ..*opt
    };
    law.reset();
    let dstar = overlap_scale(law, mass, v0)?;
    if super::adhesive::is_adhesive(law, dstar)? {
        return super::adhesive::collide_adhesive(law, mass, v0, dstar, opt);
    }
    let tstar = dstar / v0;
    let inv_m = 1.0 / mass;
    let rtol = opt.rtol;
    let mut traj = Vec::new();
    let mut steps = 0usize;
    let mut evals = 0usize;
    let record = |traj: &mut Vec<Sample>, t: f64, d: f64, v: f64| -> Result<(), LawError> {
        if opt.record {
            traj.push(Sample {
                t,
                delta: d,
                rate: v,
                force: law.force(d, v)?,
            });
        }
        Ok(())
    };
    let no_return = no_return(tstar);

    // ---- phase 1: compression start, u from 0 while v > v0/2 ----
    let mut ph = Phase::u(law, inv_m, 1.0, 0.05 * v0);
    let tol_u = Tolerance {
        rtol,
        atol: [1e-3 * rtol * v0, 1e-300],
    };
    let (mut u, mut y) = (0.0f64, [v0, 0.0f64]);
    let mut k = ph.rhs(u, &y)?;
    let mut h = opt.h0_fraction * dstar.powf(0.25);
    record(&mut traj, 0.0, 0.0, v0)?;
    let mut n = 0;
    while y[0] > 0.9 * v0 {
        // do not aim far past the switch: near δ̇ = 0 this formulation is singular
        if k[0] < 0.0 {
            h = h.min(1.5 * (y[0] - 0.4 * v0) / -k[0]).max(0.0);
        }
        n += 1;
        if n > opt.max_steps {
            return Err(no_return(
                y[1],
                u.powi(4),
                y[0],
                steps,
                "too many steps in the compression phase",
            ));
        }
        let Some(s) = in_domain(opt.method.step(&mut ph, u, &y, &k, h))? else {
            h *= 0.25;
            continue;
        };
        let e = tol_u.norm(&y, &s.y, &s.err);
        if e <= 1.0 {
            u += h;
            y = s.y;
            k = s.f;
            steps += 1;
            law.commit(u.powi(4), y[0])?;
            record(&mut traj, y[1], u.powi(4), y[0])?;
        }
        h *= opt.method.factor(e);
    }
    evals += ph.evals;

    // ---- phase 2: around maximum compression, in time ----
    let mut tp = Phase::t(law, inv_m);
    let tol_t = Tolerance {
        rtol,
        atol: [1e-3 * rtol * dstar, 1e-3 * rtol * v0],
    };
    let mut t = y[1];
    let mut z = [u.powi(4), y[0]];
    let mut kz = tp.rhs(t, &z)?;
    let hmax = opt.max_step_fraction * tstar;
    let mut h = (opt.h0_fraction * tstar).min(hmax);
    let t_limit = opt.max_time_factor * tstar;
    let mut max_overlap: Option<(f64, f64)> = None;
    let mut force_end: Option<(f64, f64, f64)> = None; // (t, δ, v)
                                                       // In this phase the force at a step's ends is −m times the acceleration the stepper already
                                                       // evaluated there: the force-criterion event needs no extra law calls.
    let mut f_now = -mass * kz[1];
    // "The force returns to 0" is located as the force falling through this tiny threshold
    // (1e-13 of the force scale m v0²/δ*): a law that clamps its force to exactly 0 (plastic
    // unloading) then has a unique first crossing, and the located state is not one reached by
    // a step across the clamp's kink. It shifts the end by 1e-13 of the contact's scale.
    let f_eps = 1e-13 * mass * v0 * v0 / dstar;
    let mut force_zero_passed = false;
    let mut n = 0;
    loop {
        if max_overlap.is_some_and(|(_, dm)| z[1] < 0.0 && z[0] <= 0.5 * dm) {
            break;
        }
        n += 1;
        let why = ["too many steps around maximum compression", "contact time limit"];
        if let Some(why) = overrun(n, opt.max_steps, t, t_limit, why) {
            return Err(no_return(t, z[0], z[1], steps, why));
        }
        h = h.min(hmax);
        let s = opt.method.step(&mut tp, t, &z, &kz, h)?;
        let e = tol_t.norm(&z, &s.y, &s.err);
        if e > 1.0 {
            h *= opt.method.factor(e);
            continue;
        }
        // A step that ends out of contact (δ ≤ 0) jumped over the rest of this phase and the
        // whole rebound phase, where the law is not smooth in time: its error estimate does not
        // see that, and at a loose tolerance such a step passed it (a linear spring-dashpot at
        // rtol 1e-7 came out 2 % off). Shorter, until the step ends in contact.
        if s.y[0] <= 0.0 {
            h *= 0.5;
            continue;
        }
        // accepted: events inside [t, t + h]
        let mut s_from = 0.0;
        if max_overlap.is_none() && s.y[1] <= 0.0 {
            let (sm, zm) = locate_speed_zero(opt, &mut tp, t, &z, &kz, h, &s)?;
            max_overlap = Some((t + sm, zm[0]));
            record(&mut traj, t + sm, zm[0], 0.0)?;
            if law.has_history() {
                // a law with memory changes branch at the maximum (loading → unloading):
                // restart there with the history of the maximum, instead of stepping across
                t += sm;
                z = [zm[0], 0.0];
                law.commit(z[0], 0.0)?;
                kz = tp.rhs(t, &z)?;
                f_now = -mass * kz[1];
                steps += 1;
                continue;
            }
            s_from = sm;
        }
        let f_new = -mass * s.f[1];
        // The force returns to 0 on rebound: the end of contact under the force criterion; for
        // a law with memory (plastic unloading to a residual overlap, where the force is
        // clamped to 0: a kink the step-size control does not see) a point to restart from.
        let force_zero = max_overlap.is_some() && s.y[1] < 0.0 && f_new <= 0.0;
        let restart_at_zero = law.has_history() && !force_zero_passed && f_now > 0.0;
        if force_zero && (end == EndCriterion::Force || restart_at_zero) {
            let f_from = if s_from > 0.0 {
                let st = opt.method.step(&mut tp, t, &z, &kz, s_from)?;
                law.force(st.y[0], st.y[1])?
            } else {
                f_now
            };
            let (t0, z0, k0) = (t, z, kz);
            let (sf, zf) = locate::<_, RhsError, _>(s_from, f_from - f_eps, h, f_new - f_eps, |sv| {
                let st = opt.method.step(&mut tp, t0, &z0, &k0, sv)?;
                Ok((law.force(st.y[0], st.y[1])? - f_eps, st.y))
            })?;
            record(&mut traj, t + sf, zf[0], zf[1])?;
            steps += 1;
            if end == EndCriterion::Force {
                force_end = Some((t + sf, zf[0], zf[1]));
                break;
            }
            force_zero_passed = true;
            t += sf;
            z = zf;
            law.commit(z[0], z[1])?;
            kz = tp.rhs(t, &z)?;
            f_now = -mass * kz[1];
            continue;
        }
        t += h;
        z = s.y;
        kz = s.f;
        f_now = f_new;
        steps += 1;
        law.commit(z[0], z[1])?;
        record(&mut traj, t, z[0], z[1])?;
        h *= opt.method.factor(e);
    }
    evals += tp.evals;
    let (max_overlap_time, max_overlap) = max_overlap.unwrap_or((t, z[0]));

    // the collision that ended at time `t_end` (s) with rate `v_end` (m/s)
    let collision = |v_end: f64, t_end: f64, steps, force_evals, trajectory| Collision {
        v0,
        restitution: -v_end / v0,
        contact_time: t_end,
        max_overlap,
        max_overlap_time,
        end,
        steps,
        force_evals,
        stuck: false,
        tensile_peak: None,
        trajectory,
    };
    if let Some((tf, _df, vf)) = force_end {
        return Ok(collision(vf, tf, steps, evals, traj));
    }

    // ---- phase 3: rebound end, u from (δ)^{1/4} down to 0 ----
    let mut ph = Phase::u(law, inv_m, -1.0, 1e-9 * v0);
    if !(z[0] > 0.0 && z[1] < 0.0) {
        // phase 2 keeps every state it accepts in contact and rebounding; never report the
        // speed of a state that is not (the rebound phase would be skipped)
        return Err(no_return(
            t,
            z[0],
            z[1],
            steps,
            "the rebound phase would start out of contact",
        ));
    }
    let mut u = z[0].powf(0.25);
    let mut y = [z[1], t];
    let mut k = ph.rhs(u, &y)?;
    let mut h = -2.0 * opt.h0_fraction * u;
    let mut f_now = -mass * kz[1];
    let mut n = 0;
    while u > 0.0 {
        n += 1;
        let why = [
            concat!("too many steps in the rebound phase", overdamped_hint!()),
            concat!("contact time limit in the rebound phase", overdamped_hint!()),
        ];
        if let Some(why) = overrun(n, opt.max_steps, y[1], t_limit, why) {
            return Err(no_return(y[1], u.powi(4), y[0], steps, why));
        }
        let last = u + h <= 0.0;
        let hh = if last { -u } else { h };
        let Some(s) = in_domain(opt.method.step(&mut ph, u, &y, &k, hh))? else {
            h *= 0.25;
            continue;
        };
        let e = tol_u.norm(&y, &s.y, &s.err);
        if e > 1.0 {
            h = hh * opt.method.factor(e);
            continue;
        }
        let un = if last { 0.0 } else { u + hh };
        if end == EndCriterion::Force {
            let f_new = law.force(un.powi(4), s.y[0])?;
            evals += 1;
            if f_new <= 0.0 && f_now > 0.0 {
                let (u0, y0, k0) = (u, y, k);
                let (sf, yf) = locate::<_, RhsError, _>(0.0, f_now - f_eps, hh, f_new - f_eps, |sv| {
                    let st = opt.method.step(&mut ph, u0, &y0, &k0, sv)?;
                    Ok((law.force((u0 + sv).max(0.0).powi(4), st.y[0])? - f_eps, st.y))
                })?;
                u += sf;
                y = yf;
                steps += 1;
                record(&mut traj, y[1], u.max(0.0).powi(4), y[0])?;
                break;
            }
            f_now = f_new;
        }
        u = un;
        y = s.y;
        k = s.f;
        steps += 1;
        law.commit(u.powi(4), y[0])?;
        record(&mut traj, y[1], u.powi(4), y[0])?;
        if !last {
            h = hh * opt.method.factor(e);
        }
    }
    evals += ph.evals;
    Ok(collision(y[0], y[1], steps, evals, traj))
}
