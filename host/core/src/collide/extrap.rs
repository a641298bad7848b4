//! Gragg–Bulirsch–Stoer extrapolation: the modified midpoint rule over a step H with
//! n = 2, 4, 6, … substeps, extrapolated to zero substep size (Aitken–Neville in h²).
//!
//! With k columns the result has order 2k, at a cost of Σ(n_j − 1) + 1 = k² + 1 evaluations
//! per step; at the tight tolerances of collision calibration (10⁻¹⁰ and below) that is several
//! times fewer evaluations than a fifth-order Runge–Kutta method, provided the right-hand side
//! is smooth, which the u = δ^{1/4} formulation of the collision guarantees.

use super::rk::{RhsError, Step, System};

/// The substep counts n_j = 2j.
const MAX_COLUMNS: usize = 10;

/// One extrapolated step of size `h` (either sign) from `(x, y)` with `f0 = f(x, y)`, using `k`
/// columns (order 2k). `err` estimates the error of the result from the last two columns.
pub fn step<S: System<N>, const N: usize>(
    sys: &mut S,
    x: f64,
    y: &[f64; N],
    f0: &[f64; N],
    h: f64,
    k: usize,
) -> Result<Step<N>, RhsError> {
    let mut g = Gbs::new(x, y, f0, h, k);
    let mut fs = [[0.0f64; N]; MAX_COLUMNS];
    for m in 1..g.rounds() {
        let n = {
            let (xs, zs) = g.points(m);
            sys.rhs_many(xs, zs, &mut fs[..xs.len()])?;
            xs.len()
        };
        g.advance(m, &fs[..n]);
    }
    let (y1, err) = g.finish();
    let f1 = sys.rhs(x + h, &y1)?;
    Ok(Step { y: y1, f: f1, err })
}

/// One extrapolated step in the making: the k modified-midpoint sequences (n_j = 2(j + 1)
/// substeps) are independent, so they advance in lockstep and their right-hand sides are
/// evaluated together, one batch per substep index m = 1 … 2k − 1, for the sequences j ≥ m/2
/// (those with n_j > m). [`step`] drives it with one system; the collisions of a restitution
/// curve drive one each, all their batches in one call of the law.
pub struct Gbs<const N: usize> {
    k: usize,
    x: f64,
    hs: [f64; MAX_COLUMNS],
    z0: [[f64; N]; MAX_COLUMNS],
    z1: [[f64; N]; MAX_COLUMNS],
    xs: [f64; MAX_COLUMNS],
}

impl<const N: usize> Gbs<N> {
    /// The most points of one substep (the columns).
    pub const MAX_POINTS: usize = MAX_COLUMNS;

    /// The step of size `h` from `(x, y)` with `f0 = f(x, y)` and `k` columns (clamped to
    /// 2 … 10), before its first substep.
    pub fn new(x: f64, y: &[f64; N], f0: &[f64; N], h: f64, k: usize) -> Self {
        let mut g = Gbs {
            k: 0,
            x: 0.0,
            hs: [0.0; MAX_COLUMNS],
            z0: [[0.0; N]; MAX_COLUMNS],
            z1: [[0.0; N]; MAX_COLUMNS],
            xs: [0.0; MAX_COLUMNS],
        };
        g.restart(x, y, f0, h, k);
        g
    }

    /// The same, in place: a new step of this one.
    pub fn restart(&mut self, x: f64, y: &[f64; N], f0: &[f64; N], h: f64, k: usize) {
        let k = k.clamp(2, MAX_COLUMNS);
        (self.k, self.x) = (k, x);
        for j in 0..k {
            self.hs[j] = h / (2 * (j + 1)) as f64;
            self.z0[j] = *y;
            for i in 0..N {
                self.z1[j][i] = y[i] + self.hs[j] * f0[i];
            }
        }
    }

    /// One past the last substep index: the substeps are m = 1 … `rounds() − 1`.
    pub fn rounds(&self) -> usize {
        2 * self.k
    }

    /// The points whose right-hand sides substep `m` needs: the abscissae and states of the
    /// sequences j = m/2 … k − 1.
    pub fn points(&mut self, m: usize) -> (&[f64], &[[f64; N]]) {
        let j0 = m / 2;
        for j in j0..self.k {
            self.xs[j] = self.x + m as f64 * self.hs[j];
        }
        (&self.xs[j0..self.k], &self.z1[j0..self.k])
    }

    /// The abscissae of substep `m`'s points, once [`points`](Gbs::points) has made them.
    pub fn abscissae(&self, m: usize) -> &[f64] {
        &self.xs[m / 2..self.k]
    }

    /// Substep `m` with the right-hand sides `fs` at its [`points`](Gbs::points).
    #[allow(clippy::needless_range_loop)] // three arrays indexed alike
    pub fn advance(&mut self, m: usize, fs: &[[f64; N]]) {
        let j0 = m / 2;
        for (j, f) in (j0..self.k).zip(fs) {
            for i in 0..N {
                let z2 = self.z0[j][i] + 2.0 * self.hs[j] * f[i];
                self.z0[j][i] = self.z1[j][i];
                self.z1[j][i] = z2;
            }
        }
    }

    /// The extrapolated state at x + h and its error estimate (the last two columns).
    pub fn finish(&self) -> ([f64; N], [f64; N]) {
        let k = self.k;
        let mut t = self.z1;
        neville(&mut t, k, k);
        let mut u = self.z1;
        neville(&mut u, k, k - 1);
        let mut err = [0.0f64; N];
        for ((e, a), b) in err.iter_mut().zip(&t[k - 1]).zip(&u[k - 1]) {
            *e = a - b;
        }
        (t[k - 1], err)
    }
}

/// Aitken–Neville in h² over rows 0..k, up to column `columns − 1`, in place: afterwards
/// `t[k − 1]` is T[k−1][columns−1]. T[j][l] = T[j][l−1] + (T[j][l−1] − T[j−1][l−1]) / ((n_j/n_{j−l})² − 1).
#[allow(clippy::needless_range_loop)] // rows and columns of a triangular table
fn neville<const N: usize>(t: &mut [[f64; N]; MAX_COLUMNS], k: usize, columns: usize) {
    for l in 1..columns {
        for j in (l..k).rev() {
            let w = NEVILLE_WEIGHT[j][l];
            let (lo, hi) = t.split_at_mut(j);
            for (a, b) in hi[0].iter_mut().zip(&lo[j - 1]) {
                *a += (*a - b) * w;
            }
        }
    }
}

/// 1/((n_j/n_{j−l})² − 1) with n_j = 2(j + 1), computed at compile time.
const NEVILLE_WEIGHT: [[f64; MAX_COLUMNS]; MAX_COLUMNS] = {
    let mut w = [[0.0; MAX_COLUMNS]; MAX_COLUMNS];
    let mut j = 1;
    while j < MAX_COLUMNS {
        let mut l = 1;
        while l <= j {
            let (a, b) = ((j + 1) as f64, (j + 1 - l) as f64);
            w[j][l] = (b * b) / (a * a - b * b);
            l += 1;
        }
        j += 1;
    }
    w
};

/// The step-size factor after a step with error norm `e` for `k` columns.
#[inline]
pub fn step_factor(e: f64, k: usize) -> f64 {
    if e == 0.0 {
        return 4.0;
    }
    (0.94 * (0.65 / e).powf(1.0 / (2 * k - 1) as f64)).clamp(0.1, 4.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::rk::tests::period_error;

    #[test]
    fn extrapolation_has_order_2k() {
        for k in [3usize, 5] {
            let err = |n: usize| period_error(n, |o, x, y, f, h| step(o, x, y, f, h, k).unwrap());
            let (e1, e2) = (err(8), err(16));
            let order = (e1 / e2).log2();
            assert!(
                (order - 2.0 * k as f64).abs() < 0.6,
                "k = {k}: observed order {order} ({e1:e}, {e2:e})"
            );
        }
    }
}
