//! Head-on impacts under an adhesive normal law (sdk 0.3: JKR, DMT): the force may be tensile,
//! and a contact lasts beyond touching until the law's reach ends it (δ < −reach).
//!
//! The three-phase scheme of [`super::two_body`] assumes the force vanishes at δ = 0, where its
//! clock u = δ^{1/4} starts and ends. An adhesive contact does not end there: it is pulled in at
//! touch, may stop and turn back while still in contact (it *sticks*), or rebounds through
//! δ = 0 and breaks at the pull-off separation. So it is integrated in time, with the same
//! embedded one-step method and step-size control, and two events located on fresh steps:
//! - the **end of contact**, the first state with δ < −reach (the reach of the committed
//!   history: for JKR the rupture separation |δ_c| once the contact has formed, 0 for DMT),
//!   where the exit speed gives the restitution;
//! - **sticking**, the rebound velocity turning back towards compression while the contact
//!   still acts: the particle lacks the energy to reach the pull-off separation, and no later
//!   motion can give it back (the law is elastic or dissipative), so it stays attached
//!   (restitution 0).
//!
//! A contact that ends at touch (reach 0) while tensile there, as DMT's (−2π w R at δ = 0⁺, 0
//! for δ < 0), has a force that jumps at δ = 0, and a law that is not smooth in time there
//! (δ^{3/2}, δ^{1/4} δ̇): a step across the jump, or through the start or end of contact in
//! time, loses the method's order. So, as [`super::two_body`] does, its start (while the speed
//! stays above 0.9 of its largest) and its end (from half the maximum overlap) are integrated in
//! u = δ^{1/4}, the end at u = 0 exactly: no step crosses the jump, and the restitution has the
//! accuracy asked. A rebound that slows below [`STICK`] of its speed at the switch may stick;
//! it is carried on in time from there, as every other adhesive contact.

use super::outcome::{in_domain, no_return, overrun};
use super::outcome::{CollideError, Collision, Options};
use super::rk::{locate, RhsError, System, Tolerance};
use super::two_body::{locate_speed_zero, Phase};
use super::{ContactForce, Sample};
use dashpot_sdk::EndCriterion;

/// Whether `law` is adhesive: tensile at rest just past touching (at 10⁻⁶ of the overlap scale
/// `dstar`, m), as JKR (−(8/9) of its pull-off force) and DMT (−2π w R) are. Leaves the
/// history reset.
pub(crate) fn is_adhesive<C: ContactForce>(law: &C, dstar: f64) -> Result<bool, CollideError> {
    law.reset();
    let f = law.force(1e-6 * dstar, 0.0)?;
    law.reset();
    Ok(f < 0.0)
}

/// One head-on impact at `v0` (m/s, > 0) of effective mass `mass` (kg) under an adhesive law,
/// `dstar` its overlap scale ([`super::two_body::overlap_scale`]): the contact lasts until δ < −reach or the
/// particles stick. [`super::collide`] comes here for every adhesive law. The result's
/// `restitution` is the exit speed over `v0` (0 when stuck), its `contact_time` the time of the
/// end of contact (or, when stuck, of the turn back that decides it), `tensile_peak` the most
/// tensile force met at an accepted state (N, negative).
pub(crate) fn collide_adhesive<C: ContactForce>(
    law: &C,
    mass: f64,
    v0: f64,
    dstar: f64,
    opt: &Options,
) -> Result<Collision, CollideError> {
    law.reset();
    // the adhesive scales: the force at touch and the reach of a formed contact set a time
    // √(m reach / |F|) that a slow impact can be much shorter than δ*/v0
    let f_touch = law.force(1e-6 * dstar, 0.0)?;
    law.commit(1e-6 * dstar, 0.0)?;
    let reach_formed = law.reach(1e-6 * dstar, 0.0)?;
    law.reset();
    let mut tstar = dstar / v0;
    let mut xscale = dstar;
    if f_touch < 0.0 && reach_formed > 0.0 {
        tstar = tstar.min((mass * reach_formed / -f_touch).sqrt());
        xscale = xscale.max(reach_formed);
    }
    // tensile at touch (an adhesive law) and no reach: the force jumps at δ = 0
    let ends_at_touch = f_touch < 0.0 && reach_formed == 0.0;
    let inv_m = 1.0 / mass;
    let no_return = no_return(tstar);
    let mut tp = Phase::t(law, inv_m);
    let tol = Tolerance {
        rtol: opt.rtol,
        atol: [1e-3 * opt.rtol * xscale, 1e-3 * opt.rtol * v0],
    };
    let hmax = opt.max_step_fraction * tstar;
    let t_limit = opt.max_time_factor * (dstar / v0).max(tstar);
    let mut h = (opt.h0_fraction * tstar).min(hmax);
    let mut run = Run {
        law,
        inv_m,
        v0,
        opt,
        t_limit,
        no_return: &no_return,
        steps: 0,
        evals: 0,
        traj: Vec::new(),
        tensile_peak: f64::INFINITY,
    };
    let (mut t, mut z) = (0.0f64, [0.0f64, v0]);
    let mut kz;
    if ends_at_touch {
        run.record(0.0, 0.0, v0, law.force(0.0, v0)?);
        (t, z) = start_in_u(&mut run, xscale)?;
        kz = tp.rhs(t, &z)?;
    } else {
        kz = tp.rhs(t, &z)?;
        law.commit(z[0], z[1])?;
        run.record(0.0, 0.0, v0, -mass * kz[1]);
    }
    // once a rebound in u slowed down (it may stick), the contact ends in time
    let mut end_in_time = !ends_at_touch;
    let mut max_overlap: Option<(f64, f64)> = None;
    let mut n = 0usize;
    let (stuck, t_end, v_end) = loop {
        n += 1;
        let why = [
            "too many steps in an adhesive contact",
            "contact time limit of an adhesive contact",
        ];
        if let Some(why) = overrun(n, opt.max_steps, t, t_limit, why) {
            return Err(no_return(t, z[0], z[1], run.steps, why));
        }
        h = h.min(hmax);
        let reach = law.reach(z[0], z[1])?;
        if !end_in_time && reach == 0.0 && max_overlap.is_some_and(|(_, dm)| z[1] < 0.0 && z[0] <= 0.5 * dm) {
            match end_in_u(&mut run, t, z)? {
                End::Touch { t, v } => break (false, t, v),
                End::Slowed { t: ts, z: zs } => {
                    (t, z) = (ts, zs);
                    kz = tp.rhs(t, &z)?;
                    end_in_time = true;
                    continue;
                }
            }
        }
        let Some(s) = in_domain(opt.method.step(&mut tp, t, &z, &kz, h))? else {
            h *= 0.25;
            continue;
        };
        if !end_in_time && max_overlap.is_some() && s.y[0] < -reach {
            // the end comes in u: shorter, until the step ends in contact
            h *= 0.5;
            continue;
        }
        // the end of contact inside the step: located on fresh steps from (t, z), each of
        // which stays on the acting side but the last bracket
        if max_overlap.is_some() && s.y[0] < -reach {
            let (t0, z0, k0) = (t, z, kz);
            let (se, ze) = locate::<_, RhsError, _>(0.0, z[0] + reach, h, s.y[0] + reach, |sv| {
                let st = opt.method.step(&mut tp, t0, &z0, &k0, sv)?;
                Ok((st.y[0] + reach, st.y))
            })?;
            run.steps += 1;
            let f = law.force(ze[0], ze[1])?;
            run.record(t + se, ze[0], ze[1], f);
            break (false, t + se, ze[1]);
        }
        let e = tol.norm(&z, &s.y, &s.err);
        if e > 1.0 {
            h *= opt.method.factor(e);
            continue;
        }
        if max_overlap.is_none() && s.y[1] <= 0.0 {
            let (sm, zm) = locate_speed_zero(opt, &mut tp, t, &z, &kz, h, &s)?;
            max_overlap = Some((t + sm, zm[0]));
            // restart at the maximum (a law with memory changes branch there)
            t += sm;
            z = [zm[0], 0.0];
            law.commit(z[0], 0.0)?;
            kz = tp.rhs(t, &z)?;
            run.steps += 1;
            run.record(t, z[0], 0.0, -mass * kz[1]);
            continue;
        }
        if max_overlap.is_some() && s.y[1] > 0.0 {
            // turned back towards compression while the contact acts: stuck
            let (sm, zm) = locate_speed_zero(opt, &mut tp, t, &z, &kz, h, &s)?;
            run.steps += 1;
            let f = law.force(zm[0], 0.0)?;
            run.record(t + sm, zm[0], 0.0, f);
            break (true, t + sm, 0.0);
        }
        t += h;
        z = s.y;
        kz = s.f;
        run.steps += 1;
        law.commit(z[0], z[1])?;
        run.record(t, z[0], z[1], -mass * kz[1]);
        h *= opt.method.factor(e);
    };
    let (max_overlap_time, max_overlap) = max_overlap.unwrap_or((t, z[0]));
    Ok(Collision {
        v0,
        restitution: if stuck { 0.0 } else { -v_end / v0 },
        contact_time: t_end,
        max_overlap,
        max_overlap_time,
        end: EndCriterion::Overlap,
        steps: run.steps,
        force_evals: tp.evals + run.evals,
        stuck,
        tensile_peak: (run.tensile_peak < 0.0).then_some(run.tensile_peak),
        trajectory: run.traj,
    })
}

/// A rebound in u that slows below this fraction of its speed at the switch may stick (turn
/// back before touch, where u's clock stops): it is carried on in time.
pub(crate) const STICK: f64 = 1e-6;

/// What an adhesive impact's phases share: the law and its inputs, the counts, the trajectory
/// and the most tensile force met at an accepted state (N).
struct Run<'a, C, R> {
    law: &'a C,
    inv_m: f64,
    v0: f64,
    opt: &'a Options,
    t_limit: f64,
    no_return: &'a R,
    steps: usize,
    evals: usize,
    traj: Vec<Sample>,
    tensile_peak: f64,
}

impl<C, R> Run<'_, C, R> {
    /// An accepted state at time `t` (s), overlap `d` (m), rate `v` (m/s) with force `f` (N).
    fn record(&mut self, t: f64, d: f64, v: f64, f: f64) {
        self.tensile_peak = self.tensile_peak.min(f);
        if self.opt.record {
            self.traj.push(Sample {
                t,
                delta: d,
                rate: v,
                force: f,
            });
        }
    }
}

impl<C: ContactForce, R: Fn(f64, f64, f64, usize, &'static str) -> CollideError> Run<'_, C, R> {
    /// Whether step `n` of a phase in u, at u (m^{1/4}) and y = (δ̇ m/s, t s), may be taken:
    /// [`CollideError::NoReturn`] past the step or time limit, for the reasons `why`.
    fn may_step(&self, n: usize, u: f64, y: &[f64; 2], why: [&'static str; 2]) -> Result<(), CollideError> {
        match overrun(n, self.opt.max_steps, y[1], self.t_limit, why) {
            Some(why) => Err((self.no_return)(y[1], u.powi(4), y[0], self.steps, why)),
            None => Ok(()),
        }
    }

    /// An accepted state of a phase in u: committed to the law's history and recorded.
    fn accept_u(&mut self, u: f64, y: &[f64; 2]) -> Result<(), CollideError> {
        self.steps += 1;
        let d = u.powi(4);
        self.law.commit(d, y[0])?;
        let f = self.law.force(d, y[0])?;
        self.record(y[1], d, y[0], f);
        Ok(())
    }
}

/// The start of a contact that ends at touch, in u = δ^{1/4} (m^{1/4}) from 0 while the speed
/// stays above 0.9 of its largest so far (the adhesion speeds the particle up before the contact
/// slows it down); `xscale` (m) sets the first step. Returns the time (s) and the state (δ m,
/// δ̇ m/s) where the integration in time takes over.
fn start_in_u<C: ContactForce, R>(
    run: &mut Run<'_, C, R>,
    xscale: f64,
) -> Result<(f64, [f64; 2]), CollideError>
where
    R: Fn(f64, f64, f64, usize, &'static str) -> CollideError,
{
    let (law, opt, v0) = (run.law, run.opt, run.v0);
    let mut ph = Phase::u(law, run.inv_m, 1.0, 0.05 * v0);
    let tol = Tolerance {
        rtol: opt.rtol,
        atol: [1e-3 * opt.rtol * v0, 1e-300],
    };
    let (mut u, mut y) = (0.0f64, [v0, 0.0f64]);
    let mut k = ph.rhs(u, &y)?;
    law.commit(0.0, v0)?;
    let mut h = opt.h0_fraction * xscale.powf(0.25);
    let mut peak = v0;
    let mut n = 0;
    while y[0] > 0.9 * peak {
        // do not aim far past the switch: near δ̇ = 0 this formulation is singular
        if k[0] < 0.0 {
            h = h.min(1.5 * (y[0] - 0.4 * peak) / -k[0]).max(0.0);
        }
        n += 1;
        let why = [
            "too many steps at the start of an adhesive contact",
            "contact time limit at the start of an adhesive contact",
        ];
        run.may_step(n, u, &y, why)?;
        let Some(s) = in_domain(opt.method.step(&mut ph, u, &y, &k, h))? else {
            h *= 0.25;
            continue;
        };
        let e = tol.norm(&y, &s.y, &s.err);
        if e <= 1.0 {
            u += h;
            y = s.y;
            k = s.f;
            run.accept_u(u, &y)?;
            peak = peak.max(y[0]);
        }
        h *= opt.method.factor(e);
    }
    run.evals += ph.evals;
    Ok((y[1], [u.powi(4), y[0]]))
}

/// How the end of a contact in u went.
enum End {
    /// The overlap returned to 0 at time `t` (s) with rate `v` (m/s).
    Touch { t: f64, v: f64 },
    /// The rebound slowed below [`STICK`] of its speed at the switch, at time `t` (s) and state
    /// `z` (δ m, δ̇ m/s): the caller carries on in time.
    Slowed { t: f64, z: [f64; 2] },
}

/// The end of a contact that ends at touch, in u = δ^{1/4} from the rebounding state `z` (δ m,
/// δ̇ m/s) at time `t` (s) down to u = 0 exactly: the end of the interval, so no step crosses
/// the force's jump at δ = 0.
fn end_in_u<C: ContactForce, R>(run: &mut Run<'_, C, R>, t: f64, z: [f64; 2]) -> Result<End, CollideError>
where
    R: Fn(f64, f64, f64, usize, &'static str) -> CollideError,
{
    let (law, opt, v0) = (run.law, run.opt, run.v0);
    let mut ph = Phase::u(law, run.inv_m, -1.0, 1e-9 * v0);
    let tol = Tolerance {
        rtol: opt.rtol,
        atol: [1e-3 * opt.rtol * v0, 1e-300],
    };
    let mut u = z[0].powf(0.25);
    let mut y = [z[1], t];
    let mut k = ph.rhs(u, &y)?;
    let mut h = -2.0 * opt.h0_fraction * u;
    let slow = STICK * -z[1];
    let mut n = 0;
    let end = loop {
        if u <= 0.0 {
            break End::Touch { t: y[1], v: y[0] };
        }
        if -y[0] < slow || h.abs() <= 1e-9 * u {
            break End::Slowed {
                t: y[1],
                z: [u.powi(4), y[0]],
            };
        }
        n += 1;
        let why = [
            "too many steps at the end of an adhesive contact",
            "contact time limit at the end of an adhesive contact",
        ];
        run.may_step(n, u, &y, why)?;
        let last = u + h <= 0.0;
        let hh = if last { -u } else { h };
        let Some(s) = in_domain(opt.method.step(&mut ph, u, &y, &k, hh))? else {
            h *= 0.25;
            continue;
        };
        let e = tol.norm(&y, &s.y, &s.err);
        if e > 1.0 {
            h = hh * opt.method.factor(e);
            continue;
        }
        u = if last { 0.0 } else { u + hh };
        y = s.y;
        k = s.f;
        run.accept_u(u, &y)?;
        if !last {
            h = hh * opt.method.factor(e);
        }
    };
    run.evals += ph.evals;
    Ok(end)
}
