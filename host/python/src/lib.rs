//! `dashpot._dashpot`: the Rust side of the `dashpot` Python package (pyo3 + numpy). The
//! Python layer (`python/dashpot/__init__.py`) converts inputs to contiguous float64 arrays and
//! documents the API; this module loads the laws, calls their batch functions without the GIL,
//! and turns every refusal into a Python exception naming the value.

use dashpot::collide::{collide as collide_one, Options, PairLaw};
use dashpot::laws::ContactModelHandle;
use dashpot::output::{law_json, Provenance};
use dashpot::registry::explicit_file;
use dashpot::{Registry, SearchPath};
use dashpot_sdk::{EndCriterion, ErrorKind, LawError, MaterialPair, NormalBatch, Pair, ParamValue, Particle};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadwriteArray1};
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

mod fit;

pyo3::create_exception!(
    _dashpot,
    PluginError,
    PyException,
    "A plugin could not be loaded: not a shared library, built against an incompatible sdk, or \
     missing its entry points."
);

/// The registry of the process: the directories of `DASHPOT_PLUGIN_PATH` and the package's own
/// plugin directory, then every file given to `load_plugin`.
static REGISTRY: OnceLock<Mutex<Registry>> = OnceLock::new();

fn registry(py: Python<'_>) -> PyResult<&'static Mutex<Registry>> {
    if let Some(r) = REGISTRY.get() {
        return Ok(r);
    }
    let dirs: Vec<PathBuf> = py
        .import("dashpot")
        .and_then(|m| m.getattr("_plugin_dirs"))
        .and_then(|f| f.call0())
        .and_then(|v| v.extract::<Vec<String>>())
        .map(|v| v.into_iter().map(PathBuf::from).collect())
        .unwrap_or_default();
    let sp = SearchPath {
        dirs,
        files: Vec::new(),
        use_env: true,
        use_default: false,
    };
    let reg = Registry::discover(&sp).map_err(plugin_err)?;
    Ok(REGISTRY.get_or_init(|| Mutex::new(reg)))
}

fn with_registry<T>(py: Python<'_>, f: impl FnOnce(&Registry) -> PyResult<T>) -> PyResult<T> {
    let m = registry(py)?;
    let reg = m.lock().unwrap_or_else(|p| p.into_inner());
    f(&reg)
}

/// A loading error: `PluginError`.
fn plugin_err(e: LawError) -> PyErr {
    PluginError::new_err(e.message)
}

/// A law's refusal: `ValueError` for bad names and values, `PluginError` for loading,
/// `RuntimeError` for a law that failed (panic, non-finite output).
fn law_err(e: LawError) -> PyErr {
    match e.kind {
        ErrorKind::Load => PluginError::new_err(e.message),
        // a NaN or infinite *input* is the caller's bad value; a non-finite output the law's failure
        ErrorKind::NonFinite if e.message.contains("input") => PyValueError::new_err(e.message),
        ErrorKind::Panic | ErrorKind::NonFinite => pyo3::exceptions::PyRuntimeError::new_err(e.message),
        _ => PyValueError::new_err(e.message),
    }
}

fn params_of(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<ParamValue>> {
    let mut out = Vec::new();
    if let Some(k) = kwargs {
        for (key, value) in k.iter() {
            let name: String = key.extract()?;
            let v: f64 = value.extract().map_err(|_| {
                PyValueError::new_err(format!(
                    "parameter {name} = {value}: a law parameter must be a number"
                ))
            })?;
            out.push(ParamValue::new(&name, v));
        }
    }
    Ok(out)
}

/// Every law found: a list of dicts (name, kind, summary, doc, plugin, params, ...), as
/// `dashpot laws --json` prints them.
#[pyfunction]
fn laws(py: Python<'_>) -> PyResult<String> {
    with_registry(py, |reg| {
        let v: Vec<serde_json::Value> = reg.laws.iter().map(|l| law_json(reg, &l.info)).collect();
        Ok(serde_json::Value::Array(v).to_string())
    })
}

/// Loads the plugin file `path` (its laws are added to those already found).
#[pyfunction]
fn load_plugin(py: Python<'_>, path: PathBuf) -> PyResult<()> {
    let m = registry(py)?;
    let mut reg = m.lock().unwrap_or_else(|p| p.into_inner());
    let file = explicit_file(&path).map_err(plugin_err)?;
    reg.load_file(&file).map_err(plugin_err)?;
    if let Some(c) = CONTACT_LAWS.get() {
        c.lock().unwrap_or_else(|e| e.into_inner()).clear();
    }
    Ok(())
}

/// The provenance of law `name` with `params`, as the CLI's JSON gives it.
#[pyfunction]
#[pyo3(signature = (name, **params))]
fn provenance(py: Python<'_>, name: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<String> {
    let p = params_of(params)?;
    with_registry(py, |reg| {
        Ok(Provenance::of(reg, name, &p).map_err(law_err)?.json().to_string())
    })
}

/// The four arrays of a batch (δ, δ̇, m, r) as slices of one length; the error names the array
/// whose length differs.
fn contact_slices<'a>(arrays: [&'a PyReadonlyArray1<'_, f64>; 4]) -> PyResult<[&'a [f64]; 4]> {
    let [d, r, m, a] = arrays;
    let s = [d.as_slice()?, r.as_slice()?, m.as_slice()?, a.as_slice()?];
    let n = s[0].len();
    for (what, x) in ["rate", "mass", "radius"].into_iter().zip(&s[1..]) {
        if x.len() != n {
            return Err(PyValueError::new_err(format!(
                "{what} has {} values, delta {n}: every array must have one value per contact",
                x.len()
            )));
        }
    }
    Ok(s)
}

/// A contact law bound to a pair of materials.
#[pyclass(module = "dashpot._dashpot", frozen)]
struct BoundContact {
    law: ContactModelHandle,
    name: String,
}

#[pymethods]
impl BoundContact {
    /// History slots per contact.
    #[getter]
    fn history_slots(&self) -> usize {
        self.law.history_slots()
    }

    /// The law's name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The benchmarks' baseline: the Rust batch call on these contacts, `reps` times into one
    /// preallocated output, without Python in the loop; returns each call's wall time (s).
    #[pyo3(signature = (delta, rate, mass, radius, reps))]
    fn _time_batch<'py>(
        &self,
        py: Python<'py>,
        delta: PyReadonlyArray1<'py, f64>,
        rate: PyReadonlyArray1<'py, f64>,
        mass: PyReadonlyArray1<'py, f64>,
        radius: PyReadonlyArray1<'py, f64>,
        reps: usize,
    ) -> PyResult<Vec<f64>> {
        let [d, r, m, a] = contact_slices([&delta, &rate, &mass, &radius])?;
        if self.law.history_slots() > 0 {
            return Err(PyValueError::new_err("_time_batch: a memoryless law"));
        }
        let mut out = vec![0.0; d.len()];
        let law = &self.law;
        py.allow_threads(|| {
            (0..reps)
                .map(|_| {
                    let t = std::time::Instant::now();
                    law.force_batch(NormalBatch {
                        delta: d,
                        rate: r,
                        mass: m,
                        radius: a,
                        slots: 0,
                        history: &mut [],
                        force: &mut out,
                    })
                    .map(|_| t.elapsed().as_secs_f64())
                })
                .collect::<Result<Vec<f64>, LawError>>()
        })
        .map_err(law_err)
    }

    /// Normal forces (N) of the contacts: `delta` (m), `rate` (m/s), `mass` (kg), `radius` (m),
    /// contiguous float64 arrays of one length; `history` (flat, `history_slots` per contact)
    /// updated in place.
    #[pyo3(signature = (delta, rate, mass, radius, history=None, out=None))]
    #[allow(clippy::too_many_arguments)]
    fn force<'py>(
        &self,
        py: Python<'py>,
        delta: PyReadonlyArray1<'py, f64>,
        rate: PyReadonlyArray1<'py, f64>,
        mass: PyReadonlyArray1<'py, f64>,
        radius: PyReadonlyArray1<'py, f64>,
        history: Option<PyReadwriteArray1<'py, f64>>,
        out: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let [d, r, m, a] = contact_slices([&delta, &rate, &mass, &radius])?;
        let n = d.len();
        let slots = self.law.history_slots();
        let mut own = Vec::new();
        let mut hist_arr = history;
        let hist: &mut [f64] = match (&mut hist_arr, slots) {
            (_, 0) => &mut own,
            (Some(h), s) => {
                let h = h.as_slice_mut()?;
                if h.len() != n * s {
                    return Err(PyValueError::new_err(format!(
                        "history has {} values: law '{}' keeps {s} per contact, {} for {n} contacts",
                        h.len(),
                        self.name,
                        n * s
                    )));
                }
                h
            }
            (None, s) => {
                return Err(PyValueError::new_err(format!(
                    "law '{}' keeps {s} history values per contact: pass history (zeros at first touch, {} values)",
                    self.name,
                    n * s
                )))
            }
        };
        // the caller's output array (reused across calls), or a new one
        let out = match out {
            Some(o) => o,
            None => PyArray1::<f64>::zeros(py, n, false),
        };
        {
            let mut w = out.try_readwrite()?;
            let f = w.as_slice_mut()?;
            if f.len() != n {
                return Err(PyValueError::new_err(format!(
                    "out has {} values, delta {n}: one per contact",
                    f.len()
                )));
            }
            let law = &self.law;
            py.allow_threads(|| {
                law.force_batch(NormalBatch {
                    delta: d,
                    rate: r,
                    mass: m,
                    radius: a,
                    slots,
                    history: hist,
                    force: f,
                })
            })
            .map_err(law_err)?;
        }
        Ok(out)
    }
}

/// Contact law `name` with `params` bound to the materials (Young's moduli in Pa, Poisson's
/// ratios), the second body another sphere (`young2`, `poisson2`: default the first's) or a
/// rigid wall.
#[pyfunction]
#[pyo3(signature = (name, params, young, poisson, young2=None, poisson2=None, wall=false))]
#[allow(clippy::too_many_arguments)]
fn bind_contact(
    py: Python<'_>,
    name: &str,
    params: Option<&Bound<'_, PyDict>>,
    young: f64,
    poisson: f64,
    young2: Option<f64>,
    poisson2: Option<f64>,
    wall: bool,
) -> PyResult<BoundContact> {
    let p = params_of(params)?;
    let mats = materials(young, poisson, young2, poisson2, wall)?;
    with_registry(py, |reg| {
        let law = reg
            .contact(name, &p)
            .map_err(law_err)?
            .bind(&mats)
            .map_err(law_err)?;
        Ok(BoundContact {
            law,
            name: name.to_string(),
        })
    })
}

/// One head-on collision, as `dashpot collide --json` computes it: law `name` with `params`,
/// the particle (diameter m, density kg/m³, Young's modulus Pa, Poisson's ratio) against an
/// identical sphere or a wall, impact speed `v0` (m/s). Returns the numbers of the CLI's JSON
/// as a dict and, with `record`, the trajectory as four arrays (t, δ, δ̇, F).
#[pyfunction]
#[pyo3(signature = (name, params, v0, diameter, density, young, poisson, wall, end, rtol, record))]
#[allow(clippy::too_many_arguments)]
fn collide<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    v0: f64,
    diameter: f64,
    density: f64,
    young: f64,
    poisson: f64,
    wall: bool,
    end: Option<&str>,
    rtol: f64,
    record: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if !(v0.is_finite() && v0 > 0.0) {
        return Err(PyValueError::new_err(format!(
            "v0 = {v0} m/s is out of range: the impact speed must be finite and > 0"
        )));
    }
    if !(1e-14..=1e-3).contains(&rtol) {
        return Err(PyValueError::new_err(format!(
            "rtol = {rtol} is out of range: it must lie in [1e-14, 1e-3]"
        )));
    }
    let end = match end {
        None | Some("overlap") => EndCriterion::Overlap,
        Some("force") => EndCriterion::Force,
        Some(e) => {
            return Err(PyValueError::new_err(format!(
                "end = '{e}' is not a criterion: 'overlap' (δ returns to 0) or 'force'"
            )))
        }
    };
    let p = params_of(params)?;
    let pair = pair_of(diameter, density, young, poisson, wall)?;
    let law = cached_contact(py, name, &p)?;
    let bound: PairLaw<ContactModelHandle> = PairLaw::bind(&law, &pair, poisson).map_err(law_err)?;
    let opt = Options {
        rtol,
        record,
        max_step_fraction: if record {
            0.01
        } else {
            Options::default().max_step_fraction
        },
        ..Options::default()
    };
    let c = py
        .allow_threads(|| collide_one(&bound, pair.mass, v0, end, &opt))
        .map_err(|e| PyValueError::new_err(format!("collision of '{name}' at v0 = {v0} m/s: {e}")))?;
    let out = PyDict::new(py);
    out.set_item("law", name)?;
    out.set_item("v0", v0)?;
    out.set_item("end", end.as_str())?;
    out.set_item("restitution", c.restitution)?;
    out.set_item("contact_time", c.contact_time)?;
    out.set_item("max_overlap", c.max_overlap)?;
    out.set_item("max_overlap_time", c.max_overlap_time)?;
    out.set_item("stuck", c.stuck)?;
    out.set_item("tensile_peak", c.tensile_peak)?;
    out.set_item("steps", c.steps)?;
    out.set_item("force_evals", c.force_evals)?;
    out.set_item("rtol", rtol)?;
    let pd = PyDict::new(py);
    pd.set_item("mass", pair.mass)?;
    pd.set_item("radius", pair.radius)?;
    pd.set_item("young", pair.young)?;
    out.set_item("pair", pd)?;
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

/// Contact laws created by `collide`, by name and parameters: a calibration loop calls the same
/// law thousands of times, and creating it (a call into the plugin that checks every parameter)
/// costs more than a short collision. Emptied when a plugin is loaded.
static CONTACT_LAWS: OnceLock<
    Mutex<std::collections::HashMap<String, Arc<dashpot::laws::ContactLawHandle>>>,
> = OnceLock::new();

fn cached_contact(
    py: Python<'_>,
    name: &str,
    p: &[ParamValue],
) -> PyResult<Arc<dashpot::laws::ContactLawHandle>> {
    let key = format!("{name}|{p:?}");
    let cache = CONTACT_LAWS.get_or_init(Default::default);
    if let Some(l) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(l.clone());
    }
    let law = Arc::new(with_registry(py, |reg| reg.contact(name, p).map_err(law_err))?);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, law.clone());
    Ok(law)
}

/// A tangential (friction) law bound to a pair of materials.
#[pyclass(module = "dashpot._dashpot", frozen)]
struct BoundTangential {
    law: dashpot::laws::TangentialModelHandle,
}

#[pymethods]
impl BoundTangential {
    /// History slots per contact.
    #[getter]
    fn history_slots(&self) -> usize {
        self.law.history_slots()
    }

    /// Tangential forces on N contacts (flat arrays: `normal` and `velocity` hold 3 N values,
    /// x y z per contact), history (N × slots, flat) advanced by `dt` (s) in place.
    #[pyo3(signature = (dt, normal, velocity, normal_force, delta, mass, radius, history))]
    #[allow(clippy::too_many_arguments)]
    fn force<'py>(
        &self,
        py: Python<'py>,
        dt: f64,
        normal: PyReadonlyArray1<'py, f64>,
        velocity: PyReadonlyArray1<'py, f64>,
        normal_force: PyReadonlyArray1<'py, f64>,
        delta: PyReadonlyArray1<'py, f64>,
        mass: PyReadonlyArray1<'py, f64>,
        radius: PyReadonlyArray1<'py, f64>,
        mut history: PyReadwriteArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let [fnorm, d, m, r] = contact_slices([&normal_force, &delta, &mass, &radius])?;
        let n = fnorm.len();
        let (nv, vv) = (normal.as_slice()?, velocity.as_slice()?);
        for (what, x) in [("normal", nv), ("velocity", vv)] {
            if x.len() != 3 * n {
                return Err(PyValueError::new_err(format!(
                    "{what} has {} values: 3 per contact (x, y, z), {} for {n} contacts",
                    x.len(),
                    3 * n
                )));
            }
        }
        let slots = self.law.history_slots();
        let h = history.as_slice_mut()?;
        if h.len() != n * slots {
            return Err(PyValueError::new_err(format!(
                "history has {} values: the law keeps {slots} per contact, {} for {n} contacts",
                h.len(),
                n * slots
            )));
        }
        let mut out = vec![[0.0f64; 3]; n];
        let three = |v: &[f64]| -> Vec<[f64; 3]> { v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect() };
        let (nt, vt) = (three(nv), three(vv));
        let law = &self.law;
        py.allow_threads(|| {
            law.force_batch(dashpot_sdk::TangentialBatch {
                dt,
                normal: &nt,
                velocity: &vt,
                normal_force: fnorm,
                delta: d,
                mass: m,
                radius: r,
                slots,
                history: h,
                force: &mut out,
            })
        })
        .map_err(law_err)?;
        Ok(out.into_iter().flatten().collect::<Vec<f64>>().into_pyarray(py))
    }
}

/// Tangential law `name` with `params` bound to the materials (as `bind_contact`).
#[pyfunction]
#[pyo3(signature = (name, params, young, poisson, young2=None, poisson2=None, wall=false))]
#[allow(clippy::too_many_arguments)]
fn bind_tangential(
    py: Python<'_>,
    name: &str,
    params: Option<&Bound<'_, PyDict>>,
    young: f64,
    poisson: f64,
    young2: Option<f64>,
    poisson2: Option<f64>,
    wall: bool,
) -> PyResult<BoundTangential> {
    let p = params_of(params)?;
    let mats = materials(young, poisson, young2, poisson2, wall)?;
    with_registry(py, |reg| {
        let law = reg
            .tangential(name, &p)
            .map_err(law_err)?
            .bind(&mats)
            .map_err(law_err)?;
        Ok(BoundTangential { law })
    })
}

/// r(v) of restitution law `name` with `params`, bound to a particle (diameter m, density
/// kg/m³, Young's modulus Pa, Poisson's ratio) against an identical one or a wall, at the
/// impact speeds `speed` (m/s).
#[pyfunction]
#[pyo3(signature = (name, params, speed, diameter, density, young, poisson, wall))]
#[allow(clippy::too_many_arguments)]
fn restitution<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    speed: PyReadonlyArray1<'py, f64>,
    diameter: f64,
    density: f64,
    young: f64,
    poisson: f64,
    wall: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let p = params_of(params)?;
    let pair = pair_of(diameter, density, young, poisson, wall)?;
    let law = with_registry(py, |reg| {
        reg.restitution(name, &p)
            .map_err(law_err)?
            .bind(&pair)
            .map_err(law_err)
    })?;
    let v = speed.as_slice()?;
    let mut out = vec![0.0; v.len()];
    py.allow_threads(|| law.restitution_batch(v, &mut out))
        .map_err(law_err)?;
    Ok(out.into_pyarray(py))
}

/// The pair of a sphere (diameter m, density kg/m³, Young's modulus Pa, Poisson's ratio) and
/// an identical one, or a wall.
fn pair_of(diameter: f64, density: f64, young: f64, poisson: f64, wall: bool) -> PyResult<Pair> {
    let particle = Particle {
        diameter,
        density,
        young,
        poisson,
    };
    if wall {
        Pair::wall(&particle)
    } else {
        Pair::spheres(&particle, &particle)
    }
    .map_err(law_err)
}

/// The material pair of a first body (Young's modulus Pa, Poisson's ratio) and a second one
/// (default the same) or a rigid wall.
fn materials(
    young: f64,
    poisson: f64,
    young2: Option<f64>,
    poisson2: Option<f64>,
    wall: bool,
) -> PyResult<MaterialPair> {
    let body = |e: f64, nu: f64| Particle {
        diameter: 1.0,
        density: 1.0,
        young: e,
        poisson: nu,
    };
    let a = body(young, poisson);
    if wall {
        MaterialPair::wall(&a)
    } else {
        MaterialPair::spheres(&a, &body(young2.unwrap_or(young), poisson2.unwrap_or(poisson)))
    }
    .map_err(law_err)
}

#[pymodule]
fn _dashpot(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PluginError", m.py().get_type::<PluginError>())?;
    m.add_function(wrap_pyfunction!(laws, m)?)?;
    m.add_function(wrap_pyfunction!(load_plugin, m)?)?;
    m.add_function(wrap_pyfunction!(provenance, m)?)?;
    m.add_function(wrap_pyfunction!(bind_contact, m)?)?;
    m.add_function(wrap_pyfunction!(collide, m)?)?;
    m.add_class::<BoundContact>()?;
    m.add_class::<BoundTangential>()?;
    m.add_function(wrap_pyfunction!(bind_tangential, m)?)?;
    m.add_function(wrap_pyfunction!(restitution, m)?)?;
    m.add_function(wrap_pyfunction!(fit::calibrate, m)?)?;
    Ok(())
}
