//! The cube root of the JKR model (its contact radius and pull-off distance), within one ulp
//! of the exact root, in straight-line arithmetic: no call, no table, no `frexp`/`ldexp`.
//!
//! A JKR contact takes two cube roots a step. The C library's `cbrt` (what LAMMPS calls) costs
//! about 130 instructions with its `frexp` and `ldexp`, Rust's `f64::cbrt` in a plugin (the
//! toolchain's correctly rounded software routine) more; this one about 40. Its results differ
//! from the C library's by at most one ulp (a relative 2.2·10⁻¹⁶), far inside the 10⁻¹⁰ to which
//! the `gran-*` laws follow LAMMPS.
//!
//! The method (for 2⁻¹⁰⁰⁰ ≤ |x| < 2¹⁰⁰⁰; beyond, x is scaled into that range by 2^∓999, exactly):
//! a first guess from the bits (the exponent divided by 3 by an integer division of
//! the whole bit pattern, good to 3.5 %), two Halley steps t ← t (t³ + 2x)/(2t³ + x) (cubic
//! convergence: 10⁻⁵, then 10⁻¹⁵), t rounded to 26 significant bits so that t² is exact, and
//! a last Halley step in the form t + t (x/t² − t)/(2t + x/t²), whose only rounding that matters
//! is the final addition's.

/// Sign bit of an f64.
pub(crate) const SIGN: u64 = 1 << 63;
/// Bits of 2⁻¹⁰⁰⁰ and 2¹⁰⁰⁰: the range of |x| taken here (beyond it t³ and 2x could leave the
/// normal range).
pub(crate) const LOWEST: u64 = 23 << 52;
pub(crate) const HIGHEST: u64 = 2023 << 52;
/// Added to bits(x)/3: two thirds of the exponent bias, less what centres the guess's error
/// over a binade (its relative error is then within ±3.5 %).
pub(crate) const GUESS: u64 = 0x2a9f_7893_782d_a1ce;
/// The low mantissa bits dropped to round t to 26 significant bits (1 + 25 stored).
pub(crate) const LOW: u64 = (1 << 27) - 1;

/// ∛x for every f64, within one ulp of the exact root; ±0, ±∞ and NaN give themselves.
#[inline(always)]
pub fn cbrt(x: f64) -> f64 {
    let bits = x.to_bits();
    let abs = bits & !SIGN;
    if abs.wrapping_sub(LOWEST) >= HIGHEST - LOWEST {
        return extreme(x);
    }
    f64::from_bits(root(abs).to_bits() | (bits & SIGN))
}

/// ∛a for 2⁻¹⁰⁰⁰ ≤ a < 2¹⁰⁰⁰ of bits `abs`.
#[inline(always)]
fn root(abs: u64) -> f64 {
    let a = f64::from_bits(abs);
    let mut t = f64::from_bits(abs / 3 + GUESS);
    let t3 = t * t * t;
    t *= (t3 + a + a) / (t3 + t3 + a);
    let t3 = t * t * t;
    t *= (t3 + a + a) / (t3 + t3 + a);
    // round to 26 significant bits: t² is then exact
    t = f64::from_bits((t.to_bits() + (1 << 26)) & !LOW);
    let s = t * t;
    let r = a / s;
    let r = (r - t) / (t + t + r);
    t + t * r
}

/// ±0, ±∞, NaN (themselves) and |x| beyond 2^±1000, scaled into the range by 2^∓999 exactly
/// (the root then by 2^±333): rare, out of line.
#[cold]
#[inline(never)]
fn extreme(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let a = x.abs();
    let (scaled, back) = if a < 1.0 {
        (a * 2f64.powi(999), 2f64.powi(-333))
    } else {
        (a * 2f64.powi(-999), 2f64.powi(333))
    };
    // every finite non-zero |x| lands in [2⁻⁷⁵, 2²⁵)
    (root(scaled.to_bits()) * back).copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// |y − ∛x| in ulps of y, the root's error measured against y³ = x: with y = ∛x (1 + ε),
    /// y³ = x (1 + 3ε); the residual x − y³ is computed with a fused multiply-add chain in
    /// double-double (y² exactly as hi + lo, then y² y and its error).
    fn ulps(x: f64, y: f64) -> f64 {
        let y2 = y * y;
        let y2_lo = y.mul_add(y, -y2);
        let y3 = y2 * y;
        let y3_lo = y2.mul_add(y, -y3) + y2_lo * y;
        let residual = (x - y3) - y3_lo;
        // ε = residual / (3 x); an ulp of y is y 2⁻⁵² at most, 2⁻⁵³ at least
        let eps = residual / (3.0 * x);
        let ulp = f64::from_bits(y.abs().to_bits() + 1) - y.abs();
        (eps * y / ulp).abs()
    }

    /// A deterministic spread of x over every binade the laws meet and far beyond, each
    /// mantissa pattern of a 64-bit LCG.
    fn samples() -> impl Iterator<Item = f64> {
        let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
        (0..400_000).map(move |i| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let exp = (i % 2000) as u64 + 24; // biased exponents 24 ..= 2023
            f64::from_bits((exp << 52) | (s >> 12))
        })
    }

    #[test]
    fn within_one_ulp_of_the_exact_root_across_the_range() {
        let mut worst = 0.0f64;
        for x in samples() {
            for x in [x, -x] {
                let y = cbrt(x);
                assert_eq!(y.is_sign_negative(), x.is_sign_negative(), "{x:e}");
                worst = worst.max(ulps(x, y));
            }
        }
        assert!(worst <= 1.0, "worst error {worst} ulp");
    }

    #[test]
    fn agrees_with_the_correctly_rounded_root_to_one_ulp_and_mostly_exactly() {
        let (mut same, mut total) = (0usize, 0usize);
        for x in samples() {
            let (y, z) = (cbrt(x), x.cbrt());
            let d = y.to_bits().abs_diff(z.to_bits());
            assert!(d <= 1, "cbrt({x:e}) = {y:e}, correctly rounded {z:e}");
            same += usize::from(d == 0);
            total += 1;
        }
        // a last step whose only rounding is the final addition's is exact most of the time
        assert!(same * 10 > total * 9, "{same} of {total} exact");
    }

    #[test]
    fn exact_cubes_give_their_roots_and_special_values_pass_through() {
        for k in [1.0, 2.0, 3.0, 5.0, 10.0, 0.5, 0.25, 1024.0, 12345.0] {
            assert_eq!(cbrt(k * k * k), k);
            assert_eq!(cbrt(-(k * k * k)), -k);
        }
        assert_eq!(cbrt(0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(cbrt(-0.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(cbrt(f64::INFINITY), f64::INFINITY);
        assert_eq!(cbrt(f64::NEG_INFINITY), f64::NEG_INFINITY);
        assert!(cbrt(f64::NAN).is_nan());
        // the extremes, scaled into range (x³ of the largest root would overflow the residual)
        for x in [
            f64::from_bits(1),
            3e-310,
            f64::MIN_POSITIVE,
            1e-305,
            3e301,
            f64::MAX,
        ] {
            for x in [x, -x] {
                let d = cbrt(x).to_bits().abs_diff(x.cbrt().to_bits());
                assert!(
                    d <= 1,
                    "cbrt({x:e}) = {:e}, correctly rounded {:e}",
                    cbrt(x),
                    x.cbrt()
                );
            }
        }
    }
}
