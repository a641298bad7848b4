//! Contact laws bound to a pair (sdk 0.1): the normal force per pair or over arrays. (Creating,
//! binding and freeing: `kinds.rs`.)
//!
//! Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while the bodies approach),
//! and the force (N) is positive when repulsive. For δ < 0 a law returns 0.

use crate::error::{
    arg, guard, output, same_lengths, slice, slice_mut, CError, DashpotStatus, DashpotStatus::*,
};
use crate::kinds::DashpotBoundContact;
use dashpot_sdk::{Contact, NormalBatch};
use std::ffi::c_char;

/// Contacts per call of the law in the pair-bound batch (stack arrays of the pair's geometry).
const CHUNK: usize = 64;

impl DashpotBoundContact {
    /// The bound law's coefficient `name`.
    fn coefficient(&self, name: &str) -> Result<f64, CError> {
        let all = self.model.coefficients(self.mass, self.radius)?;
        match all.iter().find(|c| c.name == name) {
            Some(c) => Ok(c.value),
            None => Err(CError::new(
                DASHPOT_ERR_INVALID_ARGUMENT,
                format!(
                    "contact law '{}' has no coefficient '{name}'; it has: {}",
                    self.model.name(),
                    all.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")
                ),
            )),
        }
    }

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
    output!(arg bound => out_force = bound.force(delta, rate)?)
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
        let lengths = [("delta", n_delta), ("rate", n_rate), ("out_force", n_out)];
        same_lengths("dashpot_contact_force_batch", &lengths)?;
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
    output!(arg bound, string name => out_value = bound.coefficient(name)?)
}
