//! `dashpot collide --heat LAW --t1 K --t2 K --heat-capacity C`: the heat two bodies exchange
//! during a head-on impact (see [`crate::collide::heat`]).

use super::collide::CollideArgs;
use crate::collide::heat::{impact_heat, HeatImpact};
use crate::collide::oblique::{Body, Target};
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use clap::Args;
use dashpot_sdk::{EndCriterion, ParamValue};
use serde_json::json;

/// The heat options of `dashpot collide`.
#[derive(Args, Debug, Clone, Default)]
pub struct HeatArgs {
    /// A heat-conduction law (sdk 0.4, e.g. heat-radius; see `dashpot laws`): the impact reports
    /// the heat the two bodies exchange through the contact and their temperatures after.
    #[arg(long, value_name = "NAME")]
    pub heat: Option<String>,
    /// A parameter of the heat law, NAME=VALUE (repeatable), e.g. k=40.
    #[arg(long = "hset", value_name = "NAME=VALUE", requires = "heat", value_parser = crate::config::set_arg)]
    pub hset: Vec<String>,
    /// The particle's temperature before the impact (K).
    #[arg(long, value_name = "K", requires = "heat", allow_hyphen_values = true)]
    pub t1: Option<f64>,
    /// The partner's (or the wall's) temperature before the impact (K).
    #[arg(long, value_name = "K", requires = "heat", allow_hyphen_values = true)]
    pub t2: Option<f64>,
    /// The specific heat capacity of both bodies' material (J/(kg·K)): C = m c.
    #[arg(long, value_name = "J/(kg·K)", requires = "heat", allow_hyphen_values = true)]
    pub heat_capacity: Option<f64>,
}

/// `dashpot collide --heat`.
pub fn run_heat(reg: &Registry, a: &CollideArgs, v0: f64) -> Result<()> {
    let h = &a.heat;
    let name = h.heat.as_deref().context("--heat LAW")?;
    let (Some(t1), Some(t2), Some(c)) = (h.t1, h.t2, h.heat_capacity) else {
        bail!("--heat needs --t1 K, --t2 K (the two temperatures before the impact) and --heat-capacity J/(kg·K)");
    };
    if a.tangential.is_some() || a.angle != 0.0 || a.rolling.is_some() {
        bail!("--heat is a head-on impact: it takes no --tangential, --angle or --rolling");
    }
    if !(c.is_finite() && c > 0.0) {
        bail!("--heat-capacity = {c} J/(kg·K) is out of range: it must be finite and > 0");
    }
    for (k, t) in [("--t1", t1), ("--t2", t2)] {
        if !(t.is_finite() && t >= 0.0) {
            bail!("{k} = {t} K is out of range: it must be finite and >= 0");
        }
    }
    let sel = a.law.resolve()?;
    let hparams = h
        .hset
        .iter()
        .map(|s| crate::config::parse_set(s).map(|(k, v)| ParamValue::new(&k, v)))
        .collect::<Result<Vec<_>, _>>()?;
    let end = a.integration.end_or(
        reg.find(&sel.name)?
            .0
            .info
            .end_criterion
            .unwrap_or(EndCriterion::Overlap),
    );
    let model = reg.contact(&sel.name, &sel.params)?.bind(&sel.materials)?;
    let hmodel = reg
        .heat(name, &hparams)
        .and_then(|l| l.bind(&sel.materials))
        .with_context(|| format!("the heat law '{name}'"))?;
    let (m1, r1) = (sel.particle.mass(), sel.particle.radius());
    let particle = Body::solid_sphere(m1, r1);
    let wall = a.law.particle.wall || sel.pair.radius == r1 && sel.pair.mass == m1;
    let (target, m2) = if wall {
        (Target::Wall, f64::INFINITY)
    } else {
        // the partner from the effective pair: m2 = m1 m/(m1 − m), r2 = r1 r/(r1 − r)
        let (m, r) = (sel.pair.mass, sel.pair.radius);
        let m2 = m1 * m / (m1 - m);
        (Target::Sphere(Body::solid_sphere(m2, r1 * r / (r1 - r))), m2)
    };
    let imp = HeatImpact {
        speed: v0,
        end,
        steps: a.steps,
        temperature: [t1, t2],
        capacity: [m1 * c, m2 * c],
    };
    let x = impact_heat(&model, &hmodel, &particle, &target, &imp).with_context(|| {
        format!(
            "impact of '{}' at v0 = {v0} m/s conducting through '{name}'",
            sel.name
        )
    })?;
    let hjson: serde_json::Map<String, serde_json::Value> = hparams
        .iter()
        .map(|p| (p.name.to_string(), json!(p.value)))
        .collect();
    let prov = sel.provenance(reg)?;
    let hprov = crate::output::Provenance::of(reg, name, &hparams)?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "params": sel.params_json(), "pair": sel.pair_json(),
                "heat": name, "heat_params": hjson, "v0": v0, "end": end.as_str(),
                "partner": if wall { "wall" } else { "sphere" },
                "temperature_in": [t1, t2], "temperature_out": x.temperature,
                "heat_capacity": c, "capacity": [imp.capacity[0], (!wall).then_some(imp.capacity[1])],
                "heat_exchanged": x.heat, "conductance_time": x.conductance_time,
                "max_conductance": x.max_conductance, "contact_time": x.contact_time,
                "restitution": x.restitution, "dt": x.dt, "steps": x.steps,
                "provenance": prov.json(), "heat_provenance": hprov.json(),
            }))?
        );
    } else {
        println!(
            "law: {} {} + heat {name} {}",
            sel.name,
            sel.params_json(),
            serde_json::Value::Object(hjson)
        );
        println!(
            "pair: {}: m_eff = {:.6e} kg, r_eff = {:.6e} m; C1 = {:.6e} J/K{}",
            sel.partner,
            sel.pair.mass,
            sel.pair.radius,
            imp.capacity[0],
            if wall {
                ", the wall a reservoir".to_string()
            } else {
                format!(", C2 = {:.6e} J/K", imp.capacity[1])
            }
        );
        println!("impact speed v0        = {v0} m/s (end: {})", end.as_str());
        println!("heat into the particle = {:.10e} J (the partner gave it)", x.heat);
        println!(
            "temperatures           = {t1} K, {t2} K -> {:.10} K, {:.10} K",
            x.temperature[0], x.temperature[1]
        );
        println!(
            "∫ H dt                 = {:.10e} J/K (largest H {:.6e} W/K)",
            x.conductance_time, x.max_conductance
        );
        println!(
            "contact time           = {:.8e} s ({} velocity-Verlet steps of {:.3e} s), restitution {:.8}",
            x.contact_time, x.steps, x.dt, x.restitution
        );
        for l in prov.lines().into_iter().chain(hprov.lines()) {
            println!("{l}");
        }
    }
    Ok(())
}
