//! `dashpot collide` and `dashpot calibrate` (`dashpot sweep` is in [`super::sweep`]).

use super::args::{LawArgs, Selection};
use crate::collide::calibrate::{calibrate, CalibrateSpec};
use crate::collide::two_body::{collide, Collision, Options, PairLaw};
use crate::output::write_atomic;
use crate::registry::Registry;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use dashpot_sdk::{EndCriterion, ParamValue};
use serde_json::json;
use std::path::PathBuf;

/// When a contact ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EndArg {
    /// The overlap returns to 0 (Antypov & Elliott's convention).
    Overlap,
    /// The total force returns to 0 on rebound (no attraction).
    Force,
}

impl From<EndArg> for EndCriterion {
    fn from(e: EndArg) -> Self {
        match e {
            EndArg::Overlap => EndCriterion::Overlap,
            EndArg::Force => EndCriterion::Force,
        }
    }
}

/// Integration options shared by the collision commands.
#[derive(Args, Debug, Clone)]
pub struct IntegrationArgs {
    /// When contact ends: when the overlap returns to 0, or when the force does. Default: the
    /// criterion the law declares (`dashpot laws LAW`; overlap if it declares none), the one
    /// `calibrate` fits it by, so that a calibrated law reproduces its target in `collide`.
    #[arg(long, value_enum)]
    pub end: Option<EndArg>,
    /// Relative tolerance per step, in [1e-14, 1e-3]; the realized restitution is accurate to
    /// about 20× this.
    #[arg(long, default_value_t = 1e-11)]
    pub rtol: f64,
}

impl IntegrationArgs {
    /// Validated options.
    pub fn options(&self) -> Result<Options> {
        if !(1e-14..=1e-3).contains(&self.rtol) {
            bail!(
                "--rtol = {} is out of range: it must lie in [1e-14, 1e-3]",
                self.rtol
            );
        }
        Ok(Options {
            rtol: self.rtol,
            ..Options::default()
        })
    }

    /// The end criterion, `default` if none was given.
    pub fn end_or(&self, default: EndCriterion) -> EndCriterion {
        self.end.map(EndCriterion::from).unwrap_or(default)
    }

    /// The end criterion for law `law`: `--end`, or else the one the law declares.
    pub fn end_for(&self, reg: &Registry, law: &str) -> Result<EndCriterion> {
        Ok(self.end_or(reg.end_criterion(law)?))
    }

    /// Where the end criterion came from, for the output: "given" or "declared by 'LAW'".
    pub fn end_source(&self, law: &str) -> String {
        end_source(self.end.is_some(), law)
    }
}

/// Where a run's end criterion came from: "given" (`--end`, Python's `end=`) or "declared by
/// 'LAW'" (the law's `END_CRITERION`).
pub fn end_source(given: bool, law: &str) -> String {
    if given {
        "given".to_string()
    } else {
        format!("declared by '{law}'")
    }
}

/// `dashpot collide`.
#[derive(Args, Debug)]
pub struct CollideArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// Impact speed v0 (m/s): the relative normal speed at first contact.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub v0: f64,
    #[command(flatten)]
    pub integration: IntegrationArgs,
    /// Write the trajectory (t, δ, δ̇, F at every step and event) to this CSV file.
    #[arg(long, value_name = "FILE.csv")]
    pub trajectory: Option<PathBuf>,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
    /// A tangential (friction) law composed with the contact law (see `dashpot laws`): an
    /// oblique impact of solid spheres with rotation. `--set NAME=VALUE` looks NAME up in the
    /// contact law, then in the tangential law; write `LAW.NAME=VALUE` for a name both have.
    #[arg(long, value_name = "NAME")]
    pub tangential: Option<String>,
    /// Angle of incidence from the normal (degrees, in [0, 90)); with `--v0` the speed of
    /// approach. Above 0 (or with --tangential) the impact is oblique.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub angle: f64,
    /// Initial spin of the particle (rad/s), positive in the sense of rolling along the incident
    /// tangential direction (oblique impacts).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub spin: f64,
    /// Time steps per contact time of the oblique integrator (velocity Verlet), ≥ 100.
    #[arg(long, default_value_t = 20_000)]
    pub steps: usize,
    /// A rolling-resistance law (see `dashpot laws`): instead of an impact, the particle is
    /// launched at `--v0` rolling without slip on a wall under gravity until the law stops it
    /// (needs `--tangential` for the friction that makes it roll).
    #[arg(long, value_name = "NAME")]
    pub rolling: Option<String>,
    /// A parameter of the rolling law, NAME=VALUE (repeatable).
    #[arg(long = "rset", value_name = "NAME=VALUE", value_parser = crate::config::set_arg)]
    pub rset: Vec<String>,
    /// Gravity pressing the rolling particle on the wall (m/s², > 0; with `--rolling`).
    #[arg(long, default_value_t = 9.81)]
    pub gravity: f64,
    /// The heat exchanged during the impact (`--heat LAW --t1 K --t2 K --heat-capacity C`).
    #[command(flatten)]
    pub heat: super::collide_heat::HeatArgs,
}

pub(crate) fn check_v0(v0: f64) -> Result<f64> {
    if !(v0.is_finite() && v0 > 0.0) {
        bail!("--v0 = {v0} m/s is out of range: the impact speed must be finite and > 0");
    }
    Ok(v0)
}

/// One collision of the selected law.
pub fn run_one(
    reg: &Registry,
    sel: &Selection,
    v0: f64,
    end: EndCriterion,
    opt: &Options,
) -> Result<Collision> {
    let law = reg.contact(&sel.name, &sel.params)?;
    let bound = PairLaw::new(law.bind(&sel.materials)?, sel.pair.mass, sel.pair.radius);
    collide(&bound, sel.pair.mass, v0, end, opt).with_context(|| {
        format!(
            "collision of '{}' at v0 = {v0} m/s (end: {})",
            sel.name,
            end.as_str()
        )
    })
}

/// The CSV of a trajectory.
pub fn trajectory_csv(c: &Collision) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["t_s", "delta_m", "rate_m_per_s", "force_N"])?;
    for s in &c.trajectory {
        w.write_record(&[
            s.t.to_string(),
            s.delta.to_string(),
            s.rate.to_string(),
            s.force.to_string(),
        ])?;
    }
    w.into_inner().context("csv")
}

/// `dashpot collide`.
pub fn run_collide(reg: &Registry, a: &CollideArgs) -> Result<()> {
    let v0 = check_v0(a.v0)?;
    if a.heat.heat.is_some() {
        return super::collide_heat::run_heat(reg, a, v0);
    }
    if a.rolling.is_some() {
        return super::roll::run_rolling(reg, a, v0);
    }
    if a.tangential.is_some() || a.angle != 0.0 {
        return run_oblique(reg, a, v0);
    }
    let sel = a.law.resolve()?;
    let mut opt = a.integration.options()?;
    opt.record = a.trajectory.is_some();
    if opt.record {
        opt.max_step_fraction = 0.01;
    }
    let end = a.integration.end_for(reg, &sel.name)?;
    let prov = sel.provenance(reg)?;
    let c = run_one(reg, &sel, v0, end, &opt)?;
    if let Some(p) = &a.trajectory {
        let csv = [prov.csv_comment().into_bytes(), trajectory_csv(&c)?].concat();
        write_atomic(p, &csv)?;
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "params": prov.params_json(), "pair": sel.pair_json(),
                "v0": v0, "end": end.as_str(), "end_source": a.integration.end_source(&sel.name),
                "restitution": c.restitution, "contact_time": c.contact_time,
                "max_overlap": c.max_overlap, "max_overlap_time": c.max_overlap_time,
                "stuck": c.stuck, "tensile_peak": c.tensile_peak,
                "steps": c.steps, "force_evals": c.force_evals, "rtol": opt.rtol,
                "provenance": prov.json(),
            }))?
        );
    } else {
        prov.lines().iter().for_each(|l| println!("{l}"));
        println!(
            "pair: {}: m_eff = {:.6e} kg, r_eff = {:.6e} m, E_eff = {:.6e} Pa",
            sel.partner, sel.pair.mass, sel.pair.radius, sel.pair.young
        );
        println!("impact speed v0       = {v0} m/s");
        println!(
            "end of contact        : {} ({}; {})",
            end.as_str(),
            match end {
                EndCriterion::Overlap => "overlap returns to 0",
                EndCriterion::Force => "force returns to 0",
            },
            match a.integration.end {
                Some(_) => "given by --end".to_string(),
                None => a.integration.end_source(&sel.name),
            }
        );
        if c.stuck {
            println!("restitution           = 0 (stuck: the rebound turned back before pull-off)");
            println!("stuck at              t = {:.10e} s", c.contact_time);
        } else {
            println!("restitution           = {:.12}", c.restitution);
            println!("contact time          = {:.10e} s", c.contact_time);
        }
        if let Some(f) = c.tensile_peak {
            println!("most tensile force    = {f:.10e} N");
        }
        println!(
            "maximum overlap       = {:.10e} m at t = {:.10e} s",
            c.max_overlap, c.max_overlap_time
        );
        println!("steps, force calls    = {}, {}", c.steps, c.force_evals);
        if let Some(p) = &a.trajectory {
            println!(
                "trajectory            : {} ({} points)",
                p.display(),
                c.trajectory.len()
            );
        }
    }
    Ok(())
}

/// `dashpot calibrate`.
#[derive(Args, Debug)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// Measured coefficient of restitution, in (0, 1] (or --data).
    #[arg(long, allow_hyphen_values = true, required_unless_present = "data")]
    pub restitution: Option<f64>,
    /// Measured contact time (s); fits the stiffness too (k, or else the Young's modulus).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "data")]
    pub contact_time: Option<f64>,
    /// A measured curve instead of one point: a CSV file of rows v0 (m/s), e [, contact time
    /// (s)] (a header line is allowed), fitted by least squares; prints the fitted parameters
    /// and each point's residual, and draws the data and the fitted curve into --out.
    #[arg(long, value_name = "FILE.csv", conflicts_with = "restitution")]
    pub data: Option<PathBuf>,
    /// With --data: the folder for calibration.png/.svg (data and fitted curve) and
    /// calibration.csv (each point with its fitted value and residual).
    #[arg(long, value_name = "DIR", default_value = "calibration")]
    pub out: PathBuf,
    /// Impact speed of the measurement (m/s).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub v0: f64,
    /// The law parameter to fit to the restitution. Default: `eps` if the law has one, else
    /// `damp` (LAMMPS's `gran-*` laws), else its only parameter other than `k`; a law with
    /// several others needs --fit NAME. With --data,
    /// a comma-separated list fits several (e.g. --fit A,k).
    #[arg(long)]
    pub fit: Option<String>,
    #[command(flatten)]
    pub integration: IntegrationArgs,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
}

/// `dashpot calibrate`.
pub fn run_calibrate(reg: &Registry, a: &CalibrateArgs) -> Result<()> {
    let sel = a.law.resolve()?;
    let restitution = match (a.restitution, &a.data) {
        (_, Some(file)) => return super::calibrate_data::run(reg, a, &sel, file),
        (Some(e), None) => e,
        (None, None) => {
            bail!("give the measured --restitution E (and --v0), or a curve with --data FILE.csv")
        }
    };
    let spec = CalibrateSpec {
        law: sel.name.clone(),
        fixed: sel.params.clone(),
        pair: sel.pair,
        shear: sel.materials.shear,
        restitution,
        contact_time: a.contact_time,
        v0: a.v0,
        end: a.integration.end_for(reg, &sel.name)?,
        fit: a.fit.clone(),
        options: a.integration.options()?,
    };
    let c = calibrate(reg, &spec)?;
    let fitted: Vec<ParamValue> = c.params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect();
    let prov = crate::output::Provenance::of(reg, &sel.name, &fitted)?;
    prov.warn_if_shadowed();
    let young = sel.particle.young * c.young_factor;
    if a.json {
        let params: serde_json::Map<String, serde_json::Value> =
            c.params.iter().map(|(k, v)| (k.clone(), json!(v))).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "method": c.method, "params": params,
                "young": young, "effective_young": c.effective_young, "v0": a.v0,
                "end": spec.end.as_str(),
                "target_restitution": restitution, "target_contact_time": a.contact_time,
                "restitution": c.realized.restitution, "contact_time": c.realized.contact_time,
                "max_overlap": c.realized.max_overlap,
                "restitution_residual": c.restitution_residual,
                "contact_time_residual": c.contact_time_residual,
                "collisions": c.collisions, "provenance": prov.json(),
            }))?
        );
    } else {
        println!(
            "law: {} ({}; end of contact: {})",
            sel.name,
            c.method,
            spec.end.as_str()
        );
        for (k, v) in &c.params {
            println!("  {k} = {v:.12e}");
        }
        if let (Some(t), true) = (a.contact_time, c.young_factor != 1.0) {
            println!(
                "  Young's modulus E = {young:.10e} Pa (E_eff = {:.10e} Pa), fitted to the contact time {t:e} s",
                c.effective_young
            );
        }
        println!(
            "check at v0 = {} m/s: restitution {:.12} (residual {:+.2e}, tolerance {:.0e}), contact time {:.10e} s{}",
            a.v0,
            c.realized.restitution,
            c.restitution_residual,
            crate::collide::calibrate::fit_tolerance(&spec.options),
            c.realized.contact_time,
            c.contact_time_residual
                .map(|r| format!(" (residual {r:+.2e} s)"))
                .unwrap_or_default()
        );
        println!("collisions integrated: {}", c.collisions);
        prov.lines().iter().skip(1).for_each(|l| println!("{l}"));
    }
    Ok(())
}

/// The `--set` values split between the contact law and the tangential law: a name is looked up
/// in the contact law's schema, then in the tangential law's; `LAW.NAME` names the law.
pub(super) fn split_sets(
    reg: &Registry,
    normal: &str,
    tangential: Option<&str>,
    sets: &[String],
) -> Result<(Vec<String>, Vec<ParamValue>)> {
    let schema = |law: &str| -> Result<Vec<String>> {
        Ok(reg
            .find(law)?
            .0
            .info
            .params
            .iter()
            .map(|p| p.name.to_string())
            .collect())
    };
    let ns = schema(normal)?;
    let ts = match tangential {
        Some(t) => schema(t)?,
        None => Vec::new(),
    };
    let (mut to_normal, mut to_tangential) = (Vec::new(), Vec::new());
    for s in sets {
        let (k, v) = crate::config::parse_set(s)?;
        let (law, key) = match k.split_once('.') {
            Some((l, key)) => (Some(l.to_string()), key.to_string()),
            None => (None, k.clone()),
        };
        let target = match law.as_deref() {
            Some(l) if l == normal => 'n',
            Some(l) if Some(l) == tangential => 't',
            Some(l) => bail!(
                "--set {s}: '{l}' is neither the contact law '{normal}' nor the tangential law{}",
                tangential.map(|t| format!(" '{t}'")).unwrap_or_default()
            ),
            None => match (ns.contains(&key), ts.contains(&key)) {
                (true, true) => bail!(
                    "--set {s}: both '{normal}' and '{}' have a parameter '{key}'; write \
                     --set {normal}.{key}={v} or --set {}.{key}={v}",
                    tangential.unwrap_or_default(),
                    tangential.unwrap_or_default()
                ),
                (false, true) => 't',
                _ => 'n',
            },
        };
        if target == 't' {
            if to_tangential.iter().any(|p: &ParamValue| p.name == key.as_str()) {
                bail!("--set {s}: parameter '{key}' is set twice");
            }
            to_tangential.push(ParamValue::new(&key, v));
        } else {
            to_normal.push(format!("{key}={v}"));
        }
    }
    Ok((to_normal, to_tangential))
}

/// `dashpot collide --angle/--tangential`: an oblique impact of solid spheres.
fn run_oblique(reg: &Registry, a: &CollideArgs, v0: f64) -> Result<()> {
    use crate::collide::oblique::{oblique, Body, Impact, Target};
    if !(a.angle.is_finite() && (0.0..90.0).contains(&a.angle)) {
        bail!(
            "--angle = {}° is out of range: the angle of incidence must lie in [0, 90)",
            a.angle
        );
    }
    if a.trajectory.is_some() {
        bail!("--trajectory is for head-on collisions; an oblique impact reports its end state");
    }
    let normal = match &a.law.law {
        Some(n) => n.clone(),
        None => a.law.resolve()?.name,
    };
    let (nsets, tparams) = split_sets(reg, &normal, a.tangential.as_deref(), &a.law.set)?;
    let mut la = a.law.clone();
    la.set = nsets;
    let sel = la.resolve()?;
    let end = a.integration.end_for(reg, &sel.name)?;
    let model = reg.contact(&sel.name, &sel.params)?.bind(&sel.materials)?;
    let tmodel = match &a.tangential {
        Some(t) => Some(reg.tangential(t, &tparams)?.bind(&sel.materials)?),
        None => None,
    };
    let (m1, r1) = (sel.particle.mass(), sel.particle.radius());
    let particle = Body::solid_sphere(m1, r1);
    let wall = a.law.particle.wall || sel.pair.radius == r1 && sel.pair.mass == m1;
    let target = if wall {
        Target::Wall
    } else {
        // the partner from the effective pair: m2 = m1 m/(m1 − m), r2 = r1 r/(r1 − r)
        let (m, r) = (sel.pair.mass, sel.pair.radius);
        Target::Sphere(Body::solid_sphere(m1 * m / (m1 - m), r1 * r / (r1 - r)))
    };
    let impact = Impact {
        speed: v0,
        angle: a.angle.to_radians(),
        spin: a.spin,
        end,
        steps: a.steps,
    };
    let c = oblique(&model, tmodel.as_ref(), &particle, &target, &impact)
        .with_context(|| format!("oblique impact of '{}' at v0 = {v0} m/s, {}°", sel.name, a.angle))?;
    let prov = sel.provenance(reg)?;
    let tprov = match &a.tangential {
        Some(t) => Some(crate::output::Provenance::of(reg, t, &tparams)?),
        None => None,
    };
    let tjson: serde_json::Map<String, serde_json::Value> = tparams
        .iter()
        .map(|p| (p.name.to_string(), json!(p.value)))
        .collect();
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "params": sel.params_json(), "pair": sel.pair_json(),
                "tangential": a.tangential, "tangential_params": tjson,
                "v0": v0, "angle": a.angle, "spin_in": a.spin, "end": end.as_str(),
                "partner": if wall { "wall" } else { "sphere" },
                "restitution": c.restitution, "stuck": c.stuck, "contact_time": c.contact_time,
                "max_overlap": c.max_overlap,
                "normal_velocity_in": c.normal_velocity_in,
                "tangential_velocity_in": c.tangential_velocity_in,
                "tangential_velocity_out": c.tangential_velocity_out,
                "angular_velocity_out": c.angular_velocity_out,
                "partner_angular_velocity_out": c.partner_angular_velocity_out,
                "rebound_angle": c.rebound_angle,
                "contact_point_velocity_out": c.contact_point_velocity_out,
                "sliding_share": c.sliding_share,
                "dt": c.dt, "steps": c.steps,
                "provenance": prov.json(), "tangential_provenance": tprov.as_ref().map(|p| p.json()),
            }))?
        );
    } else {
        println!(
            "law: {} {} + tangential {} {}",
            sel.name,
            sel.params_json(),
            a.tangential.as_deref().unwrap_or("(none: frictionless)"),
            serde_json::Value::Object(tjson)
        );
        println!(
            "pair: {}: m_eff = {:.6e} kg, r_eff = {:.6e} m, E_eff = {:.6e} Pa, G_eff = {:.6e} Pa",
            sel.partner, sel.pair.mass, sel.pair.radius, sel.pair.young, sel.materials.shear
        );
        println!(
            "impact: {v0} m/s at {}° from the normal (v_n = {:.6} m/s, v_t = {:.6} m/s), spin {} rad/s",
            a.angle, c.normal_velocity_in, c.tangential_velocity_in, a.spin
        );
        println!("end of contact         : {}", end.as_str());
        if c.stuck {
            println!("normal restitution     = 0 (stuck: the rebound turned back before pull-off)");
        } else {
            println!("normal restitution     = {:.8}", c.restitution);
        }
        println!("tangential velocity out= {:.8} m/s", c.tangential_velocity_out);
        println!("angular velocity out   = {:.8} rad/s", c.angular_velocity_out);
        println!("rebound angle          = {:.6}°", c.rebound_angle);
        println!(
            "contact-point velocity = {:.8} m/s (tangential, after)",
            c.contact_point_velocity_out
        );
        println!(
            "sliding share          = {:.4} of the steps in contact",
            c.sliding_share
        );
        println!(
            "contact time           = {:.8e} s ({} velocity-Verlet steps of {:.3e} s)",
            c.contact_time, c.steps, c.dt
        );
        let tlines = tprov.iter().flat_map(|p| p.lines());
        for l in prov.lines().into_iter().chain(tlines) {
            println!("{l}");
        }
    }
    Ok(())
}
