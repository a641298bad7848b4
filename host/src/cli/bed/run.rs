//! `dashpot bed`: one run (or one per seed) on either engine, its printout and its JSON.

use super::*;
use crate::bed::engine::{Bed, BedConfig, BedReport};
use crate::bed::scaling::InRun;
use crate::bed::view::{progress_bar, snapshot_figure, SaveAs};
use crate::bed::{DynRestitution, Laws};
use crate::output::write_atomic;
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use dashpot_sdk::ParamValue;
use serde_json::json;
use std::path::Path;

/// `dashpot bed`.
pub fn bed(reg: &Registry, a: &BedArgs) -> Result<()> {
    if let Some(v) = run_bed(reg, a, &|_| {})? {
        println!("{}", serde_json::to_string_pretty(&v)?);
    }
    Ok(())
}

/// `dashpot bed` for a caller other than the CLI (the Python package): with `a.json` it returns
/// the document `--json` prints, else it prints the report and returns `None`. Every seed's run
/// calls `progress(t)` now and then with its simulated time (s); `progress` may unwind to
/// abandon the runs (nothing is written before they end).
pub fn run_bed(
    reg: &Registry,
    a: &BedArgs,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<serde_json::Value>> {
    a.phys.check()?;
    if a.phys.engine == EngineKind::Dem {
        return bed_dem(reg, a, progress);
    }
    let restitution = a.phys.restitution_name()?;
    let cfg = a.phys.config(a.layers, a.freq);
    cfg.validate()?;
    let laws = a.phys.laws(reg)?;
    // provenance, and the r(v) actually used when it comes from a contact law (issue 10)
    let law_name = restitution.strip_prefix(crate::bed::FROM_CONTACT);
    let prov = crate::output::Provenance::of(reg, law_name.unwrap_or(restitution), &a.phys.params()?)?;
    prov.warn_if_shadowed();
    let r_used = match law_name {
        Some(_) => Some(r_samples(&laws)?),
        None => None,
    };
    let k = a.seeds.seeds;
    if k == 0 {
        bail!("--seeds = 0 is out of range: give at least 1 seed");
    }
    let mut bed = Bed::new(
        cfg,
        Laws {
            disk: &laws.disk,
            wall: &laws.wall,
        },
    )?;
    if a.trace.is_some() {
        bed.enable_trace();
    }
    let total = (a.phys.transient + a.phys.cycles) / a.freq;
    let pb = progress_bar((total * 1000.0).ceil() as u64, "bed (ms simulated)");
    let context = || format!("bed n = {}, f = {} Hz, law {}", a.layers, a.freq, restitution);
    // the other seeds in parallel with the first (which draws the snapshot and the trace)
    let (first, others) = rayon::join(
        || {
            bed.run_protocol(a.phys.transient, a.phys.cycles, &mut |t| {
                pb.set_position((t * 1000.0) as u64);
                progress(t)
            })
        },
        || {
            use rayon::prelude::*;
            (1..k as u64)
                .into_par_iter()
                .map(|s| {
                    let cfg = BedConfig {
                        seed: cfg.seed.wrapping_add(s),
                        ..cfg
                    };
                    Bed::new(
                        cfg,
                        Laws {
                            disk: &laws.disk,
                            wall: &laws.wall,
                        },
                    )
                    .and_then(|mut bed| {
                        bed.run_protocol(a.phys.transient, a.phys.cycles, &mut |t| progress(t))
                    })
                    .map_err(|e| e.in_run(format!("seed {}", cfg.seed)))
                })
                .collect::<Result<Vec<BedReport>, _>>()
        },
    );
    let mut runs = vec![first.with_context(context)?];
    runs.extend(others.with_context(context)?);
    let report = BedReport::combine(&runs).context("no run")?;
    pb.finish_and_clear();
    if let Some(p) = &a.trace {
        write_trace(p, &bed)?;
    }
    if let Some(p) = &a.snapshot {
        let title = format!(
            "{} n = {}, f = {} Hz, g = {} m/s², t = {:.3} s",
            restitution,
            a.layers,
            a.freq,
            a.phys.gravity,
            bed.now()
        );
        snapshot_figure(&bed, &title).save_as(p)?;
    }
    let params = a.phys.params()?;
    if a.json {
        let mut v = report_json(restitution, &params, &report);
        if let Some(o) = v.as_object_mut() {
            o.insert("engine".into(), json!("event"));
            if law_name.is_some() {
                let p = a.phys.particle();
                o.insert("young".into(), json!(p.young));
                o.insert("poisson".into(), json!(p.poisson));
            }
        }
        if let Some(o) = v.as_object_mut() {
            o.insert("provenance".into(), prov.json());
            if let Some(t) = &r_used {
                let rows: Vec<_> = t
                    .iter()
                    .map(|(v, d, w)| json!({"speed": v, "disk_disk": d, "disk_wall": w}))
                    .collect();
                o.insert("restitution_used".into(), json!(rows));
            }
        }
        return Ok(Some(v));
    } else {
        print_report(restitution, &params, &report);
        prov.lines().iter().for_each(|l| println!("{l}"));
        if let Some(t) = &r_used {
            print_r_samples(restitution, t);
        }
    }
    Ok(None)
}

/// `dashpot bed --engine dem`: the same bed on soft disks, every contact under the contact law.
fn bed_dem(
    reg: &Registry,
    a: &BedArgs,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<serde_json::Value>> {
    use crate::bed::on_dem::DemBedReport;
    use rayon::prelude::*;
    if a.snapshot.is_some() || a.trace.is_some() {
        return Err(crate::cli::UsageError(
            "--snapshot and --trace are the event-driven engine's; with --engine dem use dashpot dem --scene ... --out DIR for a trajectory".into(),
        )
        .into());
    }
    let k = a.seeds.seeds;
    if k == 0 {
        bail!("--seeds = 0 is out of range: give at least 1 seed");
    }
    let cfg = a.phys.config(a.layers, a.freq);
    cfg.validate()?;
    let dem = a.phys.dem_bed(cfg);
    let law = a.phys.law_name()?;
    let (params, tparams) = (a.phys.params()?, a.phys.tparams()?);
    let prov = crate::output::Provenance::of(reg, law, &params)?;
    prov.warn_if_shadowed();
    let c = dem.engine(a.phys.dem_laws(reg, &dem.material)?)?.step_choice;
    eprintln!(
        "DEM bed: E = {:.3e} Pa, ν = {}, dt = {:.4e} s{}, contact time {:.4e} s at {:.3} m/s ({:.1} steps per collision)",
        dem.material.young,
        dem.material.poisson,
        c.dt,
        if c.given { " (given)" } else { "" },
        c.collision_time,
        c.impact_speed,
        c.collision_time / c.dt
    );
    if let Some(w) = c.warning() {
        eprintln!("warning: {w}");
    }
    let laws = (0..k)
        .map(|_| a.phys.dem_laws(reg, &dem.material))
        .collect::<Result<Vec<_>>>()?;
    let total = (a.phys.transient + a.phys.cycles) / a.freq;
    let pb = progress_bar((total * 1000.0).ceil() as u64, "dem bed (ms simulated)");
    let runs = laws
        .into_par_iter()
        .enumerate()
        .map(|(s, l)| {
            let mut d = dem.clone();
            d.bed.seed = cfg.seed.wrapping_add(s as u64);
            d.run(l, a.phys.transient, a.phys.cycles, &mut |t| {
                if s == 0 {
                    pb.set_position((t * 1000.0) as u64)
                }
                progress(t)
            })
            .with_context(|| {
                format!(
                    "DEM bed n = {}, f = {} Hz, law {law}, seed {}",
                    a.layers, a.freq, d.bed.seed
                )
            })
        })
        .collect::<Result<Vec<DemBedReport>>>()?;
    pb.finish_and_clear();
    let r = DemBedReport::combine(&runs).context("no run")?;
    let v = dem_report_json(law, &params, a.phys.tangential.as_deref(), &tparams, &r);
    if a.json {
        let mut v = v;
        if let Some(o) = v.as_object_mut() {
            o.insert("provenance".into(), prov.json());
        }
        return Ok(Some(v));
    }
    print_dem_report(law, &params, a.phys.tangential.as_deref(), &tparams, &r);
    prov.lines().iter().for_each(|l| println!("{l}"));
    Ok(None)
}

/// The JSON of a DEM bed report: the event-driven bed's keys, `engine: "dem"`, the laws.
pub fn dem_report_json(
    law: &str,
    params: &[ParamValue],
    tangential: Option<&str>,
    tparams: &[ParamValue],
    r: &crate::bed::on_dem::DemBedReport,
) -> serde_json::Value {
    let obj = |ps: &[ParamValue]| -> serde_json::Map<String, serde_json::Value> {
        ps.iter().map(|p| (p.name.to_string(), json!(p.value))).collect()
    };
    let mut v = serde_json::to_value(r).unwrap_or_else(|_| json!({}));
    if let Some(o) = v.as_object_mut() {
        o.insert("engine".into(), json!("dem"));
        o.insert("law".into(), json!({ "name": law, "params": obj(params) }));
        o.insert(
            "tangential".into(),
            match tangential {
                Some(t) => json!({ "name": t, "params": obj(tparams) }),
                None => serde_json::Value::Null,
            },
        );
    }
    v
}

/// Prints a DEM bed report (the event-driven bed's lines, and the step).
pub fn print_dem_report(
    law: &str,
    params: &[ParamValue],
    tangential: Option<&str>,
    tparams: &[ParamValue],
    r: &crate::bed::on_dem::DemBedReport,
) {
    let c = &r.config;
    let ps =
        |ps: &[ParamValue]| -> String { ps.iter().map(|p| format!(" {}={}", p.name, p.value)).collect() };
    println!(
        "DEM bed: law {law}{}{}, n = {} (N = {}), f = {} Hz (V = {:.3} m/s), g = {} m/s², lid at {:.4} m",
        ps(params),
        tangential
            .map(|t| format!(" + {t}{}", ps(tparams)))
            .unwrap_or_default(),
        c.layers,
        r.disks,
        c.freq,
        r.piston_speed,
        c.gravity,
        r.lid
    );
    println!(
        "disks: E = {:.3e} Pa, ν = {}, ρ = {:.1} kg/m³ (m = {:.4e} kg); dt = {:.4e} s{}, contact time {:.4e} s at {:.3} m/s",
        r.young,
        r.poisson,
        r.density,
        c.mass,
        r.dt,
        if r.dt_given { " (given)" } else { "" },
        r.collision_time,
        r.impact_speed
    );
    print_observables(&Observables {
        measured_time: r.measured_time,
        seeds: r.seeds,
        single_seed: "block means over the measured periods",
        note: "; lid collisions counted per contact episode",
        pressure_label: "pressure P                 ",
        pressure: (r.pressure, r.pressure_stderr),
        rate: (r.lid_collision_rate, r.lid_collision_rate_stderr),
        impulse: (r.mean_impulse, r.mean_impulse_stderr),
        temperature: (r.temperature, r.temperature_stderr),
        piston: (r.piston_pressure, r.piston_pressure_stderr),
        piston_expected: r.pressure + r.disks as f64 * c.mass * c.gravity / c.width,
    });
    println!(
        "run: {} steps of {:.4e} s, {:.3} s wall ({:.2} s per simulated s)",
        r.steps, r.dt, r.wall_seconds, r.wall_per_simulated_second
    );
}

/// Impact speeds (m/s) at which the bed prints the r(v) it used for a `from:LAW` restitution.
pub const R_SAMPLE_SPEEDS: [f64; 5] = [0.001, 0.01, 0.1, 1.0, 10.0];

/// r(v) at [`R_SAMPLE_SPEEDS`] for the disk–disk and disk–wall pairs: (v, r_disk, r_wall).
fn r_samples(laws: &Laws<DynRestitution>) -> Result<Vec<(f64, f64, f64)>> {
    use crate::bed::Restitution as _;
    R_SAMPLE_SPEEDS
        .iter()
        .map(|&v| Ok((v, laws.disk.r(v)?, laws.wall.r(v)?)))
        .collect()
}

fn print_r_samples(name: &str, t: &[(f64, f64, f64)]) {
    println!("restitution used ({name}, tabulated from the collision driver):");
    println!("  v (m/s)      r disk-disk     r disk-wall");
    for (v, d, w) in t {
        println!("  {v:<10}   {d:.9}     {w:.9}");
    }
}

/// The JSON of a bed report, with the law.
pub fn report_json(law: &str, params: &[ParamValue], r: &BedReport) -> serde_json::Value {
    let p: serde_json::Map<String, serde_json::Value> = params
        .iter()
        .map(|p| (p.name.to_string(), json!(p.value)))
        .collect();
    let mut v = serde_json::to_value(r).unwrap_or_else(|_| json!({}));
    if let Some(o) = v.as_object_mut() {
        o.insert("restitution".into(), json!({ "law": law, "params": p }));
        o.insert(
            "max_overlap_diameters".into(),
            json!(r.max_overlap / r.config.diameter),
        );
    }
    v
}

/// The measured observables of a bed run, as both engines print them: value and standard error.
struct Observables<'a> {
    measured_time: f64,
    seeds: usize,
    /// Where the standard error of a single-seed run comes from.
    single_seed: &'a str,
    /// Appended to the line saying what ± means.
    note: &'a str,
    /// Padded to the width of the other labels.
    pressure_label: &'a str,
    pressure: (f64, Option<f64>),
    rate: (f64, Option<f64>),
    /// `None` when no disk hit the lid.
    impulse: (Option<f64>, Option<f64>),
    temperature: (f64, Option<f64>),
    piston: (f64, Option<f64>),
    /// P + N m g / L, what the piston pressure should be.
    piston_expected: f64,
}

fn print_observables(o: &Observables<'_>) {
    println!("measured over {:.3} s after the transient:", o.measured_time);
    let pm = |(v, e): (f64, Option<f64>)| match e {
        Some(e) => format!("{v:.6e} ± {e:.2e}"),
        None => format!("{v:.6e}"),
    };
    let source = if o.seeds > 1 {
        format!("spread of {} independent seeds", o.seeds)
    } else {
        o.single_seed.to_string()
    };
    println!("  (± one standard error: {source}{})", o.note);
    println!("  {} {} N/m", o.pressure_label, pm(o.pressure));
    println!("  lid collision rate Nc       {} 1/s", pm(o.rate));
    match o.impulse {
        (Some(v), e) => println!("  mean impulse ΔI             {} N·s", pm((v, e))),
        (None, _) => println!("  mean impulse ΔI             not measured: no disk hit the lid"),
    }
    println!("  temperature T               {} J", pm(o.temperature));
    println!(
        "  piston pressure             {} N/m (P + N m g / L = {:.6e})",
        pm(o.piston),
        o.piston_expected
    );
}

fn print_report(law: &str, params: &[ParamValue], r: &BedReport) {
    let c = &r.config;
    let ps: Vec<String> = params
        .iter()
        .map(|p| format!(" {}={}", p.name, p.value))
        .collect();
    println!(
        "bed: law {law}{}, n = {} (N = {}), f = {} Hz (V = {:.3} m/s), g = {} m/s², lid at {:.4} m",
        ps.concat(),
        c.layers,
        r.disks,
        c.freq,
        r.piston_speed,
        c.gravity,
        r.lid
    );
    print_observables(&Observables {
        measured_time: r.measured_time,
        seeds: r.seeds,
        single_seed: "batch means over the measured periods",
        note: "",
        pressure_label: "pressure P = Nc ΔI / L     ",
        pressure: (r.pressure, r.pressure_stderr),
        rate: (r.lid_collision_rate, r.lid_collision_rate_stderr),
        impulse: (r.mean_impulse, r.mean_impulse_stderr),
        temperature: (r.temperature, r.temperature_stderr),
        piston: (r.piston_pressure, r.piston_pressure_stderr),
        piston_expected: r.pressure + r.disks as f64 * c.mass * c.gravity / c.width,
    });
    println!(
        "run: {} events ({} collisions, {} cell crossings), {:.3e} events/s, {:.3e} collisions/s, {:.3} s wall ({:.4} s per simulated s)",
        r.events,
        r.collisions,
        r.counters.cell_crossings,
        r.events_per_second,
        r.collisions_per_second,
        r.wall_seconds,
        r.wall_per_simulated_second
    );
    println!(
        "  TC firings {} ({:.2} % of collisions), largest overlap {:.3e} m ({:.3e} d)",
        r.tc_firings,
        100.0 * r.tc_share,
        r.max_overlap,
        r.max_overlap / c.diameter
    );
}

fn write_trace<R: crate::bed::Restitution>(p: &Path, bed: &Bed<R>) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in bed.trace() {
        w.serialize(row)?;
    }
    let bytes = w.into_inner().context("trace csv")?;
    write_atomic(p, &bytes).with_context(|| format!("cannot write {}", p.display()))
}
