//! Mindlin's batch in AVX2 registers, four contacts at a time (x86-64 CPUs with AVX2, chosen at
//! run time): the per-contact form's arithmetic, operation for operation, on four lanes
//! ([`dashpot_sdk::simd`]), so every contact gets its bits (a test checks); branches become
//! selects. Contacts are taken in blocks, in two passes: the first turns each spring into the
//! tangent plane, the second advances it and applies the cap; within a pass the steps are
//! independent, so the square roots and divisions of several are in flight together (one step
//! from start to end is a chain of them that would leave the divider waiting). Written with
//! explicit lanes because the compiler's vectorisation of the portable lane loop
//! ([`super::lanes`]) costs 1.7 times as much.

use super::{MindlinBound, SLOTS};
use dashpot_sdk::simd::{
    add3, dot, put_quads, put_triples, quads, scale3, select3, sub3, triples, F64x4, SliderLanes, V3,
};
use dashpot_sdk::{BoundTangential, EnergyBatch, TangentialBatch};
use std::mem::MaybeUninit;

/// Contacts per block of the two passes.
const BLOCK: usize = 32;

/// What the first pass leaves for the second, for four contacts.
#[derive(Clone, Copy)]
struct Turned {
    kt: F64x4,
    eta: F64x4,
    // the spring turned into the tangent plane, and as it was read
    xi: V3,
    x0: V3,
    // the tangential velocity
    vt: V3,
    // k_t of the last call (read only with the energy)
    kprev: F64x4,
    delta: F64x4,
    cap: F64x4,
}

/// [`super::lanes`] on four contacts at a time, with the last `n % 4` through the per-contact
/// form (`DAMPED`: whether η_t ≠ 0 needs computing; `ENERGY`: whether to write each contact's
/// energy to `out`).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn lanes<const DAMPED: bool, const ENERGY: bool>(
    law: &MindlinBound,
    b: TangentialBatch<'_>,
    mut out: Option<EnergyBatch<'_>>,
) {
    let n = b.force.len();
    assert!(
        b.normal.len() == n
            && b.velocity.len() == n
            && b.normal_force.len() == n
            && b.delta.len() == n
            && b.mass.len() == n
            && b.radius.len() == n
            && b.history.len() == SLOTS * n,
        "a batch's arrays have its contacts' lengths"
    );
    let n4 = n - n % 4;
    let zero = F64x4::splat(0.0);
    let (eight_g, mu, two_zeta) = (
        F64x4::splat(law.eight_g),
        F64x4::splat(law.mu),
        F64x4::splat(2.0 * law.damping),
    );
    let dt = F64x4::splat(b.dt);
    // SliderStep's 1/dt, the same value for every contact
    let rate = F64x4::splat(1.0 / b.dt);
    let (normal, velocity) = (b.normal.as_flattened(), b.velocity.as_flattened());
    let mut lo = 0;
    while lo < n4 {
        let steps = (n4 - lo).min(BLOCK) / 4;
        // (not zeroed: the first pass writes the block's `steps` entries, the second reads
        // them; zeroing the whole array for every block was a memset of its size per block)
        let mut turned = [const { MaybeUninit::<Turned>::uninit() }; BLOCK / 4];
        // 1. the stiffness and dashpot, the spring turned into the tangent plane (keeping its
        // length), the tangential velocity
        for (j, t) in turned[..steps].iter_mut().enumerate() {
            let i = lo + 4 * j;
            let nv = triples(normal, i);
            let v = triples(velocity, i);
            let [x, y, z, kprev] = quads(b.history, i);
            let x0 = [x, y, z];
            let (delta, r) = (F64x4::load(b.delta, i), F64x4::load(b.radius, i));
            // k_t = 8 G √(r max(δ, 0)), η_t = 2 ζ_t √(m k_t)
            let kt = eight_g.mul(r.mul(delta.max(zero)).sqrt());
            let eta = if DAMPED {
                two_zeta.mul(F64x4::load(b.mass, i).mul(kt).sqrt())
            } else {
                zero
            };
            let xn = dot(x0, nv);
            let len2 = dot(x0, x0);
            let p = sub3(x0, scale3(nv, xn));
            let plen2 = dot(p, p);
            let s = F64x4::select(plen2.gt(zero), len2.div(plen2).sqrt(), zero);
            t.write(Turned {
                kt,
                eta,
                xi: select3(xn.ne(zero), scale3(p, s), x0),
                x0,
                vt: sub3(v, scale3(nv, dot(v, nv))),
                kprev,
                delta,
                cap: mu.mul(F64x4::load(b.normal_force, i).max(zero)),
            });
        }
        // 2. advance, trial force, Coulomb cap with the spring reset to the capped force; out of
        // touch, no force and the spring dropped
        for (j, t) in turned[..steps].iter().enumerate() {
            let i = lo + 4 * j;
            // SAFETY: the first pass wrote entries ..steps
            let Turned {
                kt,
                eta,
                xi: t0,
                x0,
                vt,
                kprev,
                delta,
                cap,
            } = unsafe { t.assume_init_read() };
            let xi = add3(t0, scale3(vt, dt));
            let ft = sub3(scale3(xi, kt.neg()), scale3(vt, eta));
            let f2 = dot(ft, ft);
            let slide = f2.gt(cap.mul(cap));
            let fs = scale3(ft, cap.div(f2.sqrt()));
            let stiff = kt.gt(zero);
            let touching = delta.gt(zero);
            let mut xs = [zero; 3];
            for k in 0..3 {
                xs[k] = F64x4::select(stiff, fs[k].add(eta.mul(vt[k])).neg().div(kt), zero);
            }
            let f = select3(touching, select3(slide, fs, ft), [zero; 3]);
            let h = select3(touching, select3(slide, xs, xi), [zero; 3]);
            put_triples(f, b.force.as_flattened_mut(), i);
            put_quads([h[0], h[1], h[2], kt], b.history, i);
            if let (true, Some(o)) = (ENERGY, out.as_mut()) {
                // SliderStep::energy from the spring the step started from (as read when the
                // contact is dropped), with k_t of the last call
                let step = SliderLanes {
                    xi_before: select3(touching, t0, x0),
                    k_before: kprev,
                    k: kt,
                    eta,
                    rate,
                    timed: b.dt > 0.0,
                };
                let (power, elastic) = step.energy(slide.or(delta.not_gt(zero)), h, vt, f);
                o.put(i, &power.to_array(), &elastic.to_array());
            }
        }
        lo += 4 * steps;
    }
    // the last contacts, one at a time
    let out = out.as_mut().filter(|_| ENERGY);
    b.each_from(n4, out, |c, h| law.force(c, h), |c, h| law.force_energy(c, h));
}
