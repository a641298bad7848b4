//! [`Slider`](super::Slider) on four contacts at once in AVX2 registers (x86-64), operation for
//! operation, so every contact gets the per-contact form's bits (the laws' tests check);
//! branches become selects. A step whose trial force overflows |F_t|² on some lane is flagged
//! for the caller to take those four contacts through the per-contact form, which measures
//! |F_t| without overflow. Also: a history of `S` slots a contact read into and written from
//! `S` lane vectors.

use crate::simd::{dot, transpose, F64x4, V3};
use std::arch::x86_64::*;

/// [`super::Slider`] with each field on four lanes.
#[derive(Clone, Copy)]
pub struct SliderX4 {
    /// Stiffness of this step.
    pub k: F64x4,
    /// Stiffness of the last step.
    pub k_before: F64x4,
    /// Dashpot.
    pub eta: F64x4,
    /// The slider's strength.
    pub cap: F64x4,
    /// 1/dt, or 0 ([`super::Slider::rate`]), the same on every lane.
    pub rate: F64x4,
    /// Time step (s), the same on every lane.
    pub dt: F64x4,
}

/// [`super::Slid`] on four lanes (`sliding` a mask), and whether some lane's |F_t|² overflowed
/// (then the caller redoes the four contacts one at a time).
#[derive(Clone, Copy)]
pub struct SlidX4 {
    /// The force.
    pub force: V3,
    /// The spring after the step.
    pub spring: V3,
    /// The dashpot's share of the force.
    pub dashpot: V3,
    /// The mask of the lanes that slid.
    pub sliding: F64x4,
    /// Whether some lane's |F_t|² was not finite.
    pub overflow: bool,
}

impl SliderX4 {
    /// [`super::Slider::advance`] on four lanes.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn advance(&self, xi: V3, v: V3) -> SlidX4 {
        let (zero, one) = (F64x4::splat(0.0), F64x4::splat(1.0));
        let (k, eta) = (self.k, self.eta);
        let g = F64x4::select(k.gt(self.k_before), self.k_before.div(k), one);
        let (mut start, mut trial, mut ft) = ([zero; 3], [zero; 3], [zero; 3]);
        for i in 0..3 {
            start[i] = xi[i].mul(g);
            trial[i] = start[i].add(v[i].mul(self.dt));
            ft[i] = k.neg().mul(trial[i]).sub(eta.mul(v[i]));
        }
        let f2 = dot(ft, ft);
        let overflow = _mm256_movemask_pd(F64x4::splat(f64::MAX).not_gt(f2).0) != 0;
        let sliding = f2.gt(self.cap.mul(self.cap));
        let s = self.cap.div(f2.sqrt());
        let c = eta.mul(self.rate);
        let kc = k.add(c);
        let stiff = kc.gt(zero);
        let (mut force, mut spring, mut dashpot) = ([zero; 3], [zero; 3], [zero; 3]);
        for i in 0..3 {
            let fs = ft[i].mul(s);
            let xs = F64x4::select(stiff, c.mul(start[i]).sub(fs).div(kc), zero);
            force[i] = F64x4::select(sliding, fs, ft[i]);
            spring[i] = F64x4::select(sliding, xs, trial[i]);
            dashpot[i] = force[i].add(k.mul(spring[i]));
        }
        SlidX4 {
            force,
            spring,
            dashpot,
            sliding,
            overflow,
        }
    }

    /// [`super::Slider::energy`] on four lanes: the power (W) and the elastic energy (J).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn energy(&self, xi: V3, fd: V3, s: &SlidX4, w: V3) -> (F64x4, F64x4) {
        let (zero, half) = (F64x4::splat(0.0), F64x4::splat(0.5));
        let (k, kb) = (self.k, self.k_before);
        let elastic = half.mul(k).mul(dot(s.spring, s.spring));
        let before = half.mul(kb).mul(dot(xi, xi));
        let mut sum = [zero; 3];
        for i in 0..3 {
            sum[i] = fd[i].sub(kb.mul(xi[i])).add(s.force[i]);
        }
        let power = before.sub(elastic).mul(self.rate).sub(half.mul(dot(sum, w)));
        (F64x4::select(self.rate.gt(zero), power, zero), elastic)
    }
}

/// The `S` history slots (4 ≤ S ≤ 8) of contacts i .. i + 3 of `x` (`S` values a contact), slot
/// by slot: `rows[s]` holds slot s of the four contacts. Two overlapping rows of four a contact
/// (slots 0..4 and S − 4..S), transposed.
///
/// # Safety
/// The CPU must support AVX2; `S (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn load_rows<const S: usize>(x: &[f64], i: usize) -> [F64x4; S] {
    debug_assert!((4..=8).contains(&S) && S * (i + 4) <= x.len());
    let p = x.as_ptr().add(S * i);
    // (no closure: one would not be compiled for AVX2)
    let (o, q) = (S - 4, 2 * S);
    let a = transpose([
        _mm256_loadu_pd(p),
        _mm256_loadu_pd(p.add(S)),
        _mm256_loadu_pd(p.add(q)),
        _mm256_loadu_pd(p.add(q + S)),
    ]);
    let b = transpose([
        _mm256_loadu_pd(p.add(o)),
        _mm256_loadu_pd(p.add(S + o)),
        _mm256_loadu_pd(p.add(q + o)),
        _mm256_loadu_pd(p.add(q + S + o)),
    ]);
    let mut out = [F64x4(_mm256_setzero_pd()); S];
    for s in 0..S {
        out[s] = F64x4(if s < 4 { a[s] } else { b[s + 4 - S] });
    }
    out
}

/// [`load_rows`] the other way: slot `s` of the four contacts i .. i + 3 from `rows[s]` into
/// `x` (slots S − 4..4 written twice, with the same values).
///
/// # Safety
/// The CPU must support AVX2; `S (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn store_rows<const S: usize>(rows: [F64x4; S], x: &mut [f64], i: usize) {
    debug_assert!((4..=8).contains(&S) && S * (i + 4) <= x.len());
    let p = x.as_mut_ptr().add(S * i);
    let a = transpose([rows[0].0, rows[1].0, rows[2].0, rows[3].0]);
    let b = transpose([rows[S - 4].0, rows[S - 3].0, rows[S - 2].0, rows[S - 1].0]);
    for j in 0..4 {
        _mm256_storeu_pd(p.add(S * j), a[j]);
        _mm256_storeu_pd(p.add(S * j + S - 4), b[j]);
    }
}

/// Contacts `lo..hi` of batch `b` through a law's per-contact forms (`force`, or
/// `force_energy` with each contact's energy written to `out` when given): the four contacts
/// of a step whose [`SlidX4::overflow`] is set, whose history the lanes have not written.
#[cold]
#[inline(never)]
pub fn one_by_one(
    b: &mut crate::VectorBatch<'_>,
    lo: usize,
    hi: usize,
    mut out: Option<&mut crate::EnergyBatch<'_>>,
    force: impl Fn(&crate::VectorContact, &mut [f64]) -> [f64; 3],
    force_energy: impl Fn(&crate::VectorContact, &mut [f64]) -> ([f64; 3], Option<crate::Energy>),
) {
    let slots = b.slots;
    for i in lo..hi {
        let c = b.contact(i);
        let h = &mut b.history[slots * i..slots * (i + 1)];
        match out.as_mut() {
            Some(o) => {
                let (f, e) = force_energy(&c, h);
                b.force[i] = f;
                o.set(i, e);
            }
            None => b.force[i] = force(&c, h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows of 6 and 7 slots go in and out unchanged.
    #[test]
    fn rows_round_trip() {
        if !crate::simd::available() {
            return;
        }
        let x: Vec<f64> = (0..7 * 9).map(|v| v as f64).collect();
        // SAFETY: AVX2 checked; 7 (1 + 4) <= 63
        let r = unsafe { load_rows::<7>(&x, 1) };
        for (s, lane) in r.iter().enumerate() {
            let v = unsafe { lane.to_array() };
            assert_eq!(v, [0, 1, 2, 3].map(|j| (7 * (1 + j) + s) as f64));
        }
        let mut y = vec![-1.0; x.len()];
        unsafe { store_rows::<7>(r, &mut y, 1) };
        assert_eq!(&y[7..35], &x[7..35]);
        let r = unsafe { load_rows::<6>(&x, 2) };
        let mut y = vec![-1.0; x.len()];
        unsafe { store_rows::<6>(r, &mut y, 2) };
        assert_eq!(&y[12..36], &x[12..36]);
    }
}
