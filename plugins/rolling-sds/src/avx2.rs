//! rolling-sds's batch in AVX2 registers, four contacts at a time (x86-64 CPUs with AVX2,
//! chosen at run time): the per-contact form's arithmetic, operation for operation, on four
//! lanes ([`dashpot_sdk::simd`]), so every contact gets its bits (a test checks); branches
//! become selects. Contacts are taken in blocks, in two passes: the first turns each spring into
//! the tangent plane, the second takes the slider's step ([`SliderX4`]); within a pass the steps
//! are independent, so the square roots and divisions of several are in flight together.

use super::{RollingSds, FRAME_EPS, SLOTS};
use dashpot_sdk::physics::lanes::{load_rows, one_by_one, store_rows, SliderX4};
use dashpot_sdk::physics::Slider;
use dashpot_sdk::simd::{dot, put_triples, scale3, select3, sub3, triples, F64x4, V3};
use dashpot_sdk::{BoundRolling, EnergyBatch, RollingBatch};
use std::mem::MaybeUninit;

/// Contacts per block of the two passes.
const BLOCK: usize = 32;

/// What the first pass leaves for the second, for four contacts.
#[derive(Clone, Copy)]
struct Turned {
    // the spring turned into the tangent plane, and as it was read
    xi: V3,
    x0: V3,
    // the dashpot's share of the last force, as read
    fd: V3,
    v: V3,
    fcrit: F64x4,
}

/// The batch four contacts at a time, with the last `n % 4` (and any four whose trial force
/// overflows |F_r|²) through the per-contact form (`ENERGY`: whether to write each contact's
/// energy to `out`).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn lanes<const ENERGY: bool>(
    law: &RollingSds,
    mut b: RollingBatch<'_>,
    mut out: Option<EnergyBatch<'_>>,
) {
    let n = b.force.len();
    assert!(
        b.normal.len() == n
            && b.velocity.len() == n
            && b.normal_force.len() == n
            && b.history.len() == SLOTS * n,
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
    // the slider's 1/dt, the same value for every contact
    let rate = F64x4::splat(Slider::rate(b.dt));
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
            let [x, y, z, fx, fy, fz] = load_rows::<SLOTS>(b.history, i);
            let x0 = [x, y, z];
            let fcrit = mu.mul(F64x4::load(b.normal_force, i).abs());
            let xn = dot(x0, nv);
            let rot = xn.abs().mul(k).gt(frame_eps.mul(fcrit));
            let len = dot(x0, x0).sqrt();
            let p = sub3(x0, scale3(nv, xn));
            let prj = dot(p, p).sqrt();
            let s = F64x4::select(prj.gt(zero), len.div(prj), zero);
            t.write(Turned {
                xi: select3(rot, scale3(p, s), x0),
                x0,
                fd: [fx, fy, fz],
                v: triples(velocity, i),
                fcrit,
            });
        }
        // 2. the slider's step
        for (j, t) in turned[..steps].iter().enumerate() {
            let i = lo + 4 * j;
            // SAFETY: the first pass wrote entries ..steps
            let Turned { xi, x0, fd, v, fcrit } = unsafe { t.assume_init_read() };
            let sl = SliderX4 {
                k,
                k_before: k,
                eta: gamma,
                cap: fcrit,
                rate,
                dt,
            };
            let s = sl.advance(xi, v);
            if s.overflow {
                // |F_r|² overflowed on some lane: these four one at a time (history unwritten)
                let o = out.as_mut().filter(|_| ENERGY);
                one_by_one(
                    &mut b,
                    i,
                    i + 4,
                    o,
                    |c, h| law.force(c, h),
                    |c, h| law.force_energy(c, h),
                );
                continue;
            }
            if let (true, Some(o)) = (ENERGY, out.as_mut()) {
                // from the spring and the dashpot's share as read
                let (power, elastic) = sl.energy(x0, fd, &s, v);
                o.put(i, &power.to_array(), &elastic.to_array());
            }
            put_triples(s.force, b.force.as_flattened_mut(), i);
            let (h, d) = (s.spring, s.dashpot);
            store_rows::<SLOTS>([h[0], h[1], h[2], d[0], d[1], d[2]], b.history, i);
        }
        lo += 4 * steps;
    }
    // the last contacts, one at a time
    let out = out.as_mut().filter(|_| ENERGY);
    b.each_from(n4, out, |c, h| law.force(c, h), |c, h| law.force_energy(c, h));
}
