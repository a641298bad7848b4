//! The history springs' batch in AVX2 registers, four contacts at a time (x86-64 CPUs with
//! AVX2, chosen at run time): `linear_history`, the four `mindlin` variants and the classic
//! springs of [`crate::tangential`], operation for operation on four lanes
//! ([`dashpot_sdk::simd`]), so every contact gets the per-contact form's bits (a test checks);
//! branches become selects. Only the forces: a batch with energy outputs, or without the
//! normal law's contexts, goes contact by contact.

use crate::tangential::{Spring, FRAME_EPS};
use crate::tangential_laws::kind;
use dashpot_sdk::physics::lanes::{load_rows, store_rows};
use dashpot_sdk::simd::{add3, dot, put_triples, scale3, select3, sub3, triples, F64x4, V3};
use dashpot_sdk::{TangentialBatch, VectorBatch};

/// The history slots of a spring of kind `KIND`: ξ (or the elastic force), and the contact
/// radius of the last step but for the classic Hookean spring.
pub(crate) const fn slots(kind: u8) -> usize {
    if kind == kind::LINEAR || kind == kind::CLASSIC_HOOKE {
        3
    } else {
        4
    }
}

/// The part of `v` in the tangent plane of `n` as [`crate::spring::tangential`] computes it:
/// `v` itself when its normal part is below 10⁻¹³ of its length.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn tangential(v: V3, n: V3) -> V3 {
    let vn = dot(v, n);
    let tangent = vn.mul(vn).le(F64x4::splat(1e-26).mul(dot(v, v)));
    select3(tangent, v, sub3(v, scale3(n, vn)))
}

/// [`crate::spring::rotate_rescale`]: `v` turned into the tangent plane of `n` at its length.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn rotate_rescale(v: V3, n: V3) -> V3 {
    let zero = F64x4::splat(0.0);
    let rsht = dot(v, n);
    let mag = dot(v, v).sqrt();
    let p = sub3(v, scale3(n, rsht));
    let pm = dot(p, p).sqrt();
    let s = F64x4::select(pm.gt(zero), mag.div(pm), zero);
    scale3(p, s)
}

/// [`crate::tangential::turn_advance`]: the spring `xi` turned into the tangent plane of `n`
/// when its normal part, as a force (stiffness `k`), exceeds 10⁻¹⁰ of `cap`, then advanced by
/// `step` `v`.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn turn_advance(xi: V3, n: V3, k: F64x4, cap: F64x4, step: F64x4, v: V3) -> V3 {
    let turn = dot(xi, n).abs().mul(k).gt(F64x4::splat(FRAME_EPS).mul(cap));
    let start = select3(turn, rotate_rescale(xi, n), xi);
    add3(start, scale3(v, step))
}

/// The flattened `[a, F_c, η_n]` triples of a batch's contexts.
#[inline(always)]
pub(crate) fn flat(ctx: &[dashpot_sdk::NormalContext]) -> &[f64] {
    // SAFETY: NormalContext is three f64 (repr(C)), so n contexts are 3 n values
    unsafe { std::slice::from_raw_parts(ctx.as_ptr() as *const f64, 3 * ctx.len()) }
}

/// The arrays of a tangential or rolling batch `b` with contexts `ctx`, checked: each of the
/// batch's length, `slots` history slots a contact.
pub(crate) fn vector_cols<'a>(
    b: &'a mut VectorBatch<'_>,
    ctx: &'a [dashpot_sdk::NormalContext],
    slots: usize,
) -> Cols<'a> {
    let n = b.force.len();
    assert!(
        b.normal.len() == n
            && b.velocity.len() == n
            && ctx.len() == n
            && b.slots == slots
            && b.history.len() == slots * n,
        "a batch's arrays have its contacts' lengths"
    );
    Cols {
        dt: b.dt,
        normal: b.normal.as_flattened(),
        motion: b.velocity.as_flattened(),
        ctx: flat(ctx),
        history: &mut *b.history,
        out: b.force.as_flattened_mut(),
    }
}

/// A batch's arrays as the lane steps read and write them, flattened: the unit normals, the
/// motion input (a velocity or a rate), the contexts (`[a, F_c, η_n]` triples), the history
/// and the output (a force or a torque); the step (s).
pub(crate) struct Cols<'a> {
    pub(crate) dt: f64,
    pub(crate) normal: &'a [f64],
    pub(crate) motion: &'a [f64],
    pub(crate) ctx: &'a [f64],
    pub(crate) history: &'a mut [f64],
    pub(crate) out: &'a mut [f64],
}

/// `four_at_a_time!(n, cols, |c, i| step)`: the lane step on contacts `i .. i + 4` of the `n`
/// contacts of `cols` (a [`Cols`]) for every four; evaluates to where the lanes stopped,
/// `n − n % 4`: the last `n % 4` contacts (all of a batch of fewer than four) are the caller's,
/// through the per-contact form (the same bits; padding them to four lanes cost more than the
/// per-contact form, which a batch of one contact pays on every call). A macro, not a function
/// taking a closure: the step must be compiled for AVX2.
macro_rules! four_at_a_time {
    ($n:expr, $cols:ident, |$c:ident, $i:ident| $step:expr) => {{
        let n: usize = $n;
        let n4 = n - n % 4;
        let mut i = 0;
        while i < n4 {
            {
                let ($c, $i) = (&mut $cols, i);
                $step;
            }
            i += 4;
        }
        n4
    }};
}
pub(crate) use four_at_a_time;

/// The spring of kind `KIND` (bound constants `s`) on contacts `i .. i + 4` of the arrays `b`:
/// the force written, the history advanced. Each line is the per-contact form's operation (`crate::tangential`).
///
/// # Safety
/// The CPU must support AVX2; `i + 4` contacts, `b.slots == slots(KIND)`.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn step<const KIND: u8>(s: &Spring, b: &mut Cols<'_>, i: usize) {
    let zero = F64x4::splat(0.0);
    let n = triples(b.normal, i);
    let v = triples(b.motion, i);
    let [a, cap_force, damping] = triples(b.ctx, i);
    let dt = F64x4::splat(b.dt);
    let classic =
        KIND == kind::CLASSIC_HOOKE || KIND == kind::CLASSIC_HERTZ || KIND == kind::CLASSIC_GRANULAR;
    let force_history = KIND == kind::MINDLIN_FORCE || KIND == kind::MINDLIN_RESCALE_FORCE;
    let rescale = KIND == kind::MINDLIN_RESCALE || KIND == kind::MINDLIN_RESCALE_FORCE;
    // the history: ξ (or F_el) and, for the a-scaled springs, the a of the last step
    let (before, a_last) = if slots(KIND) == 3 {
        (triples(b.history, i), zero)
    } else {
        let [x, y, z, l] = load_rows::<4>(b.history, i);
        ([x, y, z], l)
    };
    let vtr = tangential(v, n);
    let damp = F64x4::splat(s.xt).mul(damping);
    let fscrit = cap_force.mul(F64x4::splat(s.mu));
    // the spring's stiffness and the one its reset past the cap divides by
    let k = F64x4::splat(s.k);
    let (k_spring, k_reset) = match KIND {
        kind::LINEAR | kind::CLASSIC_HOOKE => (k, k),
        kind::CLASSIC_GRANULAR => (k.mul(a), k),
        _ => (k.mul(a), k.mul(a)),
    };
    let (xi, held) = if classic {
        // ξ += v_t dt, then projected onto the tangent plane
        let xi = add3(before, scale3(vtr, dt));
        let shrmag = dot(xi, xi).sqrt();
        let xi = sub3(xi, scale3(n, dot(xi, n)));
        (xi, shrmag.ne(zero))
    } else {
        let hist = if rescale {
            select3(a.lt(a_last), scale3(before, a.div(a_last)), before)
        } else {
            before
        };
        // turned into the tangent plane when its normal part, as a force, matters; advanced
        let (k_turn, step) = if force_history {
            (F64x4::splat(1.0), k_spring.neg().mul(dt))
        } else {
            (k_spring, dt)
        };
        let xi = turn_advance(hist, n, k_turn, fscrit, step, vtr);
        (xi, dot(xi, xi).sqrt().ne(zero))
    };
    let f = if force_history {
        add3(scale3(vtr, damp.neg()), xi)
    } else if classic || KIND == kind::LINEAR {
        sub3(scale3(xi, k_spring.neg()), scale3(vtr, damp))
    } else {
        sub3(scale3(vtr, damp.neg()), scale3(xi, k_spring))
    };
    // Coulomb's cap: past it the force scaled to μ F_c and the spring reset (a spring that held
    // nothing gives no force)
    let magfs = dot(f, f).sqrt();
    let slid = magfs.not_le(fscrit);
    let capped = scale3(f, fscrit.mul(F64x4::splat(1.0).div(magfs)));
    let mut reset = add3(capped, scale3(vtr, damp));
    if !force_history {
        reset = scale3(reset, F64x4::splat(-1.0).div(k_reset));
    }
    let force = select3(slid, select3(held, capped, [zero; 3]), f);
    let xi = select3(slid.and(held), reset, xi);
    put_triples(force, b.out, i);
    if slots(KIND) == 3 {
        put_triples(xi, b.history, i);
    } else {
        store_rows::<4>([xi[0], xi[1], xi[2], a], b.history, i);
    }
}

/// The spring of kind `KIND` on the contacts `0 .. n − n % 4` of batch `b` with contexts
/// `ctx` (one per contact), four at a time; returns where the lanes stopped (the rest is the
/// caller's).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn lanes<const KIND: u8>(
    s: &Spring,
    b: &mut TangentialBatch<'_>,
    ctx: &[dashpot_sdk::NormalContext],
) -> usize {
    let n = b.force.len();
    let mut cols = vector_cols(b, ctx, slots(KIND));
    four_at_a_time!(n, cols, |c, i| step::<KIND>(s, c, i))
}
