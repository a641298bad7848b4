//! The bed's command-line arguments and the `dashpot bed`, `dashpot scaling` and
//! `dashpot figures bed` commands (delegated to from [`crate::cli`]).

use super::engine::{Bed, BedConfig, BedReport};
use super::view::{progress_bar, snapshot_figure, SaveAs};
use super::{resolve, scaling, DynRestitution, Laws};
use crate::output::write_atomic;
use crate::plot::Figure;
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use dashpot_sdk::ParamValue;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The physics shared by `dashpot bed` and `dashpot scaling` (defaults: McNamara & Falcon).
#[derive(Args, Debug, Clone)]
pub struct PhysArgs {
    /// The restitution law (see `dashpot laws`), e.g. mcnamara-falcon or constant; or any
    /// contact law as `from:NAME` (e.g. from:kuwabara-kono), its r(v) from the collision driver.
    #[arg(long)]
    pub restitution: String,
    /// Set a law parameter, NAME=VALUE (repeatable), e.g. --set r=0.7.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub set: Vec<String>,
    /// Gravity g (m/s², 0 for none).
    #[arg(long, default_value_t = 9.8, allow_hyphen_values = true)]
    pub gravity: f64,
    /// Piston amplitude A, peak to peak (m).
    #[arg(long, default_value_t = 0.025, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Box width L (m), periodic.
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub width: f64,
    /// Disk diameter d (m).
    #[arg(long, default_value_t = 0.002, allow_hyphen_values = true)]
    pub diameter: f64,
    /// Disk mass m (kg).
    #[arg(long, default_value_t = 3.27e-5, allow_hyphen_values = true)]
    pub mass: f64,
    /// Headroom h − h0 (m): the lid is this far above n layers (h0 = n d) over the piston's top.
    #[arg(long, default_value_t = 0.015, allow_hyphen_values = true)]
    pub headroom: f64,
    /// Measured piston periods C, after the transient.
    #[arg(long, default_value_t = 200.0, allow_hyphen_values = true)]
    pub cycles: f64,
    /// Transient periods C0, not measured.
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true)]
    pub transient: f64,
    /// Rough disks: tangential restitution r_t in [-1, 1] (-1 smooth, 1 fully reversing).
    #[arg(long, allow_hyphen_values = true)]
    pub tangential: Option<f64>,
    /// The TC model: a collision of a disk that collided less than SECONDS ago is elastic.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub tc: Option<f64>,
    /// Seed of the initial state.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Independent seeds for `dashpot bed`.
#[derive(Args, Debug, Clone)]
pub struct SeedArgs {
    /// Run K independent seeds (SEED, SEED+1, ...) in parallel and report their mean, with
    /// standard errors from their spread (K = 1: batch means over the measured periods).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub seeds: usize,
}

impl PhysArgs {
    /// The law's parameters from `--set`.
    pub fn params(&self) -> Result<Vec<ParamValue>> {
        let sets = crate::config::parse_sets(&self.set).map_err(|e| crate::cli::UsageError(e.to_string()))?;
        Ok(crate::config::merge_params(&Default::default(), &sets))
    }

    /// The configuration at `layers` and `freq` (Hz).
    pub fn config(&self, layers: f64, freq: f64) -> BedConfig {
        BedConfig {
            layers,
            freq,
            gravity: self.gravity,
            amplitude: self.amplitude,
            width: self.width,
            diameter: self.diameter,
            mass: self.mass,
            headroom: self.headroom,
            tangential: self.tangential,
            tc: self.tc,
            seed: self.seed,
            ..BedConfig::paper(layers, freq)
        }
    }

    /// Loads the law and binds it to the bed's pairs.
    pub fn laws(&self, reg: &Registry) -> Result<Laws<DynRestitution>> {
        if !(self.diameter.is_finite() && self.diameter > 0.0) {
            bail!("diameter d = {} m is out of range: d must be > 0", self.diameter);
        }
        if !(self.mass.is_finite() && self.mass > 0.0) {
            bail!("mass m = {} kg is out of range: m must be > 0", self.mass);
        }
        Ok(resolve(
            reg,
            &self.restitution,
            &self.params()?,
            self.diameter,
            self.mass,
        )?)
    }

    /// Checks the protocol's lengths.
    pub fn check_cycles(&self) -> Result<()> {
        if !(self.cycles.is_finite() && self.cycles > 0.0) {
            bail!("--cycles = {} is out of range: must be > 0 periods", self.cycles);
        }
        if !(self.transient.is_finite() && self.transient >= 0.0) {
            bail!(
                "--transient = {} is out of range: must be >= 0 periods",
                self.transient
            );
        }
        Ok(())
    }
}

/// `dashpot bed`.
#[derive(Args, Debug)]
pub struct BedArgs {
    /// The law and the bed.
    #[command(flatten)]
    pub phys: PhysArgs,
    /// Number of layers n = N d / L (N = 100 n disks at the defaults).
    #[arg(long, allow_hyphen_values = true)]
    pub layers: f64,
    /// Piston frequency f (Hz).
    #[arg(long, allow_hyphen_values = true)]
    pub freq: f64,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
    /// Draw the disks at the end of the run (piston at its lowest) into FILE.png (and .svg).
    #[arg(long, value_name = "FILE.png")]
    pub snapshot: Option<PathBuf>,
    /// Write the sampled time series (64 samples per period) to FILE.csv.
    #[arg(long, value_name = "FILE.csv")]
    pub trace: Option<PathBuf>,
    /// Independent seeds.
    #[command(flatten)]
    pub seeds: SeedArgs,
}

/// `dashpot scaling`.
#[derive(Args, Debug)]
pub struct ScalingArgs {
    /// The law and the bed.
    #[command(flatten)]
    pub phys: PhysArgs,
    /// Layers, comma separated, e.g. 0.5,1,2,3.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, required = true)]
    pub layers: Vec<f64>,
    /// Frequencies FROM:TO:COUNT (Hz), evenly spaced, e.g. 10:30:11.
    #[arg(long, default_value = "10:30:11")]
    pub freqs: String,
    /// Output folder for scaling.csv, grid.csv and theta.png/.svg.
    #[arg(long, default_value = "scaling")]
    pub out: PathBuf,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
}

/// `dashpot figures ...`: the figures of one driver.
#[derive(Subcommand, Debug)]
pub enum FiguresCommand {
    /// McNamara & Falcon (2005) Figs. 2 b–d, 3 and 4 a–d, with a report.
    Bed {
        /// Output folder.
        #[arg(long, default_value = "results/bed")]
        out: PathBuf,
        /// A small grid and short runs (seconds), instead of the paper's.
        #[arg(long)]
        quick: bool,
        /// Only these figures (2, 3, 4, and 5 for the other statements of the paper; comma
        /// separated). Default: all.
        #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u8).range(2..=5))]
        only: Vec<u8>,
    },
}

/// Parses FROM:TO:COUNT into COUNT evenly spaced values.
pub fn parse_range(s: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = s.split(':').collect();
    let bad = || anyhow::anyhow!("--freqs '{s}' is not FROM:TO:COUNT (e.g. 10:30:11, frequencies in Hz)");
    if parts.len() != 3 {
        return Err(bad());
    }
    let a: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let b: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    let k: usize = parts[2].trim().parse().map_err(|_| bad())?;
    if k == 0 || !a.is_finite() || !b.is_finite() {
        return Err(bad());
    }
    if k == 1 {
        return Ok(vec![a]);
    }
    Ok((0..k).map(|i| a + (b - a) * i as f64 / (k - 1) as f64).collect())
}

/// `dashpot bed`.
pub fn bed(reg: &Registry, a: &BedArgs) -> Result<()> {
    a.phys.check_cycles()?;
    let cfg = a.phys.config(a.layers, a.freq);
    cfg.validate()?;
    let laws = a.phys.laws(reg)?;
    // provenance, and the r(v) actually used when it comes from a contact law (issue 10)
    let law_name = a.phys.restitution.strip_prefix(super::FROM_CONTACT);
    let prov =
        crate::output::Provenance::of(reg, law_name.unwrap_or(&a.phys.restitution), &a.phys.params()?)?;
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
    let context = || {
        format!(
            "bed n = {}, f = {} Hz, law {}",
            a.layers, a.freq, a.phys.restitution
        )
    };
    // the other seeds in parallel with the first (which draws the snapshot and the trace)
    let (first, others) = rayon::join(
        || {
            bed.run_protocol(a.phys.transient, a.phys.cycles, &mut |t| {
                pb.set_position((t * 1000.0) as u64)
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
                    )?
                    .run_protocol(a.phys.transient, a.phys.cycles, &mut |_| {})
                    .map_err(|e| match e {
                        super::BedError::Collapse(m) => {
                            super::BedError::Collapse(format!("seed {}: {m}", cfg.seed))
                        }
                        super::BedError::Overlap(m) => {
                            super::BedError::Overlap(format!("seed {}: {m}", cfg.seed))
                        }
                        e => e,
                    })
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
            a.phys.restitution,
            a.layers,
            a.freq,
            a.phys.gravity,
            bed.now()
        );
        snapshot_figure(&bed, &title).save_as(p)?;
    }
    let params = a.phys.params()?;
    if a.json {
        let mut v = report_json(&a.phys.restitution, &params, &report);
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
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print_report(&a.phys.restitution, &params, &report);
        prov.lines().iter().for_each(|l| println!("{l}"));
        if let Some(t) = &r_used {
            print_r_samples(&a.phys.restitution, t);
        }
    }
    Ok(())
}

/// Impact speeds (m/s) at which the bed prints the r(v) it used for a `from:LAW` restitution.
pub const R_SAMPLE_SPEEDS: [f64; 5] = [0.001, 0.01, 0.1, 1.0, 10.0];

/// r(v) at [`R_SAMPLE_SPEEDS`] for the disk–disk and disk–wall pairs: (v, r_disk, r_wall).
fn r_samples(laws: &Laws<DynRestitution>) -> Result<Vec<(f64, f64, f64)>> {
    use super::Restitution as _;
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
    println!("measured over {:.3} s after the transient:", r.measured_time);
    let pm = |v: f64, e: Option<f64>| match e {
        Some(e) => format!("{v:.6e} ± {e:.2e}"),
        None => format!("{v:.6e}"),
    };
    println!(
        "  (± one standard error: {})",
        if r.seeds > 1 {
            format!("spread of {} independent seeds", r.seeds)
        } else {
            "batch means over the measured periods".to_string()
        }
    );
    println!(
        "  pressure P = Nc ΔI / L      {} N/m",
        pm(r.pressure, r.pressure_stderr)
    );
    println!(
        "  lid collision rate Nc       {} 1/s",
        pm(r.lid_collision_rate, r.lid_collision_rate_stderr)
    );
    println!(
        "  mean impulse ΔI             {} N·s",
        pm(r.mean_impulse, r.mean_impulse_stderr)
    );
    println!(
        "  temperature T               {} J",
        pm(r.temperature, r.temperature_stderr)
    );
    println!(
        "  piston pressure             {} N/m (P + N m g / L = {:.6e})",
        pm(r.piston_pressure, r.piston_pressure_stderr),
        r.pressure + r.disks as f64 * c.mass * c.gravity / c.width
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

fn write_trace<R: super::Restitution>(p: &Path, bed: &Bed<R>) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in bed.trace() {
        w.serialize(row)?;
    }
    let bytes = w.into_inner().context("trace csv")?;
    write_atomic(p, &bytes).with_context(|| format!("cannot write {}", p.display()))
}

/// `dashpot scaling`.
pub fn scaling(reg: &Registry, a: &ScalingArgs) -> Result<()> {
    a.phys.check_cycles()?;
    let freqs = parse_range(&a.freqs)?;
    if a.layers.is_empty() {
        bail!("--layers: give at least one number of layers");
    }
    for &n in &a.layers {
        a.phys.config(n, 20.0).validate()?;
    }
    for &f in &freqs {
        a.phys.config(1.0, f).validate()?;
    }
    let laws = a.phys.laws(reg)?;
    let laws = Laws {
        disk: &laws.disk,
        wall: &laws.wall,
    };
    let grid = scaling::Grid {
        layers: a.layers.clone(),
        freqs,
        transient: a.phys.transient,
        cycles: a.phys.cycles,
    };
    let pb = progress_bar(grid.len() as u64, "scaling (runs)");
    let runs = scaling::run_grid(&laws, &|n, f| a.phys.config(n, f), &grid, &|| pb.inc(1))?;
    pb.finish_and_clear();
    let rows = scaling::fit_all(&grid, &runs);
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
    scaling::write_grid_csv(&a.out.join("grid.csv"), &runs)?;
    scaling::write_fit_csv(&a.out.join("scaling.csv"), &rows)?;
    let title = format!(
        "θ(n): {} {}, g = {} m/s²",
        a.phys.restitution,
        a.phys.set.join(" "),
        a.phys.gravity
    );
    Figure::single(scaling::theta_panel(&rows, &title)).save(&a.out, "theta")?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        println!(
            "scaling exponents θ of X ∝ V^θ, least squares of ln X on ln V over {} frequencies (max |residual| in ln units)",
            grid.freqs.len()
        );
        println!(
            "{:>6} {:>16} {:>16} {:>16} {:>16}",
            "n", "θ_P", "θ_T", "θ_Nc", "θ_ΔI"
        );
        for r in &rows {
            let c = |f: &Option<super::observables::PowerFit>| match f {
                Some(f) => format!("{:7.3} ({:.3})", f.theta, f.max_residual),
                None => "-".to_string(),
            };
            println!(
                "{:>6} {:>16} {:>16} {:>16} {:>16}",
                r.layers,
                c(&r.pressure),
                c(&r.temperature),
                c(&r.lid_collision_rate),
                c(&r.mean_impulse)
            );
        }
        println!(
            "wrote {}, {} and theta.png/.svg",
            a.out.join("scaling.csv").display(),
            a.out.join("grid.csv").display()
        );
    }
    Ok(())
}

/// `dashpot figures ...`.
pub fn figures(reg: &Registry, cmd: &FiguresCommand) -> Result<()> {
    match cmd {
        FiguresCommand::Bed { out, quick, only } => {
            let size = if *quick {
                super::figures::Size::quick()
            } else {
                super::figures::Size::paper()
            };
            let md = super::figures::run_only(reg, out, &size, only)?;
            write_atomic(&out.join("report.md"), md.as_bytes())?;
            println!("wrote {}", out.join("report.md").display());
            Ok(())
        }
    }
}
