//! The vibrated bed as one experiment: a [`BedSpec`] says which bed (geometry, frequency,
//! gravity, disks), which engine with which laws, and the protocol (transient, measured periods,
//! seeds); either engine runs it and reports the same [`BedObservables`](super::observables).
//! `dashpot bed`, `dashpot dem --bed` and `dashpot scaling` build one and check it here
//! ([`BedSpec::validate`]), the one place where a bed's values are checked before a run.

use super::engine::BedConfig;
use super::on_dem::DemBed;
use super::{bed_particle, resolve_for, DynRestitution, Laws};
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use dashpot_sdk::{ParamValue, Particle};

/// A law chosen by name, with the parameters the user set.
#[derive(Debug, Clone, PartialEq)]
pub struct LawChoice {
    /// The law's name (see `dashpot laws`).
    pub name: String,
    /// The parameters set (the others take their defaults).
    pub params: Vec<ParamValue>,
}

impl LawChoice {
    /// `name` with `params`.
    pub fn new(name: &str, params: Vec<ParamValue>) -> LawChoice {
        LawChoice {
            name: name.to_string(),
            params,
        }
    }

    /// The law as `name` or `name + tangential` with the parameters set: ` NAME a=1 b=2`.
    pub fn describe(&self) -> String {
        let ps: String = self
            .params
            .iter()
            .map(|p| format!(" {}={}", p.name, p.value))
            .collect();
        format!("{}{ps}", self.name)
    }
}

/// The engine that runs the bed, with its laws.
#[derive(Debug, Clone, PartialEq)]
pub enum BedEngine {
    /// Event-driven hard disks: instantaneous collisions under a restitution law (or a contact
    /// law's r(v) as `from:NAME`); rough disks and the TC model come with the [`BedConfig`].
    Event {
        /// The restitution law.
        restitution: LawChoice,
    },
    /// Soft-sphere DEM: every contact under a contact law over time, with optional friction
    /// and rolling resistance.
    Dem {
        /// The contact law.
        law: LawChoice,
        /// The tangential law, if any.
        tangential: Option<LawChoice>,
        /// The rolling-resistance law, if any.
        rolling: Option<LawChoice>,
        /// The step (s), or chosen from the law.
        dt: Option<f64>,
        /// Steps per collision when the step is chosen (default 50).
        steps_per_collision: Option<f64>,
    },
}

/// The most seeds a bed experiment runs (each a whole run: more would not end).
pub const MAX_SEEDS: usize = 100_000;

/// One bed experiment, run by either engine.
#[derive(Debug, Clone, PartialEq)]
pub struct BedSpec {
    /// The bed: geometry, frequency, gravity, disks' diameter and mass, seed (and, for the
    /// event-driven engine, rough disks and the TC model).
    pub config: BedConfig,
    /// Young's modulus of the disks (Pa; steel's when not given): the DEM engine's disks, and
    /// the particle a `from:LAW` table is computed for.
    pub young: Option<f64>,
    /// Poisson's ratio of the disks (0.3 when not given), like `young`.
    pub poisson: Option<f64>,
    /// The engine and its laws.
    pub engine: BedEngine,
    /// Transient periods, not measured.
    pub transient: f64,
    /// Measured periods.
    pub cycles: f64,
    /// Independent seeds (seed, seed + 1, ...) averaged.
    pub seeds: usize,
}

impl BedSpec {
    /// Checks every value of the experiment, each error naming the value (as the `bed` command's
    /// option that sets it) and its valid range: the protocol, the seeds, the disks' material,
    /// the bed's configuration, and what each engine takes (the DEM engine's step; no rough
    /// disks or TC model on soft disks).
    pub fn validate(&self) -> Result<()> {
        BedConfig::check_protocol(self.transient, self.cycles).map_err(|e| anyhow::anyhow!("--{e}"))?;
        if self.seeds == 0 || self.seeds > MAX_SEEDS {
            bail!(
                "--seeds = {} is out of range: give 1 to {MAX_SEEDS} seeds",
                self.seeds
            );
        }
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
        if let BedEngine::Dem {
            dt,
            steps_per_collision,
            ..
        } = &self.engine
        {
            self.dem_bed(self.config).check()?;
            if let Some(dt) = dt {
                if !(dt.is_finite() && *dt > 0.0) {
                    bail!("--dt = {dt} s is out of range: the step must be finite and > 0");
                }
            }
            if let Some(k) = steps_per_collision {
                crate::dem::integrator::check_steps_per_collision("--steps-per-collision", *k)
                    .map_err(anyhow::Error::msg)?;
            }
        } else {
            self.config.validate()?;
        }
        Ok(())
    }

    /// The bed at `layers` and `freq` (Hz), the rest as specified (what a grid of runs varies).
    pub fn at(&self, layers: f64, freq: f64) -> BedConfig {
        BedConfig {
            layers,
            freq,
            ..self.config
        }
    }

    /// The disks: the bed's diameter and mass, of the given material (steel's where not given).
    pub fn particle(&self) -> Particle {
        let mut p = bed_particle(self.config.diameter, self.config.mass);
        p.young = self.young.unwrap_or(p.young);
        p.poisson = self.poisson.unwrap_or(p.poisson);
        p
    }

    /// The restitution law of the event-driven engine, bound to the bed's pairs (a `from:LAW`
    /// table for the disks of [`BedSpec::particle`]).
    pub fn restitution_laws(&self, reg: &Registry) -> Result<Laws<DynRestitution>> {
        let BedEngine::Event { restitution } = &self.engine else {
            bail!("the DEM engine takes a contact law, not a restitution law");
        };
        Ok(resolve_for(reg, restitution, &self.particle())?)
    }

    /// The DEM bed at `cfg` (the disks' moduli, the step).
    pub fn dem_bed(&self, cfg: BedConfig) -> DemBed {
        let mut b = DemBed::new(cfg, self.young, self.poisson);
        if let BedEngine::Dem {
            dt,
            steps_per_collision,
            ..
        } = &self.engine
        {
            b.dt = *dt;
            if let Some(k) = steps_per_collision {
                b.steps_per_collision = *k;
            }
        }
        b
    }

    /// The DEM engine's laws (the contact law, with the tangential and rolling laws if any),
    /// bound to `mat`.
    pub fn dem_laws(&self, reg: &Registry, mat: &crate::dem::Material) -> Result<crate::dem::Laws> {
        let BedEngine::Dem {
            law,
            tangential,
            rolling,
            ..
        } = &self.engine
        else {
            bail!("the event-driven engine takes a restitution law, not a contact law");
        };
        fn pair(c: &Option<LawChoice>) -> Option<(&str, &[ParamValue])> {
            c.as_ref().map(|c| (c.name.as_str(), c.params.as_slice()))
        }
        crate::dem::Laws::from_registry(reg, (&law.name, &law.params), pair(tangential), mat)
            .and_then(|l| l.with_rotation(reg, pair(rolling), None, mat))
            .with_context(|| {
                let with = |what: &str, c: &Option<LawChoice>| {
                    c.as_ref()
                        .map(|c| format!(" {what} '{}'", c.name))
                        .unwrap_or_default()
                };
                format!(
                    "contact law '{}'{}{}",
                    law.name,
                    with("with tangential law", tangential),
                    with("and rolling law", rolling)
                )
            })
    }
}
