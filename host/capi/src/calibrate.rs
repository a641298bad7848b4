//! Closed-form calibration: the parameters of a contact law that reproduce a measured
//! restitution (and contact time) for a pair, when the law offers a closed form.

use crate::error::{arg, guard, out, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::pair::DashpotPair;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::{CalibrationTarget, EndCriterion};
use std::ffi::c_char;

/// What a calibration must reproduce.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DashpotCalibrationTarget {
    /// Measured coefficient of restitution, in (0, 1].
    pub restitution: f64,
    /// Measured contact time (s), or NaN if none.
    pub contact_time: f64,
    /// Normal impact speed (m/s) of the measurement, or NaN if unknown.
    pub impact_speed: f64,
    /// The end-of-contact criterion under which restitution and contact time were defined:
    /// 1 = overlap returns to 0 (`DASHPOT_END_OVERLAP`), 2 = force returns to 0.
    pub end_criterion: i32,
}

fn opt(v: f64) -> Option<f64> {
    if v.is_nan() {
        None
    } else {
        Some(v)
    }
}

/// The closed-form parameters of contact law `name` that reproduce `*target` for `*pair`,
/// given the parameters the user fixed (`fixed_names`/`fixed_values`, `n_fixed` of them).
/// `out_values` has one slot per parameter of the law's schema, in schema order
/// (`n_out` must equal the law's `n_params`): a slot the calibration sets receives its value,
/// the others receive NaN (keep the fixed value or the default). `*out_n_set` is the number of
/// slots set.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW`, `DASHPOT_ERR_BAD_LENGTH`
/// (`n_out` differs from the schema's length), `DASHPOT_ERR_INVALID_ARGUMENT` (an
/// end criterion other than 1 or 2), `DASHPOT_ERR_INVALID_PAIR`, `DASHPOT_ERR_INVALID_PARAMETER`
/// (a target out of range), `DASHPOT_ERR_UNSUPPORTED` (the law has no closed form for this
/// target: fit numerically), `DASHPOT_ERR_PANIC`. Thread-safe (read-only on the registry).
///
/// # Safety
/// Non-null pointers must be valid; arrays as long as their lengths say.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_calibrate(
    registry: *const DashpotRegistry,
    name: *const c_char,
    target: *const DashpotCalibrationTarget,
    pair: *const DashpotPair,
    fixed_names: *const *const c_char,
    fixed_values: *const f64,
    n_fixed: usize,
    out_values: *mut f64,
    n_out: usize,
    out_n_set: *mut usize,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let t = unsafe { arg(target, "target") }?;
        let p = unsafe { arg(pair, "pair") }?.to_pair()?;
        let n_set = unsafe { out(out_n_set, "out_n_set") }?;
        let fixed = unsafe { params(fixed_names, fixed_values, n_fixed) }?;
        let (entry, _) = r.reg.find(name)?;
        let schema = &entry.info.params;
        if n_out != schema.len() {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_calibrate: out_values must have one slot per parameter of law '{name}' ({}), got {n_out}",
                    schema.len()
                ),
            ));
        }
        let o = unsafe { slice_mut(out_values, n_out, "out_values") }?;
        let end = match t.end_criterion {
            1 => EndCriterion::Overlap,
            2 => EndCriterion::Force,
            e => {
                return Err(CError::new(
                    DASHPOT_ERR_INVALID_ARGUMENT,
                    format!("target end_criterion = {e} is not 1 (overlap) or 2 (force)"),
                ))
            }
        };
        let target = CalibrationTarget {
            restitution: t.restitution,
            contact_time: opt(t.contact_time),
            impact_speed: opt(t.impact_speed),
            end,
        };
        let Some(values) = r.reg.calibrate(name, &target, &p, &fixed)? else {
            return Err(CError::new(
                DASHPOT_ERR_UNSUPPORTED,
                format!(
                    "law '{name}' has no closed-form calibration for this target (restitution {}, contact time {}, \
                     end criterion {}): fit it numerically",
                    t.restitution,
                    if t.contact_time.is_nan() { "none".to_string() } else { format!("{} s", t.contact_time) },
                    end.as_str()
                ),
            ));
        };
        let mut slots = vec![f64::NAN; n_out];
        let mut count = 0;
        for v in &values {
            match schema.iter().position(|s| s.name == v.name) {
                Some(i) => {
                    slots[i] = v.value;
                    count += 1;
                }
                None => {
                    return Err(CError::new(
                        DASHPOT_ERR_OTHER,
                        format!(
                            "law '{name}' calibrated a parameter '{}' that is not in its schema",
                            v.name
                        ),
                    ))
                }
            }
        }
        o.copy_from_slice(&slots);
        *n_set = count;
        Ok(())
    })
}
