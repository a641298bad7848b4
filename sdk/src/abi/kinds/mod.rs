//! The law kinds of sdk 0.3 as instances of the one ABI shape of [`kind`](super::kind): normal
//! (0.2's contact batch plus reach and energy), tangential and rolling (one vector batch: 0.2's
//! tangential batch plus energy), and twisting. Each instance is its raw batch, the host's view
//! of it, and the block loop that checks and evaluates it; everything else (vtables,
//! trampolines, handles) is generic.

use super::checks::*;
use super::fault::bad_input;
use super::fault::{BatchFault, BatchStatus};
use super::kind::{blocks, check_energy, energy_out, kind_law, raw_out, slice, slice_mut, Kind, KindBound};
use super::v2;
use crate::error::{ErrorKind, LawError};
use crate::law::{BoundContact, Coefficient, Contact, ContactLaw, EnergyBatch, LawKind, NormalBatch};
use crate::lengths::length_error;
use crate::pair::MaterialPair;
use abi_stable::StableAbi;

/// Runs the law on the block `$lo..$hi` of a batch: `$eval(block)` without energy outputs
/// (`$energy` is `None`), else `$eval_energy(block, its part of the outputs)`, whose outputs are
/// then checked (a non-finite one returns its fault from the enclosing function). Evaluates to
/// whether the block's energy was written. A macro, as `blocks!`: the law's code must be compiled
/// inline into the AVX2 copy of the batch loop.
macro_rules! eval_block {
    ($energy:expr, $lo:expr, $hi:expr, $block:expr, $eval:expr, $eval_energy:expr) => {{
        match $energy.as_mut() {
            None => {
                ($eval)($block);
                false
            }
            Some((p, e)) => {
                let (p, e) = (&mut p[$lo..$hi], &mut e[$lo..$hi]);
                let written = ($eval_energy)(
                    $block,
                    EnergyBatch {
                        power: &mut *p,
                        elastic: &mut *e,
                    },
                );
                if written {
                    check_energy($lo, p, e)?;
                }
                written
            }
        }
    }};
}

/// The checked block loop of a raw motion batch `$r` (twisting, or a vector kind: its sdk batch
/// `$batch`, whose motion input `$motion` and output `$out` are arrays of `$mty` and `$oty`),
/// with the energy outputs `$power` and `$elastic` when either is wanted. `$check(lo, normal,
/// motion, normal_force, delta, mass, radius)` refuses a block's bad input, `$eval(block)` runs
/// the law on it, `$eval_energy(block, energy)` runs it with its energy outputs (whether every
/// contact reported one), and `$bad_out(outputs)` finds a non-finite output. Expands to the
/// body of a `KindBound::run` (it returns the first fault).
macro_rules! motion_run {
    ($r:expr, $power:expr, $elastic:expr,
     $batch:ident { $motion:ident: $mty:ty => $out:ident: $oty:ty },
     $check:expr, $eval:expr, $eval_energy:expr, $bad_out:expr $(,)?) => {{
        let r = $r;
        if !(r.dt >= 0.0 && r.dt < f64::INFINITY) {
            return Err((0, BatchFault::DT));
        }
        let (n, slots) = (r.n, r.slots);
        let (normal, motion, fnorm, delta, mass, radius, history, out) = unsafe {
            (
                slice(r.normal as *const [f64; 3], n),
                slice(r.$motion as *const $mty, n),
                slice(r.normal_force, n),
                slice(r.delta, n),
                slice(r.mass, n),
                slice(r.radius, n),
                slice_mut(r.history, n * slots),
                slice_mut(r.$out as *mut $oty, n),
            )
        };
        let mut scratch = Vec::new();
        let mut energy = unsafe { energy_out(n, $power, $elastic, &mut scratch) };
        let mut written = energy.is_some();
        blocks!(n, |lo, hi| {
            let (nl, ml) = (&normal[lo..hi], &motion[lo..hi]);
            let (f, d, m, a) = (&fnorm[lo..hi], &delta[lo..hi], &mass[lo..hi], &radius[lo..hi]);
            ($check)(lo, nl, ml, f, d, m, a)?;
            let o = &mut out[lo..hi];
            let block = $batch {
                dt: r.dt,
                normal: nl,
                $motion: ml,
                normal_force: f,
                delta: d,
                mass: m,
                radius: a,
                slots,
                history: &mut history[lo * slots..hi * slots],
                $out: &mut *o,
            };
            written &= eval_block!(energy, lo, hi, block, $eval, $eval_energy);
            match ($bad_out)(&*o) {
                Some(i) => Err((lo + i, BatchFault::OUTPUT)),
                None => Ok(()),
            }
        });
        Ok(written)
    }};
}

mod normal;
mod pipelined;
mod twisting;
mod vector;

pub(crate) use normal::normal_non_finite;
pub use normal::{FfiNormalBatch3, Normal, NormalCall};
pub use twisting::{FfiTwistingBatch, Twisting};
pub use vector::{FfiVectorBatch, Rolling, Tangential};

pub(super) fn non_finite_output(what: &str, name: &str, field: u8, i: usize, value: String) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "{what} law '{name}' returned a non-finite {} on contact {i} {value}{}",
            BatchFault::field_name(field),
            if field == BatchFault::REACH {
                " (the reach must be finite and ≥ 0, m)"
            } else {
                ""
            }
        ),
    )
}

/// The first bad input of a block, from `(first bad index, array)` checks in order.
#[inline(always)]
pub(super) fn first_bad<const N: usize>(
    lo: usize,
    checks: [(Option<usize>, u8); N],
) -> Result<(), (usize, u8)> {
    for (i, f) in checks {
        if let Some(i) = i {
            return Err((lo + i, f));
        }
    }
    Ok(())
}

/// The first bad input of a block of a motion kind (tangential, rolling, twisting), from
/// contact `lo`: the unit normals (`normal`, flattened `[x, y, z]` triples), then the kind's
/// own input (`input`: its first non-finite contact and its array), the normal forces (N), the
/// overlaps (m), the masses (kg) and the radii (m).
#[inline(always)]
pub(super) fn first_bad_motion(
    lo: usize,
    normal: &[f64],
    input: (Option<usize>, u8),
    fnorm: &[f64],
    delta: &[f64],
    m: &[f64],
    a: &[f64],
) -> Result<(), (usize, u8)> {
    first_bad(
        lo,
        [
            (first_non_finite(normal).map(|i| i / 3), BatchFault::NORMAL),
            input,
            (first_non_finite(fnorm), BatchFault::NORMAL_FORCE),
            (first_non_finite(delta), BatchFault::DELTA),
            (first_non_positive(m), BatchFault::MASS),
            (first_non_positive(a), BatchFault::RADIUS),
        ],
    )
}

/// The value of the scalar input of a motion contact (tangential, rolling, twisting) that the
/// fault code `field` names: its normal force (N), overlap (m), mass (kg) or radius (m), else
/// the step (s).
pub(super) fn motion_input(field: u8, [normal_force, delta, mass, radius, dt]: [f64; 5]) -> f64 {
    match field {
        BatchFault::NORMAL_FORCE => normal_force,
        BatchFault::DELTA => delta,
        BatchFault::MASS => mass,
        BatchFault::RADIUS => radius,
        _ => dt,
    }
}

/// The error for the non-finite input `value` of array `field` of contact `i`.
pub(super) fn bad_vector(what: &str, name: &str, field: u8, i: usize, value: [f64; 3]) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "{what} law '{name}': input {}[{i}] = {value:?} must be finite; refused before evaluation",
            BatchFault::field_name(field)
        ),
    )
}
