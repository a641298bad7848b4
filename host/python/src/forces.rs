//! Laws on numpy arrays: contact (normal), tangential, rolling and twisting laws bound to a
//! pair of materials, one batch call per Python call, without the GIL. The inputs are the
//! caller's contiguous float64 arrays (no copy; vectors are flat arrays of 3 N values, x y z per
//! contact), the history is the caller's array updated in place, the outputs new arrays or the
//! caller's `out`.

use super::*;
use crate::heat::BoundHeat;
use crate::rotation::{BoundRolling, BoundTangential, BoundTwisting};
use dashpot::laws::{EnergyOut, NormalLaw};
use dashpot_sdk::{Contact, NormalBatch, NormalContext};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadwriteArray1};

/// A new float64 array of one value per contact.
pub(crate) type Array<'py> = Bound<'py, PyArray1<f64>>;

/// Forces, dissipated power and elastic energy (`None` when not reported), reach.
type WithEnergy<'py> = (Array<'py>, Option<PyObject>, Option<PyObject>, Array<'py>);

/// The benchmarks' clock: the calling thread's CPU time where the platform has one (time spent
/// descheduled on a shared machine is not the call's), else wall time.
enum Clock {
    #[cfg(unix)]
    Cpu(f64),
    #[cfg(not(unix))]
    Wall(std::time::Instant),
}

impl Clock {
    #[cfg(unix)]
    fn cpu() -> f64 {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec through a valid pointer.
        unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
    }

    fn start() -> Clock {
        #[cfg(unix)]
        return Clock::Cpu(Clock::cpu());
        #[cfg(not(unix))]
        return Clock::Wall(std::time::Instant::now());
    }

    /// Seconds since `start`.
    fn seconds(&self) -> f64 {
        match self {
            #[cfg(unix)]
            Clock::Cpu(t) => Clock::cpu() - t,
            #[cfg(not(unix))]
            Clock::Wall(t) => t.elapsed().as_secs_f64(),
        }
    }
}

/// The batch of contacts `s` (δ, δ̇, m, r), their history and the forces out.
#[rustfmt::skip]
fn normal_batch<'a>(s: [&'a [f64]; 4], slots: usize, history: &'a mut [f64], force: &'a mut [f64]) -> NormalBatch<'a> {
    let [delta, rate, mass, radius] = s;
    NormalBatch { delta, rate, mass, radius, slots, history, force }
}

/// The four arrays of a batch (δ, δ̇, m, r) as slices of one length; the error names the array
/// whose length differs.
pub(crate) fn contact_slices<'a>(arrays: [&'a PyReadonlyArray1<'_, f64>; 4]) -> PyResult<[&'a [f64]; 4]> {
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

/// `x` (3 N values, x y z per contact) as N vectors; the error names the array.
pub(crate) fn vectors<'a>(what: &str, x: &'a [f64], n: usize) -> PyResult<&'a [[f64; 3]]> {
    if x.len() != 3 * n {
        return Err(PyValueError::new_err(format!(
            "{what} has {} values: 3 per contact (x, y, z), {} for {n} contacts",
            x.len(),
            3 * n
        )));
    }
    // SAFETY: [f64; 3] is three f64 without padding, aligned as one f64; the length is checked
    Ok(unsafe { std::slice::from_raw_parts(x.as_ptr().cast::<[f64; 3]>(), n) })
}

/// [`vectors`] for an output.
pub(crate) fn vectors_mut(x: &mut [f64]) -> &mut [[f64; 3]] {
    let n = x.len() / 3;
    // SAFETY: as in `vectors`; the callers allocate 3 N values
    unsafe { std::slice::from_raw_parts_mut(x.as_mut_ptr().cast::<[f64; 3]>(), n) }
}

/// The caller's history array as the `n × slots` values law `name` keeps.
pub(crate) fn history_slice<'a>(
    h: Option<&'a mut PyReadwriteArray1<'_, f64>>,
    n: usize,
    slots: usize,
    name: &str,
) -> PyResult<&'a mut [f64]> {
    match (h, slots) {
        (_, 0) => Ok(&mut []),
        (Some(h), s) => {
            let h = h.as_slice_mut()?;
            if h.len() != n * s {
                return Err(PyValueError::new_err(format!(
                    "history has {} values: law '{name}' keeps {s} per contact, {} for {n} contacts",
                    h.len(),
                    n * s
                )));
            }
            Ok(h)
        }
        (None, s) => Err(PyValueError::new_err(format!(
            "law '{name}' keeps {s} history values per contact: pass history (zeros at first touch, {} values)",
            n * s
        ))),
    }
}

/// The energy outputs of a batch of `n` contacts, when asked for.
pub(crate) struct Energies {
    power: Vec<f64>,
    elastic: Vec<f64>,
}

impl Energies {
    pub(crate) fn new(want: bool, n: usize) -> Option<Energies> {
        want.then(|| Energies {
            power: vec![0.0; n],
            elastic: vec![0.0; n],
        })
    }

    pub(crate) fn out(e: &mut Option<Energies>) -> EnergyOut<'_> {
        match e {
            Some(e) => EnergyOut {
                power: Some(&mut e.power),
                elastic: Some(&mut e.elastic),
            },
            None => EnergyOut::none(),
        }
    }

    /// `(power, elastic)` as arrays, or `(None, None)` when the law did not write them.
    pub(crate) fn into_py(self, py: Python<'_>, written: bool) -> (Option<PyObject>, Option<PyObject>) {
        if !written {
            return (None, None);
        }
        (
            Some(self.power.into_pyarray(py).into_any().unbind()),
            Some(self.elastic.into_pyarray(py).into_any().unbind()),
        )
    }
}

/// The normal contexts of `n` contacts in a flat array of 3 `n` values (contact radius, cap
/// force, damping per contact).
pub(crate) fn contexts(x: &[f64], n: usize) -> PyResult<&[NormalContext]> {
    if x.len() != 3 * n {
        return Err(PyValueError::new_err(format!(
            "context has {} values, {} for {n} contacts (contact radius, cap force, damping per contact)",
            x.len(),
            3 * n
        )));
    }
    // SAFETY: NormalContext is three f64 (repr(C)): the alignment of f64, no padding.
    Ok(unsafe { std::slice::from_raw_parts(x.as_ptr().cast::<NormalContext>(), n) })
}

/// As [`contexts`], to be written.
pub(crate) fn contexts_mut(x: &mut [f64], n: usize) -> PyResult<&mut [NormalContext]> {
    contexts(x, n)?;
    // SAFETY: as `contexts`, with the unique borrow of `x` moved into the result.
    Ok(unsafe { std::slice::from_raw_parts_mut(x.as_mut_ptr().cast::<NormalContext>(), n) })
}

/// δ, δ̇, m, r of N contacts as Python passes them: a tuple of four float64 arrays.
pub(crate) type Contacts<'py> = (
    PyReadonlyArray1<'py, f64>,
    PyReadonlyArray1<'py, f64>,
    PyReadonlyArray1<'py, f64>,
    PyReadonlyArray1<'py, f64>,
);

/// A bound law as a Python class: the law, its name, the `history_slots` and `name` getters,
/// and the methods given.
macro_rules! bound_class {
    ($(#[$doc:meta])* $class:ident, $law:ty, { $($methods:tt)* }) => {
        $(#[$doc])*
        #[pyclass(module = "dashpot._dashpot", frozen)]
        pub(crate) struct $class {
            pub(crate) law: Box<$law>,
            pub(crate) name: String,
        }

        #[pymethods]
        impl $class {
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

            /// Whether the law reads the normal law's context (sdk 0.4).
            #[getter]
            fn reads_context(&self) -> bool {
                self.law.reads_context()
            }

            $($methods)*
        }
    };
}
pub(crate) use bound_class;

bound_class!(
    /// A contact law bound to a pair of materials.
    BoundContact,
    dyn NormalLaw,
    {
    /// Normal forces (N) of the `contacts` (δ m, δ̇ m/s, m kg, r m: contiguous float64 arrays
    /// of one length); `history` (flat, `history_slots` per contact) updated in place; `out` the
    /// caller's array for the forces. With `energy`, returns `(force, power, elastic, reach)`:
    /// the dissipated power (W) and elastic energy (J) of each contact (`None` for a law that
    /// does not report them) and its reach (m: the contact lasts while δ > −reach).
    /// With `context` (a float64 array of 3 N values), each contact's normal context (sdk 0.4:
    /// contact radius m, cap force N, damping N·s/m) is written into it.
    #[pyo3(signature = (contacts, history=None, out=None, energy=false, context=None))]
    fn force<'py>(
        &self,
        py: Python<'py>,
        contacts: Contacts<'py>,
        mut history: Option<PyReadwriteArray1<'py, f64>>,
        out: Option<Array<'py>>,
        energy: bool,
        mut context: Option<PyReadwriteArray1<'py, f64>>,
    ) -> PyResult<PyObject> {
        let c = contact_slices([&contacts.0, &contacts.1, &contacts.2, &contacts.3])?;
        let (n, slots) = (c[0].len(), self.law.history_slots());
        let hist = history_slice(history.as_mut(), n, slots, &self.name)?;
        let law = &self.law;
        if let Some(x) = context.as_mut() {
            let x = contexts_mut(x.as_slice_mut()?, n)?;
            let mut f = vec![0.0; n];
            let b = normal_batch(c, slots, hist, &mut f);
            py.allow_threads(|| law.force_batch_context(b, None, x, EnergyOut::none()))
                .map_err(law_err)?;
            return Ok(f.into_pyarray(py).into_any().unbind());
        }
        if energy {
            let (mut f, mut reach, mut en) = (vec![0.0; n], vec![0.0; n], Energies::new(true, n));
            let b = normal_batch(c, slots, hist, &mut f);
            let written = py
                .allow_threads(|| law.force_batch_with(b, Some(&mut reach), Energies::out(&mut en)))
                .map_err(law_err)?;
            let (p, e) = en.map_or((None, None), |en| en.into_py(py, written));
            let r: WithEnergy<'py> = (f.into_pyarray(py), p, e, reach.into_pyarray(py));
            return Ok(r.into_pyobject(py)?.into_any().unbind());
        }
        // the caller's output array (reused across calls), or a new one (every value is written)
        let out = out.unwrap_or_else(|| unsafe { PyArray1::<f64>::new(py, n, false) });
        {
            let mut w = out.try_readwrite()?;
            let f = w.as_slice_mut()?;
            if f.len() != n {
                return Err(PyValueError::new_err(format!(
                    "out has {} values, delta {n}: one per contact",
                    f.len()
                )));
            }
            py.allow_threads(|| law.force_batch(normal_batch(c, slots, hist, f)))
                .map_err(law_err)?;
        }
        Ok(out.into_any().unbind())
    }

    /// The benchmarks' baseline: the Rust batch call on these contacts, `reps` times into one
    /// preallocated output, without Python in the loop; returns each call's time (s) on the
    /// thread's CPU clock (wall time where there is none), as the benchmark times the others.
    fn _time_batch(&self, py: Python<'_>, contacts: Contacts<'_>, reps: usize) -> PyResult<Vec<f64>> {
        let c = contact_slices([&contacts.0, &contacts.1, &contacts.2, &contacts.3])?;
        if self.law.history_slots() > 0 {
            return Err(PyValueError::new_err("_time_batch: a memoryless law"));
        }
        let mut out = vec![0.0; c[0].len()];
        let law = &self.law;
        py.allow_threads(|| {
            (0..reps)
                .map(|_| {
                    let t = Clock::start();
                    law.force_batch(normal_batch(c, 0, &mut [], &mut out))
                        .map(|_| t.seconds())
                })
                .collect::<Result<Vec<f64>, LawError>>()
        })
        .map_err(law_err)
    }

    /// The tests' references, computed in Rust on copies of the inputs: the forces of one Rust
    /// batch call into a Rust vector, and those of one call per contact, as `dashpot eval`
    /// makes it (each from its own copy of `history`, flat, zeros if not given).
    #[pyo3(signature = (contacts, history=None))]
    fn _reference<'py>(
        &self,
        py: Python<'py>,
        contacts: Contacts<'py>,
        history: Option<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<(Array<'py>, Array<'py>)> {
        let c = contact_slices([&contacts.0, &contacts.1, &contacts.2, &contacts.3])?;
        let (n, slots) = (c[0].len(), self.law.history_slots());
        let h0 = match &history {
            Some(h) => h.as_slice()?.to_vec(),
            None => vec![0.0; n * slots],
        };
        let (mut batch, mut hb, mut hc) = (vec![0.0; n], h0.clone(), h0);
        let law = &self.law;
        let [d, r, m, a] = c;
        let one = py
            .allow_threads(|| {
                law.force_batch(normal_batch(c, slots, &mut hb, &mut batch))?;
                (0..n)
                    .map(|i| {
                        let contact = Contact {
                            delta: d[i],
                            rate: r[i],
                            mass: m[i],
                            radius: a[i],
                        };
                        law.force(contact, &mut hc[i * slots..(i + 1) * slots])
                    })
                    .collect::<Result<Vec<f64>, LawError>>()
            })
            .map_err(law_err)?;
        Ok((batch.into_pyarray(py), one.into_pyarray(py)))
    }
    }
);

/// Law `name` of one kind with `params`, bound to the materials of a first body (Young's
/// modulus Pa, Poisson's ratio) and a second one (default the first's) or a rigid wall.
macro_rules! binder {
    ($fn:ident, $class:ident, $kind:ident) => {
        #[pyfunction]
        #[pyo3(signature = (name, params, young, poisson, young2=None, poisson2=None, wall=false))]
        #[allow(clippy::too_many_arguments)]
        fn $fn(
            py: Python<'_>,
            name: &str,
            params: Option<&Bound<'_, PyDict>>,
            young: f64,
            poisson: f64,
            young2: Option<f64>,
            poisson2: Option<f64>,
            wall: bool,
        ) -> PyResult<$class> {
            let p = params_of(params)?;
            let mats = materials(young, poisson, young2, poisson2, wall)?;
            with_registry(py, |reg| {
                let law = reg
                    .$kind(name, &p)
                    .map_err(law_err)?
                    .bind(&mats)
                    .map_err(law_err)?;
                Ok($class {
                    law: Box::new(law),
                    name: name.to_string(),
                })
            })
        }
    };
}

binder!(bind_contact, BoundContact, contact);
binder!(bind_tangential, BoundTangential, tangential);
binder!(bind_rolling, BoundRolling, rolling);
binder!(bind_twisting, BoundTwisting, twisting);
binder!(bind_heat, BoundHeat, heat);

/// r(v) of restitution law `name` with `params`, bound to a particle (diameter m, density
/// kg/m³, Young's modulus Pa, Poisson's ratio) against an identical one or a wall, at the
/// impact speeds `speed` (m/s).
#[pyfunction]
#[pyo3(signature = (name, params, speed, body))]
fn restitution<'py>(
    py: Python<'py>,
    name: &str,
    params: Option<&Bound<'py, PyDict>>,
    speed: PyReadonlyArray1<'py, f64>,
    body: Body,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let p = params_of(params)?;
    let pair = body.pair()?;
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

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<BoundContact>()?;
    m.add_class::<BoundTangential>()?;
    m.add_class::<BoundRolling>()?;
    m.add_class::<BoundTwisting>()?;
    m.add_class::<BoundHeat>()?;
    m.add_function(wrap_pyfunction!(bind_contact, m)?)?;
    m.add_function(wrap_pyfunction!(bind_tangential, m)?)?;
    m.add_function(wrap_pyfunction!(bind_rolling, m)?)?;
    m.add_function(wrap_pyfunction!(bind_twisting, m)?)?;
    m.add_function(wrap_pyfunction!(bind_heat, m)?)?;
    m.add_function(wrap_pyfunction!(restitution, m)?)?;
    Ok(())
}
