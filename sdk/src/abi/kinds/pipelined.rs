//! The block loop of the normal kind's straight-line laws without history
//! ([`BoundContact::STRAIGHT_LINE`]), pipelined: each block's input check runs while the law
//! evaluates the block before it.

use super::super::checks::first_non_finite;
use super::super::checks::{FiniteLanes, NormalLanes, CHECK_BLOCK, LANES};
use super::super::fault::BatchFault;
use super::super::kind::check_energy;
use crate::law::{BoundContact, EnergyBatch, NormalBatch};

/// The blocks of a straight-line law without history, a whole number of them, pipelined: the
/// law evaluates a block [`LANES`] contacts at a time, and each step also adds the same contacts
/// of the next block to its fused input check ([`NormalLanes`]) and its own outputs to the fused
/// output check, so that the checks run in the shadow of the law's arithmetic instead of in
/// passes of their own (a pass before each block left HSD's square roots idle for a third of
/// its time: its instructions sat between two blocks of square roots, beyond what the CPU
/// reorders). The law still sees only checked blocks, and the faults are the ones the plain
/// block loop finds, in its order: a block's inputs, its energy, its forces. `energy` holds the
/// energy outputs of the whole batch when they are wanted; returns whether every contact
/// reported its energy.
///
/// The compiler vectorises a step of [`LANES`] contacts only if the law's code is straight-line
/// (a branch per contact kept LSD scalar, 1.8× slower than in blocks of 64, where the loop is
/// if-converted), if the law runs with no history slots as a constant (with the slot count a
/// variable, the default batch loop's two branches kept HSD scalar, 2.5× slower), and if its
/// outputs are local arrays (see below).
#[inline(always)]
pub(super) fn pipelined_blocks<B: BoundContact>(
    law: &B,
    (delta, rate, mass, radius): (&[f64], &[f64], &[f64], &[f64]),
    force: &mut [f64],
    mut energy: Option<(&mut [f64], &mut [f64])>,
) -> Result<bool, (usize, u8)> {
    let full = force.len();
    let mut written = energy.is_some();
    let mut first = NormalLanes::new();
    for j in (0..CHECK_BLOCK).step_by(LANES) {
        first.add(delta, rate, mass, radius, j);
    }
    first.verdict(0, delta, rate, mass, radius)?;
    let mut lo = 0;
    while lo < full {
        let hi = lo + CHECK_BLOCK;
        let next = hi < full;
        let (mut ahead, mut out, mut all) = (NormalLanes::new(), FiniteLanes::new(), true);
        let mut j = lo;
        while j < hi {
            let k = j + LANES;
            // the law writes into local arrays, copied out after: the compiler then knows
            // that its stores alias none of its inputs (the batch's arrays come from raw
            // pointers) and vectorises its few contacts; writing to the batch's arrays
            // directly, HSD's step was scalar (2.5× slower)
            let mut f = [0.0; LANES];
            let block = NormalBatch {
                delta: &delta[j..k],
                rate: &rate[j..k],
                mass: &mass[j..k],
                radius: &radius[j..k],
                slots: 0,
                history: &mut [],
                force: &mut f,
            };
            all &= match energy.as_mut() {
                None => {
                    law.force_batch(block);
                    false
                }
                Some((p, e)) => {
                    let (mut pl, mut el) = ([0.0; LANES], [0.0; LANES]);
                    let w = law.force_batch_energy(
                        block,
                        EnergyBatch {
                            power: &mut pl,
                            elastic: &mut el,
                        },
                    );
                    p[j..k].copy_from_slice(&pl);
                    e[j..k].copy_from_slice(&el);
                    w
                }
            };
            force[j..k].copy_from_slice(&f);
            out.add(&f, 0);
            if next {
                ahead.add(delta, rate, mass, radius, j + CHECK_BLOCK);
            }
            j = k;
        }
        if let Some((p, e)) = energy.as_ref() {
            if all {
                check_energy(lo, &p[lo..hi], &e[lo..hi])?;
            }
        }
        written &= all;
        if !out.ok() {
            if let Some(i) = first_non_finite(&force[lo..hi]) {
                return Err((lo + i, BatchFault::OUTPUT));
            }
        }
        if next {
            ahead.verdict(hi, delta, rate, mass, radius)?;
        }
        lo = hi;
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::super::normal::{FfiNormalBatch4, Normal, NormalCall};
    use super::*;
    use crate::abi::guard::take_panic;
    use crate::abi::kind::{model_batch, Kind, KindBound};
    use crate::abi::BatchStatus;
    use crate::law::{Contact, Energy};

    /// F = 2δ + δ̇, NaN at δ̇ = 7; power ∞ at δ̇ = 9, elastic energy NaN at δ̇ = 11; panics
    /// when it sees an input the sdk must refuse. Declared straight-line (evaluated by the
    /// pipelined loop) when `S`.
    struct Probe<const S: bool>;

    impl<const S: bool> BoundContact for Probe<S> {
        const STRAIGHT_LINE: bool = S;

        fn force(&self, c: Contact, _h: &mut [f64]) -> f64 {
            let ok = |x: f64| x > 0.0 && x < f64::INFINITY;
            assert!(
                c.delta.is_finite() && c.rate.is_finite() && ok(c.mass) && ok(c.radius),
                "evaluated on a refused input {c:?}"
            );
            if c.rate == 7.0 {
                f64::NAN
            } else {
                2.0 * c.delta + c.rate
            }
        }
        fn energy(&self, c: &Contact, _h: &[f64], _f: f64) -> Option<Energy> {
            Some(Energy {
                power: if c.rate == 9.0 {
                    f64::INFINITY
                } else {
                    0.5 * c.rate
                },
                elastic: if c.rate == 11.0 { f64::NAN } else { c.delta },
            })
        }
    }

    /// The first fault of a batch as the sdk defines it: block by block of `CHECK_BLOCK`, a
    /// block's bad inputs (every δ, then every δ̇, m, r), then its energy (power, then elastic
    /// energy) when asked for, then its forces.
    fn first_fault(c: [&[f64]; 4], energy: bool) -> Option<(usize, u8)> {
        let n = c[0].len();
        for lo in (0..n).step_by(CHECK_BLOCK) {
            let block = lo..(lo + CHECK_BLOCK).min(n);
            let find = |bad: &dyn Fn(usize) -> bool| block.clone().find(|&i| bad(i));
            let fields = [
                BatchFault::DELTA,
                BatchFault::RATE,
                BatchFault::MASS,
                BatchFault::RADIUS,
            ];
            for (k, field) in fields.into_iter().enumerate() {
                let x = c[k];
                if let Some(i) = find(&|i| !(x[i].is_finite() && (k < 2 || x[i] > 0.0))) {
                    return Some((i, field));
                }
            }
            let r = c[1];
            let outputs = [
                (energy, 9.0, BatchFault::POWER),
                (energy, 11.0, BatchFault::ELASTIC),
                (true, 7.0, BatchFault::OUTPUT),
            ];
            for (asked, at, field) in outputs {
                if let Some(i) = find(&|i| asked && r[i] == at) {
                    return Some((i, field));
                }
            }
        }
        None
    }

    /// The first fault of the batch `raw` through the law `Probe<S>`: through the trampoline
    /// (the AVX2 build when the CPU has it) when `dispatched`, else through the baseline build.
    fn probe<const S: bool>(
        raw: &FfiNormalBatch4,
        dispatched: bool,
        energy: bool,
        trial: usize,
    ) -> Option<(usize, u8)> {
        if !dispatched {
            return unsafe { KindBound::<Normal>::run(&Probe::<S>, raw) }.err();
        }
        let (mut fault, mut written) = (BatchFault { index: 0, field: 0 }, false);
        let st = unsafe {
            model_batch::<Normal, Probe<S>>(
                &Probe::<S> as *const Probe<S> as *const std::ffi::c_void,
                raw,
                &mut fault,
                &mut written,
            )
        };
        assert!(
            !matches!(st, BatchStatus::Panic),
            "trial {trial}: {}",
            take_panic()
        );
        assert_eq!(written, energy && matches!(st, BatchStatus::Ok), "trial {trial}");
        (st != BatchStatus::Ok).then_some((fault.index, fault.field))
    }

    /// The pipelined loop (full blocks of a straight-line law without history) and the plain one
    /// (every block of another law, the last block of a straight-line one) find the same first
    /// fault as the definition, for every kind of bad input and
    /// output planted anywhere in batches of every length, energy outputs on and off, in the
    /// baseline and the dispatched (AVX2) builds; the law never sees a refused input; a good
    /// batch gives the law's values.
    #[test]
    fn the_block_loops_find_the_first_fault_and_never_evaluate_a_refused_block() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move |k: usize| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % k as u64) as usize
        };
        let bad_inputs = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -0.0, -1e-300];
        for trial in 0..3000 {
            let n = [1, 7, 63, 64, 65, 128, 200, 256, 333][trial % 9];
            let mut c: [Vec<f64>; 4] = [
                (0..n).map(|i| 1e-6 * i as f64).collect(),
                (0..n).map(|i| 0.25 * (i % 5) as f64 - 0.5).collect(),
                vec![2.0e-4; n],
                vec![1.5e-3; n],
            ];
            for _ in 0..next(4) {
                let i = next(n);
                match next(3) {
                    0 => {
                        let k = next(4);
                        let v = bad_inputs[next(if k < 2 { 3 } else { bad_inputs.len() })];
                        c[k][i] = v;
                    }
                    _ => c[1][i] = [7.0, 9.0, 11.0][next(3)],
                }
            }
            let energy = trial % 2 == 1;
            let want = first_fault([&c[0], &c[1], &c[2], &c[3]], energy);
            for (straight, dispatched) in [(false, false), (false, true), (true, false), (true, true)] {
                let (mut f, mut p, mut e) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                let mut call = NormalCall {
                    batch: NormalBatch {
                        delta: &c[0],
                        rate: &c[1],
                        mass: &c[2],
                        radius: &c[3],
                        slots: 0,
                        history: &mut [],
                        force: &mut f,
                    },
                    reach: None,
                    context: None,
                };
                let (pp, ep) = if energy {
                    (p.as_mut_ptr(), e.as_mut_ptr())
                } else {
                    (std::ptr::null_mut(), std::ptr::null_mut())
                };
                let raw = Normal::raw(&mut call, pp, ep);
                let got = if straight {
                    probe::<true>(&raw, dispatched, energy, trial)
                } else {
                    probe::<false>(&raw, dispatched, energy, trial)
                };
                assert_eq!(
                    got, want,
                    "trial {trial}, n {n}, energy {energy}, straight {straight}, dispatched {dispatched}"
                );
                if want.is_none() {
                    for i in 0..n {
                        assert_eq!(f[i].to_bits(), (2.0 * c[0][i] + c[1][i]).to_bits());
                        if energy {
                            assert_eq!(p[i].to_bits(), (0.5 * c[1][i]).to_bits());
                            assert_eq!(e[i].to_bits(), c[0][i].to_bits());
                        }
                    }
                }
            }
        }
    }
}
