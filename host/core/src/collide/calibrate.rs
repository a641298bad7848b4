//! Calibration: the law parameters that reproduce a measured restitution (and contact time).
//!
//! A law's own closed form is used when it offers one (for example LSD: ε → eps, τ → k); any
//! other law is fitted numerically through the integrator: its dissipation parameter for the
//! restitution and its stiffness (a parameter `k`, or else the pair's Young's modulus) for the
//! contact time, alternating until both match to 1e-9 relative.

pub use super::calibrate_error::CalibrateError;
use super::two_body::{collide, CollideError, Collision, Options, PairLaw};
use crate::registry::Registry;
use dashpot_sdk::{CalibrationTarget, EndCriterion, LawKind, MaterialPair, Pair, ParamValue, Range};

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

/// A fit is accepted when the realized restitution is within this of its target (absolute: a
/// restitution lies in (0, 1]) and a fitted contact time within this relative to its target;
/// with an integrator tolerance `rtol` coarser than 1e-11 the bound is `100 rtol` (the realized
/// restitution is only accurate to about 20 `rtol`).
pub const FIT_TOLERANCE: f64 = 1e-9;

/// The acceptance bound of a fit integrated with `options` (see [`FIT_TOLERANCE`]).
pub fn fit_tolerance(options: &Options) -> f64 {
    FIT_TOLERANCE.max(100.0 * options.rtol)
}

pub(super) fn set(params: &mut Vec<ParamValue>, name: &str, v: f64) {
    match params.iter_mut().find(|p| p.name == name) {
        Some(p) => p.value = v,
        None => params.push(ParamValue::new(name, v)),
    }
}

/// The parameter of law `law` (parameters `names`) fitted to the restitution: `fit` if given
/// (it must exist), else `eps`, else `damp` (the damping of LAMMPS's `gran-*` laws), else the
/// only parameter other than `k`.
pub(super) fn fit_name(law: &str, names: &[String], fit: Option<&str>) -> Result<String, CalibrateError> {
    if let Some(f) = fit {
        if !names.iter().any(|n| n == f) {
            return Err(CalibrateError::BadTarget(format!(
                "--fit {f}: law '{law}' has no such parameter; its parameters are: {}",
                names.join(", ")
            )));
        }
        return Ok(f.to_string());
    }
    let cands: Vec<&String> = names.iter().filter(|n| *n != "k").collect();
    if let Some(n) = ["eps", "damp"].iter().find(|d| names.iter().any(|n| n == *d)) {
        Ok(n.to_string())
    } else if cands.len() == 1 {
        Ok(cands[0].clone())
    } else {
        Err(CalibrateError::Ambiguous {
            law: law.to_string(),
            candidates: names.join(", "),
        })
    }
}

/// A calibration's collisions: law `spec.law` with given parameters and Young's modulus factor.
pub(super) struct Model<'a> {
    pub(super) reg: &'a Registry,
    pub(super) spec: &'a CalibrateSpec,
    pub(super) runs: usize,
}

impl Model<'_> {
    pub(super) fn run(
        &mut self,
        params: &[ParamValue],
        young_factor: f64,
    ) -> Result<Collision, CalibrateError> {
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
    pub(super) fn restitution(
        &mut self,
        params: &[ParamValue],
        young_factor: f64,
    ) -> Result<f64, CalibrateError> {
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
    // a bracket closed on a jump, in parameter values
    let jump = |b: Bracket, from: &dyn Fn(f64) -> f64| match b {
        Bracket::Failed(e) => e,
        Bracket::Jump { below, above, best } => CalibrateError::Jump {
            param: name.into(),
            what,
            target,
            lo: from(below.0),
            hi: from(above.0),
            f_lo: below.1 + target,
            f_hi: above.1 + target,
            reached: best.0 + target,
            residual: best.0,
        },
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
        // a side stops where the law refuses the value with the other parameters (say
        // Walton–Braun's k2 below its k1)
        let (mut open_a, mut open_b) = (true, true);
        for _ in 0..60 {
            let (na, nb) = (a / 4.0, b * 4.0);
            if open_a && inside(na) {
                match refused(f(na))? {
                    Some(v) => (a, fa) = (na, v - target),
                    None => open_a = false,
                }
            }
            if open_b && inside(nb) {
                match refused(f(nb))? {
                    Some(v) => (b, fb) = (nb, v - target),
                    None => open_b = false,
                }
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
        illinois(to(a), fa, to(b), fb, |y| Ok(f(from(y))? - target))
            .map(&from)
            .map_err(|b| jump(b, &*from))
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
        illinois(a, fa, b, fb, |y| Ok(f(y)? - target)).map_err(|b| jump(b, &|x| x))
    }
}

/// The root of f between a and b by the Illinois method: of the points it evaluated, the one
/// where |f| is least (an integrated restitution is smooth in a parameter only to the
/// integrator's tolerance, so the last point of the bracket need not be the best).
/// If even the best point misses by more than 1e-6 the bracket has closed on a jump of f
/// across 0: [`CalibrateError::Jump`] (the caller fills in the names and maps the coordinate).
/// `Ok(None)` for a value the law refuses as invalid (with the other parameters given).
fn refused(r: Result<f64, CalibrateError>) -> Result<Option<f64>, CalibrateError> {
    match r {
        Ok(v) => Ok(Some(v)),
        Err(CalibrateError::Law(e)) if e.kind == dashpot_sdk::ErrorKind::InvalidParameter => Ok(None),
        Err(e) => Err(e),
    }
}

fn illinois(
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    mut f: impl FnMut(f64) -> Result<f64, CalibrateError>,
) -> Result<f64, Bracket> {
    let mut best = if fa.abs() <= fb.abs() { (fa, a) } else { (fb, b) };
    // the closest points on either side of the root: (x, f)
    let (mut below, mut above) = if fa < 0.0 {
        ((a, fa), (b, fb))
    } else {
        ((b, fb), (a, fa))
    };
    let r = super::rk::locate(a, fa, b, fb, |x| -> Result<(f64, f64), CalibrateError> {
        let fx = f(x)?;
        if fx.abs() < best.0.abs() {
            best = (fx, x);
        }
        if fx < 0.0 && fx >= below.1 {
            below = (x, fx);
        } else if fx > 0.0 && fx <= above.1 {
            above = (x, fx);
        }
        Ok((fx, x))
    });
    match r {
        Err(e) => Err(Bracket::Failed(e)),
        Ok(_) if best.0.abs() > 1e-6 => Err(Bracket::Jump { below, above, best }),
        Ok(_) => Ok(best.1),
    }
}

/// Why [`illinois`] found no root.
enum Bracket {
    /// f failed.
    Failed(CalibrateError),
    /// f jumps across 0 between `below` and `above` ((x, f) each, f < 0 and > 0); `best` is
    /// the (f, x) of least |f|.
    Jump {
        below: (f64, f64),
        above: (f64, f64),
        best: (f64, f64),
    },
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

    // the parameter fitted numerically to the restitution, and its range
    let mut fitted: Option<(String, Range)> = None;
    if method == "numerical" {
        // the parameter fitted to the restitution
        let names: Vec<String> = schema.iter().map(|s| s.name.to_string()).collect();
        let fit = fit_name(&spec.law, &names, spec.fit.as_deref())?;
        let fit_spec = schema
            .iter()
            .find(|s| s.name == fit.as_str())
            .cloned()
            .ok_or_else(|| {
                CalibrateError::BadTarget(format!("law '{}' has no parameter '{fit}'", spec.law))
            })?;
        fitted = Some((fit.clone(), fit_spec.range));
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
    let mut realized = match model.run(&params, young_factor) {
        // the fitted value captures the particle: restitution 0, refused below with the reason
        Err(e @ CalibrateError::Collide(CollideError::NoReturn { .. })) if fitted.is_some() => {
            check_reached(&mut model, &params, young_factor, 0.0, None, fitted.as_ref())?;
            return Err(e);
        }
        r => r?,
    };
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
    let reached = if realized.stuck { 0.0 } else { realized.restitution };
    let time = Some(realized.contact_time);
    check_reached(&mut model, &params, young_factor, reached, time, fitted.as_ref())?;
    Ok(Calibration {
        method,
        params: complete(&params, &schema),
        young_factor,
        effective_young: spec.pair.young * young_factor,
        restitution_residual: realized.restitution - eps,
        contact_time_residual: spec.contact_time.map(|t| realized.contact_time - t),
        realized,
        collisions: model.runs,
    })
}

/// `params` with the defaults of the parameters of `schema` they do not name, as (name, value).
pub(super) fn complete(params: &[ParamValue], schema: &[dashpot_sdk::ParamSpec]) -> Vec<(String, f64)> {
    let mut full: Vec<(String, f64)> = params.iter().map(|p| (p.name.to_string(), p.value)).collect();
    for s in schema {
        if !full.iter().any(|(n, _)| n == s.name.as_str()) {
            if let Some(d) = s.default {
                full.push((s.name.to_string(), d));
            }
        }
    }
    full
}

/// Refuses a calibration whose parameters do not reproduce its targets within
/// [`fit_tolerance`] (`reached`: the realized restitution, 0 for a capture), saying why as far
/// as a probe around the fitted value can tell.
fn check_reached(
    model: &mut Model<'_>,
    params: &[ParamValue],
    young_factor: f64,
    reached: f64,
    contact_time: Option<f64>,
    fitted: Option<&(String, Range)>,
) -> Result<(), CalibrateError> {
    let spec = model.spec;
    let tolerance = fit_tolerance(&spec.options);
    let value_of = |n: &str| params.iter().find(|p| p.name == n).map(|p| p.value);
    let named = match fitted {
        Some((n, _)) => format!("{n} = {:e}", value_of(n).unwrap_or(f64::NAN)),
        None => params
            .iter()
            .map(|p| format!("{} = {:e}", p.name, p.value))
            .collect::<Vec<_>>()
            .join(", "),
    };
    let residual = reached - spec.restitution;
    // (a NaN misses too)
    if residual.abs() > tolerance || residual.is_nan() {
        let why = match fitted {
            Some((n, range)) => {
                let x = value_of(n).unwrap_or(f64::NAN);
                why_missed(model, params, young_factor, n, *range, x)
            }
            None => format!(
                "the closed form of '{}' does not reproduce it with contacts ending by {}",
                spec.law,
                spec.end.as_str()
            ),
        };
        return Err(CalibrateError::Missed {
            law: spec.law.clone(),
            what: "restitution",
            param: named,
            target: spec.restitution,
            reached,
            residual,
            tolerance,
            why,
        });
    }
    if let (Some(tau), Some(t)) = (spec.contact_time, contact_time) {
        let rel = t / tau - 1.0;
        if rel.abs() > tolerance || rel.is_nan() {
            return Err(CalibrateError::Missed {
                law: spec.law.clone(),
                what: "contact time (s)",
                param: format!("{named} and a Young's modulus factor {young_factor:e}"),
                target: tau,
                reached: t,
                residual: t - tau,
                tolerance,
                why: "the stiffness that places the contact time moves the restitution off its \
                      target (or the reverse) and the alternation did not settle"
                    .to_string(),
            });
        }
    }
    Ok(())
}

/// Why the restitution of `name` = `x` misses the target (the search closed on it, so f is
/// continuous there to the integrator's resolution, or not at all).
fn why_missed(
    model: &mut Model<'_>,
    params: &[ParamValue],
    young_factor: f64,
    name: &str,
    range: Range,
    x: f64,
) -> String {
    let target = model.spec.restitution;
    let miss = (model
        .restitution(&with(params, name, x), young_factor)
        .unwrap_or(f64::NAN)
        - target)
        .abs();
    if miss <= 1e-6 {
        format!(
            "the integrated restitution is smooth in '{name}' only to about {miss:.0e} here (the \
             resolution of the integrator at --rtol {}): try a smaller --rtol",
            model.spec.options.rtol
        )
    } else {
        format!(
            "no value of '{name}' in its range {range} was found that gives {target}: the \
             restitution is not a continuous function of '{name}' there"
        )
    }
}

/// `params` with `name` set to `v`.
fn with(params: &[ParamValue], name: &str, v: f64) -> Vec<ParamValue> {
    let mut p = params.to_vec();
    set(&mut p, name, v);
    p
}
