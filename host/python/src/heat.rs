//! Heat laws (sdk 0.4) on numpy arrays: the temperatures `[T_i, T_j]` of N contacts (2 N
//! values, K), their normal forces (N), overlaps (m) and effective radii (m), the caller's
//! history and optionally the normal law's contexts; out, the heat flow into particle i (W) and
//! the conductance (W/K) of each contact.

use super::*;
use crate::forces::{bound_class, contexts, history_slice};
use dashpot::laws::HeatConduction;
use dashpot_sdk::{HeatBatch, HeatFlow};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadwriteArray1};

/// Two arrays of N values: the heat flows (W) and the conductances (W/K).
type Flows<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

bound_class!(
    /// A heat-conduction law bound to a pair of materials (sdk 0.4).
    BoundHeat,
    dyn HeatConduction,
    {
    /// One batch: `(heat, conductance)`, each N values; `temperature` 2 N values `[T_i, T_j]`
    /// per contact, `normal_force`, `delta`, `radius` N each, `history` N × slots (advanced in
    /// place over `dt`, s), `context` the normal law's contexts (3 N values) or none.
    #[pyo3(signature = (dt, temperature, normal_force, delta, radius, history, context=None))]
    #[allow(clippy::too_many_arguments)]
    fn heat<'py>(
        &self,
        py: Python<'py>,
        dt: f64,
        temperature: PyReadonlyArray1<'py, f64>,
        normal_force: PyReadonlyArray1<'py, f64>,
        delta: PyReadonlyArray1<'py, f64>,
        radius: PyReadonlyArray1<'py, f64>,
        mut history: PyReadwriteArray1<'py, f64>,
        context: Option<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Flows<'py>> {
        let (normal_force, delta, radius) = (normal_force.as_slice()?, delta.as_slice()?, radius.as_slice()?);
        let n = normal_force.len();
        let t = temperature.as_slice()?;
        if t.len() != 2 * n {
            return Err(PyValueError::new_err(format!(
                "temperature has {} values, {} for {n} contacts ([T_i, T_j] per contact)",
                t.len(),
                2 * n
            )));
        }
        // SAFETY: [f64; 2] has the alignment of f64 and no padding; n whole pairs.
        let t: &[[f64; 2]] = unsafe { std::slice::from_raw_parts(t.as_ptr().cast::<[f64; 2]>(), n) };
        let context = match context.as_ref() {
            Some(x) => contexts(x.as_slice()?, n)?,
            None => &[],
        };
        let slots = self.law.history_slots();
        let history = history_slice(Some(&mut history), n, slots, &self.name)?;
        let mut flow = vec![HeatFlow::default(); n];
        let b = HeatBatch { dt, temperature: t, normal_force, delta, radius, context, slots, history, flow: &mut flow };
        py.allow_threads(|| self.law.heat_batch(b)).map_err(law_err)?;
        let heat: Vec<f64> = flow.iter().map(|f| f.heat).collect();
        let conductance: Vec<f64> = flow.iter().map(|f| f.conductance).collect();
        Ok((heat.into_pyarray(py), conductance.into_pyarray(py)))
    }
    }
);
