//! The arguments of `dashpot bed`, `scaling` and `figures bed`: the physics, the seeds, the
//! engine and the output choices.

use crate::bed::engine::BedConfig;
use crate::bed::{DynRestitution, Laws};
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
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
                    ("--rolling", self.rolling.is_some()),
                    ("--rset", !self.rset.is_empty()),
                ] {
                    if given {
                        return Err(
                            UsageError(format!("{flag} is the DEM engine's: add --engine dem")).into(),
                        );
                    }
                }
                if (self.young.is_some() || self.poisson.is_some())
                    && !name.starts_with(crate::bed::FROM_CONTACT)
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
    pub fn dem_bed(&self, cfg: BedConfig) -> crate::bed::on_dem::DemBed {
        let mut b = crate::bed::on_dem::DemBed::new(
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
        let sets =
            crate::config::parse_sets(&self.rset).map_err(|e| crate::cli::UsageError(e.to_string()))?;
        let rparams = crate::config::merge_params(&Default::default(), &sets);
        crate::dem::Laws::from_registry(
            reg,
            (law, params.as_slice()),
            self.tangential.as_deref().map(|t| (t, tparams.as_slice())),
            mat,
        )
        .and_then(|l| {
            l.with_rotation(
                reg,
                self.rolling.as_deref().map(|r| (r, rparams.as_slice())),
                None,
                mat,
            )
        })
        .with_context(|| {
            format!(
                "contact law '{law}'{}",
                self.tangential
                    .as_deref()
                    .map(|t| format!(" with tangential law '{t}'"))
                    .unwrap_or_default()
                    + &self
                        .rolling
                        .as_deref()
                        .map(|r| format!(" and rolling law '{r}'"))
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
        Ok(crate::bed::resolve_for(
            reg,
            name,
            &self.params()?,
            &self.particle(),
        )?)
    }

    /// The bed's disks: diameter and mass, and the material of --young and --poisson (steel's
    /// where not given).
    pub fn particle(&self) -> dashpot_sdk::Particle {
        let mut p = crate::bed::bed_particle(self.diameter, self.mass);
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
