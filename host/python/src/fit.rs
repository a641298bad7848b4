//! `dashpot.calibrate`: a law fitted to a measured restitution, as the CLI's `calibrate --json`.

use super::*;
use dashpot::collide::Options;
use dashpot_sdk::EndCriterion;

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
        let declared = reg
            .find(name)
            .map_err(law_err)?
            .0
            .info
            .end_criterion
            .unwrap_or(EndCriterion::Overlap);
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
        let fitted: Vec<ParamValue> = c.params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect();
        let prov = Provenance::of(reg, name, &fitted).map_err(law_err)?;
        let params: serde_json::Map<String, serde_json::Value> = c
            .params
            .iter()
            .map(|(k, v)| (k.clone(), serde_json::json!(v)))
            .collect();
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
