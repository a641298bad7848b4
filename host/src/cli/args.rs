//! The arguments that choose a law, its parameters and the particles it acts on, shared by the
//! commands (kept apart from the command dispatch so that the command modules import it, not
//! each other).

use crate::config::{merge_params, parse_sets, Config, Partner, Sphere, Wall};
use crate::output::Provenance;
use crate::registry::Registry;
use anyhow::{Context, Result};
use clap::Args;
use dashpot_sdk::{MaterialPair, Pair, ParamValue, Particle};
use serde_json::json;
use std::path::PathBuf;

/// A malformed command line found after parsing (a parameter set twice, ...): exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(pub String);

/// The two particles of a pair (identical spheres by default) or a particle and a wall.
#[derive(Args, Debug, Clone)]
pub struct ParticleArgs {
    /// Particle diameter (m). Default: 0.01 (the MCC granule of Antypov & Elliott).
    #[arg(long, allow_hyphen_values = true)]
    pub diameter: Option<f64>,
    /// Particle density (kg/m³). Default: 1500.
    #[arg(long, allow_hyphen_values = true)]
    pub density: Option<f64>,
    /// Young's modulus (Pa). Default: 6e9.
    #[arg(long, allow_hyphen_values = true)]
    pub young: Option<f64>,
    /// Poisson's ratio, in (-1, 0.5). Default: 0.3.
    #[arg(long, allow_hyphen_values = true)]
    pub poisson: Option<f64>,
    /// The particle hits a flat rigid wall (infinite mass) instead of an identical sphere.
    #[arg(long)]
    pub wall: bool,
}

impl ParticleArgs {
    /// The particle and the pair, from the command line over the file over the MCC defaults.
    pub fn resolve(&self, cfg: &Config) -> Result<(Particle, Pair, MaterialPair, String)> {
        let d = Particle::MCC;
        let f = &cfg.particle;
        let p = Particle {
            diameter: self.diameter.or(f.diameter).unwrap_or(d.diameter),
            density: self.density.or(f.density).unwrap_or(d.density),
            young: self.young.or(f.young).unwrap_or(d.young),
            poisson: self.poisson.or(f.poisson).unwrap_or(d.poisson),
        };
        p.validate()?;
        let (wall, sphere) = (Wall {}, Sphere::default());
        let partner: &dyn Partner = if self.wall {
            &wall
        } else {
            cfg.partner.as_deref().unwrap_or(&sphere)
        };
        let pair = partner.pair(&p)?;
        let materials = partner.materials(&p)?;
        Ok((p, pair, materials, partner.describe(&p)))
    }
}

/// A law chosen by name, its parameters, and the pair it acts on.
#[derive(Args, Debug, Clone)]
pub struct LawArgs {
    /// The law (see `dashpot laws`); may come from --config instead.
    #[arg(long)]
    pub law: Option<String>,
    /// Set a law parameter, NAME=VALUE (repeatable, once per parameter; overrides --config).
    /// Parameters not set keep the defaults `dashpot law NAME` lists.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub set: Vec<String>,
    /// TOML file with [law], [particle] and [partner] tables.
    #[arg(long)]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub particle: ParticleArgs,
}

/// A resolved [`LawArgs`].
#[derive(Debug, Clone)]
pub struct Selection {
    /// The law's name.
    pub name: String,
    /// Its parameters (file values overridden by --set).
    pub params: Vec<ParamValue>,
    /// The particle.
    pub particle: Particle,
    /// The effective pair.
    pub pair: Pair,
    /// The pair's effective moduli (what a contact or tangential law binds to).
    pub materials: MaterialPair,
    /// What the particle hits, in words.
    pub partner: String,
}

impl LawArgs {
    /// Reads the config file, merges `--set`, resolves the particle and the pair.
    pub fn resolve(&self) -> Result<Selection> {
        let cfg = match &self.config {
            Some(p) => Config::from_file(p)?,
            None => Config::default(),
        };
        let name = self
            .law
            .clone()
            .or(cfg.law.name.clone())
            .context("no law given: use --law NAME (see `dashpot laws`) or a [law] name in --config")?;
        let sets = parse_sets(&self.set).map_err(|e| UsageError(e.to_string()))?;
        let params = merge_params(&cfg.law.params, &sets);
        let (particle, pair, materials, partner) = self.particle.resolve(&cfg)?;
        Ok(Selection {
            name,
            params,
            particle,
            pair,
            materials,
            partner,
        })
    }
}

impl Selection {
    /// Where a result computed with this selection comes from (see [`Provenance`]); warns on
    /// stderr if the law's name is shadowed.
    pub fn provenance(&self, reg: &Registry) -> Result<Provenance> {
        let p = Provenance::of(reg, &self.name, &self.params)?;
        p.warn_if_shadowed();
        Ok(p)
    }

    /// The parameters as a JSON object.
    pub fn params_json(&self) -> serde_json::Value {
        let m: serde_json::Map<String, serde_json::Value> = self
            .params
            .iter()
            .map(|p| (p.name.to_string(), json!(p.value)))
            .collect();
        serde_json::Value::Object(m)
    }

    /// The pair as a JSON object.
    pub fn pair_json(&self) -> serde_json::Value {
        json!({"mass": self.pair.mass, "radius": self.pair.radius, "young": self.pair.young, "partner": self.partner})
    }
}
