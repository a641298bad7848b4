//! The rolling and twisting springs' batches in AVX2 registers, four contacts at a time (x86-64
//! CPUs with AVX2, chosen at run time): `rolling sds` and `twisting marshall` of
//! [`crate::rotation`], operation for operation on four lanes ([`dashpot_sdk::simd`]), so
//! every contact gets the per-contact form's bits (a test checks); branches become selects.
//! Only the outputs: a batch with energy outputs, or without the normal law's contexts, goes
//! contact by contact.

use crate::rotation::{Sds, TWOTHIRDS};
use crate::tangential::Spring;
use crate::tangential_avx2::{flat, four_at_a_time, turn_advance, vector_cols, Cols};
use dashpot_sdk::simd::{add3, dot, put_triples, scale3, select3, triples, F64x4};
use dashpot_sdk::{NormalContext, RollingBatch, TwistingBatch};
use std::arch::x86_64::*;

/// `rolling sds` ([`crate::rotation::rolling_sds`]) on contacts `i .. i + 4` of `b`.
///
/// # Safety
/// The CPU must support AVX2; `i + 4` contacts.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn sds_step(s: &Sds, b: &mut Cols<'_>, i: usize) {
    let zero = F64x4::splat(0.0);
    let (k, mu, dt) = (F64x4::splat(s.k), F64x4::splat(s.mu), F64x4::splat(b.dt));
    let (neg_k, neg_gamma) = (F64x4::splat(-s.k), F64x4::splat(-s.gamma));
    let nv = triples(b.normal, i);
    let vrl = triples(b.motion, i);
    let [_, cap, _] = triples(b.ctx, i);
    let frcrit = mu.mul(cap);
    let xi = turn_advance(triples(b.history, i), nv, k, frcrit, dt, vrl);
    let f = add3(scale3(xi, neg_k), scale3(vrl, neg_gamma));
    let magfr = dot(f, f).sqrt();
    let slid = magfr.gt(frcrit);
    let held = dot(xi, xi).sqrt().ne(zero);
    // past the cap, with ξ ≠ 0: ξ = −(μ F_c F/|F| + γ v)/k and F scaled to μ F_c
    let k_inv = F64x4::splat(1.0).div(k);
    let magfr_inv = F64x4::splat(1.0).div(magfr);
    let reset = add3(
        scale3(f, frcrit.neg().mul(k_inv).mul(magfr_inv)),
        scale3(vrl, neg_gamma.mul(k_inv)),
    );
    let capped = scale3(f, frcrit.mul(magfr_inv));
    let force = select3(slid, select3(held, capped, [zero; 3]), f);
    put_triples(force, b.out, i);
    put_triples(select3(slid.and(held), reset, xi), b.history, i);
}

/// `rolling sds` on the contacts `0 .. n − n % 4` of batch `b` with contexts `ctx` (one per
/// contact), four at a time; returns where the lanes stopped (the rest is the caller's).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn rolling_sds(s: &Sds, b: &mut RollingBatch<'_>, ctx: &[NormalContext]) -> usize {
    let n = b.force.len();
    let mut cols = vector_cols(b, ctx, 3);
    four_at_a_time!(n, cols, |c, i| sds_step(s, c, i))
}

/// `twisting marshall` ([`crate::rotation::marshall_twist`], [`crate::rotation::Twist::step`])
/// of the tangential constants `s` on contacts `i .. i + 4` of `b` (history rows [θ, a]).
///
/// # Safety
/// The CPU must support AVX2; `i + 4` contacts.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn marshall_step(s: &Spring, b: &mut Cols<'_>, i: usize) {
    let zero = F64x4::splat(0.0);
    let (half, one, dt) = (F64x4::splat(0.5), F64x4::splat(1.0), F64x4::splat(b.dt));
    let [a, cap, damping] = triples(b.ctx, i);
    let rate = F64x4::load(b.motion, i);
    debug_assert!(2 * (i + 4) <= b.history.len());
    let h = b.history.as_mut_ptr().add(2 * i);
    // rows [θ0 a0 θ1 a1] [θ2 a2 θ3 a3]: unpacked to [θ0 θ2 θ1 θ3], put in order
    let (lo, hi) = (_mm256_loadu_pd(h), _mm256_loadu_pd(h.add(4)));
    let before = F64x4(_mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpacklo_pd(lo, hi)));
    // Marshall's constants: k = k_t a²/2, γ = x_t η_n a²/2, μ = (2/3) μ_t a
    let k = F64x4::splat(0.5 * s.k).mul(a).mul(a);
    let damp = half.mul(F64x4::splat(s.xt).mul(damping)).mul(a).mul(a);
    let mu = F64x4::splat(TWOTHIRDS * s.mu).mul(a);
    let theta = before.add(rate.mul(dt));
    let m = k.neg().mul(theta).sub(damp.mul(rate));
    let sign = F64x4::select(rate.gt(zero), one, F64x4::select(rate.lt(zero), one.neg(), zero));
    let mtcrit = mu.mul(cap);
    let slid = m.abs().gt(mtcrit);
    let theta = F64x4::select(slid, mtcrit.mul(sign).sub(damp.mul(rate)).div(k), theta);
    let m = F64x4::select(slid, mtcrit.neg().mul(sign), m);
    _mm256_storeu_pd(b.out.as_mut_ptr().add(i), m.0);
    // the rows back: [θ0 θ2 θ1 θ3] and [a0 a2 a1 a3] interleaved
    let t = _mm256_permute4x64_pd::<0b11_01_10_00>(theta.0);
    let r = _mm256_permute4x64_pd::<0b11_01_10_00>(a.0);
    _mm256_storeu_pd(h, _mm256_unpacklo_pd(t, r));
    _mm256_storeu_pd(h.add(4), _mm256_unpackhi_pd(t, r));
}

/// `twisting marshall` of the tangential constants `s` on the contacts `0 .. n − n % 4` of
/// batch `b` with contexts `ctx` (one per contact), four at a time; returns where the lanes
/// stopped (the rest is the caller's).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn twisting_marshall(
    s: &Spring,
    b: &mut TwistingBatch<'_>,
    ctx: &[NormalContext],
) -> usize {
    let n = b.torque.len();
    assert!(
        b.normal.len() == n
            && b.rate.len() == n
            && ctx.len() == n
            && b.slots == 2
            && b.history.len() == 2 * n,
        "a batch's arrays have its contacts' lengths"
    );
    let mut cols = Cols {
        dt: b.dt,
        normal: b.normal.as_flattened(),
        motion: b.rate,
        ctx: flat(ctx),
        history: b.history,
        out: b.torque,
    };
    four_at_a_time!(n, cols, |c, i| marshall_step(s, c, i))
}
