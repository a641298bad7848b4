//! `dashpot bed`: one run (or one per seed) on either engine, its printout and its JSON.

use super::*;
use crate::bed::engine::{Bed, BedConfig, BedReport};
use crate::bed::observables::BedObservables;
use crate::bed::scaling::InRun;
use crate::bed::spec::{BedEngine, BedSpec, LawChoice};
use crate::bed::{DynRestitution, Laws};
use crate::output::progress_bar;
use crate::output::write_atomic;
use crate::registry::Registry;
use crate::report::snapshot::{SaveAs, Scene};
use anyhow::{Context, Result};
use dashpot_sdk::ParamValue;
use serde_json::json;
use std::path::Path;

/// What a bed run writes besides its printout.
#[derive(Debug, Clone, Copy, Default)]
pub struct BedOutput<'a> {
    /// Machine-readable output instead of the printout.
    pub json: bool,
    /// Draw the disks at the end of the run into this file (event-driven engine).
    pub snapshot: Option<&'a Path>,
    /// Write the sampled time series here (event-driven engine).
    pub trace: Option<&'a Path>,
}

/// `dashpot bed`.
pub fn bed(reg: &Registry, a: &BedArgs) -> Result<()> {
    crate::budget::check_max_hours(a.limits.max_hours)?;
    let simulated = (a.phys.transient + a.phys.cycles) / a.freq;
    let waves = a.seeds.seeds.div_ceil(rayon::current_num_threads().max(1)) as f64;
    let watch = super::check::PaceWatch::new(simulated, waves, a.limits.max_hours);
    let v = super::check::watch(|| run_bed(reg, a, &|t| watch.tick(t)))?;
    if let Some(v) = v {
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
    let spec = a.phys.spec(a.layers, a.freq, a.seeds.seeds)?;
    if a.check {
        return super::check::check(reg, &spec, a.json, a.limits.max_hours);
    }
    let out = BedOutput {
        json: a.json,
        snapshot: a.snapshot.as_deref(),
        trace: a.trace.as_deref(),
    };
    run(reg, &spec, out, progress)
}

/// Runs the bed experiment `spec` on its engine (`dashpot bed`, `dashpot dem --bed`, the Python
/// package): its checks, the runs (one per seed, in parallel, behind one progress bar, each
/// calling `progress` with its simulated time), then the printout, or with `out.json` the
/// document, returned.
pub fn run(
    reg: &Registry,
    spec: &BedSpec,
    out: BedOutput<'_>,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<serde_json::Value>> {
    spec.validate()?;
    match &spec.engine {
        BedEngine::Event { restitution } => run_event(reg, spec, restitution, out, progress),
        BedEngine::Dem { law, tangential, .. } => run_dem(reg, spec, law, tangential.as_ref(), out, progress),
    }
}

/// The bed on the event-driven engine.
fn run_event(
    reg: &Registry,
    spec: &BedSpec,
    restitution: &LawChoice,
    out: BedOutput<'_>,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<serde_json::Value>> {
    let cfg = spec.config;
    let name = restitution.name.as_str();
    let laws = spec.restitution_laws(reg)?;
    // provenance, and the r(v) actually used when it comes from a contact law (issue 10)
    let law_name = name.strip_prefix(crate::bed::FROM_CONTACT);
    let prov = crate::output::Provenance::of(reg, law_name.unwrap_or(name), &restitution.params)?;
    prov.warn_if_shadowed();
    let r_used = match law_name {
        Some(_) => Some(r_samples(&laws)?),
        None => None,
    };
    let laws = Laws {
        disk: &laws.disk,
        wall: &laws.wall,
    };
    let mut bed = Bed::new(cfg, laws)?;
    if out.trace.is_some() {
        bed.enable_trace();
    }
    let pb = protocol_bar(spec, "bed (ms simulated)");
    let context = || format!("bed n = {}, f = {} Hz, law {}", cfg.layers, cfg.freq, name);
    // the other seeds in parallel with the first (which draws the snapshot and the trace)
    let (first, others) = rayon::join(
        || {
            bed.run_protocol(spec.transient, spec.cycles, &mut |t| {
                pb.set_position((t * 1000.0) as u64);
                progress(t)
            })
        },
        || {
            other_seeds(spec, |cfg| {
                Bed::new(cfg, laws)
                    .and_then(|mut bed| bed.run_protocol(spec.transient, spec.cycles, &mut |t| progress(t)))
                    .map_err(|e| e.in_run(format!("seed {}", cfg.seed)))
            })
        },
    );
    let mut runs = vec![first.with_context(context)?];
    runs.extend(others.with_context(context)?);
    let report = BedReport::combine(&runs).context("no run")?;
    pb.finish_and_clear();
    if let Some(p) = out.trace {
        write_trace(p, &bed)?;
    }
    if let Some(p) = out.snapshot {
        let title = format!(
            "{} n = {}, f = {} Hz, g = {} m/s², t = {:.3} s",
            name,
            cfg.layers,
            cfg.freq,
            cfg.gravity,
            bed.now()
        );
        Scene::bed(&bed).figure(&title).save_as(p)?;
    }
    if out.json {
        let mut v = report_json(name, &restitution.params, &report);
        if let Some(o) = v.as_object_mut() {
            o.insert("engine".into(), json!("event"));
            if law_name.is_some() {
                let p = spec.particle();
                o.insert("young".into(), json!(p.young));
                o.insert("poisson".into(), json!(p.poisson));
            }
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
        print_report(name, &restitution.params, &report);
        prov.lines().iter().for_each(|l| println!("{l}"));
        if let Some(t) = &r_used {
            print_r_samples(name, t);
        }
    }
    Ok(None)
}

/// The one progress bar of a bed run: simulated milliseconds of the first seed's protocol.
fn protocol_bar(spec: &BedSpec, what: &str) -> indicatif::ProgressBar {
    let total = (spec.transient + spec.cycles) / spec.config.freq;
    progress_bar((total * 1000.0).ceil() as u64, what)
}

/// `run(cfg)` for the seeds after the first (seed + 1, seed + 2, ...), in parallel.
fn other_seeds<R: Send, E: Send>(
    spec: &BedSpec,
    run: impl Fn(BedConfig) -> Result<R, E> + Sync,
) -> Result<Vec<R>, E> {
    use rayon::prelude::*;
    (1..spec.seeds as u64)
        .into_par_iter()
        .map(|s| {
            run(BedConfig {
                seed: spec.config.seed.wrapping_add(s),
                ..spec.config
            })
        })
        .collect()
}

/// The bed on the DEM engine: soft disks, every contact under the contact law.
fn run_dem(
    reg: &Registry,
    spec: &BedSpec,
    law: &LawChoice,
    tangential: Option<&LawChoice>,
    out: BedOutput<'_>,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<Option<serde_json::Value>> {
    use crate::bed::on_dem::DemBedReport;
    if out.snapshot.is_some() || out.trace.is_some() {
        return Err(crate::cli::UsageError(
            "--snapshot and --trace are the event-driven engine's; with --engine dem use dashpot dem --scene ... --out DIR for a trajectory".into(),
        )
        .into());
    }
    let cfg = spec.config;
    let dem = spec.dem_bed(cfg);
    let prov = crate::output::Provenance::of(reg, &law.name, &law.params)?;
    prov.warn_if_shadowed();
    let c = dem.engine(spec.dem_laws(reg, &dem.material)?)?.step_choice;
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
    let pb = protocol_bar(spec, "dem bed (ms simulated)");
    let run = |cfg: BedConfig, progress: &mut dyn FnMut(f64)| -> Result<DemBedReport> {
        let d = crate::bed::on_dem::DemBed {
            bed: cfg,
            ..dem.clone()
        };
        d.run(
            spec.dem_laws(reg, &dem.material)?,
            spec.transient,
            spec.cycles,
            progress,
        )
        .with_context(|| {
            format!(
                "DEM bed n = {}, f = {} Hz, law {}, seed {}",
                cfg.layers, cfg.freq, law.name, cfg.seed
            )
        })
    };
    let (first, others) = rayon::join(
        || {
            run(cfg, &mut |t| {
                pb.set_position((t * 1000.0) as u64);
                progress(t)
            })
        },
        || other_seeds(spec, |cfg| run(cfg, &mut |t| progress(t))),
    );
    let mut runs = vec![first?];
    runs.extend(others?);
    pb.finish_and_clear();
    let r = DemBedReport::combine(&runs).context("no run")?;
    if out.json {
        let mut v = dem_report_json(law, tangential, &r);
        if let Some(o) = v.as_object_mut() {
            o.insert("provenance".into(), prov.json());
        }
        return Ok(Some(v));
    }
    print_dem_report(law, tangential, &r);
    prov.lines().iter().for_each(|l| println!("{l}"));
    Ok(None)
}

/// The JSON of a DEM bed report: the event-driven bed's keys, `engine: "dem"`, the laws.
pub fn dem_report_json(
    law: &LawChoice,
    tangential: Option<&LawChoice>,
    r: &crate::bed::on_dem::DemBedReport,
) -> serde_json::Value {
    let obj = |l: &LawChoice| {
        let ps: serde_json::Map<String, serde_json::Value> = l
            .params
            .iter()
            .map(|p| (p.name.to_string(), json!(p.value)))
            .collect();
        json!({ "name": l.name, "params": ps })
    };
    let mut v = serde_json::to_value(r).unwrap_or_else(|_| json!({}));
    if let Some(o) = v.as_object_mut() {
        o.insert("engine".into(), json!("dem"));
        o.insert("law".into(), obj(law));
        o.insert(
            "tangential".into(),
            tangential.map_or(serde_json::Value::Null, obj),
        );
    }
    v
}

/// Prints a DEM bed report (the event-driven bed's lines, and the step).
pub fn print_dem_report(
    law: &LawChoice,
    tangential: Option<&LawChoice>,
    r: &crate::bed::on_dem::DemBedReport,
) {
    let c = &r.config;
    let laws = law.describe()
        + &tangential
            .map(|t| format!(" + {}", t.describe()))
            .unwrap_or_default();
    print_header("DEM bed", &laws, &r.measured);
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
    print_observables(
        &r.measured,
        Labels {
            single_seed: "block means over the measured periods",
            note: "; lid collisions counted per contact episode",
            pressure: "pressure P                 ",
        },
    );
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

/// How an engine's printout labels the observables: where a single run's standard error comes
/// from, a note on what ± means, and the pressure's label (padded to the others' width).
struct Labels<'a> {
    single_seed: &'a str,
    note: &'a str,
    pressure: &'a str,
}

/// The first line of a bed run's printout, either engine's: `what` with its laws `laws`, the
/// bed and the piston.
fn print_header(what: &str, laws: &str, o: &BedObservables) {
    let c = &o.config;
    println!(
        "{what}: law {laws}, n = {} (N = {}), f = {} Hz (V = {:.3} m/s), g = {} m/s², lid at {:.4} m",
        c.layers, o.disks, c.freq, o.piston_speed, c.gravity, o.lid
    );
}

/// The observables of a bed run, either engine's: value ± standard error.
fn print_observables(o: &BedObservables, labels: Labels<'_>) {
    println!("measured over {:.3} s after the transient:", o.measured_time);
    let pm = |(v, e): (f64, Option<f64>)| match e {
        Some(e) => format!("{v:.6e} ± {e:.2e}"),
        None => format!("{v:.6e}"),
    };
    let source = if o.seeds > 1 {
        format!("spread of {} independent seeds", o.seeds)
    } else {
        labels.single_seed.to_string()
    };
    println!("  (± one standard error: {source}{})", labels.note);
    println!(
        "  {} {} N/m",
        labels.pressure,
        pm((o.pressure, o.pressure_stderr))
    );
    println!(
        "  lid collision rate Nc       {} 1/s",
        pm((o.lid_collision_rate, o.lid_collision_rate_stderr))
    );
    match o.mean_impulse {
        Some(v) => println!(
            "  mean impulse ΔI             {} N·s",
            pm((v, o.mean_impulse_stderr))
        ),
        None => println!("  mean impulse ΔI             not measured: no disk hit the lid"),
    }
    println!(
        "  temperature T               {} J",
        pm((o.temperature, o.temperature_stderr))
    );
    println!(
        "  piston pressure             {} N/m (P + N m g / L = {:.6e})",
        pm((o.piston_pressure, o.piston_pressure_stderr)),
        o.piston_expected()
    );
}

fn print_report(law: &str, params: &[ParamValue], r: &BedReport) {
    let c = &r.config;
    print_header(
        "bed",
        &LawChoice::new(law, params.to_vec()).describe(),
        &r.measured,
    );
    print_observables(
        &r.measured,
        Labels {
            single_seed: "batch means over the measured periods",
            note: "",
            pressure: "pressure P = Nc ΔI / L     ",
        },
    );
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
    Ok(write_atomic(p, &bytes)?)
}
