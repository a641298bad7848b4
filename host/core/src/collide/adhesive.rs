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

use super::outcome::{in_domain, no_return, overrun};
use super::outcome::{CollideError, Collision, Options};
use super::rk::{locate, RhsError, System, Tolerance};
use super::two_body::{locate_speed_zero, Phase};
use super::ContactForce;
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
    let (mut t, mut z) = (0.0f64, [0.0f64, v0]);
    let mut kz = tp.rhs(t, &z)?;
    law.commit(z[0], z[1])?;
    let mut traj = Vec::new();
    let mut tensile_peak = f64::INFINITY;
    let mut max_overlap: Option<(f64, f64)> = None;
    let mut steps = 0usize;
    let mut record = |t: f64, d: f64, v: f64, f: f64| {
        tensile_peak = tensile_peak.min(f);
        if opt.record {
            traj.push(super::Sample {
                t,
                delta: d,
                rate: v,
                force: f,
            });
        }
    };
    record(0.0, 0.0, v0, -mass * kz[1]);
    let mut n = 0usize;
    let (stuck, t_end, v_end) = loop {
        n += 1;
        let why = [
            "too many steps in an adhesive contact",
            "contact time limit of an adhesive contact",
        ];
        if let Some(why) = overrun(n, opt.max_steps, t, t_limit, why) {
            return Err(no_return(t, z[0], z[1], steps, why));
        }
        h = h.min(hmax);
        let reach = law.reach(z[0], z[1])?;
        let Some(s) = in_domain(opt.method.step(&mut tp, t, &z, &kz, h))? else {
            h *= 0.25;
            continue;
        };
        // the end of contact inside the step: located on fresh steps from (t, z), each of
        // which stays on the acting side but the last bracket
        if max_overlap.is_some() && s.y[0] < -reach {
            let (t0, z0, k0) = (t, z, kz);
            let (se, ze) = locate::<_, RhsError, _>(0.0, z[0] + reach, h, s.y[0] + reach, |sv| {
                let st = opt.method.step(&mut tp, t0, &z0, &k0, sv)?;
                Ok((st.y[0] + reach, st.y))
            })?;
            steps += 1;
            let f = law.force(ze[0], ze[1])?;
            record(t + se, ze[0], ze[1], f);
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
            steps += 1;
            record(t, z[0], 0.0, -mass * kz[1]);
            continue;
        }
        if max_overlap.is_some() && s.y[1] > 0.0 {
            // turned back towards compression while the contact acts: stuck
            let (sm, zm) = locate_speed_zero(opt, &mut tp, t, &z, &kz, h, &s)?;
            steps += 1;
            let f = law.force(zm[0], 0.0)?;
            record(t + sm, zm[0], 0.0, f);
            break (true, t + sm, 0.0);
        }
        t += h;
        z = s.y;
        kz = s.f;
        steps += 1;
        law.commit(z[0], z[1])?;
        record(t, z[0], z[1], -mass * kz[1]);
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
        steps,
        force_evals: tp.evals,
        stuck,
        tensile_peak: (tensile_peak < 0.0).then_some(tensile_peak),
        trajectory: traj,
    })
}
