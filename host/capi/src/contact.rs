//! Contact laws: create by name, bind to a pair, evaluate the normal force per pair or over
//! arrays.
//!
//! Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while the bodies approach),
//! and the force (N) is positive when repulsive. For δ < 0 a law returns 0.

use crate::error::{arg, guard, out, slice, slice_mut, string, CError, DashpotStatus, DashpotStatus::*};
use crate::pair::DashpotPair;
use crate::registry::{params, DashpotRegistry};
use dashpot_sdk::abi::{ContactLawHandle, ContactModelHandle};
use dashpot_sdk::{Contact, NormalBatch};
use std::ffi::c_char;

/// A configured contact law (opaque).
pub struct DashpotContactLaw {
    pub(crate) law: ContactLawHandle,
}

/// A contact law bound to a pair (opaque): the hot path.
pub struct DashpotBoundContact {
    pub(crate) model: ContactModelHandle,
    pub(crate) mass: f64,
    pub(crate) radius: f64,
}

/// Contacts per call of the law in the pair-bound batch (stack arrays of the pair's geometry).
const CHUNK: usize = 64;

impl DashpotBoundContact {
    fn force(&self, delta: f64, rate: f64) -> Result<f64, dashpot_sdk::LawError> {
        let c = Contact {
            delta,
            rate,
            mass: self.mass,
            radius: self.radius,
        };
        self.model.force(c, &mut [])
    }

    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), dashpot_sdk::LawError> {
        let (m, r) = ([self.mass; CHUNK], [self.radius; CHUNK]);
        for (k, ((d, v), o)) in delta
            .chunks(CHUNK)
            .zip(rate.chunks(CHUNK))
            .zip(out.chunks_mut(CHUNK))
            .enumerate()
        {
            let n = o.len();
            self.model
                .force_batch(NormalBatch {
                    delta: d,
                    rate: v,
                    mass: &m[..n],
                    radius: &r[..n],
                    slots: 0,
                    history: &mut [],
                    force: o,
                })
                .map_err(|e| {
                    // report indices of the caller's arrays, not of the chunk
                    e.with_message(|msg| shift_indices(msg, k * CHUNK))
                })?;
        }
        Ok(())
    }
}

/// Rewrites "name[i]" in a batch error to "name[i + offset]".
fn shift_indices(msg: &str, offset: usize) -> String {
    if offset == 0 {
        return msg.to_string();
    }
    let mut out = String::with_capacity(msg.len());
    let mut rest = msg;
    while let Some(i) = rest.find('[') {
        out.push_str(&rest[..=i]);
        rest = &rest[i + 1..];
        if let Some((j, v)) = rest
            .find(']')
            .and_then(|j| rest[..j].parse::<usize>().ok().map(|v| (j, v)))
        {
            out.push_str(&(v + offset).to_string());
            rest = &rest[j..];
        }
    }
    out.push_str(rest);
    out
}

/// Creates contact law `name` from `n_params` named values (parameters left out take their
/// defaults; the values are validated against the law's schema).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW` (also for a restitution law's
/// name), `DASHPOT_ERR_UNKNOWN_PARAMETER`, `DASHPOT_ERR_INVALID_PARAMETER`, `DASHPOT_ERR_PANIC`.
/// Ownership: inputs are copied; `*out_law` is owned by the caller (free with
/// `dashpot_contact_free`) and may outlive the registry. Thread-safe.
///
/// # Safety
/// `param_names`/`param_values` must be null (only if `n_params` is 0) or hold `n_params`
/// elements; strings NUL-terminated; other non-null pointers valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_new(
    registry: *const DashpotRegistry,
    name: *const c_char,
    param_names: *const *const c_char,
    param_values: *const f64,
    n_params: usize,
    out_law: *mut *mut DashpotContactLaw,
) -> DashpotStatus {
    guard(|| {
        let r = unsafe { arg(registry, "registry") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_law, "out_law") }?;
        let p = unsafe { params(param_names, param_values, n_params) }?;
        let law = r.reg.contact(name, &p)?;
        *o = Box::into_raw(Box::new(DashpotContactLaw { law }));
        Ok(())
    })
}

/// Frees a contact law (null is ignored). Bound laws made from it stay valid.
///
/// # Safety
/// `law` must be null or a live handle from `dashpot_contact_new`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_free(law: *mut DashpotContactLaw) {
    if !law.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(law) })
        }));
    }
}

/// Binds a contact law to a pair: every constant of the force is computed here, once.
///
/// The pair carries no shear modulus; this binding takes the one of two bodies of Poisson's
/// ratio 0.3 (no normal law of the project uses it). A law with per-contact history (e.g.
/// `thornton`) cannot be bound to a pair: use the material binding of the sdk 0.2 functions,
/// which carry each contact's history.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR` (a pair field not finite or not
/// positive), `DASHPOT_ERR_INVALID_PARAMETER` (the law rejects this pair, or keeps history),
/// `DASHPOT_ERR_PANIC`.
/// Ownership: `*out_bound` is owned by the caller (free with `dashpot_bound_contact_free`) and
/// may outlive the law. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_bind(
    law: *const DashpotContactLaw,
    pair: *const DashpotPair,
    out_bound: *mut *mut DashpotBoundContact,
) -> DashpotStatus {
    guard(|| {
        let l = unsafe { arg(law, "law") }?;
        let p = unsafe { arg(pair, "pair") }?.to_pair()?;
        let o = unsafe { out(out_bound, "out_bound") }?;
        let slots = l.law.info().history.len();
        if slots > 0 {
            return Err(CError::new(
                DASHPOT_ERR_INVALID_PARAMETER,
                format!(
                    "contact law '{}' keeps per-contact history ({slots} slots), which a pair-bound \
                     law has nowhere to store: bind it to materials and pass the history with each batch",
                    l.law.info().name
                ),
            ));
        }
        let model = l.law.bind(&p.materials(0.3)?)?;
        *o = Box::into_raw(Box::new(DashpotBoundContact {
            model,
            mass: p.mass,
            radius: p.radius,
        }));
        Ok(())
    })
}

/// Frees a bound contact law (null is ignored).
///
/// # Safety
/// `bound` must be null or a live handle from `dashpot_contact_bind`, not used concurrently.
#[no_mangle]
pub unsafe extern "C" fn dashpot_bound_contact_free(bound: *mut DashpotBoundContact) {
    if !bound.is_null() {
        // SAFETY: a live handle, by contract.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(bound) })
        }));
    }
}

/// The normal force F(δ, δ̇) (N) at overlap `delta` (m) and overlap rate `rate` (m/s).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_NON_FINITE` (the law returned NaN or inf;
/// `*out_force` is not written), `DASHPOT_ERR_PANIC` (the law panicked; the handle stays
/// usable). Thread-safe: any number of threads may evaluate the same bound law at once.
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_force(
    bound: *const DashpotBoundContact,
    delta: f64,
    rate: f64,
    out_force: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        let o = unsafe { out(out_force, "out_force") }?;
        *o = b.force(delta, rate)?;
        Ok(())
    })
}

/// `out_force[i] = F(delta[i], rate[i])` (N) for every i: the call a DEM code makes once per
/// step (per kind of pair) with all its contacts. The three lengths must be equal. Every
/// input and output is checked for NaN and infinity inside the plugin, fused with the
/// computation: a non-finite overlap or rate is refused with `DASHPOT_ERR_NON_FINITE` naming its
/// index and value.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (a handle, or an array whose length is > 0),
/// `DASHPOT_ERR_BAD_LENGTH`, `DASHPOT_ERR_NON_FINITE` (the message names the first bad
/// index's inputs; `out_force` is then partly written), `DASHPOT_ERR_PANIC`.
/// Ownership: the arrays stay the caller's. Thread-safe (distinct output arrays per thread).
///
/// # Safety
/// Non-null arrays must hold as many elements as their length says; `out_force` must not
/// overlap the inputs.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_force_batch(
    bound: *const DashpotBoundContact,
    delta: *const f64,
    n_delta: usize,
    rate: *const f64,
    n_rate: usize,
    out_force: *mut f64,
    n_out: usize,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        if n_delta != n_out || n_rate != n_out {
            return Err(CError::new(
                DASHPOT_ERR_BAD_LENGTH,
                format!(
                    "dashpot_contact_force_batch: delta, rate and out_force must have the same length, \
                     got {n_delta}, {n_rate} and {n_out}"
                ),
            ));
        }
        let d = unsafe { slice(delta, n_delta, "delta") }?;
        let r = unsafe { slice(rate, n_rate, "rate") }?;
        let o = unsafe { slice_mut(out_force, n_out, "out_force") }?;
        b.force_batch(d, r, o)?;
        Ok(())
    })
}

/// A derived constant of the bound law by name (for HSD: `"K"`, `"c"`, `"alpha"`, ...).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_ARGUMENT` (no coefficient of that
/// name; the message lists those that exist), `DASHPOT_ERR_PANIC`. Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid; `name` NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn dashpot_contact_coefficient(
    bound: *const DashpotBoundContact,
    name: *const c_char,
    out_value: *mut f64,
) -> DashpotStatus {
    guard(|| {
        let b = unsafe { arg(bound, "bound") }?;
        let name = unsafe { string(name, "name") }?;
        let o = unsafe { out(out_value, "out_value") }?;
        let all = b.model.coefficients(b.mass, b.radius)?;
        match all.iter().find(|c| c.name == name) {
            Some(c) => {
                *o = c.value;
                Ok(())
            }
            None => Err(CError::new(
                DASHPOT_ERR_INVALID_ARGUMENT,
                format!(
                    "contact law '{}' has no coefficient '{name}'; it has: {}",
                    b.model.name(),
                    all.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")
                ),
            )),
        }
    })
}
