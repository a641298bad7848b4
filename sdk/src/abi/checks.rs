//! The input and output checks of the batch trampolines, shared by every law kind: fused,
//! branch-free tests that a block of values is finite (and positive where it must be), cheap
//! enough to hide behind the law's arithmetic, the exact searches that name the culprit when
//! they say no, and the run-time choice of the AVX2 build of the block loops.

use super::fault::BatchFault;
use crate::NormalContext;

/// Whether every value is finite (vectorises with plain SSE2: v − v is NaN exactly when v is not
/// finite).
#[inline]
#[allow(clippy::eq_op)]
pub(crate) fn all_finite(x: &[f64]) -> bool {
    if x.len() < 8 {
        // a few values (a batch of one or two contacts): the sum alone, without the lanes'
        // setup and reduction
        return x.iter().fold(0.0, |a, v| a + (v - v)) == 0.0;
    }
    let mut acc = [0.0f64; 8];
    let mut it = x.chunks_exact(8);
    for c in &mut it {
        for j in 0..8 {
            acc[j] += c[j] - c[j];
        }
    }
    let tail = it.remainder().iter().fold(0.0, |a, v| a + (v - v));
    acc.iter().sum::<f64>() + tail == 0.0
}

/// Whether every value is finite and > 0.
#[inline]
pub(crate) fn all_positive(x: &[f64]) -> bool {
    x.iter().fold(true, |ok, &v| ok & (v > 0.0) & (v < f64::INFINITY))
}

/// Inputs and outputs are checked in blocks of this many contacts, right before and after the
/// law runs on the block: the block's values are then still in L1, and the fused checks
/// (vectorised sums and minima, see [`normal_inputs_ok`]) overlap the law's square roots in
/// the CPU's out-of-order window instead of costing separate passes over memory. Measured on
/// HSD with per-contact geometry (sdk 0.2): blocks of 64 cost about a fifth less than blocks of
/// 16 (per-block overhead); larger blocks gained nothing more.
pub const CHECK_BLOCK: usize = 64;

/// Contacts per step of the pipelined normal block loop: one 8-lane vector of f64 (AVX-512),
/// two of AVX2, four of SSE2. A block of [`CHECK_BLOCK`] contacts is evaluated in steps of
/// `LANES`, and each step also checks the inputs of the same `LANES` contacts of the next block
/// (see [`NormalLanes`]).
pub const LANES: usize = 8;
const _: () = assert!(CHECK_BLOCK % LANES == 0);

/// The fused input check of a normal block ([`normal_inputs_ok`]'s sums and minima), accumulated
/// in [`LANES`] independent lanes, `LANES` contacts at a time, so that it can be interleaved
/// with the law's evaluation of the previous block: a separate pass before each block kept
/// the CPU's square-root unit idle while it ran (its instructions sat between two blocks of
/// square roots, beyond the out-of-order window), about 0.7 ns a contact on HSD.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalLanes {
    sum: [f64; LANES],
    min: [f64; LANES],
}

impl NormalLanes {
    /// Nothing checked yet.
    #[inline(always)]
    pub(crate) fn new() -> NormalLanes {
        NormalLanes {
            sum: [0.0; LANES],
            min: [f64::INFINITY; LANES],
        }
    }

    /// Adds the contacts `[i, i + LANES)` of the overlaps `d`, rates `r`, masses `m` and radii
    /// `a` (each lane: a running sum of all four, a running minimum of m and a).
    #[inline(always)]
    pub(crate) fn add(&mut self, d: &[f64], r: &[f64], m: &[f64], a: &[f64], i: usize) {
        let k = i + LANES;
        let (d, r, m, a) = (&d[i..k], &r[i..k], &m[i..k], &a[i..k]);
        for j in 0..LANES {
            self.sum[j] += (d[j] + r[j]) + (m[j] + a[j]);
            self.min[j] = min(self.min[j], min(m[j], a[j]));
        }
    }

    /// Whether every contact added is surely good: each lane's sum finite (NaN and ±∞ stick
    /// in a sum; an overflow only sends a good block to the exact check) and its minimum > 0.
    #[inline(always)]
    #[allow(clippy::eq_op)]
    pub(crate) fn ok(&self) -> bool {
        let mut ok = true;
        for j in 0..LANES {
            ok &= (self.sum[j] - self.sum[j] == 0.0) & (self.min[j] > 0.0);
        }
        ok
    }

    /// `Ok` when the block of [`CHECK_BLOCK`] contacts from `lo`, whose inputs these lanes
    /// added, is good; else the first bad input, found by the exact check (a false alarm lets
    /// the block through).
    #[inline(always)]
    pub(crate) fn verdict(
        &self,
        lo: usize,
        d: &[f64],
        r: &[f64],
        m: &[f64],
        a: &[f64],
    ) -> Result<(), (usize, u8)> {
        if self.ok() {
            return Ok(());
        }
        let hi = lo + CHECK_BLOCK;
        match check_normal_inputs(&d[lo..hi], &r[lo..hi], &m[lo..hi], &a[lo..hi]) {
            Some((i, f)) => Err((lo + i, f)),
            None => Ok(()),
        }
    }
}

/// The fused output check ([`all_finite`]) accumulated in [`LANES`] lanes, `LANES` values at
/// a time.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FiniteLanes([f64; LANES]);

impl FiniteLanes {
    /// Nothing checked yet.
    #[inline(always)]
    pub(crate) fn new() -> FiniteLanes {
        FiniteLanes([0.0; LANES])
    }

    /// Adds the values `[i, i + LANES)` of `x`.
    #[inline(always)]
    #[allow(clippy::eq_op)]
    pub(crate) fn add(&mut self, x: &[f64], i: usize) {
        for (acc, v) in self.0.iter_mut().zip(&x[i..i + LANES]) {
            *acc += v - v;
        }
    }

    /// Whether every value added is finite.
    #[inline(always)]
    pub(crate) fn ok(&self) -> bool {
        let mut ok = true;
        for j in 0..LANES {
            ok &= self.0[j] == 0.0;
        }
        ok
    }
}

/// Whether `x` is finite (x − x is NaN exactly when it is not).
#[inline(always)]
#[allow(clippy::eq_op)]
pub(crate) fn is_finite(x: f64) -> bool {
    x - x == 0.0
}

/// Whether one contact's inputs are surely good, by the fused test of [`NormalLanes`]:
/// δ + δ̇ + m + r finite and min(m, r) > 0 (an overflowing sum of finite values is a false
/// alarm, which the exact check clears).
#[inline(always)]
pub(crate) fn contact_ok(d: f64, r: f64, m: f64, a: f64) -> bool {
    is_finite((d + r) + (m + a)) & (min(m, a) > 0.0)
}

/// The smaller of `x` and `y` (`y` when either is NaN: one `minpd`).
#[inline(always)]
fn min(x: f64, y: f64) -> f64 {
    if x < y {
        x
    } else {
        y
    }
}

/// Index of the first context of `x` that is not valid (a field not finite or < 0,
/// [`NormalContext::is_valid`]), if any: one fused, branch-free pass over the fields that
/// vectorises (the sum of v − v is NaN unless every v is finite; the minimum is ≥ 0 unless
/// some v is not), then the search only when it says no (its early exits cost ~40
/// instructions a context).
#[inline(always)]
#[allow(clippy::eq_op)]
pub(crate) fn first_invalid_context(x: &[NormalContext]) -> Option<usize> {
    const _: () = assert!(std::mem::size_of::<NormalContext>() == 3 * std::mem::size_of::<f64>());
    // SAFETY: NormalContext is repr(C) with three f64 fields and no padding (asserted above).
    let flat = unsafe { std::slice::from_raw_parts(x.as_ptr().cast::<f64>(), 3 * x.len()) };
    if flat.len() < 8 {
        // one or two contexts: the sum and the minimum alone, without the lanes' setup
        let (sum, low) = flat
            .iter()
            .fold((0.0, 0.0), |(s, l), &v| (s + (v - v), min(l, v)));
        return if sum == 0.0 && low >= 0.0 {
            None
        } else {
            x.iter().position(|c| !c.is_valid())
        };
    }
    let (mut sum, mut low) = ([0.0f64; 8], [0.0f64; 8]);
    let mut it = flat.chunks_exact(8);
    for c in &mut it {
        for j in 0..8 {
            sum[j] += c[j] - c[j];
            low[j] = min(low[j], c[j]);
        }
    }
    let tail = it.remainder();
    let finite = sum.iter().chain(tail).fold(0.0, |a, &v| a + (v - v)) == 0.0;
    let non_negative = low.iter().chain(tail).fold(0.0, |a, &v| min(a, v)) >= 0.0;
    if finite && non_negative {
        None
    } else {
        x.iter().position(|c| !c.is_valid())
    }
}

/// Index of the first non-finite value of `o`, if any.
#[inline(always)]
pub(crate) fn first_non_finite(o: &[f64]) -> Option<usize> {
    if all_finite(o) {
        None
    } else {
        o.iter().position(|v| !v.is_finite())
    }
}

/// Index of the first value of `o` that is not finite and > 0.
#[inline(always)]
pub(crate) fn first_non_positive(o: &[f64]) -> Option<usize> {
    if all_positive(o) {
        None
    } else {
        o.iter().position(|&v| !(v > 0.0 && v < f64::INFINITY))
    }
}

/// Whether a block's inputs are surely good: δ, δ̇ finite, m, r finite and > 0. One fused,
/// branch-free pass that the compiler vectorises, cheap enough to hide behind the law's
/// arithmetic: a sum of all the values is finite unless one of them is NaN or ±∞ (or the sum
/// overflows, which only sends a good block to the slow path), and a running minimum of m and r
/// is > 0 unless one of them is not. When this says no, [`check_normal_inputs`] names the
/// culprit, or finds none and the block goes on.
#[inline(always)]
pub(crate) fn normal_inputs_ok(d: &[f64], r: &[f64], m: &[f64], a: &[f64]) -> bool {
    // four independent lanes in locals (not an indexed array, which the compiler keeps in
    // memory), so that the adds pipeline and pair up into SIMD registers
    let (mut s0, mut s1, mut s2, mut s3) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut l0, mut l1, mut l2, mut l3) = (f64::INFINITY, f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let (dc, rc, mc, ac) = (
        d.chunks_exact(4),
        r.chunks_exact(4),
        m.chunks_exact(4),
        a.chunks_exact(4),
    );
    let (dt, rt, mt, at) = (dc.remainder(), rc.remainder(), mc.remainder(), ac.remainder());
    for (((d, r), m), a) in dc.zip(rc).zip(mc).zip(ac) {
        s0 += (d[0] + r[0]) + (m[0] + a[0]);
        s1 += (d[1] + r[1]) + (m[1] + a[1]);
        s2 += (d[2] + r[2]) + (m[2] + a[2]);
        s3 += (d[3] + r[3]) + (m[3] + a[3]);
        l0 = min(l0, min(m[0], a[0]));
        l1 = min(l1, min(m[1], a[1]));
        l2 = min(l2, min(m[2], a[2]));
        l3 = min(l3, min(m[3], a[3]));
    }
    for (((&d, &r), &m), &a) in dt.iter().zip(rt).zip(mt).zip(at) {
        s0 += (d + r) + (m + a);
        l0 = min(l0, min(m, a));
    }
    let s = (s0 + s1) + (s2 + s3);
    s.is_finite() & (min(min(l0, l1), min(l2, l3)) > 0.0)
}

/// Checks the inputs of contacts `[lo, lo + len)`, returning the first bad one.
#[inline(never)]
#[cold]
pub(crate) fn check_normal_inputs(d: &[f64], r: &[f64], m: &[f64], a: &[f64]) -> Option<(usize, u8)> {
    if let Some(i) = first_non_finite(d) {
        return Some((i, BatchFault::DELTA));
    }
    if let Some(i) = first_non_finite(r) {
        return Some((i, BatchFault::RATE));
    }
    if let Some(i) = first_non_positive(m) {
        return Some((i, BatchFault::MASS));
    }
    if let Some(i) = first_non_positive(a) {
        return Some((i, BatchFault::RADIUS));
    }
    None
}

/// Whether a motion block's inputs are surely good (tangential, rolling, twisting: every
/// component finite, m and r finite and > 0), by the same fused sums and minima as
/// [`normal_inputs_ok`]; `normal` is the flattened unit normals, `motion` the kind's own input
/// flattened (a velocity's three components, or one rate, a contact).
#[inline(always)]
pub(crate) fn motion_inputs_ok(
    normal: &[f64],
    motion: &[f64],
    fnorm: &[f64],
    delta: &[f64],
    m: &[f64],
    a: &[f64],
) -> bool {
    let (mut s0, mut s1) = (0.0f64, 0.0f64);
    for x in [normal, motion] {
        let c = x.chunks_exact(2);
        let tail = c.remainder();
        for v in c {
            s0 += v[0];
            s1 += v[1];
        }
        for v in tail {
            s0 += v;
        }
    }
    let (mut l0, mut l1) = (f64::INFINITY, f64::INFINITY);
    let (fc, dc, mc, ac) = (
        fnorm.chunks_exact(2),
        delta.chunks_exact(2),
        m.chunks_exact(2),
        a.chunks_exact(2),
    );
    let (ft, dt, mt, at) = (fc.remainder(), dc.remainder(), mc.remainder(), ac.remainder());
    for (((f, d), m), a) in fc.zip(dc).zip(mc).zip(ac) {
        s0 += (f[0] + d[0]) + (m[0] + a[0]);
        s1 += (f[1] + d[1]) + (m[1] + a[1]);
        l0 = min(l0, min(m[0], a[0]));
        l1 = min(l1, min(m[1], a[1]));
    }
    for (((&f, &d), &m), &a) in ft.iter().zip(dt).zip(mt).zip(at) {
        s0 += (f + d) + (m + a);
        l0 = min(l0, min(m, a));
    }
    (s0 + s1).is_finite() & (min(l0, l1) > 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finiteness_and_positivity_checks() {
        assert!(all_finite(&[0.0, -1.0, f64::MAX, f64::MIN_POSITIVE]));
        assert!(!all_finite(&[0.0, f64::NAN]));
        assert!(!all_finite(&[f64::NEG_INFINITY, 1.0]));
        assert!(all_finite(&[]));
        assert!(all_positive(&[1e-30, 2.0]));
        assert!(!all_positive(&[1.0, 0.0]));
        assert!(!all_positive(&[f64::NAN]));
        assert!(!all_positive(&[f64::INFINITY]));
        // short slices (their own path) and long ones, a bad value anywhere
        for n in 1..20 {
            assert!(all_finite(&vec![-1e300; n]));
            for i in 0..n {
                for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut x = vec![1.0; n];
                    x[i] = v;
                    assert!(!all_finite(&x), "{n} values, {v} at {i}");
                    assert_eq!(first_non_finite(&x), Some(i));
                }
            }
        }
    }

    /// The fused check agrees with the exact one on every kind of bad value, at every position
    /// of a full block and of a short tail block.
    #[test]
    fn fused_input_check_finds_every_bad_value() {
        let bad_any = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        let bad_positive = [f64::NAN, f64::INFINITY, 0.0, -0.0, -1e-30, f64::NEG_INFINITY];
        for n in [CHECK_BLOCK, 7, 1] {
            let good = || (vec![1e-6; n], vec![-0.5; n], vec![2.0e-4; n], vec![1.5e-3; n]);
            let (d, r, m, a) = good();
            assert!(normal_inputs_ok(&d, &r, &m, &a));
            assert_eq!(check_normal_inputs(&d, &r, &m, &a), None);
            for i in 0..n {
                for field in 0..4 {
                    let values: &[f64] = if field < 2 { &bad_any } else { &bad_positive };
                    for &v in values {
                        let (mut d, mut r, mut m, mut a) = good();
                        [&mut d, &mut r, &mut m, &mut a][field][i] = v;
                        assert!(
                            !normal_inputs_ok(&d, &r, &m, &a),
                            "n {n}, field {field}, index {i}, value {v}"
                        );
                        let (at, _) = check_normal_inputs(&d, &r, &m, &a).expect("found");
                        assert_eq!(at, i);
                    }
                }
            }
        }
    }

    /// The lanes of the pipelined loop catch every kind of bad value at every position of a
    /// block, and their verdict names it as the exact check does.
    #[test]
    fn the_lanes_find_every_bad_value() {
        let bad_any = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        let bad_positive = [f64::NAN, f64::INFINITY, 0.0, -0.0, -1e-30, f64::NEG_INFINITY];
        let n = 2 * CHECK_BLOCK;
        let good = || [vec![1e-6; n], vec![-0.5; n], vec![2.0e-4; n], vec![1.5e-3; n]];
        let lanes = |c: &[Vec<f64>; 4], lo: usize| {
            let mut l = NormalLanes::new();
            for j in (lo..lo + CHECK_BLOCK).step_by(LANES) {
                l.add(&c[0], &c[1], &c[2], &c[3], j);
            }
            (l.ok(), l.verdict(lo, &c[0], &c[1], &c[2], &c[3]))
        };
        assert_eq!(lanes(&good(), CHECK_BLOCK), (true, Ok(())));
        let fields = [
            BatchFault::DELTA,
            BatchFault::RATE,
            BatchFault::MASS,
            BatchFault::RADIUS,
        ];
        for i in CHECK_BLOCK..n {
            for (k, field) in fields.into_iter().enumerate() {
                for &v in if k < 2 { &bad_any[..] } else { &bad_positive[..] } {
                    let mut c = good();
                    c[k][i] = v;
                    assert_eq!(lanes(&c, CHECK_BLOCK), (false, Err((i, field))), "{i} {k} {v}");
                    // the block before does not see it
                    assert_eq!(lanes(&c, 0), (true, Ok(())));
                }
            }
        }
        let mut out = FiniteLanes::new();
        out.add(&[1.0; LANES], 0);
        assert!(out.ok());
        for v in bad_any {
            let mut x = [1.0; 2 * LANES];
            x[LANES + 3] = v;
            let mut out = FiniteLanes::new();
            out.add(&x, 0);
            assert!(out.ok());
            out.add(&x, LANES);
            assert!(!out.ok());
        }
    }

    /// Huge but finite values may overflow the fused sum: that only sends the block to the exact
    /// check, which lets it through.
    #[test]
    fn an_overflowing_sum_is_not_an_error() {
        let big = vec![1e308; 8];
        assert!(!normal_inputs_ok(&big, &big, &big, &big));
        assert_eq!(check_normal_inputs(&big, &big, &big, &big), None);
        let big = vec![1e308; CHECK_BLOCK];
        let mut l = NormalLanes::new();
        for j in (0..CHECK_BLOCK).step_by(LANES) {
            l.add(&big, &big, &big, &big, j);
        }
        assert!(!l.ok());
        assert_eq!(l.verdict(0, &big, &big, &big, &big), Ok(()));
    }
    /// The fused motion check catches a bad value in every field and every component, with a
    /// vector input (tangential, rolling) or a scalar one (twisting).
    #[test]
    fn fused_motion_check_finds_every_bad_value() {
        for (n, width) in [
            (CHECK_BLOCK, 3),
            (5, 3),
            (3, 3),
            (1, 3),
            (CHECK_BLOCK, 1),
            (4, 1),
            (2, 1),
            (1, 1),
        ] {
            let good = || {
                vec![
                    vec![0.6; 3 * n],
                    vec![-0.1; width * n],
                    vec![3.0; n],
                    vec![1e-6; n],
                    vec![2.0e-4; n],
                    vec![1.5e-3; n],
                ]
            };
            let ok = |v: &[Vec<f64>]| motion_inputs_ok(&v[0], &v[1], &v[2], &v[3], &v[4], &v[5]);
            assert!(ok(&good()));
            for field in 0..6 {
                let bad: &[f64] = if field < 4 {
                    &[f64::NAN, f64::INFINITY]
                } else {
                    &[0.0, -2.0, f64::NAN, f64::INFINITY]
                };
                for i in 0..good()[field].len() {
                    for &b in bad {
                        let mut v = good();
                        v[field][i] = b;
                        assert!(!ok(&v), "field {field}, index {i}, value {b}");
                    }
                }
            }
        }
    }

    /// The fused context check names the contact [`NormalContext::is_valid`] refuses,
    /// whichever field and contact is bad (−0 is valid, as ≥ 0 holds for it).
    #[test]
    fn the_context_check_agrees_with_is_valid() {
        let good = NormalContext {
            contact_radius: 1e-4,
            cap_force: 2.0,
            damping: 0.0,
        };
        for n in [1, 2, 3, 5, CHECK_BLOCK] {
            assert_eq!(first_invalid_context(&vec![good; n]), None);
            for i in 0..n {
                for field in 0..3 {
                    for v in [
                        -0.0,
                        5e-324,
                        f64::MAX,
                        -1e-300,
                        f64::NAN,
                        f64::INFINITY,
                        -f64::INFINITY,
                    ] {
                        let mut x = vec![good; n];
                        let f = match field {
                            0 => &mut x[i].contact_radius,
                            1 => &mut x[i].cap_force,
                            _ => &mut x[i].damping,
                        };
                        *f = v;
                        let valid = v == 0.0 || (v > 0.0 && v.is_finite());
                        assert_eq!(x[i].is_valid(), valid);
                        assert_eq!(
                            first_invalid_context(&x),
                            (!valid).then_some(i),
                            "contact {i} of {n}, field {field} = {v}"
                        );
                    }
                }
            }
        }
        assert_eq!(first_invalid_context(&[]), None);
    }
}
