//! `dashpot._dashpot`: the Rust side of the `dashpot` Python package (pyo3 + numpy). The
//! Python layer (`python/dashpot/`) converts inputs to contiguous float64 arrays and documents
//! the API; this module loads the laws, calls their batch functions and runs the collisions,
//! sweeps, beds and DEM scenes of the host crate without the GIL, stops a long run on Ctrl-C,
//! and turns every refusal into a Python exception naming the value.
//!
//! - [`forces`] — contact, tangential, rolling and twisting laws on numpy arrays; [`heat`] —
//!   heat laws (sdk 0.4);
//! - [`runs`] — `collide` and `sweep` (the two-body driver);
//! - [`fit`] — `calibrate`;
//! - [`bed`] — the vibrated bed, as `dashpot bed --json`;
//! - [`scene`] — DEM scenes, as `dashpot dem --scene FILE --json`;
//! - [`interrupt`] — Ctrl-C during long runs.

use dashpot::output::{law_json, Provenance};
use dashpot::registry::explicit_file;
use dashpot::{Registry, SearchPath};
use dashpot_sdk::{ErrorKind, LawError, MaterialPair, Pair, ParamValue, Particle};
use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::{OnceLock, RwLock, RwLockReadGuard, TryLockError};

mod bed;
mod fit;
mod forces;
mod heat;
mod interrupt;
mod rotation;
mod runs;
mod scene;

pyo3::create_exception!(
    _dashpot,
    PluginError,
    PyException,
    "A plugin could not be loaded: not a shared library, built against an incompatible sdk, or \
     missing its entry points."
);

/// The registry of the process: the directories of `DASHPOT_PLUGIN_PATH` and the package's own
/// plugin directory, then every file given to `load_plugin`.
static REGISTRY: OnceLock<RwLock<Registry>> = OnceLock::new();

fn registry_lock(py: Python<'_>) -> PyResult<&'static RwLock<Registry>> {
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
    // DASHPOT_PLUGIN_PATH first, then the package's own plugins (a file name found in both is
    // loaded once, from the first)
    let mut search: Vec<PathBuf> = std::env::var_os(dashpot::registry::PLUGIN_PATH_ENV)
        .map(|p| {
            std::env::split_paths(&p)
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        })
        .unwrap_or_default();
    search.extend(dirs);
    let sp = SearchPath {
        dirs: search,
        files: Vec::new(),
        use_env: false,
        use_default: false,
    };
    let reg = Registry::discover(&sp).map_err(plugin_err)?;
    Ok(REGISTRY.get_or_init(|| RwLock::new(reg)))
}

/// Waits for a lock without ever blocking while holding the GIL (a thread that holds the GIL
/// and blocks on the registry could wait for a run that needs the GIL for its Ctrl-C checks):
/// it tries, and between tries sleeps a millisecond with the GIL released and lets Ctrl-C stop
/// the wait.
fn acquire<T>(py: Python<'_>, mut attempt: impl FnMut() -> Option<T>) -> PyResult<T> {
    loop {
        if let Some(g) = attempt() {
            return Ok(g);
        }
        py.allow_threads(|| std::thread::sleep(std::time::Duration::from_millis(1)));
        py.check_signals()?;
    }
}

/// The registry, shared (runs hold it while they last; `load_plugin` waits for them).
fn registry(py: Python<'_>) -> PyResult<RwLockReadGuard<'static, Registry>> {
    let lock = registry_lock(py)?;
    acquire(py, || match lock.try_read() {
        Ok(g) => Some(g),
        Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
        Err(TryLockError::WouldBlock) => None,
    })
}

fn with_registry<T>(py: Python<'_>, f: impl FnOnce(&Registry) -> PyResult<T>) -> PyResult<T> {
    let reg = registry(py)?;
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
        ErrorKind::Panic | ErrorKind::NonFinite => PyRuntimeError::new_err(e.message),
        _ => PyValueError::new_err(e.message),
    }
}

/// An error of a host run (`anyhow`, the CLI's type): a law's error as [`law_err`], a run that
/// went wrong (an overlap beyond the bound, a non-finite state, a particle lost, inelastic
/// collapse) a `RuntimeError`, anything else (a value out of range, a malformed option) a
/// `ValueError`; the message is the whole chain, as the CLI prints it.
fn run_err(e: anyhow::Error) -> PyErr {
    use dashpot::bed::BedError;
    use dashpot::dem::DemError;
    let msg = format!("{e:#}");
    for c in e.chain() {
        if let Some(l) = c.downcast_ref::<LawError>() {
            return law_err(LawError::new(l.kind, msg));
        }
        let failed = match c.downcast_ref::<DemError>() {
            Some(DemError::Law(l)) => return law_err(LawError::new(l.kind, msg)),
            Some(DemError::Invalid(_)) => false,
            Some(DemError::InRun { .. }) => continue,
            Some(_) => true,
            None => matches!(
                c.downcast_ref::<BedError>(),
                Some(BedError::Collapse(_) | BedError::Overlap(_))
            ),
        };
        if failed {
            return PyRuntimeError::new_err(msg);
        }
    }
    PyValueError::new_err(msg)
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
    let lock = registry_lock(py)?;
    let mut reg = acquire(py, || match lock.try_write() {
        Ok(g) => Some(g),
        Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
        Err(TryLockError::WouldBlock) => None,
    })?;
    let file = explicit_file(&path).map_err(plugin_err)?;
    reg.load_file(&file).map_err(plugin_err)?;
    runs::forget_laws();
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

/// Refuses law `name` of `kind` ("contact", "tangential", "rolling", "twisting", "heat",
/// "restitution") with `params` when the registry would: an unknown law or one of another kind,
/// an unknown parameter name (with "did you mean"), a value out of range. A law's constructor
/// calls it, so a bad law is refused where it is written, not where it is first bound.
#[pyfunction]
#[pyo3(signature = (kind, name, **params))]
fn check_law(py: Python<'_>, kind: &str, name: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    let p = params_of(params)?;
    with_registry(py, |reg| {
        let made = match kind {
            "contact" => reg.contact(name, &p).map(drop),
            "tangential" => reg.tangential(name, &p).map(drop),
            "rolling" => reg.rolling(name, &p).map(drop),
            "twisting" => reg.twisting(name, &p).map(drop),
            "heat" => reg.heat(name, &p).map(drop),
            "restitution" => reg.restitution(name, &p).map(drop),
            k => {
                return Err(PyValueError::new_err(format!(
                "kind '{k}' is not a law kind: contact, tangential, rolling, twisting, heat or restitution"
            )))
            }
        };
        made.map_err(law_err)
    })
}

/// A particle and its partner, as Python passes them: `(diameter, density, young, poisson,
/// wall)`, a sphere (m, kg/m³, Pa, Poisson's ratio) against an identical one or a rigid wall.
#[derive(FromPyObject, Clone, Copy)]
struct Body(f64, f64, f64, f64, bool);

impl Body {
    /// The effective pair.
    fn pair(&self) -> PyResult<Pair> {
        pair_of(self.0, self.1, self.2, self.3, self.4)
    }

    /// The effective moduli (what a contact law binds to).
    fn materials(&self) -> PyResult<MaterialPair> {
        materials(self.2, self.3, None, None, self.4)
    }
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
    m.add_function(wrap_pyfunction!(check_law, m)?)?;
    forces::register(m)?;
    runs::register(m)?;
    m.add_function(wrap_pyfunction!(fit::calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(fit::calibrate_curve, m)?)?;
    m.add_function(wrap_pyfunction!(bed::bed, m)?)?;
    m.add_class::<scene::Scene>()?;
    Ok(())
}
