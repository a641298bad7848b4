//! The closed-form calibrations of the `gran-*` normal laws: LAMMPS's Hookean laws with
//! `velocity`, `mass_velocity` or `coeff_restitution` damping to a restitution and a contact
//! time, the Hertzian `coeff_restitution` ones to a restitution.

use crate::normal::{CoeffRestitution, MassVelocity, NormalModel, Tsuji, Velocity, Viscoelastic};
use crate::normal_laws::{GranNormal, NormalSpec};
use dashpot_sdk::{CalibrationTarget, EndCriterion, LawError, Pair, ParamValue, Params};
use std::f64::consts::PI;

/// The closed-form calibration of a Hookean law to a target restitution e (and contact time τ),
/// contact ended as δ returns to 0 (LAMMPS's end of a non-adhesive contact), for a pair of
/// effective mass m: ζ = −ln e/√(π² + ln² e); the stiffness k given, or from τ as
/// k = m (π² + ln² e)/τ² (then returned too); `damp(k, ζ, m, e)` the law's `damp`. `None` when
/// the target is under another end criterion, or k is both given and implied by τ, or neither.
fn hooke_closed_form(
    t: &CalibrationTarget,
    pair: &Pair,
    fixed: &Params,
    damp: fn(f64, f64, f64, f64) -> f64,
) -> Result<Option<Vec<ParamValue>>, LawError> {
    if t.end != EndCriterion::Overlap {
        return Ok(None);
    }
    let (e, m) = (t.restitution, pair.mass);
    let l = e.ln();
    let s = l * l + PI * PI;
    let zeta = -l / s.sqrt();
    let mut out = Vec::new();
    let k = match (fixed.get_opt("k")?, t.contact_time) {
        (Some(k), None) => k,
        (None, Some(tau)) => {
            let k = m * s / (tau * tau);
            out.push(ParamValue::new("k", k));
            k
        }
        _ => return Ok(None),
    };
    out.push(ParamValue::new("damp", damp(k, zeta, m, e)));
    Ok(Some(out))
}

/// The closed-form calibration of a law, if it has one (LAMMPS's Hookean laws with velocity,
/// mass-velocity or restitution damping; the restitution damping of the Hertzian ones).
pub trait Calibrate {
    /// See [`ContactLaw::calibrate`](dashpot_sdk::ContactLaw::calibrate).
    fn closed_form(
        _t: &CalibrationTarget,
        _pair: &Pair,
        _fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        Ok(None)
    }
}

impl<S: NormalSpec> Calibrate for GranNormal<S, Velocity> {
    /// hooke: η_n = 2ζ √(k m).
    fn closed_form(
        t: &CalibrationTarget,
        pair: &Pair,
        fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        if !S::Model::HOOKE {
            return Ok(None);
        }
        hooke_closed_form(t, pair, fixed, |k, zeta, m, _| 2.0 * zeta * (k * m).sqrt())
    }
}

impl<S: NormalSpec> Calibrate for GranNormal<S, MassVelocity> {
    /// hooke: damp = 2ζ √(k/m).
    fn closed_form(
        t: &CalibrationTarget,
        pair: &Pair,
        fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        if !S::Model::HOOKE {
            return Ok(None);
        }
        hooke_closed_form(t, pair, fixed, |k, zeta, m, _| 2.0 * zeta * (k / m).sqrt())
    }
}

impl<S> Calibrate for GranNormal<S, Viscoelastic> {}
impl<S> Calibrate for GranNormal<S, Tsuji> {}

impl<S: NormalSpec> Calibrate for GranNormal<S, CoeffRestitution> {
    /// damp = e (and, for hooke, k from the contact time).
    fn closed_form(
        t: &CalibrationTarget,
        pair: &Pair,
        fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        if S::Model::HOOKE {
            return hooke_closed_form(t, pair, fixed, |_, _, _, e| e);
        }
        if t.end != EndCriterion::Overlap || t.contact_time.is_some() {
            return Ok(None);
        }
        Ok(Some(vec![ParamValue::new("damp", t.restitution)]))
    }
}
