//! Rolling and twisting resistance (sdk 0.3), and the energy outputs of contact laws: create a
//! law by name, bind it to a pair of materials, evaluate it on every contact with its history.
//!
//! Rolling: per contact the unit normal n̂ (from the partner j to the particle i) and the rolling
//! velocity v_roll = R_eff (ω_i − ω_j) × n̂ (m/s), as `[x, y, z]` triples; the result is the
//! rolling-resistance force F_r (N), whose torque on i is R_eff n̂ × F_r (on j its opposite; F_r
//! itself is not applied to the centres). Twisting: the twisting rate (ω_i − ω_j)·n̂ (rad/s);
//! the result is the torque about n̂ on i (N·m; on j its opposite). History is kept by the caller
//! as for the other kinds: zero at first touch, updated in place, dropped when the contact ends.
//! Energy outputs, where given (non-null): each contact's dissipated power (W, ≥ 0) and stored
//! elastic energy (J); `*out_energy_written` says whether the law reported them (a law of an
//! older sdk does not).

use crate::contact_model::DashpotContactModel;
use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::materials::DashpotMaterials;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::{EnergyOut, LawHandle, ModelHandle, Rolling, Twisting};
use dashpot_sdk::{NormalBatch, RollingBatch, TwistingBatch};
use std::ffi::{c_char, c_int};

/// A configured rolling-resistance law (opaque).
pub struct DashpotRollingLaw {
    law: LawHandle<Rolling>,
}

/// A rolling-resistance law bound to a pair of materials (opaque).
pub struct DashpotRollingModel {
    model: ModelHandle<Rolling>,
}

/// A configured twisting-resistance law (opaque).
pub struct DashpotTwistingLaw {
    law: LawHandle<Twisting>,
}

/// A twisting-resistance law bound to a pair of materials (opaque).
pub struct DashpotTwistingModel {
    model: ModelHandle<Twisting>,
}

/// `*out_law` = a new handle made by `make` from the registry, the law's name and its
/// parameters (the body of every `dashpot_*_new`).
unsafe fn new_law<T>(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut T,
    make: impl FnOnce(
        &dashpot_core::Registry,
        &str,
        &[dashpot_sdk::ParamValue],
    ) -> Result<T, dashpot_sdk::LawError>,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        *o = Box::into_raw(Box::new(make(&r.reg, name, &p)?));
        Ok(())
    })
}

/// `*out_model` = `law` bound to `materials` by `bind` (the body of every `_bind_materials`).
unsafe fn bind_law<L, M>(
    law: *const L,
    materials: *const DashpotMaterials,
    out_model: *mut *mut M,
    bind: impl FnOnce(&L, &dashpot_sdk::MaterialPair) -> Result<M, dashpot_sdk::LawError>,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let m = unsafe { arg(materials, "materials") }?.to_materials()?;
        let o = unsafe { out(out_model, "out_model") }?;
        *o = Box::into_raw(Box::new(bind(l, &m)?));
        Ok(())
    })
}

/// `*out_slots` = `slots(model)` (the body of every `_history_slots`).
unsafe fn slots_of<M>(
    model: *const M,
    out_slots: *mut usize,
    slots: impl FnOnce(&M) -> usize,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        *unsafe { out(out_slots, "out_slots") }? = slots(m);
        Ok(())
    })
}

/// Frees a boxed handle (null is ignored), catching a panic of its destructor.
unsafe fn free_box<T>(p: *mut T) {
    if !p.is_null() {
        // SAFETY: a live handle from this library, by the caller's contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(unsafe { Box::from_raw(p) })));
    }
}

/// `n_history` must be `n × slots`.
fn check_history(what: &str, law: &str, n: usize, slots: usize, n_history: usize) -> Result<(), CError> {
    if Some(n_history) == n.checked_mul(slots) {
        return Ok(());
    }
    Err(CError::new(
        DASHPOT_ERR_BAD_LENGTH,
        format!("{what}: history must hold n × slots = {n} × {slots} values (law '{law}'), got n_history = {n_history}"),
    ))
}

/// The energy outputs: each of `power` and `elastic` null (not wanted) or `n` values.
unsafe fn energy_out<'a>(power: *mut f64, elastic: *mut f64, n: usize) -> Result<EnergyOut<'a>, CError> {
    let opt = |p: *mut f64, what| -> Result<Option<&'a mut [f64]>, CError> {
        if p.is_null() {
            Ok(None)
        } else {
            unsafe { slice_mut(p, n, what) }.map(Some)
        }
    };
    Ok(EnergyOut {
        power: opt(power, "out_power")?,
        elastic: opt(elastic, "out_elastic")?,
    })
}

fn triples(v: &[f64]) -> &[[f64; 3]] {
    // SAFETY: [f64; 3] has the alignment of f64 and no padding; len / 3 whole triples.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}

fn triples_mut(v: &mut [f64]) -> &mut [[f64; 3]] {
    // SAFETY: as `triples`, with the unique borrow of `v` moved into the result.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<[f64; 3]>(), v.len() / 3) }
}

/// Creates rolling law `name` (e.g. `"rolling-sds"`) from `n_params` named values (parameters
/// left out take their defaults; the values are validated against the law's schema).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW` (also for a law of another kind),
/// `DASHPOT_ERR_UNKNOWN_PARAMETER`, `DASHPOT_ERR_INVALID_PARAMETER`, `DASHPOT_ERR_PANIC`.
/// Ownership: `*out_law` is the caller's (free with `dashpot_rolling_free`). Thread-safe.
///
/// # Safety
/// `param_names`/`param_values` must be null (only if `n_params` is 0) or hold `n_params`
/// elements; strings NUL-terminated; other non-null pointers valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotRollingLaw,
) -> DashpotStatus {
    unsafe {
        new_law(
            registry,
            name,
            param_names,
            param_values,
            n_params,
            out_law,
            |reg, name, p| {
                Ok(DashpotRollingLaw {
                    law: reg.rolling(name, p)?,
                })
            },
        )
    }
}

/// Frees a rolling law (null is ignored). Models bound from it stay valid.
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_rolling_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_free(law: *mut DashpotRollingLaw) {
    unsafe { free_box(law) }
}

/// Binds a rolling law to a pair of materials (see `dashpot_materials_spheres`, `_wall`).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR`, `DASHPOT_ERR_INVALID_PARAMETER`,
/// `DASHPOT_ERR_PANIC`. Ownership: `*out_model` is the caller's (free with
/// `dashpot_rolling_model_free`). Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_bind_materials(
    law: *const DashpotRollingLaw,
    materials: *const DashpotMaterials,
    out_model: *mut *mut DashpotRollingModel,
) -> DashpotStatus {
    unsafe {
        bind_law(law, materials, out_model, |l: &DashpotRollingLaw, m| {
            Ok(DashpotRollingModel {
                model: l.law.bind(m)?,
            })
        })
    }
}

/// Frees a bound rolling law (null is ignored).
///
/// # Safety
/// `model` must be null or a live handle, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_model_free(model: *mut DashpotRollingModel) {
    unsafe { free_box(model) }
}

/// The number of history values (doubles) the rolling law keeps per contact.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_model_history_slots(
    model: *const DashpotRollingModel,
    out_slots: *mut usize,
) -> DashpotStatus {
    unsafe { slots_of(model, out_slots, |m| m.model.history_slots()) }
}

/// The rolling-resistance force on `n` contacts, history advanced by the step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal (partner to particle), `velocity[3i..3i+3]`
/// the rolling velocity R_eff (ω_i − ω_j) × n̂ (m/s), `normal_force[i]` (N), `delta[i]` (m),
/// `mass[i]` (kg), `radius[i]` (m, R_eff), `history` (`n × slots` values, in place),
/// `out_force[3i..3i+3]` the rolling force F_r (N; torque on i: R_eff n̂ × F_r); `out_power`,
/// `out_elastic` (null, or `n` values each) the energy outputs, `*out_energy_written` (may be
/// null) whether the law wrote them.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE`
/// (naming the array, index and value), `DASHPOT_ERR_PANIC`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_rolling_model_force_batch(
    model: *const DashpotRollingModel,
    n: usize,
    dt: f64,
    normal: *const f64,
    velocity: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = m.model.history_slots();
        check_history(
            "dashpot_rolling_model_force_batch",
            m.model.name(),
            n,
            slots,
            n_history,
        )?;
        let n3 = n
            .checked_mul(3)
            .ok_or_else(|| CError::new(DASHPOT_ERR_BAD_LENGTH, format!("n = {n} contacts is too many")))?;
        let batch = RollingBatch {
            dt,
            normal: triples(unsafe { slice(normal, n3, "normal") }?),
            velocity: triples(unsafe { slice(velocity, n3, "velocity") }?),
            normal_force: unsafe { slice(normal_force, n, "normal_force") }?,
            delta: unsafe { slice(delta, n, "delta") }?,
            mass: unsafe { slice(mass, n, "mass") }?,
            radius: unsafe { slice(radius, n, "radius") }?,
            slots,
            history: unsafe { slice_mut(history, n_history, "history") }?,
            force: triples_mut(unsafe { slice_mut(out_force, n3, "out_force") }?),
        };
        let energy = unsafe { energy_out(out_power, out_elastic, n) }?;
        let written = m.model.batch(batch, energy)?;
        if !out_energy_written.is_null() {
            unsafe { *out_energy_written = c_int::from(written) };
        }
        Ok(())
    })
}

/// Creates twisting law `name` (e.g. `"twisting-sds"`), as `dashpot_rolling_new`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW`, `DASHPOT_ERR_UNKNOWN_PARAMETER`,
/// `DASHPOT_ERR_INVALID_PARAMETER`, `DASHPOT_ERR_PANIC`. Ownership: `*out_law` is the caller's
/// (free with `dashpot_twisting_free`). Thread-safe.
///
/// # Safety
/// As `dashpot_rolling_new`.
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotTwistingLaw,
) -> DashpotStatus {
    unsafe {
        new_law(
            registry,
            name,
            param_names,
            param_values,
            n_params,
            out_law,
            |reg, name, p| {
                Ok(DashpotTwistingLaw {
                    law: reg.twisting(name, p)?,
                })
            },
        )
    }
}

/// Frees a twisting law (null is ignored). Models bound from it stay valid.
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_twisting_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_free(law: *mut DashpotTwistingLaw) {
    unsafe { free_box(law) }
}

/// Binds a twisting law to a pair of materials.
///
/// Errors: as `dashpot_rolling_bind_materials`. Ownership: `*out_model` is the caller's (free
/// with `dashpot_twisting_model_free`). Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_bind_materials(
    law: *const DashpotTwistingLaw,
    materials: *const DashpotMaterials,
    out_model: *mut *mut DashpotTwistingModel,
) -> DashpotStatus {
    unsafe {
        bind_law(law, materials, out_model, |l: &DashpotTwistingLaw, m| {
            Ok(DashpotTwistingModel {
                model: l.law.bind(m)?,
            })
        })
    }
}

/// Frees a bound twisting law (null is ignored).
///
/// # Safety
/// `model` must be null or a live handle, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_model_free(model: *mut DashpotTwistingModel) {
    unsafe { free_box(model) }
}

/// The number of history values (doubles) the twisting law keeps per contact.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_model_history_slots(
    model: *const DashpotTwistingModel,
    out_slots: *mut usize,
) -> DashpotStatus {
    unsafe { slots_of(model, out_slots, |m| m.model.history_slots()) }
}

/// The twisting torque on `n` contacts, history advanced by the step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal, `rate[i]` the twisting rate
/// (ω_i − ω_j)·n̂ (rad/s), `normal_force[i]` (N), `delta[i]` (m), `mass[i]` (kg), `radius[i]`
/// (m), `history` (`n × slots` values, in place), `out_torque[i]` the torque about n̂ on i (N·m);
/// energy outputs as in `dashpot_rolling_model_force_batch`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE`,
/// `DASHPOT_ERR_PANIC`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_twisting_model_torque_batch(
    model: *const DashpotTwistingModel,
    n: usize,
    dt: f64,
    normal: *const f64,
    rate: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_torque: *mut f64,
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = m.model.history_slots();
        check_history(
            "dashpot_twisting_model_torque_batch",
            m.model.name(),
            n,
            slots,
            n_history,
        )?;
        let n3 = n
            .checked_mul(3)
            .ok_or_else(|| CError::new(DASHPOT_ERR_BAD_LENGTH, format!("n = {n} contacts is too many")))?;
        let batch = TwistingBatch {
            dt,
            normal: triples(unsafe { slice(normal, n3, "normal") }?),
            rate: unsafe { slice(rate, n, "rate") }?,
            normal_force: unsafe { slice(normal_force, n, "normal_force") }?,
            delta: unsafe { slice(delta, n, "delta") }?,
            mass: unsafe { slice(mass, n, "mass") }?,
            radius: unsafe { slice(radius, n, "radius") }?,
            slots,
            history: unsafe { slice_mut(history, n_history, "history") }?,
            torque: unsafe { slice_mut(out_torque, n, "out_torque") }?,
        };
        let energy = unsafe { energy_out(out_power, out_elastic, n) }?;
        let written = m.model.batch(batch, energy)?;
        if !out_energy_written.is_null() {
            unsafe { *out_energy_written = c_int::from(written) };
        }
        Ok(())
    })
}

/// `dashpot_contact_model_force_batch` with sdk 0.3's outputs, each null or `n` values:
/// `out_reach[i]` how far beyond touching the contact still acts (m: it ends once δ < −reach;
/// 0 for a non-adhesive law), `out_power[i]` the dissipated power (W), `out_elastic[i]` the
/// stored elastic energy (J); `*out_energy_written` (may be null) whether the law reported the
/// energy.
///
/// Errors: as `dashpot_contact_model_force_batch`. Thread-safe (distinct outputs).
///
/// # Safety
/// Non-null arrays must hold the lengths stated; outputs must not overlap each other or inputs.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_model_force_batch_energy(
    model: *const DashpotContactModel,
    n: usize,
    delta: *const f64,
    rate: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
    out_reach: *mut f64,
    out_power: *mut f64,
    out_elastic: *mut f64,
    out_energy_written: *mut c_int,
) -> DashpotStatus {
    guard(|| {
        let m = unsafe { arg(model, "model") }?;
        let slots = m.model.history_slots();
        check_history(
            "dashpot_contact_model_force_batch_energy",
            m.model.name(),
            n,
            slots,
            n_history,
        )?;
        let batch = NormalBatch {
            delta: unsafe { slice(delta, n, "delta") }?,
            rate: unsafe { slice(rate, n, "rate") }?,
            mass: unsafe { slice(mass, n, "mass") }?,
            radius: unsafe { slice(radius, n, "radius") }?,
            slots,
            history: unsafe { slice_mut(history, n_history, "history") }?,
            force: unsafe { slice_mut(out_force, n, "out_force") }?,
        };
        let reach = if out_reach.is_null() {
            None
        } else {
            Some(unsafe { slice_mut(out_reach, n, "out_reach") }?)
        };
        let energy = unsafe { energy_out(out_power, out_elastic, n) }?;
        let written = m.model.force_batch_with(batch, reach, energy)?;
        if !out_energy_written.is_null() {
            unsafe { *out_energy_written = c_int::from(written) };
        }
        Ok(())
    })
}
