//! `dashpot calibrate --data FILE.csv`: a law fitted to a measured curve e(v0) [and t_c(v0)] by
//! least squares, with each point's residual and a figure of the data and the fitted curve.

use super::args::Selection;
use super::collide::CalibrateArgs;
use crate::collide::calibrate::CalibrateSpec;
use crate::collide::fit_curve::{fit_curve, fitted_curve, parse_measurements, CurveFit};
use crate::output::write_atomic;
use crate::registry::Registry;
use crate::report::plot::{Figure, Mark, Panel, Series};
use anyhow::{Context, Result};
use dashpot_sdk::ParamValue;
use serde_json::json;
use std::path::Path;

/// Points of the drawn fitted curve.
const CURVE_POINTS: usize = 60;

/// Fits the selected law to the curve in `file`.
pub fn run(reg: &Registry, a: &CalibrateArgs, sel: &Selection, file: &Path) -> Result<()> {
    let text = std::fs::read_to_string(file)
        .with_context(|| format!("--data {}: cannot read it", file.display()))?;
    let data = parse_measurements(&text).with_context(|| format!("--data {}", file.display()))?;
    let spec = CalibrateSpec {
        law: sel.name.clone(),
        fixed: sel.params.clone(),
        pair: sel.pair,
        shear: sel.materials.shear,
        restitution: data[0].restitution,
        contact_time: None,
        v0: data[0].v0,
        end: a.integration.end_for(reg, &sel.name)?,
        fit: a.fit.clone(),
        options: a.integration.options()?,
    };
    let fit = fit_curve(reg, &spec, &data)
        .with_context(|| format!("fitting '{}' to {}", sel.name, file.display()))?;
    let fitted: Vec<ParamValue> = fit.params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect();
    let prov = crate::output::Provenance::of(reg, &sel.name, &fitted)?;
    prov.warn_if_shadowed();
    write_outputs(reg, &spec, &fit, &a.out)?;
    let young = sel.particle.young * fit.young_factor;
    if a.json {
        let params: serde_json::Map<String, serde_json::Value> =
            fit.params.iter().map(|(k, v)| (k.clone(), json!(v))).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "law": sel.name, "method": "least squares", "data": file.display().to_string(),
                "end": spec.end.as_str(), "fitted": fit.free, "params": params,
                "young": young, "effective_young": fit.effective_young,
                "points": fit.points, "rms": fit.rms, "rms_contact_time": fit.rms_contact_time,
                "iterations": fit.iterations, "collisions": fit.collisions,
                "figure": a.out.join("calibration.png").display().to_string(),
                "provenance": prov.json(),
            }))?
        );
        return Ok(());
    }
    println!(
        "law: {} (least squares over {} points of {}; end of contact: {})",
        sel.name,
        fit.points.len(),
        file.display(),
        spec.end.as_str()
    );
    for f in &fit.free {
        if f.name == "young" {
            println!(
                "  Young's modulus E = {young:.10e} Pa (E_eff = {:.10e} Pa, factor {:.10e} ± {:.2e})",
                fit.effective_young, f.value, f.std_error
            );
        } else {
            println!("  {} = {:.12e} ± {:.2e} (fitted)", f.name, f.value, f.std_error);
        }
    }
    for (k, v) in fit
        .params
        .iter()
        .filter(|(k, _)| !fit.free.iter().any(|f| &f.name == k))
    {
        println!("  {k} = {v:.12e}");
    }
    let timed = fit.rms_contact_time.is_some();
    println!(
        "  {:>12}  {:>12}  {:>14}  {:>10}{}",
        "v0 (m/s)",
        "e measured",
        "e fitted",
        "residual",
        if timed {
            "   t_c measured (s)  t_c fitted (s)  residual (s)"
        } else {
            ""
        }
    );
    for p in &fit.points {
        let t = match p.measured.contact_time {
            Some(tm) => format!(
                "   {tm:>17.6e}  {:>14.6e}  {:>+12.3e}",
                p.fitted_contact_time,
                p.contact_time_residual.unwrap_or(f64::NAN)
            ),
            None => String::new(),
        };
        println!(
            "  {:>12.6e}  {:>12.6}  {:>14.10}  {:>+10.3e}{t}",
            p.measured.v0, p.measured.restitution, p.fitted_restitution, p.residual
        );
    }
    println!(
        "rms residual: restitution {:.3e}{}",
        fit.rms,
        fit.rms_contact_time
            .map(|r| format!(", contact time {r:.3e} s"))
            .unwrap_or_default()
    );
    println!(
        "iterations: {}, collisions integrated: {}",
        fit.iterations, fit.collisions
    );
    println!(
        "figure: {} (and .svg); points: {}",
        a.out.join("calibration.png").display(),
        a.out.join("calibration.csv").display()
    );
    prov.lines().iter().skip(1).for_each(|l| println!("{l}"));
    Ok(())
}

/// Writes `out/calibration.csv` (each point with its fitted values and residuals) and
/// `out/calibration.png/.svg` (the data and the fitted curve; the contact times beside).
fn write_outputs(reg: &Registry, spec: &CalibrateSpec, fit: &CurveFit, out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("--out {}: cannot create it", out.display()))?;
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "v0_m_per_s",
        "e_measured",
        "e_fitted",
        "e_residual",
        "contact_time_measured_s",
        "contact_time_fitted_s",
        "contact_time_residual_s",
    ])?;
    let opt = |x: Option<f64>| x.map(|v| v.to_string()).unwrap_or_default();
    for p in &fit.points {
        w.write_record(&[
            p.measured.v0.to_string(),
            p.measured.restitution.to_string(),
            p.fitted_restitution.to_string(),
            p.residual.to_string(),
            opt(p.measured.contact_time),
            p.fitted_contact_time.to_string(),
            opt(p.contact_time_residual),
        ])?;
    }
    write_atomic(&out.join("calibration.csv"), &w.into_inner().context("csv")?)?;

    let (lo, hi) = fit.points.iter().fold((f64::INFINITY, 0.0f64), |(l, h), p| {
        (l.min(p.measured.v0), h.max(p.measured.v0))
    });
    let log_x = hi > 10.0 * lo;
    let speeds: Vec<f64> = (0..CURVE_POINTS)
        .map(|i| {
            let t = i as f64 / (CURVE_POINTS - 1) as f64;
            if log_x {
                lo * (hi / lo).powf(t)
            } else {
                lo + (hi - lo) * t
            }
        })
        .collect();
    let curve = fitted_curve(reg, spec, fit, &speeds)?;
    let named: Vec<String> = fit
        .free
        .iter()
        .map(|f| format!("{} = {:.6e}", f.name, f.value))
        .collect();
    let panel = |y_label: &str, measured: Vec<(f64, f64)>, model: Vec<(f64, f64)>| Panel {
        title: format!("{}: {} (rms {:.2e})", spec.law, named.join(", "), fit.rms),
        x_label: "impact speed v0 (m/s)".into(),
        y_label: y_label.into(),
        log_x,
        series: vec![
            Series::new("measured", measured, Mark::Circles, 1),
            Series::new("fitted law", model, Mark::Line, 0),
        ],
        ..Panel::default()
    };
    let mut panels = vec![panel(
        "coefficient of restitution e",
        fit.points
            .iter()
            .map(|p| (p.measured.v0, p.measured.restitution))
            .collect(),
        speeds.iter().zip(&curve).map(|(&v, &(e, _))| (v, e)).collect(),
    )];
    if fit.rms_contact_time.is_some() {
        panels.push(panel(
            "contact time (s)",
            fit.points
                .iter()
                .filter_map(|p| p.measured.contact_time.map(|t| (p.measured.v0, t)))
                .collect(),
            speeds
                .iter()
                .zip(&curve)
                .filter(|(_, (_, t))| t.is_finite())
                .map(|(&v, &(_, t))| (v, t))
                .collect(),
        ));
    }
    let columns = panels.len();
    Figure::in_columns(panels, columns).save(out, "calibration")?;
    Ok(())
}
