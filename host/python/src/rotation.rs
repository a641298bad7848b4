//! The laws with a direction: tangential (friction), rolling and twisting laws on numpy arrays.
//! Each takes the unit normals n̂ (3 N values), one quantity of its own (a velocity, 3 N values,
//! or a twisting rate, N values), the normal forces, overlaps, effective masses and radii (N
//! each), a step and the caller's history, and gives forces (3 N) or torques (N), with the
//! energy outputs of sdk 0.3 when asked.

use super::*;
use crate::forces::{contact_slices, contexts, history_slice, vectors, vectors_mut, Energies};
use dashpot::laws::{EnergyOut, RollingResistance, TangentialForce, TwistingResistance};
use dashpot_sdk::{NormalContext, RollingBatch, TangentialBatch, TwistingBatch};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadwriteArray1};

/// What every kind's batch shares: the step, n̂, then F_n, δ, m, R, the normal contexts (none:
/// the defaults), and the history.
pub(crate) struct Common<'a> {
    dt: f64,
    normal: &'a [[f64; 3]],
    scalars: [&'a [f64]; 4],
    context: &'a [NormalContext],
    slots: usize,
    history: &'a mut [f64],
}

/// One kind of law with a direction: its own input, its output's width, its batch call.
pub(crate) trait Kind {
    /// The bound law.
    type Law: ?Sized + Sync;
    /// The kind's own input, as the errors name it.
    const OWN: &'static str;
    /// Values per contact of the own input and of the output (3: a vector, 1: a number).
    const WIDTH: usize;
    /// The batch call: `own` and `out` hold `WIDTH` values per contact.
    fn call(
        law: &Self::Law,
        c: Common<'_>,
        own: &[f64],
        out: &mut [f64],
        e: EnergyOut<'_>,
    ) -> Result<bool, LawError>;
}

/// Tangential laws: the contact-point velocity in, the tangential force out.
pub(crate) struct Tangential;
/// Rolling laws: the rolling velocity in, the rolling-resistance force out.
pub(crate) struct Rolling;
/// Twisting laws: the twisting rate in, the twisting torque about n̂ out.
pub(crate) struct Twisting;

/// The kinds whose own input and output are vectors: the same batch fields, another law.
macro_rules! vector_kind {
    ($kind:ty, $law:ty, $own:literal, $call:ident, $batch:ident) => {
        impl Kind for $kind {
            type Law = $law;
            const OWN: &'static str = $own;
            const WIDTH: usize = 3;
            #[rustfmt::skip]
            fn call(law: &Self::Law, c: Common<'_>, own: &[f64], out: &mut [f64], e: EnergyOut<'_>) -> Result<bool, LawError> {
                let Common { dt, normal, scalars: [normal_force, delta, mass, radius], context, slots, history } = c;
                let (velocity, force) = (as_vectors(own), vectors_mut(out));
                law.$call($batch { dt, normal, velocity, normal_force, delta, mass, radius, context, slots, history, force }, e)
            }
        }
    };
}

vector_kind!(
    Tangential,
    dyn TangentialForce,
    "velocity",
    force_batch_with,
    TangentialBatch
);
vector_kind!(
    Rolling,
    dyn RollingResistance,
    "velocity (rolling)",
    force_batch,
    RollingBatch
);

impl Kind for Twisting {
    type Law = dyn TwistingResistance;
    const OWN: &'static str = "rate";
    const WIDTH: usize = 1;
    #[rustfmt::skip]
    fn call(law: &Self::Law, c: Common<'_>, rate: &[f64], torque: &mut [f64], e: EnergyOut<'_>) -> Result<bool, LawError> {
        let Common { dt, normal, scalars: [normal_force, delta, mass, radius], context, slots, history } = c;
        law.torque_batch(TwistingBatch { dt, normal, rate, normal_force, delta, mass, radius, context, slots, history, torque }, e)
    }
}

/// `x` (checked to hold 3 values per contact) as vectors.
fn as_vectors(x: &[f64]) -> &[[f64; 3]] {
    // (the length is a multiple of 3: checked by `call`)
    vectors("", x, x.len() / 3).unwrap_or(&[])
}

/// The arrays of one call of kind `K`.
pub(crate) struct Arrays<'py> {
    pub(crate) dt: f64,
    pub(crate) normal: PyReadonlyArray1<'py, f64>,
    pub(crate) own: PyReadonlyArray1<'py, f64>,
    pub(crate) normal_force: PyReadonlyArray1<'py, f64>,
    pub(crate) delta: PyReadonlyArray1<'py, f64>,
    pub(crate) mass: PyReadonlyArray1<'py, f64>,
    pub(crate) radius: PyReadonlyArray1<'py, f64>,
    pub(crate) context: Option<PyReadonlyArray1<'py, f64>>,
    pub(crate) history: PyReadwriteArray1<'py, f64>,
}

/// One batch of kind `K` on law `law` (named `name`, `slots` history values per contact): the
/// output array, or with `energy` `(output, (power, elastic))`, each `None` when not reported.
pub(crate) fn call<'py, K: Kind>(
    py: Python<'py>,
    law: &K::Law,
    name: &str,
    slots: usize,
    mut a: Arrays<'py>,
    energy: bool,
) -> PyResult<PyObject> {
    let scalars = contact_slices([&a.normal_force, &a.delta, &a.mass, &a.radius])?;
    let n = scalars[0].len();
    let normal = vectors("normal", a.normal.as_slice()?, n)?;
    dashpot::checks::unit_normals(normal).map_err(PyValueError::new_err)?;
    let own = a.own.as_slice()?;
    if own.len() != K::WIDTH * n {
        return Err(PyValueError::new_err(format!(
            "{} has {} values, {} for {n} contacts ({} per contact)",
            K::OWN,
            own.len(),
            K::WIDTH * n,
            K::WIDTH
        )));
    }
    let context = match a.context.as_ref() {
        Some(x) => contexts(x.as_slice()?, n)?,
        None => &[],
    };
    let history = history_slice(Some(&mut a.history), n, slots, name)?;
    let c = Common {
        dt: a.dt,
        normal,
        scalars,
        context,
        slots,
        history,
    };
    // (every value is written by the call)
    let out = unsafe { PyArray1::<f64>::new(py, K::WIDTH * n, false) };
    let mut en = Energies::new(energy, n);
    let written = {
        let mut w = out.try_readwrite()?;
        let o = w.as_slice_mut()?;
        py.allow_threads(|| K::call(law, c, own, o, Energies::out(&mut en)))
            .map_err(law_err)?
    };
    Ok(match en {
        None => out.into_any().unbind(),
        Some(en) => (out, en.into_py(py, written))
            .into_pyobject(py)?
            .into_any()
            .unbind(),
    })
}

/// A bound law of one kind, as a Python class whose method `$method` runs a batch.
macro_rules! bound_kind {
    ($(#[$doc:meta])* $class:ident, $kind:ty, $method:ident, $own:ident) => {
        crate::forces::bound_class!($(#[$doc])* $class, <$kind as Kind>::Law, {
            /// One batch (see the module's docs and the Python wrapper's): the flat arrays of
            /// N contacts, history advanced by `dt` (s) in place; `context`, when given, the
            /// normal law's contexts (3 N values: contact radius, cap force, damping).
            #[pyo3(signature = (dt, normal, $own, normal_force, delta, mass, radius, history, energy=false, context=None))]
            #[allow(clippy::too_many_arguments)]
            fn $method<'py>(
                &self,
                py: Python<'py>,
                dt: f64,
                normal: PyReadonlyArray1<'py, f64>,
                $own: PyReadonlyArray1<'py, f64>,
                normal_force: PyReadonlyArray1<'py, f64>,
                delta: PyReadonlyArray1<'py, f64>,
                mass: PyReadonlyArray1<'py, f64>,
                radius: PyReadonlyArray1<'py, f64>,
                history: PyReadwriteArray1<'py, f64>,
                energy: bool,
                context: Option<PyReadonlyArray1<'py, f64>>,
            ) -> PyResult<PyObject> {
                let a = Arrays { dt, normal, own: $own, normal_force, delta, mass, radius, context, history };
                call::<$kind>(py, &*self.law, &self.name, self.law.history_slots(), a, energy)
            }
        });
    };
}

bound_kind!(
    /// A tangential (friction) law bound to a pair of materials.
    BoundTangential,
    Tangential,
    force,
    velocity
);
bound_kind!(
    /// A rolling-resistance law bound to a pair of materials (sdk 0.3).
    BoundRolling,
    Rolling,
    force,
    velocity
);
bound_kind!(
    /// A twisting-resistance law bound to a pair of materials (sdk 0.3).
    BoundTwisting,
    Twisting,
    torque,
    rate
);
