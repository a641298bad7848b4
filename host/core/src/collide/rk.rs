//! An adaptive Dormand–Prince 5(4) Runge–Kutta integrator with event location.
//!
//! Written for the two-body collision: small fixed-size states (`[f64; N]`), a right-hand side
//! that may fail (a plugin error) or refuse a point outside its domain (a stage that would divide
//! by a vanishing speed), and events located to round-off by root finding on the step size: the
//! solution at `x + s` is one fresh step of length `s`, so the located point has the full order
//! of the method, not that of an interpolant.

use dashpot_sdk::LawError;

/// Why a right-hand side evaluation failed.
#[derive(Debug)]
pub enum RhsError {
    /// The point is outside the domain of this formulation (the step is rejected and retried
    /// smaller).
    OutOfDomain,
    /// The law failed; the integration stops with this error.
    Law(LawError),
}

impl From<LawError> for RhsError {
    fn from(e: LawError) -> Self {
        RhsError::Law(e)
    }
}

/// A first-order system y' = f(x, y).
pub trait System<const N: usize> {
    /// f(x, y).
    fn rhs(&mut self, x: f64, y: &[f64; N]) -> Result<[f64; N], RhsError>;

    /// `out[i] = f(x[i], y[i])` for independent points (at most 16). Systems whose evaluation
    /// is a batch call (a contact law through its plugin) override this.
    fn rhs_many(&mut self, x: &[f64], y: &[[f64; N]], out: &mut [[f64; N]]) -> Result<(), RhsError> {
        for i in 0..x.len() {
            out[i] = self.rhs(x[i], &y[i])?;
        }
        Ok(())
    }

    /// The extrapolation step of size `h` from `(x, y)` with `f0 = f(x, y)` and `k` columns
    /// when it is taken elsewhere (with the steps of other collisions, in lockstep), or `None`
    /// to take it here.
    fn lockstep_step(
        &mut self,
        _x: f64,
        _y: &[f64; N],
        _f0: &[f64; N],
        _h: f64,
        _k: usize,
    ) -> Option<Result<Step<N>, RhsError>> {
        None
    }
}

// Dormand & Prince (1980), RK5(4)7M: nodes, stage weights, 5th-order weights (the last stage is
// the first of the next step, "first same as last") and the difference to the embedded 4th order.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
// the rows of the stage matrix a_ij, j < i
const A2: [f64; 1] = [1.0 / 5.0];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
// the 5th-order weights b_1, b_3 .. b_6 (b_2 = 0)
const B: [f64; 5] = [
    35.0 / 384.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
// b − b̂ (the embedded 4th order) for stages 1, 3 .. 7
const E: [f64; 6] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// The result of one trial step.
#[derive(Debug, Clone, Copy)]
pub struct Step<const N: usize> {
    /// The 5th-order solution at x + h.
    pub y: [f64; N],
    /// f(x + h, y): the first stage of the next step.
    pub f: [f64; N],
    /// The embedded error estimate y5 − y4.
    pub err: [f64; N],
}

#[inline(always)]
fn comb<const N: usize>(y: &[f64; N], h: f64, terms: &[(f64, &[f64; N])]) -> [f64; N] {
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        *o += h * s;
    }
    out
}

/// One Dormand–Prince step of size `h` (either sign) from `(x, y)` with `k1 = f(x, y)`.
pub fn step<S: System<N>, const N: usize>(
    sys: &mut S,
    x: f64,
    y: &[f64; N],
    k1: &[f64; N],
    h: f64,
) -> Result<Step<N>, RhsError> {
    let k2 = sys.rhs(x + C2 * h, &comb(y, h, &[(A2[0], k1)]))?;
    let k3 = sys.rhs(x + C3 * h, &comb(y, h, &[(A3[0], k1), (A3[1], &k2)]))?;
    let k4 = sys.rhs(
        x + C4 * h,
        &comb(y, h, &[(A4[0], k1), (A4[1], &k2), (A4[2], &k3)]),
    )?;
    let k5 = sys.rhs(
        x + C5 * h,
        &comb(y, h, &[(A5[0], k1), (A5[1], &k2), (A5[2], &k3), (A5[3], &k4)]),
    )?;
    let a6 = [
        (A6[0], k1),
        (A6[1], &k2),
        (A6[2], &k3),
        (A6[3], &k4),
        (A6[4], &k5),
    ];
    let k6 = sys.rhs(x + h, &comb(y, h, &a6))?;
    let y5 = comb(
        y,
        h,
        &[(B[0], k1), (B[1], &k3), (B[2], &k4), (B[3], &k5), (B[4], &k6)],
    );
    let k7 = sys.rhs(x + h, &y5)?;
    let mut err = [0.0; N];
    for i in 0..N {
        err[i] =
            h * (E[0] * k1[i] + E[1] * k3[i] + E[2] * k4[i] + E[3] * k5[i] + E[4] * k6[i] + E[5] * k7[i]);
    }
    Ok(Step { y: y5, f: k7, err })
}

/// Tolerances of the error control: component i is scaled by `atol[i] + rtol·max(|y_i|, |y'_i|)`.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance<const N: usize> {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per component.
    pub atol: [f64; N],
}

impl<const N: usize> Tolerance<N> {
    /// The RMS norm of `err` scaled per component (≤ 1 means the step is accepted).
    #[inline]
    pub fn norm(&self, y0: &[f64; N], y1: &[f64; N], err: &[f64; N]) -> f64 {
        let mut s = 0.0;
        for i in 0..N {
            let sc = self.atol[i] + self.rtol * y0[i].abs().max(y1[i].abs());
            let e = err[i] / sc;
            s += e * e;
        }
        (s / N as f64).sqrt()
    }
}

/// The step-size factor after a step with error norm `e` (elementary controller, order 5).
#[inline]
pub fn step_factor(e: f64) -> f64 {
    if e == 0.0 {
        5.0
    } else {
        (0.9 * e.powf(-0.2)).clamp(0.2, 5.0)
    }
}

/// Finds `s` between `a` and `b` where `g` changes sign, given `g(a) = ga` and `g(b) = gb` of
/// opposite signs (or one of them zero), by the Illinois variant of regula falsi. `g(s)` returns
/// the event function and a payload (typically the state at `s`); the payload of the last
/// evaluation, at the root, is returned with it.
pub fn locate<T, E, G>(a: f64, ga: f64, b: f64, gb: f64, mut g: G) -> Result<(f64, T), E>
where
    G: FnMut(f64) -> Result<(f64, T), E>,
    E: From<RhsError>,
{
    let (mut a, mut fa, mut b, mut fb) = (a, ga, b, gb);
    let scale = a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
    let mut side = 0i8;
    let mut best: Option<(f64, T)> = None;
    for _ in 0..200 {
        let s = if fb != fa {
            (a * fb - b * fa) / (fb - fa)
        } else {
            0.5 * (a + b)
        };
        let s = if s.is_finite() && (s - a) * (s - b) <= 0.0 {
            s
        } else {
            0.5 * (a + b)
        };
        let (fs, t) = g(s)?;
        best = Some((s, t));
        if fs == 0.0 {
            break;
        }
        if (fs > 0.0) == (fb > 0.0) {
            b = s;
            fb = fs;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = s;
            fa = fs;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
        if (b - a).abs() <= 4.0 * f64::EPSILON * scale {
            break;
        }
    }
    best.ok_or_else(|| RhsError::OutOfDomain.into())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// y'' = −y from (0, 1) over one period in `n` fixed steps of `step`: the largest error of
    /// (y, y') against (sin, cos) at the end. The order tests of the integrators.
    pub(crate) fn period_error(
        n: usize,
        mut step: impl FnMut(&mut Osc, f64, &[f64; 2], &[f64; 2], f64) -> Step<2>,
    ) -> f64 {
        let h = 2.0 * std::f64::consts::PI / n as f64;
        let (mut x, mut y) = (0.0, [0.0, 1.0]);
        let mut f = Osc.rhs(x, &y).unwrap();
        for _ in 0..n {
            let s = step(&mut Osc, x, &y, &f, h);
            x += h;
            y = s.y;
            f = s.f;
        }
        (y[0] - x.sin()).abs().max((y[1] - x.cos()).abs())
    }

    /// The harmonic oscillator y'' = −y as a first-order system (y, y').
    pub(crate) struct Osc;
    impl System<2> for Osc {
        fn rhs(&mut self, _x: f64, y: &[f64; 2]) -> Result<[f64; 2], RhsError> {
            Ok([y[1], -y[0]])
        }
    }

    /// Fixed steps over one period of y'' = −y: the error must fall as h^5 (order 5).
    #[test]
    fn dormand_prince_is_fifth_order() {
        let err = |n: usize| period_error(n, |o, x, y, f, h| step(o, x, y, f, h).unwrap());
        let (e1, e2) = (err(40), err(80));
        let order = (e1 / e2).log2();
        assert!((order - 5.0).abs() < 0.15, "observed order {order}");
        // and the embedded estimate tracks the true local error within a factor ~10
        let s = step(&mut Osc, 0.0, &[0.0, 1.0], &[1.0, 0.0], 0.3).unwrap();
        let true_err = (s.y[0] - 0.3f64.sin()).abs();
        let est = s.err[0].abs();
        assert!(
            est > true_err && est < 1e3 * true_err.max(1e-18),
            "{est} vs {true_err}"
        );
    }

    #[test]
    fn locate_finds_the_zero_of_sine() {
        // event: sin crosses zero between 3 and 3.5 (at π)
        let (s, v) = locate::<_, RhsError, _>(0.0, 3f64.sin(), 0.5, 3.5f64.sin(), |s| {
            Ok(((3.0 + s).sin(), 3.0 + s))
        })
        .unwrap();
        assert!((v - std::f64::consts::PI).abs() < 1e-15, "{s} {v}");
    }
}
