//! `dashpot collide --rolling NAME`: a sphere launched rolling without slip on a wall, stopped by
//! a rolling-resistance law.

use super::args::UsageError;
use super::collide::{split_sets, CollideArgs};
use crate::collide::rolling::{roll, RollingSpec};
use crate::output::{write_atomic, Provenance};
use crate::registry::Registry;
use anyhow::{Context, Result};
use dashpot_sdk::Pair;
use serde_json::json;

/// Time steps per period of the normal contact's oscillation about rest.
const STEPS_PER_PERIOD: usize = 50;

/// Runs the rolling sphere of `a` at launch speed `v0` (m/s).
pub fn run_rolling(reg: &Registry, a: &CollideArgs, v0: f64) -> Result<()> {
    let rolling = a.rolling.as_deref().unwrap_or_default();
    let Some(tangential) = a.tangential.as_deref() else {
        return Err(UsageError(format!(
            "--rolling {rolling} needs --tangential NAME: without friction at the contact the sphere \
             slides instead of rolling (e.g. --tangential mindlin)"
        ))
        .into());
    };
    if a.angle != 0.0 || a.spin != 0.0 {
        return Err(UsageError(
            "--rolling launches the sphere rolling along the wall: --angle and --spin do not apply".into(),
        )
        .into());
    }
    if !(a.gravity.is_finite() && a.gravity > 0.0) {
        anyhow::bail!(
            "--gravity = {} m/s^2 is out of range: it must be finite and > 0",
            a.gravity
        );
    }
    let normal = match &a.law.law {
        Some(n) => n.clone(),
        None => a.law.resolve()?.name,
    };
    let (nsets, tparams) = split_sets(reg, &normal, Some(tangential), &a.law.set)?;
    let mut la = a.law.clone();
    la.set = nsets;
    la.particle.wall = true;
    let sel = la.resolve()?;
    let rsets = crate::config::parse_sets(&a.rset).map_err(|e| UsageError(e.to_string()))?;
    let rparams = crate::config::merge_params(&Default::default(), &rsets);
    let p = sel.particle;
    let mats = Pair::wall(&p)?.materials(p.poisson)?;
    let nlaw = reg.contact(&sel.name, &sel.params)?.bind(&mats)?;
    let tlaw = reg.tangential(tangential, &tparams)?.bind(&mats)?;
    let rlaw = reg.rolling(rolling, &rparams)?.bind(&mats)?;
    let (m, r) = (p.mass(), p.radius());
    let spec = RollingSpec {
        mass: m,
        radius: r,
        inertia: 0.4 * m * r * r,
        v0,
        gravity: a.gravity,
        steps: STEPS_PER_PERIOD,
    };
    let every = if a.trajectory.is_some() { 100 } else { 0 };
    let s = roll(&nlaw, &tlaw, &rlaw, &spec, every)
        .with_context(|| format!("sphere rolling at {v0} m/s against '{rolling}'"))?;
    let provs = [
        Provenance::of(reg, &sel.name, &sel.params)?,
        Provenance::of(reg, tangential, &tparams)?,
        Provenance::of(reg, rolling, &rparams)?,
    ];
    if let Some(path) = &a.trajectory {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(["t_s", "x_m", "v_m_per_s", "omega_rad_per_s"])?;
        for q in &s.samples {
            w.write_record(q.iter().map(|v| v.to_string()))?;
        }
        let body = w.into_inner().context("csv")?;
        let head: String = provs.iter().map(|p| p.csv_comment()).collect();
        write_atomic(path, &[head.into_bytes(), body].concat())?;
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "tangential": tangential, "rolling": rolling,
                "v0": v0, "gravity": a.gravity, "mass": m, "radius": r,
                "stop_time": s.stop_time, "stop_distance": s.stop_distance,
                "deceleration": s.deceleration, "rest_overlap": s.rest_overlap,
                "max_slip": s.max_slip, "dt": s.dt, "steps": s.steps,
                "provenance": provs.iter().map(|p| p.json()).collect::<Vec<_>>(),
            }))?
        );
    } else {
        provs.iter().flat_map(|p| p.lines()).for_each(|l| println!("{l}"));
        println!(
            "sphere: m = {m:.6e} kg, r = {r:.6e} m, I = (2/5) m r², on a wall, g = {} m/s²",
            a.gravity
        );
        println!(
            "launched rolling at v0 = {v0} m/s; resting overlap {:.6e} m",
            s.rest_overlap
        );
        println!(
            "stopped after         t = {:.8e} s, x = {:.8e} m",
            s.stop_time, s.stop_distance
        );
        println!("mean deceleration     = {:.8e} m/s²", s.deceleration);
        println!(
            "largest slip speed    = {:.3e} m/s (rolling without slip: ≪ v0)",
            s.max_slip
        );
        println!("steps                 = {} of {:.3e} s", s.steps, s.dt);
    }
    Ok(())
}
