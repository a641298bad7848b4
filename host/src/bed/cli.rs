//! The bed's command-line arguments and the `dashpot bed`, `dashpot scaling` and
//! `dashpot figures bed` commands (delegated to from [`crate::cli`]).

use super::engine::{Bed, BedConfig, BedReport};
use super::scaling::InRun;
use super::view::{progress_bar, snapshot_figure, SaveAs};
use super::{scaling, DynRestitution, Laws};
use crate::output::write_atomic;
use crate::plot::Figure;
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use dashpot_sdk::ParamValue;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Which engine runs the bed.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EngineKind {
    /// Event-driven hard disks: instantaneous collisions under a restitution law.
    #[default]
    Event,
    /// Soft-sphere DEM: every contact under a contact law (and a tangential law) over time.
    Dem,
}

/// The physics shared by `dashpot bed` and `dashpot scaling` (defaults: McNamara & Falcon).
#[derive(Args, Debug, Clone)]
pub struct PhysArgs {
    /// The engine: `event` (hard disks, a restitution law) or `dem` (soft disks, a contact law
    /// acting over each contact, optional friction).
    #[arg(long, value_enum, default_value_t = EngineKind::Event)]
    pub engine: EngineKind,
    /// The restitution law of the event-driven engine (see `dashpot laws`), e.g.
    /// mcnamara-falcon or constant; or any contact law as `from:NAME` (e.g.
    /// from:kuwabara-kono), its r(v) from the collision driver.
    #[arg(long)]
    pub restitution: Option<String>,
    /// The contact law of the DEM engine (`--engine dem`), e.g. hsd or kuwabara-kono.
    #[arg(long)]
    pub law: Option<String>,
    /// Set a parameter of the law (the restitution law, or with --engine dem the contact law),
    /// NAME=VALUE (repeatable), e.g. --set r=0.7.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub set: Vec<String>,
    /// Set a parameter of the tangential law (--engine dem), NAME=VALUE (repeatable), e.g.
    /// --tset mu=0.3.
    #[arg(long = "tset", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub tset: Vec<String>,
    /// Young's modulus of the disks (Pa; default steel, 2e11): the DEM engine's disks, and the
    /// particle a `--restitution from:LAW` table is computed for, so both engines can be
    /// compared on one material. Real steel makes the DEM step ~0.1 µs; 1e8 makes it ~1.6 µs.
    #[arg(long, allow_hyphen_values = true)]
    pub young: Option<f64>,
    /// Poisson's ratio of the disks (default 0.3), like --young.
    #[arg(long, allow_hyphen_values = true)]
    pub poisson: Option<f64>,
    /// The DEM step (s); default: the law's contact time at the largest impact speed / 50.
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Steps per collision when the DEM step is chosen (default 50).
    #[arg(long, allow_hyphen_values = true)]
    pub steps_per_collision: Option<f64>,
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
    /// Event engine: rough disks, tangential restitution r_t in [-1, 1] (-1 smooth, 1 fully
    /// reversing). DEM engine: a tangential law by name (e.g. mindlin), parameters by --tset.
    #[arg(long, allow_hyphen_values = true, value_name = "R_T|NAME")]
    pub tangential: Option<String>,
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

    /// The tangential law's parameters from `--tset`.
    pub fn tparams(&self) -> Result<Vec<ParamValue>> {
        let sets =
            crate::config::parse_sets(&self.tset).map_err(|e| crate::cli::UsageError(e.to_string()))?;
        Ok(crate::config::merge_params(&Default::default(), &sets))
    }

    /// The event-driven engine's rough-disk r_t (checked by [`PhysArgs::check`]).
    fn rough(&self) -> Option<f64> {
        match self.engine {
            EngineKind::Event => self.tangential.as_deref().and_then(|s| s.trim().parse().ok()),
            EngineKind::Dem => None,
        }
    }

    /// The restitution law's name (event engine).
    pub fn restitution_name(&self) -> Result<&str> {
        self.restitution.as_deref().ok_or_else(|| {
            crate::cli::UsageError(
                "the event-driven bed needs --restitution LAW (e.g. mcnamara-falcon, or from:kuwabara-kono); a contact law over time is --engine dem --law NAME".into(),
            )
            .into()
        })
    }

    /// The contact law's name (DEM engine).
    pub fn law_name(&self) -> Result<&str> {
        self.law.as_deref().ok_or_else(|| {
            crate::cli::UsageError("--engine dem needs --law NAME (a contact law, e.g. hsd)".into()).into()
        })
    }

    /// Checks the arguments against the engine: each engine's options are refused by the
    /// other, with the value named.
    pub fn check(&self) -> Result<()> {
        use crate::cli::UsageError;
        self.check_cycles()?;
        if let Some(e) = self.young {
            if !(e.is_finite() && e > 0.0) {
                bail!("--young = {e} Pa is out of range: Young's modulus must be finite and > 0");
            }
        }
        if let Some(nu) = self.poisson {
            if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                bail!("--poisson = {nu} is out of range: Poisson's ratio must lie in (-1, 0.5)");
            }
        }
        match self.engine {
            EngineKind::Event => {
                let name = self.restitution_name()?;
                if let Some(l) = &self.law {
                    return Err(UsageError(format!(
                        "--law {l} is the DEM engine's: add --engine dem (or give the event-driven engine a --restitution law)"
                    ))
                    .into());
                }
                for (flag, given) in [
                    ("--dt", self.dt.is_some()),
                    ("--steps-per-collision", self.steps_per_collision.is_some()),
                    ("--tset", !self.tset.is_empty()),
                ] {
                    if given {
                        return Err(
                            UsageError(format!("{flag} is the DEM engine's: add --engine dem")).into(),
                        );
                    }
                }
                if (self.young.is_some() || self.poisson.is_some()) && !name.starts_with(super::FROM_CONTACT)
                {
                    return Err(UsageError(format!(
                        "--young/--poisson reach the event-driven engine only through a contact law's table, --restitution from:LAW; '{name}' is a restitution law, which does not use them"
                    ))
                    .into());
                }
                if let Some(t) = &self.tangential {
                    // its range is the bed configuration's to check (BedConfig::validate)
                    match t.trim().parse::<f64>() {
                        Ok(_) => {}
                        Err(_) => {
                            return Err(UsageError(format!(
                                "--tangential '{t}' is not a number: with --engine event it is the tangential restitution r_t in [-1, 1]; a tangential law by name needs --engine dem"
                            ))
                            .into())
                        }
                    }
                }
            }
            EngineKind::Dem => {
                self.law_name()?;
                if let Some(r) = &self.restitution {
                    return Err(UsageError(format!(
                        "--restitution {r} is the event-driven engine's: --engine dem takes a contact law, --law NAME"
                    ))
                    .into());
                }
                if let Some(tc) = self.tc {
                    return Err(UsageError(format!(
                        "--tc {tc} is the event-driven engine's TC model: soft contacts need none"
                    ))
                    .into());
                }
                if let Some(t) = &self.tangential {
                    if t.trim().parse::<f64>().is_ok() {
                        return Err(UsageError(format!(
                            "--tangential {t}: with --engine dem give a tangential law by name (e.g. mindlin, parameters by --tset mu=0.3), not a tangential restitution"
                        ))
                        .into());
                    }
                } else if !self.tset.is_empty() {
                    return Err(UsageError("--tset needs --tangential NAME".into()).into());
                }
                if let Some(dt) = self.dt {
                    if !(dt.is_finite() && dt > 0.0) {
                        bail!("--dt = {dt} s is out of range: the step must be finite and > 0");
                    }
                }
                if let Some(k) = self.steps_per_collision {
                    crate::dem::integrator::check_steps_per_collision("--steps-per-collision", k)
                        .map_err(anyhow::Error::msg)?;
                }
                self.params()?;
                self.tparams()?;
            }
        }
        Ok(())
    }

    /// The DEM bed at `cfg` (the disks' moduli from --young/--poisson, the step from --dt).
    pub fn dem_bed(&self, cfg: BedConfig) -> crate::dem::bed::DemBed {
        let mut b = crate::dem::bed::DemBed::new(
            BedConfig {
                tangential: None,
                tc: None,
                ..cfg
            },
            self.young,
            self.poisson,
        );
        b.dt = self.dt;
        if let Some(k) = self.steps_per_collision {
            b.steps_per_collision = k;
        }
        b
    }

    /// The DEM engine's laws (--law with --set, --tangential with --tset), bound to `mat`.
    pub fn dem_laws(&self, reg: &Registry, mat: &crate::dem::Material) -> Result<crate::dem::Laws> {
        let (params, tparams) = (self.params()?, self.tparams()?);
        let law = self.law_name()?;
        crate::dem::Laws::from_registry(
            reg,
            (law, params.as_slice()),
            self.tangential.as_deref().map(|t| (t, tparams.as_slice())),
            mat,
        )
        .with_context(|| {
            format!(
                "contact law '{law}'{}",
                self.tangential
                    .as_deref()
                    .map(|t| format!(" with tangential law '{t}'"))
                    .unwrap_or_default()
            )
        })
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
            tangential: self.rough(),
            tc: self.tc,
            seed: self.seed,
            ..BedConfig::paper(layers, freq)
        }
    }

    /// Loads the law and binds it to the bed's pairs (a `from:LAW` table for disks of
    /// --young and --poisson when given, else steel's).
    pub fn laws(&self, reg: &Registry) -> Result<Laws<DynRestitution>> {
        if !(self.diameter.is_finite() && self.diameter > 0.0) {
            bail!("diameter d = {} m is out of range: d must be > 0", self.diameter);
        }
        if !(self.mass.is_finite() && self.mass > 0.0) {
            bail!("mass m = {} kg is out of range: m must be > 0", self.mass);
        }
        let name = self.restitution_name()?;
        Ok(super::resolve_for(reg, name, &self.params()?, &self.particle())?)
    }

    /// The bed's disks: diameter and mass, and the material of --young and --poisson (steel's
    /// where not given).
    pub fn particle(&self) -> dashpot_sdk::Particle {
        let mut p = super::bed_particle(self.diameter, self.mass);
        p.young = self.young.unwrap_or(p.young);
        p.poisson = self.poisson.unwrap_or(p.poisson);
        p
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
        /// The engine: `event` (the paper's figures) or `dem` (the cross-check of the two
        /// engines, and Figs. 2 and 4 with contact laws on soft disks).
        #[arg(long, value_enum, default_value_t = EngineKind::Event)]
        engine: EngineKind,
        /// DEM only: Young's modulus of the disks (Pa); softened from steel's 2e11 so that the
        /// step is ~1.6 µs rather than ~0.1 µs (the report says so).
        #[arg(long, default_value_t = 1e8, allow_hyphen_values = true)]
        young: f64,
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
    a.phys.check()?;
    if a.phys.engine == EngineKind::Dem {
        return bed_dem(reg, a);
    }
    let restitution = a.phys.restitution_name()?;
    let cfg = a.phys.config(a.layers, a.freq);
    cfg.validate()?;
    let laws = a.phys.laws(reg)?;
    // provenance, and the r(v) actually used when it comes from a contact law (issue 10)
    let law_name = restitution.strip_prefix(super::FROM_CONTACT);
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
                    )
                    .and_then(|mut bed| bed.run_protocol(a.phys.transient, a.phys.cycles, &mut |_| {}))
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
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print_report(restitution, &params, &report);
        prov.lines().iter().for_each(|l| println!("{l}"));
        if let Some(t) = &r_used {
            print_r_samples(restitution, t);
        }
    }
    Ok(())
}

/// `dashpot bed --engine dem`: the same bed on soft disks, every contact under the contact law.
fn bed_dem(reg: &Registry, a: &BedArgs) -> Result<()> {
    use crate::dem::bed::DemBedReport;
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
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print_dem_report(law, &params, a.phys.tangential.as_deref(), &tparams, &r);
        prov.lines().iter().for_each(|l| println!("{l}"));
    }
    Ok(())
}

/// The JSON of a DEM bed report: the event-driven bed's keys, `engine: "dem"`, the laws.
pub fn dem_report_json(
    law: &str,
    params: &[ParamValue],
    tangential: Option<&str>,
    tparams: &[ParamValue],
    r: &crate::dem::bed::DemBedReport,
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
    r: &crate::dem::bed::DemBedReport,
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
    a.phys.check()?;
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
    let grid = scaling::Grid {
        layers: a.layers.clone(),
        freqs,
        transient: a.phys.transient,
        cycles: a.phys.cycles,
    };
    let prov = scaling_provenance(reg, &a.phys)?;
    let pb = progress_bar(grid.len() as u64, "scaling (runs)");
    let (rows, law) = match a.phys.engine {
        EngineKind::Event => {
            let laws = a.phys.laws(reg)?;
            let laws = Laws {
                disk: &laws.disk,
                wall: &laws.wall,
            };
            let runs = scaling::run_grid(&laws, &|n, f| a.phys.config(n, f), &grid, &|| pb.inc(1))?;
            std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
            scaling::write_grid_csv(&a.out.join("grid.csv"), &runs, &prov)?;
            (
                scaling::fit_all(&grid, &runs),
                a.phys.restitution_name()?.to_string(),
            )
        }
        EngineKind::Dem => {
            let mat = a.phys.dem_bed(a.phys.config(1.0, 20.0)).material;
            let laws = (0..grid.len())
                .map(|_| a.phys.dem_laws(reg, &mat))
                .collect::<Result<Vec<_>>>()?;
            let runs =
                scaling::run_dem_grid(laws, &|n, f| a.phys.dem_bed(a.phys.config(n, f)), &grid, &|| {
                    pb.inc(1)
                })?;
            std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
            scaling::write_grid_csv(&a.out.join("grid.csv"), &runs, &prov)?;
            let law = format!(
                "DEM {}{}, E = {:.3e} Pa",
                a.phys.law_name()?,
                a.phys
                    .tangential
                    .as_deref()
                    .map(|t| format!(" + {t} {}", a.phys.tset.join(" ")))
                    .unwrap_or_default(),
                mat.young
            );
            (scaling::fit_all(&grid, &runs), law)
        }
    };
    pb.finish_and_clear();
    scaling::write_fit_csv(&a.out.join("scaling.csv"), &rows, &prov)?;
    let title = format!(
        "θ(n): {} {}, g = {} m/s²",
        law,
        a.phys.set.join(" "),
        a.phys.gravity
    );
    Figure::single(scaling::theta_panel(&rows, &title)).save(&a.out, "theta")?;
    if a.json {
        let mut v = scaling::provenance_json(&prov);
        v.insert("exponents".into(), serde_json::to_value(&rows)?);
        println!("{}", serde_json::to_string_pretty(&v)?);
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
        prov.iter().flat_map(|p| p.lines()).for_each(|l| println!("{l}"));
        println!(
            "wrote {}, {} and theta.png/.svg",
            a.out.join("scaling.csv").display(),
            a.out.join("grid.csv").display()
        );
    }
    Ok(())
}

/// The provenance of `dashpot scaling`'s laws: the restitution law (a contact law's own for
/// `from:NAME`), or on the DEM engine the contact law and the tangential law.
fn scaling_provenance(reg: &Registry, phys: &PhysArgs) -> Result<Vec<crate::output::Provenance>> {
    let prov = match phys.engine {
        EngineKind::Event => {
            let r = phys.restitution_name()?;
            let name = r.strip_prefix(super::FROM_CONTACT).unwrap_or(r);
            scaling::provenance(reg, name, &phys.params()?, None)?
        }
        EngineKind::Dem => {
            let t = phys.tparams()?;
            let tangential = phys.tangential.as_deref().map(|n| (n, &t[..]));
            scaling::provenance(reg, phys.law_name()?, &phys.params()?, tangential)?
        }
    };
    prov.iter().for_each(|p| p.warn_if_shadowed());
    Ok(prov)
}

/// `dashpot figures ...`.
pub fn figures(reg: &Registry, cmd: &FiguresCommand) -> Result<()> {
    match cmd {
        FiguresCommand::Bed {
            out,
            quick,
            only,
            engine,
            young,
        } => {
            let size = if *quick {
                super::figures::Size::quick()
            } else {
                super::figures::Size::paper()
            };
            let md = match engine {
                EngineKind::Event => super::figures::run_only(reg, out, &size, only)?,
                EngineKind::Dem => {
                    if !(young.is_finite() && *young > 0.0) {
                        bail!("--young = {young} Pa is out of range: Young's modulus must be finite and > 0");
                    }
                    super::figures::run_dem(reg, out, &size, *young, only)?
                }
            };
            write_atomic(&out.join("report.md"), md.as_bytes())?;
            println!("wrote {}", out.join("report.md").display());
            Ok(())
        }
    }
}
