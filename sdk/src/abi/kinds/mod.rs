//! The law kinds as instances of the one ABI shape of [`kind`](super::kind): normal (0.2's
//! contact batch plus 0.3's reach and energy and 0.4's context outputs), tangential and rolling
//! (one vector batch: 0.2's tangential batch plus 0.3's energy outputs and 0.4's context
//! input), twisting, and heat (new in 0.4). Each instance is its raw batch (0.3's, which the frozen
//! [`v3`] module keeps, extended), the host's view of it, and the block loop that
//! checks and evaluates it; everything else (vtables, trampolines, handles) is generic.

use super::checks::*;
use super::fault::bad_input;
use super::fault::{BatchFault, BatchStatus};
use super::kind::{blocks, check_energy, energy_out, kind_law, raw_out, slice, slice_mut, Kind, KindBound};
use super::{v2, v3};
use crate::context::NormalContext;
use crate::error::{ErrorKind, LawError};
use crate::law::{
    history_of, BoundContact, Coefficient, Contact, ContactLaw, EnergyBatch, LawKind, NormalBatch,
};
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
/// `$batch`, whose motion input `$motion` and output `$out` are arrays of `$mty` and `$oty`,
/// `$mty` being `$width` f64 values; a bad motion input is reported as array `$field`), with
/// the energy outputs `$power` and `$elastic` when either is wanted and the normal contexts
/// `$context` (null: none, the defaults). `$eval(block)` runs the law on a block,
/// `$eval_energy(block, energy)` runs it with its energy outputs (whether every contact
/// reported one). Each block's inputs are checked before the law runs on it (the fused test
/// [`motion_inputs_ok`], the search only when it says no) and its outputs after. Expands to
/// the body of a `KindBound::run` (it returns the first fault).
macro_rules! motion_run {
    ($r:expr, $power:expr, $elastic:expr, $context:expr,
     $batch:ident { $motion:ident: $mty:ty => $out:ident: $oty:ty }, $width:expr, $field:expr,
     $eval:expr, $eval_energy:expr $(,)?) => {{
        let r = $r;
        if !(r.dt >= 0.0 && r.dt < f64::INFINITY) {
            return Err((0, BatchFault::DT));
        }
        const W: usize = $width;
        const _: () = assert!(std::mem::size_of::<$mty>() == W * 8 && std::mem::size_of::<$oty>() == W * 8);
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
        let context = contexts($context, n);
        let mut scratch = Vec::new();
        let mut energy = unsafe { energy_out(n, $power, $elastic, &mut scratch) };
        let mut written = energy.is_some();
        blocks!(n, |lo, hi| {
            let (nl, ml) = (&normal[lo..hi], &motion[lo..hi]);
            let (f, d, m, a) = (&fnorm[lo..hi], &delta[lo..hi], &mass[lo..hi], &radius[lo..hi]);
            // SAFETY: $mty is W f64 values (asserted above)
            let mf = unsafe { slice(ml.as_ptr() as *const f64, W * (hi - lo)) };
            check_motion(lo, nl.as_flattened(), mf, W, $field, [f, d, m, a])?;
            let x = context_block(context, lo, hi)?;
            let o = &mut out[lo..hi];
            let block = $batch {
                dt: r.dt,
                normal: nl,
                $motion: ml,
                normal_force: f,
                delta: d,
                mass: m,
                radius: a,
                context: x,
                slots,
                history: &mut history[lo * slots..hi * slots],
                $out: &mut *o,
            };
            written &= eval_block!(energy, lo, hi, block, $eval, $eval_energy);
            // SAFETY: $oty is W f64 values (asserted above)
            let of = unsafe { slice(o.as_ptr() as *const f64, W * (hi - lo)) };
            match first_non_finite(of) {
                Some(i) => Err((lo + i / W, BatchFault::OUTPUT)),
                None => Ok(()),
            }
        });
        Ok(written)
    }};
}

/// Checks the inputs of a block of a motion kind (tangential, rolling, twisting) from contact
/// `lo`: the unit normals (flattened), the kind's own input `motion` (flattened, `width` values
/// a contact; a bad one reported as array `field`), the normal forces (N), overlaps (m),
/// masses (kg) and radii (m). The fused test first, the search only when it says no: `Ok`, or
/// the first bad contact and its array.
#[inline(always)]
pub(super) fn check_motion(
    lo: usize,
    normal: &[f64],
    motion: &[f64],
    width: usize,
    field: u8,
    [f, d, m, a]: [&[f64]; 4],
) -> Result<(), (usize, u8)> {
    if motion_inputs_ok(normal, motion, f, d, m, a) {
        return Ok(());
    }
    first_bad_motion(lo, normal, motion, width, field, [f, d, m, a])
}

mod heat;
mod normal;
mod pipelined;
mod twisting;
mod vector;

pub use heat::{FfiHeatBatch, Heat};
pub(crate) use normal::normal_non_finite;
pub use normal::{FfiNormalBatch4, Normal, NormalCall};
pub use twisting::{FfiTwistingBatch4, Twisting};
pub use vector::{FfiVectorBatch4, Rolling, Tangential};

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

/// The contexts of a raw batch of `n` contacts: none (empty) when `p` is null.
///
/// # Safety
/// A non-null `p` is valid for `n` values.
#[inline(always)]
pub(super) unsafe fn contexts<'a>(p: *const NormalContext, n: usize) -> &'a [NormalContext] {
    if p.is_null() {
        &[]
    } else {
        unsafe { slice(p, n) }
    }
}

/// The contexts of the block `lo..hi` of a batch whose contexts are `all` (none, or one per
/// contact), checked: each field finite and ≥ 0, else the first bad contact.
#[inline(always)]
pub(super) fn context_block(
    all: &[NormalContext],
    lo: usize,
    hi: usize,
) -> Result<&[NormalContext], (usize, u8)> {
    if all.is_empty() {
        return Ok(&[]);
    }
    let x = &all[lo..hi];
    match first_invalid_context(x) {
        Some(i) => Err((lo + i, BatchFault::CONTEXT_INPUT)),
        None => Ok(x),
    }
}

/// The raw pointer of a batch's contexts: null for none.
pub(super) fn context_ptr(x: &[NormalContext]) -> *const NormalContext {
    if x.is_empty() {
        std::ptr::null()
    } else {
        x.as_ptr()
    }
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
/// contact `lo`, the search of [`check_motion`] (a bad block, or a false alarm of its fused
/// test): the unit normals (`normal`, flattened `[x, y, z]` triples), then the kind's own input
/// (`motion`, flattened, `width` values a contact, reported as array `field`), the normal
/// forces (N), the overlaps (m), the masses (kg) and the radii (m).
#[cold]
#[inline(never)]
fn first_bad_motion(
    lo: usize,
    normal: &[f64],
    motion: &[f64],
    width: usize,
    field: u8,
    [fnorm, delta, m, a]: [&[f64]; 4],
) -> Result<(), (usize, u8)> {
    first_bad(
        lo,
        [
            (first_non_finite(normal).map(|i| i / 3), BatchFault::NORMAL),
            (first_non_finite(motion).map(|i| i / width), field),
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

/// The error for the bad context of contact `i` of a batch whose contexts are `all`.
pub(super) fn bad_context(what: &str, name: &str, i: usize, all: &[NormalContext]) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "{what} law '{name}': input context[{i}] = {:?} must have every field finite and ≥ 0 \
             (contact radius m, cap force N, damping N·s/m); refused before evaluation",
            all.get(i).copied().unwrap_or_default()
        ),
    )
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
