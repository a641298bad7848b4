//! The two-body collision driver: `collide` (one collision, as `dashpot collide --json`) and
//! `sweep` (collisions over grids, as `dashpot sweep`).

use super::*;
use dashpot::cli::sweep::{sweep as sweep_rows, SweepSpec};
use dashpot::collide::{collide as collide_one, collide_many, Options, PairLaw};
use dashpot::laws::{ContactLawHandle, ContactModelHandle};
use dashpot::output::ParamSource;
use dashpot_sdk::EndCriterion;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::intern;
use pyo3::types::{PyList, PyString};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// The end criterion named `end` (`None`: `default`).
pub(crate) fn end_of(end: Option<&str>, default: EndCriterion) -> PyResult<EndCriterion> {
    match end {
        None => Ok(default),
        Some("overlap") => Ok(EndCriterion::Overlap),
        Some("force") => Ok(EndCriterion::Force),
        Some(e) => Err(PyValueError::new_err(format!(
            "end = '{e}' is not a criterion: 'overlap' (δ returns to 0) or 'force'"
        ))),
    }
}

fn check_v0(v0: f64) -> PyResult<f64> {
    if !(v0.is_finite() && v0 > 0.0) {
        return Err(PyValueError::new_err(format!(
            "v0 = {v0} m/s is out of range: the impact speed must be finite and > 0"
        )));
    }
    Ok(v0)
}

/// The integrator's options at `rtol`, as the CLI checks them.
pub(crate) fn options(rtol: f64) -> PyResult<Options> {
    if !(1e-14..=1e-3).contains(&rtol) {
        return Err(PyValueError::new_err(format!(
            "rtol = {rtol} is out of range: it must lie in [1e-14, 1e-3]"
        )));
    }
    Ok(Options {
        rtol,
        ..Options::default()
    })
}

/// A law `collide` created, and the template of its provenance. No Python object is kept: a
/// calibration loop that gives a new value at every call would otherwise fill the cache with
/// dicts that outlive the garbage collector's young generation.
struct Cached {
    law: Arc<ContactLawHandle>,
    template: Arc<Template>,
    /// The end-of-contact criterion the law declares (the default of `end`).
    end: EndCriterion,
}

/// What a law's provenance holds besides the parameter values, for one law and one set of
/// given parameter names: built once, so that a calibration loop, which gives a new value at
/// every call, builds only the two small `params` dicts and a shallow copy of the rest.
struct Template {
    /// Every parameter sorted by name (the JSON objects are): its name, its key, its value
    /// when not given (the default, or `None` when the law derives it), and whether it is given.
    params: Vec<(String, Py<PyString>, Option<f64>, bool)>,
    /// The provenance dict, its `params` to be set (in its place: the keys are in JSON order).
    base: Py<PyDict>,
}

/// Laws `collide` created (by name and parameters: a calibration loop calls the same law
/// thousands of times, and creating it is a call into the plugin that checks every parameter)
/// and provenance templates (by name and given parameter names). Emptied when a plugin is
/// loaded.
#[derive(Default)]
struct Caches {
    laws: HashMap<String, Arc<Cached>>,
    templates: HashMap<String, Arc<Template>>,
}

static CACHES: OnceLock<Mutex<Caches>> = OnceLock::new();

fn caches() -> std::sync::MutexGuard<'static, Caches> {
    CACHES
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner())
}

/// Forgets the laws `collide` created and their templates (a plugin loaded since may shadow
/// them).
pub(crate) fn forget_laws() {
    let mut c = caches();
    c.laws.clear();
    c.templates.clear();
}

/// At most this many laws are kept (a fit that tries a new parameter value at every call would
/// otherwise grow the cache without bound); as many templates.
const CACHED_LAWS: usize = 256;

fn cached_contact(py: Python<'_>, name: &str, p: &[ParamValue]) -> PyResult<Arc<Cached>> {
    let mut key = name.to_string();
    for v in p {
        key.push('|');
        key.push_str(&v.name);
        key.push_str(&v.value.to_bits().to_string());
    }
    if let Some(l) = caches().laws.get(&key) {
        return Ok(l.clone());
    }
    let (law, end) = with_registry(py, |reg| {
        let law = reg.contact(name, p).map_err(law_err)?;
        Ok((law, reg.end_criterion(name).map_err(law_err)?))
    })?;
    let entry = Arc::new(Cached {
        law: Arc::new(law),
        template: template(py, name, p)?,
        end,
    });
    let mut c = caches();
    if c.laws.len() >= CACHED_LAWS {
        c.laws.clear();
    }
    c.laws.insert(key, entry.clone());
    Ok(entry)
}

/// The provenance template of law `name` given the parameters named in `p`.
fn template(py: Python<'_>, name: &str, p: &[ParamValue]) -> PyResult<Arc<Template>> {
    let mut key = name.to_string();
    for v in p {
        key.push('|');
        key.push_str(&v.name);
    }
    if let Some(t) = caches().templates.get(&key) {
        return Ok(t.clone());
    }
    let prov = with_registry(py, |reg| Provenance::of(reg, name, p).map_err(law_err))?;
    let t = Arc::new(template_of(py, &prov)?);
    let mut c = caches();
    if c.templates.len() >= CACHED_LAWS {
        c.templates.clear();
    }
    c.templates.insert(key, t.clone());
    Ok(t)
}

/// The template of provenance `p`: the keys, values and order of [`Provenance::json`].
fn template_of(py: Python<'_>, p: &Provenance) -> PyResult<Template> {
    let mut by_name: Vec<_> = p.params.iter().collect();
    by_name.sort_by(|a, b| a.0.cmp(&b.0));
    let sources = PyDict::new(py);
    let mut params = Vec::with_capacity(by_name.len());
    for (n, v, src) in by_name {
        sources.set_item(n, src.as_str())?;
        let given = *src == ParamSource::Given;
        params.push((
            n.clone(),
            PyString::new(py, n).unbind(),
            v.filter(|_| !given),
            given,
        ));
    }
    let plugin = PyDict::new(py);
    plugin.set_item(intern!(py, "file"), &p.plugin_file)?;
    plugin.set_item(intern!(py, "name"), &p.plugin_name)?;
    plugin.set_item(intern!(py, "sdk_version"), &p.plugin_sdk)?;
    plugin.set_item(intern!(py, "version"), &p.plugin_version)?;
    let d = PyDict::new(py);
    d.set_item(intern!(py, "dashpot_version"), p.dashpot)?;
    d.set_item(intern!(py, "host_sdk_version"), p.host_sdk)?;
    d.set_item(intern!(py, "kind"), p.kind)?;
    d.set_item(intern!(py, "law"), &p.law)?;
    d.set_item(intern!(py, "param_sources"), sources)?;
    d.set_item(intern!(py, "params"), py.None())?;
    d.set_item(intern!(py, "plugin"), plugin)?;
    d.set_item(intern!(py, "shadows"), PyList::new(py, &p.hidden)?)?;
    Ok(Template {
        params,
        base: d.unbind(),
    })
}

/// `(params, provenance)` of the law of template `t` with the parameters `given`, as the CLI's
/// JSON gives them ([`Provenance::params_json`], [`Provenance::json`]: the same keys, values
/// and order), built as Python objects directly.
fn provenance_of<'py>(
    py: Python<'py>,
    t: &Template,
    given: &[ParamValue],
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
    let params = PyDict::new(py);
    for (n, key, value, is_given) in &t.params {
        let v = match is_given {
            true => given.iter().find(|g| g.name == *n).map(|g| g.value),
            false => *value,
        };
        params.set_item(key.bind(py), v)?;
    }
    let d = t.base.bind(py).copy()?;
    d.set_item(intern!(py, "params"), params.copy()?)?;
    Ok((params, d))
}

/// The benchmark's floor: the collisions of a calibration loop in Rust alone, as `collide`
/// makes each (the law created and bound to the default pair, integrated to its end), for
/// each `(value, v0)` of parameter `param`; returns the wall time of the loop (s) and the
/// realized restitutions.
#[pyfunction]
#[pyo3(signature = (name, param, cases, rtol, end=None))]
fn _time_collisions(
    py: Python<'_>,
    name: &str,
    param: &str,
    cases: Vec<(f64, f64)>,
    rtol: f64,
    end: Option<&str>,
) -> PyResult<(f64, Vec<f64>)> {
    let opt = options(rtol)?;
    let end = end_of(end, EndCriterion::Overlap)?;
    let p = dashpot_sdk::Particle::MCC;
    let pair = pair_of(p.diameter, p.density, p.young, p.poisson, false)?;
    let reg = registry(py)?;
    let reg: &Registry = &reg;
    py.allow_threads(|| {
        let t = std::time::Instant::now();
        let e = cases
            .iter()
            .map(|&(value, v0)| {
                let law = reg.contact(name, &[ParamValue::new(param, value)])?;
                let bound: PairLaw<ContactModelHandle> = PairLaw::bind(&law, &pair, p.poisson)?;
                collide_one(&bound, pair.mass, v0, end, &opt)
                    .map(|c| c.restitution)
                    .map_err(|e| LawError::new(dashpot_sdk::ErrorKind::Other, e.to_string()))
            })
            .collect::<Result<Vec<f64>, LawError>>()?;
        Ok((t.elapsed().as_secs_f64(), e))
    })
    .map_err(law_err)
}

/// One head-on collision, as `dashpot collide --json` computes it: law `name` with `params`,
/// the particle (diameter m, density kg/m³, Young's modulus Pa, Poisson's ratio) against an
/// identical sphere or a wall, impact speed `v0` (m/s). Returns the CLI's JSON as a dict (the
/// `plugin`, `param_sources` and `shadows` of its `provenance` shared by the results of the
/// same law) and, with `record`, the trajectory as four arrays (t, δ, δ̇, F).
#[pyfunction]
#[pyo3(signature = (name, params, v0, body, end, rtol, record))]
#[allow(clippy::too_many_arguments)]
fn collide<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    v0: f64,
    body: Body,
    end: Option<&str>,
    rtol: f64,
    record: bool,
) -> PyResult<Bound<'py, PyDict>> {
    check_v0(v0)?;
    let mut opt = options(rtol)?;
    let p = params_of(params)?;
    let pair = body.pair()?;
    let cached = cached_contact(py, name, &p)?;
    let given = end.is_some();
    let end = end_of(end, cached.end)?;
    let bound: PairLaw<ContactModelHandle> = PairLaw::bind(&cached.law, &pair, body.3).map_err(law_err)?;
    opt.record = record;
    if record {
        opt.max_step_fraction = 0.01;
    }
    let c = py
        .allow_threads(|| collide_one(&bound, pair.mass, v0, end, &opt))
        .map_err(|e| PyValueError::new_err(format!("collision of '{name}' at v0 = {v0} m/s: {e}")))?;
    let out = PyDict::new(py);
    out.set_item(intern!(py, "law"), name)?;
    out.set_item(intern!(py, "v0"), v0)?;
    out.set_item(intern!(py, "end"), end.as_str())?;
    out.set_item(
        intern!(py, "end_source"),
        dashpot::cli::collide::end_source(given, name),
    )?;
    out.set_item(intern!(py, "restitution"), c.restitution)?;
    out.set_item(intern!(py, "contact_time"), c.contact_time)?;
    out.set_item(intern!(py, "max_overlap"), c.max_overlap)?;
    out.set_item(intern!(py, "max_overlap_time"), c.max_overlap_time)?;
    out.set_item(intern!(py, "stuck"), c.stuck)?;
    out.set_item(intern!(py, "tensile_peak"), c.tensile_peak)?;
    out.set_item(intern!(py, "steps"), c.steps)?;
    out.set_item(intern!(py, "force_evals"), c.force_evals)?;
    run_items(py, &out, rtol, &pair, &cached.template, &p)?;
    if record {
        let col =
            |f: fn(&dashpot::collide::Sample) -> f64| -> Vec<f64> { c.trajectory.iter().map(f).collect() };
        out.set_item("t", col(|s| s.t).into_pyarray(py))?;
        out.set_item("delta", col(|s| s.delta).into_pyarray(py))?;
        out.set_item("rate", col(|s| s.rate).into_pyarray(py))?;
        out.set_item("force", col(|s| s.force).into_pyarray(py))?;
    }
    Ok(out)
}

/// What a collision's dict holds besides its observables: `rtol`, the `pair` (mass kg, radius
/// m, young Pa), `params` and `provenance`.
fn run_items(
    py: Python<'_>,
    out: &Bound<'_, PyDict>,
    rtol: f64,
    pair: &dashpot_sdk::Pair,
    template: &Template,
    p: &[ParamValue],
) -> PyResult<()> {
    out.set_item(intern!(py, "rtol"), rtol)?;
    let pd = PyDict::new(py);
    pd.set_item(intern!(py, "mass"), pair.mass)?;
    pd.set_item(intern!(py, "radius"), pair.radius)?;
    pd.set_item(intern!(py, "young"), pair.young)?;
    out.set_item(intern!(py, "pair"), pd)?;
    let (params, provenance) = provenance_of(py, template, p)?;
    out.set_item(intern!(py, "params"), params)?;
    out.set_item(intern!(py, "provenance"), provenance)?;
    Ok(())
}

/// Impact speeds per block of a curve, with a Ctrl-C check between blocks.
const CURVE_BLOCK: usize = 1024;

/// The head-on collisions at each impact speed of `v0` (m/s, a contiguous float64 array) for
/// one law and particle: a restitution curve, its collisions in lockstep
/// ([`collide_many`]), each the bits of `collide` at that speed. Returns the dict of `collide`
/// with an array (one value per speed) for each observable. Ctrl-C stops it between blocks.
#[pyfunction]
#[pyo3(signature = (name, params, v0, body, end, rtol))]
fn collide_curve<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    v0: PyReadonlyArray1<'py, f64>,
    body: Body,
    end: Option<&str>,
    rtol: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let v0s = v0.as_slice()?;
    for (i, &v) in v0s.iter().enumerate() {
        check_v0(v).map_err(|e| PyValueError::new_err(format!("v0[{i}]: {}", e.value(py))))?;
    }
    let opt = options(rtol)?;
    let p = params_of(params)?;
    let pair = body.pair()?;
    let cached = cached_contact(py, name, &p)?;
    let given = end.is_some();
    let end = end_of(end, cached.end)?;
    let bound: PairLaw<ContactModelHandle> = PairLaw::bind(&cached.law, &pair, body.3).map_err(law_err)?;
    let n = v0s.len();
    let (mut e, mut tc, mut dm, mut tm, mut tp) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let (mut stuck, mut steps, mut evals) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for block in v0s.chunks(CURVE_BLOCK) {
        let got = py.allow_threads(|| collide_many(&bound, pair.mass, block, end, &opt));
        for (c, &v) in got.into_iter().zip(block) {
            let c =
                c.map_err(|e| PyValueError::new_err(format!("collision of '{name}' at v0 = {v} m/s: {e}")))?;
            e.push(c.restitution);
            tc.push(c.contact_time);
            dm.push(c.max_overlap);
            tm.push(c.max_overlap_time);
            tp.push(c.tensile_peak.unwrap_or(f64::NAN));
            stuck.push(c.stuck);
            steps.push(c.steps as i64);
            evals.push(c.force_evals as i64);
        }
        py.check_signals()?;
    }
    let out = PyDict::new(py);
    out.set_item(intern!(py, "law"), name)?;
    out.set_item(intern!(py, "v0"), v0s.to_vec().into_pyarray(py))?;
    out.set_item(intern!(py, "end"), end.as_str())?;
    out.set_item(
        intern!(py, "end_source"),
        dashpot::cli::collide::end_source(given, name),
    )?;
    out.set_item(intern!(py, "restitution"), e.into_pyarray(py))?;
    out.set_item(intern!(py, "contact_time"), tc.into_pyarray(py))?;
    out.set_item(intern!(py, "max_overlap"), dm.into_pyarray(py))?;
    out.set_item(intern!(py, "max_overlap_time"), tm.into_pyarray(py))?;
    out.set_item(intern!(py, "stuck"), stuck.into_pyarray(py))?;
    out.set_item(intern!(py, "tensile_peak"), tp.into_pyarray(py))?;
    out.set_item(intern!(py, "steps"), steps.into_pyarray(py))?;
    out.set_item(intern!(py, "force_evals"), evals.into_pyarray(py))?;
    run_items(py, &out, rtol, &pair, &cached.template, &p)?;
    Ok(out)
}

/// A grid: a sequence of numbers, or the CLI's `START:STOP:COUNT[:log|lin]` or `a,b,c`.
fn grid(what: &str, g: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(s) = g.extract::<String>() {
        return dashpot::cli::grid::parse_grid(&s).map_err(|e| PyValueError::new_err(format!("{what}: {e}")));
    }
    g.extract::<Vec<f64>>().map_err(|_| {
        PyValueError::new_err(format!(
            "{what} = {g}: give a sequence of numbers or a grid START:STOP:COUNT[:log|lin]"
        ))
    })
}

/// Collisions over the product of the impact speeds `v0` and the parameter grids `vary`, as
/// `dashpot sweep` runs them (in parallel), in its order: every v0 for the first parameter
/// set, then the next. Returns `(names, values, results, end)`: the parameter names, each
/// row's parameter values, each row's v0, restitution, contact time, maximum overlap and its
/// time, and the end criterion used (`end`, or else the law's own). Ctrl-C stops it between
/// blocks of collisions.
#[pyfunction]
#[pyo3(signature = (name, params, v0, vary, body, end, rtol))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn sweep(
    py: Python<'_>,
    name: &str,
    params: Option<&Bound<'_, PyDict>>,
    v0: &Bound<'_, PyAny>,
    vary: Vec<(String, Bound<'_, PyAny>)>,
    body: Body,
    end: Option<&str>,
    rtol: f64,
) -> PyResult<(Vec<String>, Vec<Vec<f64>>, Vec<[f64; 5]>, &'static str)> {
    let base = params_of(params)?;
    let v0s = grid("v0", v0)?;
    for &v in &v0s {
        check_v0(v)?;
    }
    let varied = vary
        .iter()
        .map(|(n, g)| Ok((n.clone(), grid(&format!("vary {n}"), g)?)))
        .collect::<PyResult<Vec<_>>>()?;
    let opt = options(rtol)?;
    let declared = with_registry(py, |reg| reg.end_criterion(name).map_err(law_err))?;
    let end = end_of(end, declared)?;
    let (pair, mats) = (body.pair()?, body.materials()?);
    // (a product of grids past the machine is refused before anything is allocated)
    dashpot::cli::sweep::check_size(v0s.len(), &varied, base.len())
        .map_err(|r| PyValueError::new_err(r.0))?;
    let combos: usize = varied.iter().map(|(_, g)| g.len()).product();
    // blocks of about 64 collisions, whole impact speeds each, with a Ctrl-C check between
    let per_block = 64usize.div_ceil(combos.max(1)).max(1);
    let reg = registry(py)?;
    let mut rows = vec![None; combos * v0s.len()];
    for (b, speeds) in v0s.chunks(per_block).enumerate() {
        let spec = SweepSpec {
            law: name,
            base: &base,
            pair: &pair,
            materials: &mats,
            v0s: speeds,
            varied: &varied,
            end,
            options: opt,
        };
        let got = py.allow_threads(|| sweep_rows(&reg, &spec)).map_err(run_err)?;
        // block rows: parameter set i, speed j of the block → row i × |v0| + b × per_block + j
        for (k, r) in got.into_iter().enumerate() {
            let (i, j) = (k / speeds.len(), k % speeds.len());
            rows[i * v0s.len() + b * per_block + j] = Some(r);
        }
        py.check_signals()?;
    }
    let rows: Vec<_> = rows.into_iter().flatten().collect();
    let names = rows
        .first()
        .map(|r| r.params.iter().map(|p| p.name.to_string()).collect())
        .unwrap_or_default();
    let values = rows
        .iter()
        .map(|r| r.params.iter().map(|p| p.value).collect())
        .collect();
    let results = rows
        .iter()
        .map(|r| {
            let c = &r.collision;
            [
                c.v0,
                c.restitution,
                c.contact_time,
                c.max_overlap,
                c.max_overlap_time,
            ]
        })
        .collect();
    Ok((names, values, results, end.as_str()))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(collide, m)?)?;
    m.add_function(wrap_pyfunction!(collide_curve, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(_time_collisions, m)?)?;
    Ok(())
}
