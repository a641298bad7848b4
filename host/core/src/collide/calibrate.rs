//! Calibration: the law parameters that reproduce a measured restitution (and contact time).
//!
//! A law's own closed form is used when it offers one (for example LSD: ε → eps, τ → k); any
//! other law is fitted numerically through the integrator: its dissipation parameter for the
//! restitution and its stiffness (a parameter `k`, or else the pair's Young's modulus) for the
//! contact time, alternating until both match to 1e-9 relative.

use super::two_body::{collide, CollideError, Collision, Options, PairLaw};
use crate::registry::Registry;
use dashpot_sdk::{
    CalibrationTarget, EndCriterion, LawError, LawKind, MaterialPair, Pair, ParamValue, Range,
};

/// What to calibrate.
#[derive(Debug, Clone)]
pub struct CalibrateSpec {
    /// The contact law.
    pub law: String,
    /// Parameters the user fixed (`--set`).
    pub fixed: Vec<ParamValue>,
    /// The pair (its Young's modulus may be fitted).
    pub pair: Pair,
    /// The pair's effective shear modulus G_eff (Pa), scaled with the Young's modulus.
    pub shear: f64,
    /// Measured restitution, in (0, 1].
    pub restitution: f64,
    /// Measured contact time (s), if any.
    pub contact_time: Option<f64>,
    /// Impact speed of the measurement (m/s).
    pub v0: f64,
    /// End-of-contact criterion of the measurement.
    pub end: EndCriterion,
    /// The parameter to fit to the restitution (default: the law's only dissipation parameter).
    pub fit: Option<String>,
    /// Integrator settings.
    pub options: Options,
}

/// The answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Calibration {
    /// "closed form" or "numerical".
    pub method: &'static str,
    /// The law's parameters, complete.
    pub params: Vec<(String, f64)>,
    /// Factor applied to the Young's moduli (1 unless the contact time was fitted through E).
    pub young_factor: f64,
    /// The effective modulus of the calibrated pair (Pa).
    pub effective_young: f64,
    /// The collision computed with the calibrated parameters.
    pub realized: Collision,
    /// realized restitution − target.
    pub restitution_residual: f64,
    /// realized contact time − target (s).
    pub contact_time_residual: Option<f64>,
    /// Collisions integrated by the fit.
    pub collisions: usize,
}

/// Why a calibration failed.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// Bad target values.
    #[error("{0}")]
    BadTarget(String),
    /// The law or the integrator failed.
    #[error(transparent)]
    Collide(#[from] CollideError),
    /// The law failed.
    #[error(transparent)]
    Law(#[from] LawError),
    /// Which parameter to fit is ambiguous.
    #[error(
        "say which parameter of '{law}' to fit to the restitution with --fit NAME (one of: \
         {candidates}); the default is `eps`, or else the only parameter other than `k`, and \
         '{law}' has neither"
    )]
    Ambiguous {
        /// The law.
        law: String,
        /// Its parameters.
        candidates: String,
    },
    /// No parameter value in range gives the target.
    #[error(
        "no value of '{param}' reproduces {what} = {target}: over {lo:e} … {hi:e} the law gives \
         {f_lo} … {f_hi}"
    )]
    Unreachable {
        /// The fitted parameter.
        param: String,
        /// "restitution" or "contact time".
        what: &'static str,
        /// The target.
        target: f64,
        /// Searched interval.
        lo: f64,
        /// Searched interval.
        hi: f64,
        /// Values at its ends.
        f_lo: f64,
        /// Values at its ends.
        f_hi: f64,
    },
}

fn set(params: &mut Vec<ParamValue>, name: &str, v: f64) {
    match params.iter_mut().find(|p| p.name == name) {
        Some(p) => p.value = v,
        None => params.push(ParamValue::new(name, v)),
    }
}

struct Model<'a> {
    reg: &'a Registry,
    spec: &'a CalibrateSpec,
    runs: usize,
}

impl From<super::rk::RhsError> for CalibrateError {
    fn from(e: super::rk::RhsError) -> Self {
        CalibrateError::Collide(e.into())
    }
}

impl Model<'_> {
    fn run(&mut self, params: &[ParamValue], young_factor: f64) -> Result<Collision, CalibrateError> {
        let pair = Pair::new(
            self.spec.pair.mass,
            self.spec.pair.radius,
            self.spec.pair.young * young_factor,
        )?;
        let materials = MaterialPair::new(pair.young, self.spec.shear * young_factor)?;
        let model = self.reg.contact(&self.spec.law, params)?.bind(&materials)?;
        let law = PairLaw::new(model, pair.mass, pair.radius);
        self.runs += 1;
        Ok(collide(
            &law,
            pair.mass,
            self.spec.v0,
            self.spec.end,
            &self.spec.options,
        )?)
    }

    /// Restitution, with a law that captures the particles counted as restitution 0.
    fn restitution(&mut self, params: &[ParamValue], young_factor: f64) -> Result<f64, CalibrateError> {
        match self.run(params, young_factor) {
            Ok(c) => Ok(c.restitution),
            Err(CalibrateError::Collide(CollideError::NoReturn { .. })) => Ok(0.0),
            Err(e) => Err(e),
        }
    }
}

/// Finds x in `range` with f(x) = target, f continuous (monotone in practice). Positive
/// half-infinite ranges are searched in log space outward from `start`.
fn solve(
    name: &str,
    what: &'static str,
    range: Range,
    start: f64,
    target: f64,
    mut f: impl FnMut(f64) -> Result<f64, CalibrateError>,
) -> Result<f64, CalibrateError> {
    let log = range.min >= 0.0 && range.max.is_infinite();
    type Map = Box<dyn Fn(f64) -> f64>;
    let (to, from): (Map, Map) = if log {
        (Box::new(|x: f64| x.ln()), Box::new(|y: f64| y.exp()))
    } else {
        (Box::new(|x| x), Box::new(|y| y))
    };
    // an interior, valid bracket
    let inside = |x: f64| range.contains(x);
    // no sign change of f − target over [lo, hi]
    let unreachable = |lo: f64, hi: f64, f_lo: f64, f_hi: f64| CalibrateError::Unreachable {
        param: name.into(),
        what,
        target,
        lo,
        hi,
        f_lo: f_lo + target,
        f_hi: f_hi + target,
    };
    let (mut a, mut b);
    if log {
        let s = if start > 0.0 && start.is_finite() {
            start
        } else {
            1.0
        };
        a = s;
        b = s;
        let fs = f(s)? - target;
        if fs == 0.0 {
            return Ok(s);
        }
        let mut fa = fs;
        let mut fb = fs;
        let mut found = false;
        for _ in 0..60 {
            let (na, nb) = (a / 4.0, b * 4.0);
            if inside(na) {
                a = na;
                fa = f(a)? - target;
            }
            if inside(nb) {
                b = nb;
                fb = f(b)? - target;
            }
            if (fa > 0.0) != (fs > 0.0) {
                b = a * 4.0;
                fb = f(b)? - target;
                found = (fa > 0.0) != (fb > 0.0);
                if !found {
                    b = s;
                    fb = fs;
                    found = true;
                }
                break;
            }
            if (fb > 0.0) != (fs > 0.0) {
                a = b / 4.0;
                fa = f(a)? - target;
                if (fa > 0.0) == (fb > 0.0) {
                    a = s;
                    fa = fs;
                }
                found = true;
                break;
            }
        }
        if !found {
            return Err(unreachable(a, b, fa, fb));
        }
        illinois(to(a), fa, to(b), fb, |y| Ok(f(from(y))? - target)).map(from)
    } else {
        let w = range.max - range.min;
        a = if range.min_inclusive {
            range.min
        } else {
            range.min + 1e-9 * w
        };
        b = if range.max_inclusive {
            range.max
        } else {
            range.max - 1e-9 * w
        };
        let fa = f(a)? - target;
        let fb = f(b)? - target;
        if fa == 0.0 {
            return Ok(a);
        }
        if fb == 0.0 {
            return Ok(b);
        }
        if (fa > 0.0) == (fb > 0.0) {
            return Err(unreachable(a, b, fa, fb));
        }
        illinois(a, fa, b, fb, |y| Ok(f(y)? - target))
    }
}

fn illinois(
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    mut f: impl FnMut(f64) -> Result<f64, CalibrateError>,
) -> Result<f64, CalibrateError> {
    super::rk::locate(a, fa, b, fb, |x| Ok((f(x)?, x))).map(|(x, _)| x)
}

/// Calibrates `spec.law`.
pub fn calibrate(reg: &Registry, spec: &CalibrateSpec) -> Result<Calibration, CalibrateError> {
    let eps = spec.restitution;
    if !(eps > 0.0 && eps <= 1.0) {
        return Err(CalibrateError::BadTarget(format!(
            "--restitution = {eps} is out of range: a coefficient of restitution lies in (0, 1]"
        )));
    }
    if let Some(t) = spec.contact_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(CalibrateError::BadTarget(format!(
                "--contact-time = {t} s is out of range: it must be finite and > 0"
            )));
        }
    }
    if !(spec.v0.is_finite() && spec.v0 > 0.0) {
        return Err(CalibrateError::BadTarget(format!(
            "--v0 = {} m/s is out of range: it must be finite and > 0",
            spec.v0
        )));
    }
    let (entry, _) = reg.find(&spec.law)?;
    if entry.info.kind != LawKind::Contact {
        return Err(CalibrateError::BadTarget(format!(
            "'{}' is a {} law: calibration fits a contact (normal) law's parameters",
            spec.law,
            entry.info.kind.as_str()
        )));
    }
    let schema = entry.info.params.clone();
    let mut model = Model { reg, spec, runs: 0 };
    let target = CalibrationTarget {
        restitution: eps,
        contact_time: spec.contact_time,
        impact_speed: Some(spec.v0),
        end: spec.end,
    };

    // 1. the law's closed form
    let closed = reg.calibrate(&spec.law, &target, &spec.pair, &spec.fixed)?;
    let (mut params, mut young_factor, method) = match closed {
        Some(p) => {
            let mut all = spec.fixed.clone();
            for v in p {
                set(&mut all, &v.name, v.value);
            }
            (all, 1.0, "closed form")
        }
        None => (spec.fixed.clone(), 1.0, "numerical"),
    };

    if method == "numerical" {
        // the parameter fitted to the restitution
        let names: Vec<String> = schema.iter().map(|s| s.name.to_string()).collect();
        let fit = match &spec.fit {
            Some(f) => {
                if !names.contains(f) {
                    return Err(CalibrateError::BadTarget(format!(
                        "--fit {f}: law '{}' has no such parameter; its parameters are: {}",
                        spec.law,
                        names.join(", ")
                    )));
                }
                f.clone()
            }
            None => {
                let cands: Vec<&String> = names.iter().filter(|n| *n != "k").collect();
                if names.iter().any(|n| n == "eps") {
                    "eps".to_string()
                } else if cands.len() == 1 {
                    cands[0].clone()
                } else {
                    return Err(CalibrateError::Ambiguous {
                        law: spec.law.clone(),
                        candidates: names.join(", "),
                    });
                }
            }
        };
        let fit_spec = schema
            .iter()
            .find(|s| s.name == fit.as_str())
            .cloned()
            .ok_or_else(|| {
                CalibrateError::BadTarget(format!("law '{}' has no parameter '{fit}'", spec.law))
            })?;
        let stiff_k = names.iter().any(|n| n == "k") && fit != "k";
        let mut p_fit = params
            .iter()
            .find(|p| p.name == fit.as_str())
            .map(|p| p.value)
            .or(fit_spec.default)
            .unwrap_or(1.0);
        for _round in 0..40 {
            // restitution by the dissipation parameter
            let base = params.clone();
            p_fit = solve(&fit, "restitution", fit_spec.range, p_fit, eps, |x| {
                let mut p = base.clone();
                set(&mut p, &fit, x);
                model.restitution(&p, young_factor)
            })?;
            set(&mut params, &fit, p_fit);
            let Some(tau) = spec.contact_time else { break };
            // contact time by the stiffness
            let c = model.run(&params, young_factor)?;
            let eps_ok = (c.restitution - eps).abs() <= 1e-9;
            if eps_ok && (c.contact_time / tau - 1.0).abs() <= 1e-10 {
                break;
            }
            if stiff_k {
                let k0 = params
                    .iter()
                    .find(|p| p.name == "k")
                    .map(|p| p.value)
                    .unwrap_or_else(|| {
                        Pair::new(spec.pair.mass, spec.pair.radius, spec.pair.young * young_factor)
                            .map(|p| p.mapped_linear_stiffness())
                            .unwrap_or(1.0)
                    });
                let base = params.clone();
                let k = solve("k", "contact time", Range::positive(), k0, tau, |x| {
                    let mut p = base.clone();
                    set(&mut p, "k", x);
                    Ok(model.run(&p, young_factor)?.contact_time)
                })?;
                set(&mut params, "k", k);
            } else {
                let base = params.clone();
                young_factor = solve(
                    "young",
                    "contact time",
                    Range::positive(),
                    young_factor,
                    tau,
                    |s| Ok(model.run(&base, s)?.contact_time),
                )?;
            }
        }
    }
    let mut realized = model.run(&params, young_factor)?;
    if let (Some(tau), "closed form") = (spec.contact_time, method) {
        // a closed form that did not place the contact time is completed numerically
        if (realized.contact_time / tau - 1.0).abs() > 1e-9 {
            let base = params.clone();
            young_factor = solve("young", "contact time", Range::positive(), 1.0, tau, |s| {
                Ok(model.run(&base, s)?.contact_time)
            })?;
            realized = model.run(&params, young_factor)?;
        }
    }
    let mut full: Vec<(String, f64)> = params.iter().map(|p| (p.name.to_string(), p.value)).collect();
    for s in &schema {
        if !full.iter().any(|(n, _)| n == s.name.as_str()) {
            if let Some(d) = s.default {
                full.push((s.name.to_string(), d));
            }
        }
    }
    Ok(Calibration {
        method,
        params: full,
        young_factor,
        effective_young: spec.pair.young * young_factor,
        restitution_residual: realized.restitution - eps,
        contact_time_residual: spec.contact_time.map(|t| realized.contact_time - t),
        realized,
        collisions: model.runs,
    })
}
