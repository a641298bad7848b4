//! A law fitted to a measured curve: restitution e(v0) (and optionally contact time t_c(v0)) at
//! several impact speeds, by least squares (Levenberg–Marquardt on the integrator's collisions).
//!
//! The residuals are e_model − e_measured for every point and, where a contact time is given,
//! t_model / t_measured − 1 (relative, so both kinds weigh alike). The free parameters are the
//! law's dissipation parameter (as `calibrate` chooses it, or those named) and, when contact
//! times are given, its stiffness (`k`, or else the pair's Young's modulus). Positive unbounded
//! parameters are fitted in log space; bounded ones stay inside their range. The start is the
//! single-point calibration at the middle speed of the data.

use super::calibrate::{calibrate, fit_name, set, CalibrateError, CalibrateSpec, Model};
use crate::registry::Registry;
use dashpot_sdk::{ParamValue, Range};
use nalgebra::{DMatrix, DVector};

/// One measured impact.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Measurement {
    /// Impact speed v0 (m/s), > 0.
    pub v0: f64,
    /// Measured restitution, in (0, 1].
    pub restitution: f64,
    /// Measured contact time (s), > 0, if any.
    pub contact_time: Option<f64>,
}

/// One point of a fitted curve.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FittedPoint {
    /// The measurement.
    #[serde(flatten)]
    pub measured: Measurement,
    /// The fitted law's restitution at v0 (0 if it captures the particle).
    pub fitted_restitution: f64,
    /// fitted − measured restitution.
    pub residual: f64,
    /// The fitted law's contact time at v0 (s).
    pub fitted_contact_time: f64,
    /// fitted − measured contact time (s), where one was measured.
    pub contact_time_residual: Option<f64>,
}

/// A fitted parameter.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FreeParam {
    /// Its name (`young` for the Young's modulus factor).
    pub name: String,
    /// Its fitted value.
    pub value: f64,
    /// Its standard error from the fit's covariance (s² (JᵀJ)⁻¹, s² the residual variance),
    /// NaN with as many residuals as parameters.
    pub std_error: f64,
}

/// The answer of [`fit_curve`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct CurveFit {
    /// The fitted parameters with their standard errors.
    pub free: Vec<FreeParam>,
    /// The law's parameters, complete.
    pub params: Vec<(String, f64)>,
    /// Factor applied to the Young's moduli (1 unless fitted to contact times through E).
    pub young_factor: f64,
    /// The effective modulus of the fitted pair (Pa).
    pub effective_young: f64,
    /// Every point with its residuals, in the order given.
    pub points: Vec<FittedPoint>,
    /// Root mean square of the restitution residuals.
    pub rms: f64,
    /// Root mean square of the contact time residuals (s), if contact times were given.
    pub rms_contact_time: Option<f64>,
    /// Levenberg–Marquardt iterations.
    pub iterations: usize,
    /// Collisions integrated (the start included).
    pub collisions: usize,
}

/// Reads measurements from CSV text: columns v0 (m/s), e [, contact time (s)], separated by
/// commas (or blanks); a first line that is not numbers is a header; blank lines and lines
/// starting with `#` are skipped.
pub fn parse_measurements(text: &str) -> Result<Vec<Measurement>, CalibrateError> {
    let bad = |m: String| CalibrateError::BadTarget(m);
    let mut out = Vec::new();
    let mut first = true;
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = l
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|c| !c.is_empty())
            .collect();
        let nums: Vec<Option<f64>> = cells.iter().map(|c| c.parse::<f64>().ok()).collect();
        if std::mem::take(&mut first) && nums.iter().all(Option::is_none) {
            continue; // the header
        }
        let row = i + 1;
        if !(2..=3).contains(&cells.len()) {
            return Err(bad(format!(
                "line {row}: '{l}' has {} columns: a measurement is v0 (m/s), e [, contact time (s)]",
                cells.len()
            )));
        }
        let mut v = Vec::with_capacity(3);
        for (c, n) in cells.iter().zip(&nums) {
            v.push(n.ok_or_else(|| bad(format!("line {row}: '{c}' is not a number")))?);
        }
        out.push(Measurement {
            v0: v[0],
            restitution: v[1],
            contact_time: v.get(2).copied(),
        });
    }
    check_measurements(&out)?;
    Ok(out)
}

/// Checks measurements: speeds finite and > 0, restitutions in (0, 1], contact times finite and
/// > 0 and given for every point or none, at least one point.
pub fn check_measurements(data: &[Measurement]) -> Result<(), CalibrateError> {
    let bad = |m: String| Err(CalibrateError::BadTarget(m));
    if data.is_empty() {
        return bad("no measurement: give rows of v0 (m/s), e [, contact time (s)]".into());
    }
    let timed = data[0].contact_time.is_some();
    for (i, m) in data.iter().enumerate() {
        let n = i + 1;
        if !(m.v0.is_finite() && m.v0 > 0.0) {
            return bad(format!(
                "measurement {n}: v0 = {} m/s is out of range: it must be finite and > 0",
                m.v0
            ));
        }
        if !(m.restitution > 0.0 && m.restitution <= 1.0) {
            return bad(format!(
                "measurement {n}: e = {} is out of range: a coefficient of restitution lies in (0, 1]",
                m.restitution
            ));
        }
        match m.contact_time {
            Some(t) if !(t.is_finite() && t > 0.0) => {
                return bad(format!(
                    "measurement {n}: contact time = {t} s is out of range: it must be finite and > 0"
                ))
            }
            t if t.is_some() != timed => {
                return bad(format!(
                    "measurement {n}: give a contact time for every measurement or for none"
                ))
            }
            _ => {}
        }
    }
    Ok(())
}

/// The residuals at a point of the fit and each measurement's (restitution, contact time).
type Evaluated = (DVector<f64>, Vec<(f64, f64)>);

/// One free coordinate of the fit: a law parameter or the Young's modulus factor, in log space
/// when its range is positive and unbounded.
struct Free {
    name: String,
    range: Range,
    log: bool,
}

impl Free {
    fn to_y(&self, x: f64) -> f64 {
        if self.log {
            x.ln()
        } else {
            x
        }
    }

    /// The value of coordinate y, kept strictly inside the range.
    fn to_x(&self, y: f64) -> f64 {
        if self.log {
            return y.exp();
        }
        let w = self.range.max - self.range.min;
        let pad = if w.is_finite() { 1e-12 * w } else { 0.0 };
        let lo = if self.range.min_inclusive {
            self.range.min
        } else {
            self.range.min + pad
        };
        let hi = if self.range.max_inclusive {
            self.range.max
        } else {
            self.range.max - pad
        };
        y.clamp(lo, hi)
    }
}

/// Fits `spec.law` to `data` by least squares. `spec.fit` names the parameter(s) to fit
/// (comma-separated; default as `calibrate`); `spec.restitution`, `spec.contact_time` and
/// `spec.v0` are ignored (the data replace them).
pub fn fit_curve(
    reg: &Registry,
    spec: &CalibrateSpec,
    data: &[Measurement],
) -> Result<CurveFit, CalibrateError> {
    check_measurements(data)?;
    let (entry, _) = reg.find(&spec.law)?;
    let schema = entry.info.params.clone();
    let names: Vec<String> = schema.iter().map(|s| s.name.to_string()).collect();
    let timed = data[0].contact_time.is_some();
    let mut frees = Vec::new();
    let asked: Vec<String> = match spec.fit.as_deref() {
        Some(f) => f
            .split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect(),
        None => vec![fit_name(&spec.law, &names, None)?],
    };
    for n in &asked {
        let n = fit_name(&spec.law, &names, Some(n))?;
        let range = schema
            .iter()
            .find(|s| s.name == n.as_str())
            .map(|s| s.range)
            .unwrap_or(Range::positive());
        if frees.iter().any(|f: &Free| f.name == n) {
            return Err(CalibrateError::BadTarget(format!("--fit names '{n}' twice")));
        }
        frees.push(Free {
            log: range.min >= 0.0 && range.max.is_infinite(),
            name: n,
            range,
        });
    }
    if timed {
        let (name, range) = if names.iter().any(|n| n == "k") {
            (
                "k",
                schema
                    .iter()
                    .find(|s| s.name == "k")
                    .map(|s| s.range)
                    .unwrap_or(Range::positive()),
            )
        } else {
            ("young", Range::positive())
        };
        if !frees.iter().any(|f| f.name == name) {
            frees.push(Free {
                name: name.into(),
                range,
                log: true,
            });
        }
    }
    let young = frees.iter().any(|f| f.name == "young");
    let residual_count = data.len() * if timed { 2 } else { 1 };
    if residual_count < frees.len() {
        return Err(CalibrateError::BadTarget(format!(
            "{} measurement(s) cannot fix {} parameters ({}): give at least as many values as parameters",
            data.len(),
            frees.len(),
            frees
                .iter()
                .map(|f| f.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }

    // the start: the single-point calibration at the middle speed, else the given values
    let mut by_speed: Vec<&Measurement> = data.iter().collect();
    by_speed.sort_by(|a, b| a.v0.total_cmp(&b.v0));
    let mid = by_speed[by_speed.len() / 2];
    let start_spec = CalibrateSpec {
        restitution: mid.restitution,
        contact_time: mid.contact_time,
        v0: mid.v0,
        fit: Some(frees[0].name.clone()),
        ..spec.clone()
    };
    let mut collisions = 0;
    let (params, young_factor): (Vec<ParamValue>, f64) = match calibrate(reg, &start_spec) {
        Ok(c) => {
            collisions += c.collisions;
            (
                c.params
                    .iter()
                    .map(|(k, v)| ParamValue::new(k, *v))
                    .collect::<Vec<_>>(),
                c.young_factor,
            )
        }
        Err(_) => (spec.fixed.clone(), 1.0),
    };
    let value = |params: &[ParamValue], yf: f64, f: &Free| -> f64 {
        if f.name == "young" && young {
            return yf;
        }
        params
            .iter()
            .find(|p| p.name == f.name.as_str())
            .map(|p| p.value)
            .or_else(|| {
                schema
                    .iter()
                    .find(|s| s.name == f.name.as_str())
                    .and_then(|s| s.default)
            })
            .unwrap_or(1.0)
    };
    let mut y = DVector::from_iterator(
        frees.len(),
        frees.iter().map(|f| f.to_y(value(&params, young_factor, f))),
    );

    let mut runs = 0;
    // the parameters and Young's factor at coordinates y
    let at = |y: &DVector<f64>, base: &[ParamValue]| -> (Vec<ParamValue>, f64) {
        let mut p = base.to_vec();
        let mut yf = 1.0;
        for (f, &yi) in frees.iter().zip(y.iter()) {
            if f.name == "young" && young {
                yf = f.to_x(yi);
            } else {
                set(&mut p, &f.name, f.to_x(yi));
            }
        }
        (p, yf)
    };
    let base = params.clone();
    let eval = |y: &DVector<f64>, runs: &mut usize| -> Result<Evaluated, CalibrateError> {
        let (p, yf) = at(y, &base);
        let mut r = Vec::with_capacity(residual_count);
        let mut out = Vec::with_capacity(data.len());
        for m in data {
            let (e, t) = at_speed(reg, spec, &p, yf, m.v0)?;
            *runs += 1;
            r.push(e - m.restitution);
            if let Some(tm) = m.contact_time {
                // a contact that never ends counts as a contact time of 0
                r.push(if t.is_finite() { t / tm - 1.0 } else { -1.0 });
            }
            out.push((e, t));
        }
        Ok((DVector::from_vec(r), out))
    };

    let (mut r, _) = eval(&y, &mut runs)?;
    let mut cost = r.norm_squared();
    let mut lambda: f64 = 1e-3;
    let mut iterations = 0;
    let mut jac = DMatrix::zeros(residual_count, frees.len());
    let mut converged = false;
    while iterations < 200 {
        iterations += 1;
        // forward differences
        for j in 0..frees.len() {
            let h = 1e-6 * y[j].abs().max(1.0);
            let mut yj = y.clone();
            yj[j] += h;
            let (rj, _) = eval(&yj, &mut runs)?;
            jac.set_column(j, &((rj - &r) / h));
        }
        let jtj = jac.transpose() * &jac;
        let g = jac.transpose() * &r;
        if g.amax() <= 1e-15 * (1.0 + cost) {
            converged = true;
            break;
        }
        let mut stepped = false;
        while lambda < 1e16 {
            let mut a = jtj.clone();
            for i in 0..frees.len() {
                a[(i, i)] += lambda * jtj[(i, i)].max(1e-300);
            }
            let Some(d) = a.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let y_new = &y + &d;
            // coordinates clamped into their ranges
            let y_new = DVector::from_iterator(
                frees.len(),
                frees
                    .iter()
                    .zip(y_new.iter())
                    .map(|(f, &v)| if f.log { v } else { f.to_x(v) }),
            );
            let (r_new, _) = eval(&y_new, &mut runs)?;
            let c_new = r_new.norm_squared();
            if c_new <= cost {
                let small = (&y_new - &y)
                    .iter()
                    .zip(y.iter())
                    .all(|(dy, yi)| dy.abs() <= 1e-10 * yi.abs().max(1.0));
                y = y_new;
                r = r_new;
                let drop = cost - c_new;
                cost = c_new;
                lambda = (lambda / 10.0).max(1e-12);
                stepped = true;
                converged = small || drop <= 1e-15 * cost.max(f64::MIN_POSITIVE);
                break;
            }
            lambda *= 10.0;
        }
        if !stepped {
            // no step lowers the cost: a minimum to the integrator's resolution
            converged = true;
        }
        if converged {
            break;
        }
    }
    if !converged {
        return Err(CalibrateError::BadTarget(format!(
            "the least-squares fit of '{}' did not converge in {iterations} iterations (rms residual {:.3e})",
            spec.law,
            (cost / residual_count as f64).sqrt()
        )));
    }
    let (params, young_factor) = at(&y, &base);
    let (_, outs) = eval(&y, &mut runs)?;
    // standard errors: s² (JᵀJ)⁻¹ in y, mapped to x
    let dof = residual_count as f64 - frees.len() as f64;
    let cov = (jac.transpose() * &jac).try_inverse();
    let free = frees
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let x = f.to_x(y[j]);
            let sy = match (&cov, dof > 0.0) {
                (Some(c), true) => (c[(j, j)] * cost / dof).sqrt(),
                _ => f64::NAN,
            };
            FreeParam {
                name: f.name.clone(),
                value: x,
                std_error: if f.log { x * sy } else { sy },
            }
        })
        .collect();
    let points: Vec<FittedPoint> = data
        .iter()
        .zip(&outs)
        .map(|(m, &(e, t))| FittedPoint {
            measured: *m,
            fitted_restitution: e,
            residual: e - m.restitution,
            fitted_contact_time: t,
            contact_time_residual: m.contact_time.map(|tm| t - tm),
        })
        .collect();
    let n = points.len() as f64;
    let rms = (points.iter().map(|p| p.residual * p.residual).sum::<f64>() / n).sqrt();
    let rms_contact_time = timed.then(|| {
        (points
            .iter()
            .filter_map(|p| p.contact_time_residual)
            .map(|r| r * r)
            .sum::<f64>()
            / n)
            .sqrt()
    });
    Ok(CurveFit {
        free,
        params: super::calibrate::complete(&params, &schema),
        young_factor,
        effective_young: spec.pair.young * young_factor,
        points,
        rms,
        rms_contact_time,
        iterations,
        collisions: collisions + runs,
    })
}

/// The restitution and contact time (s) of the fitted law at each of `speeds` (m/s), for drawing
/// its curve: restitution 0 where it captures the particle.
pub fn fitted_curve(
    reg: &Registry,
    spec: &CalibrateSpec,
    fit: &CurveFit,
    speeds: &[f64],
) -> Result<Vec<(f64, f64)>, CalibrateError> {
    let params: Vec<ParamValue> = fit.params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect();
    speeds
        .iter()
        .map(|&v0| at_speed(reg, spec, &params, fit.young_factor, v0))
        .collect()
}

/// The restitution (0 for a capture) and contact time (s; NaN if the contact never ends) of
/// `spec.law` with `params` and Young's factor `young_factor` at impact speed `v0` (m/s).
fn at_speed(
    reg: &Registry,
    spec: &CalibrateSpec,
    params: &[ParamValue],
    young_factor: f64,
    v0: f64,
) -> Result<(f64, f64), CalibrateError> {
    let sub = CalibrateSpec { v0, ..spec.clone() };
    let mut m = Model {
        reg,
        spec: &sub,
        runs: 0,
    };
    match m.run(params, young_factor) {
        Ok(c) if c.stuck => Ok((0.0, c.contact_time)),
        Ok(c) => Ok((c.restitution, c.contact_time)),
        Err(CalibrateError::Collide(super::CollideError::NoReturn { .. })) => Ok((0.0, f64::NAN)),
        Err(e) => Err(e),
    }
}
