//! `dashpot.calibrate`: a law fitted to a measured restitution, as the CLI's `calibrate --json`.

use super::*;
use dashpot::collide::Options;

/// Fits a law's parameters to a measured restitution (and optionally contact time) at impact
/// speed `v0` (m/s), as `dashpot calibrate --json` does: law `name` with the `fixed`
/// parameters, the particle (diameter m, density kg/m³, Young's modulus Pa, Poisson's ratio)
/// against an identical one or a wall. Returns the CLI's JSON as a string.
#[pyfunction]
#[pyo3(signature = (name, fixed, restitution, contact_time, v0, body, end, fit, rtol))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn calibrate(
    py: Python<'_>,
    name: &str,
    fixed: Option<&Bound<'_, PyDict>>,
    restitution: f64,
    contact_time: Option<f64>,
    v0: f64,
    body: Body,
    end: Option<&str>,
    fit: Option<String>,
    rtol: f64,
) -> PyResult<String> {
    use dashpot::collide::calibrate::{calibrate as fit_law, CalibrateSpec};
    let p = params_of(fixed)?;
    let (pair, mats) = (body.pair()?, body.materials()?);
    with_registry(py, |reg| {
        let declared = reg.end_criterion(name).map_err(law_err)?;
        let end = super::runs::end_of(end, declared)?;
        let spec = CalibrateSpec {
            law: name.to_string(),
            fixed: p.clone(),
            pair,
            shear: mats.shear,
            restitution,
            contact_time,
            v0,
            end,
            fit,
            options: Options {
                rtol,
                ..Options::default()
            },
        };
        let c = fit_law(reg, &spec).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let (params, prov) = fitted_json(reg, name, &c.params)?;
        Ok(serde_json::json!({
            "law": name, "method": c.method, "params": params,
            "young": body.2 * c.young_factor, "effective_young": c.effective_young, "v0": v0,
            "end": end.as_str(),
            "target_restitution": restitution, "target_contact_time": contact_time,
            "restitution": c.realized.restitution, "contact_time": c.realized.contact_time,
            "max_overlap": c.realized.max_overlap,
            "restitution_residual": c.restitution_residual,
            "contact_time_residual": c.contact_time_residual,
            "collisions": c.collisions, "provenance": prov.json(),
        })
        .to_string())
    })
}

/// Fits a law's parameters to a measured curve by least squares, as `dashpot calibrate --data
/// FILE.csv --json` does (without the figure): the measurements as `rows` of v0 (m/s), e [,
/// contact time (s)], or the CSV file at `path`; `fit` names the parameter(s) to fit,
/// comma-separated (default: the law's dissipation parameter, and its stiffness when contact
/// times are given). Returns the JSON as a string.
#[pyfunction]
#[pyo3(signature = (name, fixed, rows, path, body, end, fit, rtol))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn calibrate_curve(
    py: Python<'_>,
    name: &str,
    fixed: Option<&Bound<'_, PyDict>>,
    rows: Option<Vec<Vec<f64>>>,
    path: Option<std::path::PathBuf>,
    body: Body,
    end: Option<&str>,
    fit: Option<String>,
    rtol: f64,
) -> PyResult<String> {
    use dashpot::collide::calibrate::CalibrateSpec;
    use dashpot::collide::fit_curve::{check_measurements, fit_curve, parse_measurements, Measurement};
    let bad = |e: dashpot::collide::calibrate::CalibrateError| PyValueError::new_err(e.to_string());
    let data = match (rows, path) {
        (Some(rows), None) => {
            let mut data = Vec::with_capacity(rows.len());
            for (i, r) in rows.iter().enumerate() {
                if !(2..=3).contains(&r.len()) {
                    return Err(PyValueError::new_err(format!(
                        "data row {i} has {} values: a measurement is v0 (m/s), e [, contact time (s)]",
                        r.len()
                    )));
                }
                data.push(Measurement {
                    v0: r[0],
                    restitution: r[1],
                    contact_time: r.get(2).copied(),
                });
            }
            check_measurements(&data).map_err(bad)?;
            data
        }
        (None, Some(p)) => {
            let text = std::fs::read_to_string(&p).map_err(|e| {
                PyValueError::new_err(format!("data = '{}': cannot read it: {e}", p.display()))
            })?;
            parse_measurements(&text)
                .map_err(|e| PyValueError::new_err(format!("data = '{}': {e}", p.display())))?
        }
        _ => {
            return Err(PyValueError::new_err(
                "give the data as rows or as a path, not both",
            ))
        }
    };
    let options = super::runs::options(rtol)?;
    let p = params_of(fixed)?;
    let (pair, mats) = (body.pair()?, body.materials()?);
    let reg = registry(py)?;
    let declared = reg.end_criterion(name).map_err(law_err)?;
    let end = super::runs::end_of(end, declared)?;
    let spec = CalibrateSpec {
        law: name.to_string(),
        fixed: p,
        pair,
        shear: mats.shear,
        restitution: data[0].restitution,
        contact_time: None,
        v0: data[0].v0,
        end,
        fit,
        options,
    };
    let reg: &Registry = &reg;
    let c = py.allow_threads(|| fit_curve(reg, &spec, &data)).map_err(bad)?;
    let (params, prov) = fitted_json(reg, name, &c.params)?;
    Ok(serde_json::json!({
        "law": name, "method": "least squares", "end": end.as_str(), "fitted": c.free,
        "params": params, "young": body.2 * c.young_factor, "effective_young": c.effective_young,
        "points": c.points, "rms": c.rms, "rms_contact_time": c.rms_contact_time,
        "iterations": c.iterations, "collisions": c.collisions, "provenance": prov.json(),
    })
    .to_string())
}

/// A fit's parameters as the JSON object the CLI prints, and the provenance of the law with them.
fn fitted_json(
    reg: &Registry,
    name: &str,
    params: &[(String, f64)],
) -> PyResult<(serde_json::Map<String, serde_json::Value>, Provenance)> {
    let fitted: Vec<ParamValue> = params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect();
    let prov = Provenance::of(reg, name, &fitted).map_err(law_err)?;
    let json = params
        .iter()
        .map(|(k, v)| (k.clone(), serde_json::json!(v)))
        .collect();
    Ok((json, prov))
}
