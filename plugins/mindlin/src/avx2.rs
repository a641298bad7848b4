//! Mindlin's batch in AVX2 registers, four contacts at a time (x86-64 CPUs with AVX2, chosen at
//! run time): the per-contact form's arithmetic, operation for operation, on four lanes
//! ([`dashpot_sdk::simd`]), so every contact gets its bits (a test checks); branches become
//! selects. Contacts are taken in blocks, in two passes: the first turns each spring into the
//! tangent plane, the second takes the slider's step ([`SliderX4`]); within a pass the steps are
//! independent, so the square roots and divisions of several are in flight together (one step
//! from start to end is a chain of them that would leave the divider waiting). Written with
//! explicit lanes because the compiler's vectorisation of a portable lane loop cost 1.7 times
//! as much.

use super::{MindlinBound, SLOTS};
use dashpot_sdk::physics::lanes::{load_rows, one_by_one, store_rows, SlidX4, SliderX4};
use dashpot_sdk::physics::Slider;
use dashpot_sdk::simd::{dot, put_triples, scale3, select3, sub3, triples, F64x4, V3};
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
    // the dashpot's share of the last force, as read
    fd: V3,
    // the relative velocity, and its tangential part
    v: V3,
    vt: V3,
    // k_t of the last call
    kprev: F64x4,
    delta: F64x4,
    cap: F64x4,
}

/// The batch four contacts at a time, with the last `n % 4` (and any four whose trial force
/// overflows |F_t|²) through the per-contact form (`DAMPED`: whether η_t ≠ 0 needs computing;
/// `ENERGY`: whether to write each contact's energy to `out`).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn lanes<const DAMPED: bool, const ENERGY: bool>(
    law: &MindlinBound,
    mut b: TangentialBatch<'_>,
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
    // the slider's 1/dt, the same value for every contact
    let rate = F64x4::splat(Slider::rate(b.dt));
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
            let [x, y, z, kprev, fx, fy, fz] = load_rows::<SLOTS>(b.history, i);
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
                fd: [fx, fy, fz],
                v,
                vt: sub3(v, scale3(nv, dot(v, nv))),
                kprev,
                delta,
                cap: mu.mul(F64x4::load(b.normal_force, i).max(zero)),
            });
        }
        // 2. the slider's step; out of touch, no force and the spring dropped
        for (j, t) in turned[..steps].iter().enumerate() {
            let i = lo + 4 * j;
            // SAFETY: the first pass wrote entries ..steps
            let Turned {
                kt,
                eta,
                xi: t0,
                x0,
                fd,
                v,
                vt,
                kprev,
                delta,
                cap,
            } = unsafe { t.assume_init_read() };
            let sl = SliderX4 {
                k: kt,
                k_before: kprev,
                eta,
                cap,
                rate,
                dt,
            };
            let s = sl.advance(t0, vt);
            if s.overflow {
                // |F_t|² overflowed on some lane: these four one at a time (history unwritten)
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
            let touching = delta.gt(zero);
            let none = [zero; 3];
            let s = SlidX4 {
                force: select3(touching, s.force, none),
                spring: select3(touching, s.spring, none),
                dashpot: select3(touching, s.dashpot, none),
                sliding: s.sliding,
                overflow: false,
            };
            put_triples(s.force, b.force.as_flattened_mut(), i);
            let (h, d) = (s.spring, s.dashpot);
            store_rows::<SLOTS>([h[0], h[1], h[2], kt, d[0], d[1], d[2]], b.history, i);
            if let (true, Some(o)) = (ENERGY, out.as_mut()) {
                // Slider::energy from the spring and dashpot's share as read (out of touch: a
                // step to rest, Slider::dropped), against the whole relative velocity
                let (power, elastic) = sl.energy(x0, fd, &s, v);
                o.put(i, &power.to_array(), &elastic.to_array());
            }
        }
        lo += 4 * steps;
    }
    // the last contacts, one at a time
    let out = out.as_mut().filter(|_| ENERGY);
    b.each_from(n4, out, |c, h| law.force(c, h), |c, h| law.force_energy(c, h));
}
