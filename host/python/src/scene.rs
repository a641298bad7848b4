//! `dashpot.Scene`: a soft-sphere DEM scene on the host's engine, built from a scene file (the
//! TOML of `dashpot dem --scene`) or from a dict of the same tables, run in blocks of steps
//! without the GIL, with numpy views of the particles' state and, at the end, the document
//! `dashpot dem --scene FILE --json` prints.

use super::*;
use dashpot::cli::dem::{final_json, scene_engine};
use dashpot::dem::scene::SceneFile;
use dashpot::dem::{DemError, Engine};
use numpy::ndarray::{ArrayViewD, IxDyn};
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
use pyo3::types::{PyList, PyTuple};
use std::time::{Duration, Instant};

/// The engine of a 2D or a 3D scene.
enum Dim {
    Two(Engine<2>),
    Three(Engine<3>),
}

/// `$body` with `$e` bound to the engine, whatever its dimension.
macro_rules! on {
    ($dim:expr, $e:ident => $body:expr) => {
        match $dim {
            Dim::Two($e) => $body,
            Dim::Three($e) => $body,
        }
    };
}

/// How long one block of steps runs between two Ctrl-C checks (the block's step count adapts).
const BLOCK: Duration = Duration::from_millis(50);

/// A DEM scene and its engine.
#[pyclass(module = "dashpot._dashpot")]
pub(crate) struct Scene {
    e: Dim,
    file: SceneFile,
    /// The species and the laws of every class of contacts.
    plan: dashpot::dem::scene::PairPlan,
    /// The scene file's text (what `dashpot dem --scene` would read).
    text: String,
    /// The scene's `duration` (s).
    duration: f64,
    energy_initial: f64,
    /// Wall-clock time spent stepping (s).
    wall: f64,
}

fn dem_err(e: DemError) -> PyErr {
    run_err(anyhow::Error::new(e))
}

impl Scene {
    fn build(py: Python<'_>, text: String, source: &str) -> PyResult<Scene> {
        let file = SceneFile::parse(&text).map_err(|e| PyValueError::new_err(format!("{source}: {e}")))?;
        let dim = file
            .dimension()
            .map_err(|e| PyValueError::new_err(format!("{source}: {e}")))?;
        let reg = registry(py)?;
        let scene_err = |e: dashpot::dem::scene::SceneError| PyValueError::new_err(format!("{source}: {e}"));
        let (e, energy_initial, duration, plan) = if dim == 2 {
            let mut s = file.scene::<2>().map_err(scene_err)?;
            s.plan.resolve_names(&reg);
            let (e, en) = scene_engine(&reg, &file, &s).map_err(run_err)?;
            (Dim::Two(e), en, s.duration, s.plan)
        } else {
            let mut s = file.scene::<3>().map_err(scene_err)?;
            s.plan.resolve_names(&reg);
            let (e, en) = scene_engine(&reg, &file, &s).map_err(run_err)?;
            (Dim::Three(e), en, s.duration, s.plan)
        };
        Ok(Scene {
            e,
            file,
            plan,
            text,
            duration,
            energy_initial,
            wall: 0.0,
        })
    }
}

/// A Python value (dict, list, tuple, str, bool, int, float, None, or anything with
/// `tolist()`, such as a numpy array) as a JSON value; floats exactly. `at` names the key.
fn to_json(o: &Bound<'_, PyAny>, at: &str) -> PyResult<serde_json::Value> {
    use serde_json::Value;
    if o.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = o.downcast::<pyo3::types::PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if o.is_instance_of::<pyo3::types::PyInt>() {
        return Ok(Value::from(o.extract::<i64>()?));
    }
    if let Ok(s) = o.extract::<String>() {
        return Ok(Value::String(s));
    }
    if let Ok(x) = o.extract::<f64>() {
        return serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| PyValueError::new_err(format!("scene: {at} = {x} is not a finite number")));
    }
    if let Ok(d) = o.downcast::<PyDict>() {
        let mut m = serde_json::Map::new();
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let key = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            m.insert(k, to_json(&v, &key)?);
        }
        return Ok(Value::Object(m));
    }
    if o.is_instance_of::<PyList>() || o.is_instance_of::<PyTuple>() {
        let items = o
            .try_iter()?
            .enumerate()
            .map(|(i, v)| to_json(&v?, &format!("{at}[{i}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    if o.hasattr("tolist")? {
        return to_json(&o.call_method0("tolist")?, at);
    }
    Err(PyValueError::new_err(format!(
        "scene: {at} = {o}: expected a number, a string, a bool, a list or a dict"
    )))
}

#[pymethods]
impl Scene {
    /// The scene of the TOML file `path` (the format of `dashpot dem --scene`).
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PyValueError::new_err(format!("reading {}: {e}", path.display())))?;
        Scene::build(py, text, &path.display().to_string())
    }

    /// The scene of `spec`, a dict of the scene file's tables (`dimension`, `duration`,
    /// `law = {name, params}`, `material`, `particle = [...]`, ...), checked as the file is.
    #[staticmethod]
    fn from_spec(py: Python<'_>, spec: &Bound<'_, PyDict>) -> PyResult<Scene> {
        let v = to_json(spec.as_any(), "")?;
        let text = toml::to_string(&v)
            .map_err(|e| PyValueError::new_err(format!("scene: cannot be written as a scene file: {e}")))?;
        Scene::build(py, text, "scene")
    }

    /// The scene file's text: what `dashpot dem --scene` reads for this scene; with `duration`
    /// (s), that duration in place of the scene's.
    #[pyo3(signature = (duration=None))]
    fn to_toml(&self, duration: Option<f64>) -> PyResult<String> {
        let Some(d) = duration else {
            return Ok(self.text.clone());
        };
        let mut doc: toml::Table = toml::from_str(&self.text)
            .map_err(|e| PyValueError::new_err(format!("the scene's text: {e}")))?;
        doc.insert("duration".into(), toml::Value::Float(d));
        toml::to_string(&doc).map_err(|e| PyValueError::new_err(format!("duration = {d}: {e}")))
    }

    /// The scene's `duration` (s): the end time of `dashpot dem --scene`.
    #[getter]
    fn duration(&self) -> f64 {
        self.duration
    }

    /// 2 or 3.
    #[getter]
    fn dimension(&self) -> usize {
        match self.e {
            Dim::Two(_) => 2,
            Dim::Three(_) => 3,
        }
    }

    /// Number of particles.
    fn __len__(&self) -> usize {
        on!(&self.e, e => e.p.len())
    }

    /// Each particle's species by name, in the particles' order (empty names without species).
    fn particle_species(&self) -> Vec<String> {
        let kinds = on!(&self.e, e => e.particle_species());
        kinds
            .into_iter()
            .map(|s| self.plan.species[s as usize].name.clone())
            .collect()
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        on!(&self.e, e => e.time())
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        on!(&self.e, e => e.steps())
    }

    /// The time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        on!(&self.e, e => e.dt())
    }

    /// The step choice: `dt` (s), `given`, `collision_time` (s) at `impact_speed` (m/s).
    fn step_choice<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = on!(&self.e, e => e.step_choice);
        let d = PyDict::new(py);
        d.set_item("dt", c.dt)?;
        d.set_item("given", c.given)?;
        d.set_item("collision_time", c.collision_time)?;
        d.set_item("impact_speed", c.impact_speed)?;
        d.set_item("warning", c.warning())?;
        Ok(d)
    }

    /// Steps, without the GIL, while t + dt/2 < `t_end` (s) and the step count is below `stop`;
    /// in blocks of about 50 ms, Ctrl-C checked between them (the blocks do not change the
    /// result: the engine's state after k steps is the same however they are split).
    fn _advance(&mut self, py: Python<'_>, t_end: f64, stop: u64) -> PyResult<()> {
        // a step count past any machine's reach is refused before the first step
        let (dt, t, n, steps) = on!(&self.e, e => (e.dt(), e.time(), e.p.len(), e.steps()));
        let span = (t_end - t).min(stop.saturating_sub(steps) as f64 * dt);
        dashpot::budget::check_steps(
            "Scene.run",
            dt,
            span,
            n,
            "a law or material far stiffer than meant (young, a stiffness k), a far smaller dt or more steps_per_collision than meant, or a far longer duration",
        )
        .map_err(|r| PyValueError::new_err(r.0))?;
        // the blocks keep a large pile in the engine's memory order (no permutation of its
        // arrays per block); the views see the user's order again before Python does
        let done = self.advance_blocks(py, t_end, stop);
        on!(&mut self.e, e => e.to_user_order());
        done
    }

    /// A read-only numpy view of one of the engine's arrays (no copy: it shows the state as the
    /// run goes on): `positions`, `velocities`, `forces` (contact forces of the last step, N,
    /// gravity excluded), shape (N, D); `angular_velocities` and `torques`, shape (N,) in 2D
    /// (about z), (N, 3) in 3D; `radii` (m), `masses` (kg), `inertia` (kg·m²), shape (N,); in a
    /// scene with a heat law, `temperatures` (K) and `heat_capacities` (m c, J/K), shape (N,).
    fn _view<'py>(slf: Bound<'py, Self>, which: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (ptr, shape): (*const f64, Vec<usize>) = {
            let s = slf.borrow();
            on!(&s.e, e => {
                let (n, d) = (e.p.len(), s.dimension());
                let spin = if d == 2 { vec![n] } else { vec![n, 3] };
                match which {
                    "positions" => (e.p.pos.as_ptr().cast(), vec![n, d]),
                    "velocities" => (e.p.vel.as_ptr().cast(), vec![n, d]),
                    "forces" => (e.p.force.as_ptr().cast(), vec![n, d]),
                    "angular_velocities" => (e.p.omega.as_ptr(), spin),
                    "torques" => (e.p.torque.as_ptr(), spin),
                    "radii" => (e.p.radius.as_ptr(), vec![n]),
                    "masses" => (e.p.mass.as_ptr(), vec![n]),
                    "inertia" => (e.p.inertia.as_ptr(), vec![n]),
                    "temperatures" | "heat_capacities" => {
                        let v = if which == "temperatures" { e.temperatures() } else { e.heat_capacities() };
                        match v {
                            Some(v) => (v.as_ptr(), vec![n]),
                            None => {
                                return Err(PyValueError::new_err(format!(
                                    "{which}: the scene has no heat law (give heat=..., or a [heat] table, with heat_capacity and temperatures)"
                                )))
                            }
                        }
                    }
                    w => return Err(PyValueError::new_err(format!("no array '{w}'"))),
                }
            })
        };
        // SAFETY: the engine's particle vectors are allocated once (their length is the particle
        // count, fixed) and never moved while the scene lives, which the view keeps alive as its
        // base; a D-vector is D contiguous f64 (nalgebra's column storage is `repr(C)`).
        let view = unsafe { ArrayViewD::from_shape_ptr(IxDyn(&shape), ptr) };
        let arr = unsafe { PyArrayDyn::borrow_from_array(&view, slf.into_any()) };
        // read-only: a write would bypass the engine's neighbour list and checks
        unsafe { (*arr.as_array_ptr()).flags &= !numpy::npyffi::NPY_ARRAY_WRITEABLE };
        Ok(arr)
    }

    /// The energies now (J): `translational`, `rotational`, `gravity`, `total` (their sum), the
    /// `elastic` energy stored in the contacts, and the energy each family of laws `dissipated`
    /// since the start (`normal`, `tangential`, `rolling`, `twisting`, `total`; `None` for a
    /// law that does not report it), `initial`, the total with the elastic at the start, and
    /// `wall_work`, the work the moving walls did on the particles.
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (en, elastic, dissipated, unreported, on, work) = on!(&self.e, e => (
            e.energy(), e.elastic(), e.dissipated, e.unreported, e.config().energy, e.wall_work
        ));
        let d = PyDict::new(py);
        d.set_item("translational", en.translational)?;
        d.set_item("rotational", en.rotational)?;
        d.set_item("gravity", en.gravity)?;
        d.set_item("total", en.total())?;
        // without the accounting (`energy=False`) the laws were not asked: None, not zeros
        d.set_item("elastic", on.then(|| elastic.iter().sum::<f64>()))?;
        if on {
            let dis = PyDict::new(py);
            let fam = |k: usize| (!unreported[k]).then_some(dissipated[k]);
            for (k, name) in ["normal", "tangential", "rolling", "twisting"]
                .into_iter()
                .enumerate()
            {
                dis.set_item(name, fam(k))?;
            }
            dis.set_item("total", (0..4).map(fam).sum::<Option<f64>>())?;
            d.set_item("dissipated", dis)?;
        } else {
            d.set_item("dissipated", py.None())?;
        }
        d.set_item("initial", on.then_some(self.energy_initial))?;
        d.set_item("wall_work", on.then_some(work))?;
        Ok(d)
    }

    /// The thermal books now, in a scene with a heat law (else `None`): `thermal` Σ m c T (J),
    /// `thermal_initial`, `wall_heat` (the heat the walls gave, J), `balance` (thermal −
    /// initial − wall heat: 0 to rounding), `stability_limit` (the smallest m c/ΣH met, s) and
    /// `warning` (when dt exceeds it).
    fn heat<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(b) = on!(&self.e, e => e.heat_books()) else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("thermal", b.thermal)?;
        d.set_item("thermal_initial", b.thermal_initial)?;
        d.set_item("wall_heat", b.wall_heat)?;
        d.set_item("balance", b.balance)?;
        d.set_item(
            "stability_limit",
            b.stability_limit.is_finite().then_some(b.stability_limit),
        )?;
        d.set_item("warning", b.warning())?;
        Ok(Some(d))
    }

    /// What `dashpot dem --scene FILE --check` estimates of the scene's run from t = 0 to its
    /// duration, as JSON text: steps, peak memory, wall time from a timed sample of about
    /// `sample` seconds (s) of its own steps on a second engine built from the scene (this
    /// scene's state is not touched). The GIL is released meanwhile.
    fn _check(&self, py: Python<'_>, sample: f64) -> PyResult<String> {
        if !(sample.is_finite() && sample > 0.0 && sample <= 3600.0) {
            return Err(PyValueError::new_err(format!(
                "sample = {sample} s is out of range: it must lie in (0, 3600]"
            )));
        }
        let reg = registry(py)?;
        let reg: &Registry = &reg;
        let file = &self.file;
        let started = Instant::now();
        let budget = Duration::from_secs_f64(sample);
        let v = py
            .allow_threads(|| -> anyhow::Result<serde_json::Value> {
                fn one<const D: usize>(
                    reg: &Registry,
                    file: &SceneFile,
                    started: Instant,
                    budget: Duration,
                ) -> anyhow::Result<serde_json::Value> {
                    let mut scene = file.scene::<D>()?;
                    scene.plan.resolve_names(reg);
                    let (mut e, _, mut fp) = dashpot::cli::dem::scene_engine_sized(reg, file, &scene)?;
                    // (result() builds the final document only when asked: counted apart)
                    fp.final_json = false;
                    let setup = started.elapsed().as_secs_f64();
                    let est = dashpot::cli::budget::estimate(&mut e, fp, scene.duration, setup, 0, budget)?;
                    Ok(est.json())
                }
                match file.dimension()? {
                    2 => one::<2>(reg, file, started, budget),
                    _ => one::<3>(reg, file, started, budget),
                }
            })
            .map_err(run_err)?;
        Ok(v.to_string())
    }

    /// The document `dashpot dem --scene FILE --json` prints after the same steps, as JSON
    /// text; `wall_seconds` is the time spent stepping here.
    fn result(&self, py: Python<'_>) -> PyResult<String> {
        let reg = registry(py)?;
        let v =
            on!(&self.e, e => final_json(&reg, &self.file, &self.plan, e, self.energy_initial, self.wall))
                .map_err(run_err)?;
        Ok(v.to_string())
    }
}

impl Scene {
    /// [`Scene::_advance`]'s blocks, the arrays left in the engine's order.
    fn advance_blocks(&mut self, py: Python<'_>, t_end: f64, stop: u64) -> PyResult<()> {
        let mut block = 1u64;
        loop {
            // (steps_to counts step by step: ask for one block at most)
            let k = on!(&self.e, e => e.steps_to(t_end, stop.saturating_sub(e.steps()).min(block)));
            if k == 0 {
                return Ok(());
            }
            let t0 = Instant::now();
            let e = &mut self.e;
            py.allow_threads(|| on!(e, e => e.advance_held(k)))
                .map_err(dem_err)?;
            let took = t0.elapsed();
            self.wall += took.as_secs_f64();
            py.check_signals()?;
            let scale = BLOCK.as_secs_f64() / took.as_secs_f64().max(1e-9);
            block = ((k as f64 * scale.min(4.0)) as u64).clamp(1, 1 << 24);
        }
    }
}
