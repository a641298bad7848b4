//! Scaling exponents: least-squares fits of log X against log V.

use serde::Serialize;

/// A straight-line fit of ln y = c + θ ln x.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PowerFit {
    /// The exponent θ (slope of ln y against ln x).
    pub theta: f64,
    /// The prefactor c of ln y = c + θ ln x.
    pub intercept: f64,
    /// Root mean square of the residuals of ln y.
    pub rms_residual: f64,
    /// Largest |ln y_observed − ln y_fitted| (the paper drops a point when it reaches 0.25).
    pub max_residual: f64,
    /// Number of points used.
    pub points: usize,
    /// Standard error of θ propagated from the standard errors of the points (None when they
    /// were not given): σ_θ² = Σ ((ln x_i − mean)/Sxx)² (σ_i/y_i)², the least-squares slope
    /// being linear in the ln y_i.
    pub theta_stderr: Option<f64>,
}

impl PowerFit {
    /// Whether the paper would show this exponent: every residual below 0.25 (in ln units).
    pub fn is_power_law(&self) -> bool {
        self.max_residual < 0.25
    }
}

/// Fits y = e^c x^θ by least squares of ln y on ln x over the points with x, y > 0 and finite.
/// None with fewer than two such points or all x equal.
pub fn fit_power(points: &[(f64, f64)]) -> Option<PowerFit> {
    let p: Vec<(f64, f64, Option<f64>)> = points.iter().map(|&(x, y)| (x, y, None)).collect();
    fit_power_err(&p)
}

/// Like [`fit_power`], with a standard error of each y (or None), propagated to θ.
pub fn fit_power_err(points: &[(f64, f64, Option<f64>)]) -> Option<PowerFit> {
    let kept: Vec<(f64, f64, Option<f64>)> = points
        .iter()
        .copied()
        .filter(|(x, y, _)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .collect();
    let pts: Vec<(f64, f64)> = kept.iter().map(|(x, y, _)| (x.ln(), y.ln())).collect();
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n as f64;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n as f64;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let theta = sxy / sxx;
    let c = my - theta * mx;
    let res: Vec<f64> = pts.iter().map(|p| p.1 - (c + theta * p.0)).collect();
    let theta_stderr = kept
        .iter()
        .zip(&pts)
        .map(|((_, y, e), p)| e.map(|e| ((p.0 - mx) / sxx * e / y).powi(2)))
        .sum::<Option<f64>>()
        .map(f64::sqrt);
    Some(PowerFit {
        theta,
        intercept: c,
        rms_residual: (res.iter().map(|r| r * r).sum::<f64>() / n as f64).sqrt(),
        max_residual: res.iter().fold(0.0, |a: f64, r| a.max(r.abs())),
        points: n,
        theta_stderr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_an_exact_power_law() {
        let pts: Vec<(f64, f64)> = (1..=11).map(|k| (k as f64, 3.0 * (k as f64).powf(1.5))).collect();
        let f = fit_power(&pts).unwrap();
        assert!((f.theta - 1.5).abs() < 1e-12 && (f.intercept - 3f64.ln()).abs() < 1e-12);
        assert!(f.max_residual < 1e-12 && f.is_power_law());
        assert!(fit_power(&[(1.0, 1.0)]).is_none() && f.theta_stderr.is_none());
        // two points 1 % uncertain each, a decade apart: σ_θ = √2 · 0.01 / ln 10
        let f = fit_power_err(&[(1.0, 1.0, Some(0.01)), (10.0, 10.0, Some(0.1))]).unwrap();
        let s = 2f64.sqrt() * 0.01 / 10f64.ln();
        assert!((f.theta - 1.0).abs() < 1e-12 && (f.theta_stderr.unwrap() - s).abs() < 1e-12 * s);
        assert!(fit_power(&[(1.0, 1.0), (1.0, 2.0)]).is_none());
    }
}
