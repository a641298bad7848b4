//! The arguments of `dashpot bed`, `scaling` and `figures bed`: the physics, the seeds, the
//! engine and the output choices.

use crate::bed::engine::BedConfig;
use crate::bed::spec::{BedEngine, BedSpec, LawChoice};
use anyhow::Result;
use clap::{Args, Subcommand};
use dashpot_sdk::ParamValue;
use std::path::PathBuf;

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
    /// A rolling-resistance law of the DEM engine's contacts (--engine dem), e.g. rolling-sds;
    /// its parameters by --rset.
    #[arg(long, value_name = "NAME")]
    pub rolling: Option<String>,
    /// Set a parameter of the rolling law (--engine dem), NAME=VALUE (repeatable).
    #[arg(long = "rset", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub rset: Vec<String>,
    /// The disks' material and the DEM step.
    #[command(flatten)]
    pub disks: DiskArgs,
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

/// The disks' material and the DEM step, shared by `dashpot bed` (and `scaling`) and
/// `dashpot dem --bed`.
#[derive(Args, Debug, Clone)]
pub struct DiskArgs {
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
}

/// Independent seeds for `dashpot bed`.
#[derive(Args, Debug, Clone)]
pub struct SeedArgs {
    /// Run K independent seeds (SEED, SEED+1, ...) in parallel and report their mean, with
    /// standard errors from their spread (K = 1: batch means over the measured periods).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub seeds: usize,
}

/// `NAME=VALUE` options as parameters.
pub(crate) fn param_values(sets: &[String]) -> Result<Vec<ParamValue>> {
    let sets = crate::config::parse_sets(sets).map_err(|e| crate::cli::UsageError(e.to_string()))?;
    Ok(crate::config::merge_params(&Default::default(), &sets))
}

/// The DEM engine's tangential law from `--tangential NAME` and `--tset`: a law by name (not a
/// tangential restitution, which is the event-driven engine's), and `--tset` only with one.
pub(crate) fn dem_tangential(name: Option<&str>, tset: &[String]) -> Result<Option<LawChoice>> {
    use crate::cli::UsageError;
    match name {
        Some(t) if t.trim().parse::<f64>().is_ok() => Err(UsageError(format!(
            "--tangential {t}: with --engine dem give a tangential law by name (e.g. mindlin, parameters by --tset mu=0.3), not a tangential restitution"
        ))
        .into()),
        Some(t) => Ok(Some(LawChoice::new(t, param_values(tset)?))),
        None if !tset.is_empty() => Err(UsageError("--tset needs --tangential NAME".into()).into()),
        None => Ok(None),
    }
}

impl PhysArgs {
    /// The experiment at `layers` and `freq` (Hz) with `seeds` seeds: each engine's options are
    /// refused by the other, with the value named; the values themselves are checked by
    /// [`BedSpec::validate`].
    pub fn spec(&self, layers: f64, freq: f64, seeds: usize) -> Result<BedSpec> {
        use crate::cli::UsageError;
        let engine = match self.engine {
            EngineKind::Event => {
                let name = self.restitution.as_deref().ok_or_else(|| {
                    UsageError(
                        "the event-driven bed needs --restitution LAW (e.g. mcnamara-falcon, or from:kuwabara-kono); a contact law over time is --engine dem --law NAME".into(),
                    )
                })?;
                if let Some(l) = &self.law {
                    return Err(UsageError(format!(
                        "--law {l} is the DEM engine's: add --engine dem (or give the event-driven engine a --restitution law)"
                    ))
                    .into());
                }
                for (flag, given) in [
                    ("--dt", self.disks.dt.is_some()),
                    ("--steps-per-collision", self.steps_per_collision.is_some()),
                    ("--tset", !self.tset.is_empty()),
                    ("--rolling", self.rolling.is_some()),
                    ("--rset", !self.rset.is_empty()),
                ] {
                    if given {
                        return Err(
                            UsageError(format!("{flag} is the DEM engine's: add --engine dem")).into(),
                        );
                    }
                }
                if (self.disks.young.is_some() || self.disks.poisson.is_some())
                    && !name.starts_with(crate::bed::FROM_CONTACT)
                {
                    return Err(UsageError(format!(
                        "--young/--poisson reach the event-driven engine only through a contact law's table, --restitution from:LAW; --restitution '{name}' names a restitution law r(v), which does not use them"
                    ))
                    .into());
                }
                if let Some(t) = &self.tangential {
                    // its range is the bed configuration's to check (BedConfig::validate)
                    if t.trim().parse::<f64>().is_err() {
                        return Err(UsageError(format!(
                            "--tangential '{t}' is not a number: with --engine event it is the tangential restitution r_t in [-1, 1]; a tangential law by name needs --engine dem"
                        ))
                        .into());
                    }
                }
                BedEngine::Event {
                    restitution: LawChoice::new(name, param_values(&self.set)?),
                }
            }
            EngineKind::Dem => {
                let law = self.law.as_deref().ok_or_else(|| {
                    UsageError("--engine dem needs --law NAME (a contact law, e.g. hsd)".into())
                })?;
                if let Some(r) = &self.restitution {
                    return Err(UsageError(format!(
                        "--restitution {r} is the event-driven engine's: --engine dem takes a contact law, --law NAME"
                    ))
                    .into());
                }
                BedEngine::Dem {
                    law: LawChoice::new(law, param_values(&self.set)?),
                    tangential: dem_tangential(self.tangential.as_deref(), &self.tset)?,
                    rolling: self
                        .rolling
                        .as_deref()
                        .map(|r| Ok::<_, anyhow::Error>(LawChoice::new(r, param_values(&self.rset)?)))
                        .transpose()?,
                    dt: self.disks.dt,
                    steps_per_collision: self.steps_per_collision,
                }
            }
        };
        let rough = match engine {
            BedEngine::Event { .. } => self.tangential.as_deref().and_then(|s| s.trim().parse().ok()),
            BedEngine::Dem { .. } => None,
        };
        Ok(BedSpec {
            config: BedConfig {
                layers,
                freq,
                gravity: self.gravity,
                amplitude: self.amplitude,
                width: self.width,
                diameter: self.diameter,
                mass: self.mass,
                headroom: self.headroom,
                tangential: rough,
                tc: self.tc,
                seed: self.seed,
                ..BedConfig::paper(layers, freq)
            },
            young: self.disks.young,
            poisson: self.disks.poisson,
            engine,
            transient: self.transient,
            cycles: self.cycles,
            seeds,
        })
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
    /// Estimate the run and stop: the disks, the peak memory, and the wall time from a timed
    /// sample of the bed's own run on this machine (about a second); nothing is written.
    #[arg(long)]
    pub check: bool,
    /// The limits of a long run (`--max-hours`).
    #[command(flatten)]
    pub limits: crate::cli::budget::LimitArgs,
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
    /// The limits of a long run (`--max-hours`).
    #[command(flatten)]
    pub limits: crate::cli::budget::LimitArgs,
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
    if k > 1_000_000 {
        anyhow::bail!("--freqs '{s}': COUNT = {k} is out of range: at most 1000000 frequencies");
    }
    if k == 1 {
        return Ok(vec![a]);
    }
    Ok((0..k).map(|i| a + (b - a) * i as f64 / (k - 1) as f64).collect())
}
