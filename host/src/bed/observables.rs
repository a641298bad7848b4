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
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
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
    Some(PowerFit {
        theta,
        intercept: c,
        rms_residual: (res.iter().map(|r| r * r).sum::<f64>() / n as f64).sqrt(),
        max_residual: res.iter().fold(0.0, |a: f64, r| a.max(r.abs())),
        points: n,
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
        assert!(fit_power(&[(1.0, 1.0)]).is_none());
        assert!(fit_power(&[(1.0, 1.0), (1.0, 2.0)]).is_none());
    }
}
