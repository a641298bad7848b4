//! Four-lane f64 arithmetic in AVX2 registers, for laws whose batch kernels evaluate four
//! contacts at a time (x86-64 only; the caller checks [`available`] and keeps a portable path).
//!
//! Every lane operation is one IEEE 754 operation, exactly rounded and never fused with
//! another, so a kernel that writes a law's per-contact arithmetic in the same order on
//! [`F64x4`] lanes gives every contact the per-contact form's bits; branches become masks and
//! [`F64x4::select`]. The lanes carry whatever the law computes: values keep their units.
//!
//! Every function here is `unsafe` and compiled for AVX2: call it only from code that has
//! checked the CPU (a `#[target_feature(enable = "avx2")]` function), where it is inlined.
//! Closures are avoided on purpose: one compiled without AVX2 would call every operation.

use std::arch::x86_64::*;

/// Whether a law's AVX2 kernels may run: the CPU has AVX2 and `DASHPOT_SIMD=baseline` was not
/// set when the plugin was first called, the same rule as the sdk's own batch loops (so that
/// one variable takes every AVX2 path out, to measure or rule out the difference; the results
/// are the same bits either way).
#[inline]
pub fn available() -> bool {
    static AVX2: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVX2.get_or_init(|| {
        std::arch::is_x86_feature_detected!("avx2")
            && std::env::var("DASHPOT_SIMD").map_or(true, |v| v != "baseline")
    })
}

/// Four f64 lanes (one AVX2 register); a mask is a lane vector with all bits set where the
/// condition holds and none where it does not.
#[derive(Clone, Copy, Debug)]
pub struct F64x4(pub __m256d);

/// Three lane vectors: the x, y, z components of four 3-vectors.
pub type V3 = [F64x4; 3];

macro_rules! binary {
    ($($(#[$doc:meta])* $name:ident => $intrinsic:ident;)*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// The CPU must support AVX2.
        #[inline]
        #[target_feature(enable = "avx2")]
        pub unsafe fn $name(self, o: F64x4) -> F64x4 {
            F64x4($intrinsic(self.0, o.0))
        }
    )*};
}

macro_rules! compare {
    ($($(#[$doc:meta])* $name:ident => $predicate:ident;)*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// The CPU must support AVX2.
        #[inline]
        #[target_feature(enable = "avx2")]
        pub unsafe fn $name(self, o: F64x4) -> F64x4 {
            F64x4(_mm256_cmp_pd::<$predicate>(self.0, o.0))
        }
    )*};
}

impl F64x4 {
    binary! {
        /// a + b, lane by lane.
        add => _mm256_add_pd;
        /// a − b, lane by lane.
        sub => _mm256_sub_pd;
        /// a b, lane by lane.
        mul => _mm256_mul_pd;
        /// a / b, lane by lane.
        div => _mm256_div_pd;
        /// `a.max(b)` as Rust's `f64::max` compiles on x86-64 (`maxsd`): b where a is NaN or not
        /// greater than b.
        max => _mm256_max_pd;
        /// The bitwise and of two masks.
        and => _mm256_and_pd;
        /// The bitwise or of two masks.
        or => _mm256_or_pd;
    }

    compare! {
        /// The mask of a > b (false with a NaN, as Rust's `>`).
        gt => _CMP_GT_OQ;
        /// The mask of a ≠ b (true with a NaN, as Rust's `!=`).
        ne => _CMP_NEQ_UQ;
        /// The mask of !(a > b) (true with a NaN).
        not_gt => _CMP_NGT_UQ;
        /// The mask of a < b (false with a NaN, as Rust's `<`).
        lt => _CMP_LT_OQ;
        /// The mask of a ≤ b (false with a NaN, as Rust's `<=`).
        le => _CMP_LE_OQ;
        /// The mask of !(a ≤ b) (true with a NaN).
        not_le => _CMP_NLE_UQ;
    }

    /// x in every lane.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn splat(x: f64) -> F64x4 {
        F64x4(_mm256_set1_pd(x))
    }

    /// √x, lane by lane (exactly rounded, as `f64::sqrt`).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn sqrt(self) -> F64x4 {
        F64x4(_mm256_sqrt_pd(self.0))
    }

    /// −x (the sign bit flipped, as Rust's unary minus).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn neg(self) -> F64x4 {
        F64x4(_mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)))
    }

    /// |x| (the sign bit cleared, as `f64::abs`).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn abs(self) -> F64x4 {
        F64x4(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0))
    }

    /// `if mask { a } else { b }`, lane by lane.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn select(mask: F64x4, a: F64x4, b: F64x4) -> F64x4 {
        F64x4(_mm256_blendv_pd(b.0, a.0, mask.0))
    }

    /// `x[i..i + 4]`.
    ///
    /// # Safety
    /// The CPU must support AVX2; `i + 4 <= x.len()`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn load(x: &[f64], i: usize) -> F64x4 {
        debug_assert!(i + 4 <= x.len());
        F64x4(_mm256_loadu_pd(x.as_ptr().add(i)))
    }

    /// The four lanes as an array.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn to_array(self) -> [f64; 4] {
        let mut o = [0.0; 4];
        _mm256_storeu_pd(o.as_mut_ptr(), self.0);
        o
    }
}

/// a · b in [`crate::physics::dot`]'s order, lane by lane.
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn dot(a: V3, b: V3) -> F64x4 {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

/// a + b, component by component.
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn add3(a: V3, b: V3) -> V3 {
    [a[0].add(b[0]), a[1].add(b[1]), a[2].add(b[2])]
}

/// a − b, component by component.
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn sub3(a: V3, b: V3) -> V3 {
    [a[0].sub(b[0]), a[1].sub(b[1]), a[2].sub(b[2])]
}

/// a s (each component times the lanes of s, in that order).
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn scale3(a: V3, s: F64x4) -> V3 {
    [a[0].mul(s), a[1].mul(s), a[2].mul(s)]
}

/// `if mask { a } else { b }`, component by component.
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn select3(mask: F64x4, a: V3, b: V3) -> V3 {
    [
        F64x4::select(mask, a[0], b[0]),
        F64x4::select(mask, a[1], b[1]),
        F64x4::select(mask, a[2], b[2]),
    ]
}

/// One step of a capped spring–dashpot on four lanes, as [`crate::physics::SliderStep`] holds
/// it: what [`SliderLanes::energy`] needs of the step.
#[derive(Clone, Copy)]
pub struct SliderLanes {
    /// The spring as the step read it (m, or rad for a rotation).
    pub xi_before: V3,
    /// The stiffness of the last step (N/m).
    pub k_before: F64x4,
    /// The stiffness of this step (N/m).
    pub k: F64x4,
    /// The dashpot (N·s/m).
    pub eta: F64x4,
    /// 1/dt (1/s), the same on every lane.
    pub rate: F64x4,
    /// Whether dt > 0: a step of no length dissipates nothing.
    pub timed: bool,
}

impl SliderLanes {
    /// [`crate::physics::SliderStep::energy`] lane by lane, operation for operation (the same
    /// bits): the power dissipated (W) and the energy stored (J) by a step that ended with
    /// spring `xi`, relative velocity `v` and force `force`, sliding on the lanes of `sliding`.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn energy(&self, sliding: F64x4, xi: V3, v: V3, force: V3) -> (F64x4, F64x4) {
        let (zero, half) = (F64x4::splat(0.0), F64x4::splat(0.5));
        let elastic = half.mul(self.k).mul(dot(xi, xi));
        let x0 = dot(self.xi_before, self.xi_before);
        let before = half.mul(self.k_before).mul(x0);
        let formed = x0.gt(zero);
        let kb = F64x4::select(formed, self.k_before, zero);
        let held = F64x4::select(formed, self.eta, zero);
        let mut mean = [zero; 3];
        for (q, m) in mean.iter_mut().enumerate() {
            *m = half.mul(force[q].sub(kb.mul(self.xi_before[q])).sub(held.mul(v[q])));
        }
        let work = F64x4::select(sliding, dot(mean, v).neg(), self.eta.mul(dot(v, v)));
        let stored = F64x4::select(sliding, before.sub(elastic), before.sub(half.mul(self.k).mul(x0)));
        let power = if self.timed {
            work.add(stored.mul(self.rate))
        } else {
            zero
        };
        (power, elastic)
    }
}

/// Rows of four lanes to columns (and back: the same operation).
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn transpose(r: [__m256d; 4]) -> [__m256d; 4] {
    let t0 = _mm256_unpacklo_pd(r[0], r[1]);
    let t1 = _mm256_unpackhi_pd(r[0], r[1]);
    let t2 = _mm256_unpacklo_pd(r[2], r[3]);
    let t3 = _mm256_unpackhi_pd(r[2], r[3]);
    [
        _mm256_permute2f128_pd::<0x20>(t0, t2),
        _mm256_permute2f128_pd::<0x20>(t1, t3),
        _mm256_permute2f128_pd::<0x31>(t0, t2),
        _mm256_permute2f128_pd::<0x31>(t1, t3),
    ]
}

/// The x, y, z columns of the four consecutive triples of contacts i .. i + 3 in `x` (a
/// batch's `[f64; 3]` array flattened: `x[3 i..3 i + 12]`).
///
/// # Safety
/// The CPU must support AVX2; `3 (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn triples(x: &[f64], i: usize) -> V3 {
    debug_assert!(3 * (i + 4) <= x.len());
    let p = x.as_ptr().add(3 * i);
    // rows from p, p + 3, p + 6 (each with the next triple's x), the last as [x3 y3 z3 z3]
    let last = _mm256_permute4x64_pd::<0b11_11_10_01>(_mm256_loadu_pd(p.add(8)));
    let c = transpose([
        _mm256_loadu_pd(p),
        _mm256_loadu_pd(p.add(3)),
        _mm256_loadu_pd(p.add(6)),
        last,
    ]);
    [F64x4(c[0]), F64x4(c[1]), F64x4(c[2])]
}

/// Writes the x, y, z columns `v` as the four consecutive triples of contacts i .. i + 3 of
/// `x` (`x[3 i..3 i + 12]`).
///
/// # Safety
/// The CPU must support AVX2; `3 (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn put_triples(v: V3, x: &mut [f64], i: usize) {
    debug_assert!(3 * (i + 4) <= x.len());
    let p = x.as_mut_ptr().add(3 * i);
    let r = transpose([v[0].0, v[1].0, v[2].0, v[2].0]);
    // overlapping stores, each row's fourth value overwritten by the next row's first; the last
    // row written as [z2 x3 y3 z3] at p + 8
    _mm256_storeu_pd(p, r[0]);
    _mm256_storeu_pd(p.add(3), r[1]);
    _mm256_storeu_pd(p.add(6), r[2]);
    let shifted = _mm256_permute4x64_pd::<0b10_01_00_00>(r[3]);
    let z2 = _mm256_permute4x64_pd::<0b10_10_10_10>(v[2].0);
    _mm256_storeu_pd(p.add(8), _mm256_blend_pd::<0b0001>(shifted, z2));
}

/// The four columns of the four consecutive rows of four values of contacts i .. i + 3 in `x`
/// (a history of four slots per contact: `x[4 i..4 i + 16]`).
///
/// # Safety
/// The CPU must support AVX2; `4 (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn quads(x: &[f64], i: usize) -> [F64x4; 4] {
    debug_assert!(4 * (i + 4) <= x.len());
    let p = x.as_ptr().add(4 * i);
    let c = transpose([
        _mm256_loadu_pd(p),
        _mm256_loadu_pd(p.add(4)),
        _mm256_loadu_pd(p.add(8)),
        _mm256_loadu_pd(p.add(12)),
    ]);
    [F64x4(c[0]), F64x4(c[1]), F64x4(c[2]), F64x4(c[3])]
}

/// Writes the four columns `v` as the rows of four values of contacts i .. i + 3 of `x`
/// (`x[4 i..4 i + 16]`).
///
/// # Safety
/// The CPU must support AVX2; `4 (i + 4) <= x.len()`.
#[inline]
#[target_feature(enable = "avx2")]
pub unsafe fn put_quads(v: [F64x4; 4], x: &mut [f64], i: usize) {
    debug_assert!(4 * (i + 4) <= x.len());
    let p = x.as_mut_ptr().add(4 * i);
    let r = transpose([v[0].0, v[1].0, v[2].0, v[3].0]);
    for (l, row) in r.iter().enumerate() {
        _mm256_storeu_pd(p.add(4 * l), *row);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transposes move every value to its place, and back.
    #[test]
    fn triples_and_quads_round_trip() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        let x: Vec<f64> = (0..40).map(|i| i as f64 + 0.5).collect();
        // SAFETY: AVX2 checked; the indices stay within the arrays.
        unsafe {
            let c = triples(&x, 2);
            for (k, col) in c.iter().enumerate() {
                let a = col.to_array();
                for l in 0..4 {
                    assert_eq!(a[l], x[3 * (2 + l) + k]);
                }
            }
            let mut y = vec![-1.0; 40];
            put_triples(c, &mut y, 2);
            assert!(y[..6].iter().chain(&y[18..]).all(|&v| v == -1.0));
            assert_eq!(&y[6..18], &x[6..18]);
            let q = quads(&x, 1);
            for (k, col) in q.iter().enumerate() {
                let a = col.to_array();
                for l in 0..4 {
                    assert_eq!(a[l], x[4 * (1 + l) + k]);
                }
            }
            let mut z = vec![-1.0; 40];
            put_quads(q, &mut z, 1);
            assert!(z[..4].iter().chain(&z[20..]).all(|&v| v == -1.0));
            assert_eq!(&z[4..20], &x[4..20]);
        }
    }
}
