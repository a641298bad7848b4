//! rolling-sds's batch in AVX2 registers, four contacts at a time (x86-64 CPUs with AVX2,
//! chosen at run time): the per-contact form's arithmetic, operation for operation, on four
//! lanes ([`dashpot_sdk::simd`]), so every contact gets its bits (a test checks); branches
//! become selects. Contacts are taken in blocks, in two passes: the first turns each spring into
//! the tangent plane, the second advances it and applies the cap; within a pass the steps are
//! independent, so the square roots and divisions of several are in flight together. Written
//! with explicit lanes because the compiler's vectorisation of the portable lane loop
//! ([`super::lanes`]) costs more.

use super::{RollingSds, FRAME_EPS};
use dashpot_sdk::simd::{add3, dot, put_triples, scale3, select3, sub3, triples, F64x4, SliderLanes, V3};
use dashpot_sdk::{BoundRolling, EnergyBatch, RollingBatch};
use std::mem::MaybeUninit;

/// Contacts per block of the two passes.
const BLOCK: usize = 32;

/// What the first pass leaves for the second, for four contacts.
#[derive(Clone, Copy)]
struct Turned {
    // the spring turned into the tangent plane
    xi: V3,
    v: V3,
    fcrit: F64x4,
}

/// [`super::lanes`] on four contacts at a time, with the last `n % 4` through the per-contact
/// form (`ENERGY`: whether to write each contact's energy to `out`).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn lanes<const ENERGY: bool>(
    law: &RollingSds,
    b: RollingBatch<'_>,
    mut out: Option<EnergyBatch<'_>>,
) {
    let n = b.force.len();
    assert!(
        b.normal.len() == n && b.velocity.len() == n && b.normal_force.len() == n && b.history.len() == 3 * n,
        "a batch's arrays have its contacts' lengths"
    );
    let n4 = n - n % 4;
    let zero = F64x4::splat(0.0);
    let (k, gamma, mu, dt) = (
        F64x4::splat(law.k),
        F64x4::splat(law.gamma),
        F64x4::splat(law.mu),
        F64x4::splat(b.dt),
    );
    let frame_eps = F64x4::splat(FRAME_EPS);
    // SliderStep's 1/dt, the same value for every contact
    let rate = F64x4::splat(1.0 / b.dt);
    let (normal, velocity) = (b.normal.as_flattened(), b.velocity.as_flattened());
    let mut lo = 0;
    while lo < n4 {
        let steps = (n4 - lo).min(BLOCK) / 4;
        // (not zeroed: the first pass writes the block's `steps` entries, the second reads
        // them; zeroing the whole array for every block was a memset of its size per block)
        let mut turned = [const { MaybeUninit::<Turned>::uninit() }; BLOCK / 4];
        // 1. the frame update: projected into the tangent plane, rescaled to its length
        for (j, t) in turned[..steps].iter_mut().enumerate() {
            let i = lo + 4 * j;
            let nv = triples(normal, i);
            let x0 = triples(b.history, i);
            let fcrit = mu.mul(F64x4::load(b.normal_force, i).abs());
            let xn = dot(x0, nv);
            let rot = xn.abs().mul(k).gt(frame_eps.mul(fcrit));
            let len = dot(x0, x0).sqrt();
            let p = sub3(x0, scale3(nv, xn));
            let prj = dot(p, p).sqrt();
            let s = F64x4::select(prj.gt(zero), len.div(prj), zero);
            t.write(Turned {
                xi: select3(rot, scale3(p, s), x0),
                v: triples(velocity, i),
                fcrit,
            });
        }
        // 2. advance, trial force, the cap: the spring reset to the capped force, or no force
        // from a zero spring
        for (j, t) in turned[..steps].iter().enumerate() {
            let i = lo + 4 * j;
            // SAFETY: the first pass wrote entries ..steps
            let Turned { xi: before, v, fcrit } = unsafe { t.assume_init_read() };
            let xi = add3(before, scale3(v, dt));
            let ft = sub3(scale3(xi, k.neg()), scale3(v, gamma));
            let mag = dot(ft, ft).sqrt();
            let capped = mag.gt(fcrit);
            let spring = dot(xi, xi).ne(zero);
            let scale = fcrit.div(mag);
            let mut xs = [zero; 3];
            for q in 0..3 {
                xs[q] = fcrit.mul(ft[q]).div(mag).add(gamma.mul(v[q])).neg().div(k);
            }
            let held = select3(spring, scale3(ft, scale), [zero; 3]);
            let f = select3(capped, held, ft);
            let h = select3(capped.and(spring), xs, xi);
            put_triples(f, b.force.as_flattened_mut(), i);
            put_triples(h, b.history, i);
            if let (true, Some(o)) = (ENERGY, out.as_mut()) {
                // dashpot_sdk::physics::SliderStep::energy, a constant stiffness and dashpot
                let step = SliderLanes {
                    xi_before: before,
                    k_before: k,
                    k,
                    eta: gamma,
                    rate,
                    timed: b.dt > 0.0,
                };
                let (power, elastic) = step.energy(capped, h, v, f);
                o.put(i, &power.to_array(), &elastic.to_array());
            }
        }
        lo += 4 * steps;
    }
    // the last contacts, one at a time
    let out = out.as_mut().filter(|_| ENERGY);
    b.each_from(n4, out, |c, h| law.force(c, h), |c, h| law.force_energy(c, h));
}
