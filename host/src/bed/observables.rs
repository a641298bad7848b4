//! What the bed measures, the same for either engine: [`BedObservables`] (the lid pressure, the
//! lid collision rate, the mean impulse per lid collision, the temperature and the piston
//! pressure, each with its standard error), their mean over independent seeds
//! ([`BedObservables::combine`]) and their CSV columns; and the scaling exponents, least-squares
//! fits of log X against log V.

use super::BedConfig;
use serde::Serialize;

/// What the bed measured after the transient, by either engine, with the standard error of each
/// observable (`*_stderr`: batch means over the measured periods in one run, or the spread of
/// independent seeds). An engine's report carries these under the same JSON keys, beside its
/// own counters.
#[derive(Debug, Clone, Serialize)]
pub struct BedObservables {
    /// The bed (geometry, frequency, gravity, mass, seed).
    pub config: BedConfig,
    /// Number of disks N.
    pub disks: usize,
    /// Lid height (m).
    pub lid: f64,
    /// Piston peak speed V = 4Af (m/s).
    pub piston_speed: f64,
    /// Measured time (s) after the transient.
    pub measured_time: f64,
    /// Lid pressure P (N/m): the impulse the lid received over the measured time and the width
    /// (event engine: P = Nc ΔI / L).
    pub pressure: f64,
    /// Lid collisions per second Nc (1/s) (DEM: contact episodes, however long each).
    pub lid_collision_rate: f64,
    /// Mean impulse per lid collision ΔI (N·s); `None` (JSON `null`) when no disk hit the lid:
    /// not measured, and left out of a mean over seeds.
    pub mean_impulse: Option<f64>,
    /// Granular temperature T: the time-averaged translational kinetic energy per disk (J),
    /// sampled 64 times a period.
    pub temperature: f64,
    /// Standard error of `pressure` (N/m).
    pub pressure_stderr: Option<f64>,
    /// Standard error of `lid_collision_rate` (1/s).
    pub lid_collision_rate_stderr: Option<f64>,
    /// Standard error of `mean_impulse` (N·s).
    pub mean_impulse_stderr: Option<f64>,
    /// Standard error of `temperature` (J).
    pub temperature_stderr: Option<f64>,
    /// Time-averaged pressure on the piston (N/m): by momentum balance, `pressure` + N m g / L.
    pub piston_pressure: f64,
    /// Standard error of `piston_pressure` (N/m).
    pub piston_pressure_stderr: Option<f64>,
    /// Independent seeds averaged (1: one run, standard errors by batch means).
    pub seeds: usize,
    /// Wall time (s), summed over seeds.
    pub wall_seconds: f64,
    /// Wall seconds per simulated second (of one run).
    pub wall_per_simulated_second: f64,
}

/// An observable's field: a number always measured (`f64`), or one that may not have been
/// (`Option<f64>`: the mean impulse per lid collision, when no disk hit the lid).
trait Observable {
    fn get(&self) -> Option<f64>;
    fn put(&mut self, v: f64);
}

impl Observable for f64 {
    fn get(&self) -> Option<f64> {
        Some(*self)
    }
    fn put(&mut self, v: f64) {
        *self = v;
    }
}

impl Observable for Option<f64> {
    fn get(&self) -> Option<f64> {
        *self
    }
    fn put(&mut self, v: f64) {
        *self = Some(v);
    }
}

/// The standard error of the mean of independent values: sd / √n (None below 2 values).
pub fn stderr_of(v: &[f64]) -> Option<f64> {
    let n = v.len();
    if n < 2 {
        return None;
    }
    let m = v.iter().sum::<f64>() / n as f64;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1) as f64;
    Some((var / n as f64).sqrt())
}

impl BedObservables {
    /// The five observables with their standard errors: lid pressure, lid collision rate, mean
    /// impulse, temperature, piston pressure.
    fn fields(&mut self) -> [(&mut dyn Observable, &mut Option<f64>); 5] {
        [
            (&mut self.pressure, &mut self.pressure_stderr),
            (&mut self.lid_collision_rate, &mut self.lid_collision_rate_stderr),
            (&mut self.mean_impulse, &mut self.mean_impulse_stderr),
            (&mut self.temperature, &mut self.temperature_stderr),
            (&mut self.piston_pressure, &mut self.piston_pressure_stderr),
        ]
    }

    /// The mean of `runs` (independent seeds of one configuration): each observable's mean over
    /// the seeds that measured it (a seed in which no disk hit the lid has no mean impulse, and
    /// must not pull the mean towards 0), its standard error from their spread; the wall time
    /// summed, the rest from the first run. None for no runs; one run is returned as it is.
    pub fn combine<'a>(runs: impl IntoIterator<Item = &'a BedObservables>) -> Option<BedObservables> {
        let runs: Vec<&BedObservables> = runs.into_iter().collect();
        let first = *runs.first()?;
        if runs.len() == 1 {
            return Some(first.clone());
        }
        let values: Vec<[Option<f64>; 5]> = runs
            .iter()
            .map(|r| (*r).clone().fields().map(|(v, _)| v.get()))
            .collect();
        let mut out = first.clone();
        for (k, (v, e)) in out.fields().into_iter().enumerate() {
            let column: Vec<f64> = values.iter().filter_map(|x| x[k]).collect();
            if column.is_empty() {
                // measured by no seed: not measured (the first run's None stays)
                *e = None;
                continue;
            }
            v.put(column.iter().sum::<f64>() / column.len() as f64);
            *e = stderr_of(&column);
        }
        out.seeds = runs.len();
        out.wall_seconds = runs.iter().map(|r| r.wall_seconds).sum();
        Some(out)
    }

    /// The values the exponent fits use, with their standard errors: P, T, Nc, ΔI (`None` where
    /// not measured: ΔI without lid collisions).
    pub fn fit_values(&self) -> [(Option<f64>, Option<f64>); 4] {
        [
            (Some(self.pressure), self.pressure_stderr),
            (Some(self.temperature), self.temperature_stderr),
            (Some(self.lid_collision_rate), self.lid_collision_rate_stderr),
            (self.mean_impulse, self.mean_impulse_stderr),
        ]
    }

    /// The header of [`BedObservables::csv`].
    pub const CSV_HEADER: &'static str = "layers,freq_hz,piston_speed_m_s,pressure_n_m,pressure_stderr,lid_collision_rate_per_s,lid_collision_rate_stderr,mean_impulse_n_s,mean_impulse_stderr,temperature_j,temperature_stderr,piston_pressure_n_m,piston_pressure_stderr";

    /// The grid CSV's columns of a run, either engine's: n, f, V, P, Nc, ΔI, T and the piston
    /// pressure, each with its standard error.
    pub fn csv(&self) -> String {
        let e = |x: Option<f64>| x.map(|v| format!("{v:e}")).unwrap_or_default();
        format!(
            "{},{},{},{:e},{},{:e},{},{},{},{:e},{},{:e},{}",
            self.config.layers,
            self.config.freq,
            self.piston_speed,
            self.pressure,
            e(self.pressure_stderr),
            self.lid_collision_rate,
            e(self.lid_collision_rate_stderr),
            e(self.mean_impulse),
            e(self.mean_impulse_stderr),
            self.temperature,
            e(self.temperature_stderr),
            self.piston_pressure,
            e(self.piston_pressure_stderr),
        )
    }

    /// The piston pressure momentum balance predicts: P + N m g / L (N/m).
    pub fn piston_expected(&self) -> f64 {
        let c = &self.config;
        self.pressure + self.disks as f64 * c.mass * c.gravity / c.width
    }
}

/// Makes an engine's report, whose `measured` field holds the [`BedObservables`], read as them
/// (`report.pressure`).
macro_rules! measured_report {
    ($t:ty) => {
        impl std::ops::Deref for $t {
            type Target = $crate::bed::observables::BedObservables;
            fn deref(&self) -> &Self::Target {
                &self.measured
            }
        }
    };
}
pub(crate) use measured_report;

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

    fn seed(rate: f64, impulse: f64, temperature: f64) -> BedObservables {
        BedObservables {
            config: BedConfig::paper(1.0, 10.0),
            disks: 100,
            lid: 0.05,
            piston_speed: 1.0,
            measured_time: 1.0,
            lid_collision_rate: rate,
            mean_impulse: (rate > 0.0).then_some(impulse),
            pressure: rate * impulse,
            temperature,
            pressure_stderr: None,
            lid_collision_rate_stderr: None,
            mean_impulse_stderr: None,
            temperature_stderr: None,
            piston_pressure: 0.0,
            piston_pressure_stderr: None,
            seeds: 1,
            wall_seconds: 1.0,
            wall_per_simulated_second: 1.0,
        }
    }

    /// A seed in which no disk hit the lid has no mean impulse per collision: the mean over
    /// seeds is over the others, not pulled towards 0.
    #[test]
    fn a_seed_without_lid_collisions_does_not_enter_the_mean_impulse() {
        let runs = [seed(10.0, 2e-6, 1.0), seed(0.0, 0.0, 2.0), seed(30.0, 4e-6, 3.0)];
        let m = BedObservables::combine(&runs).unwrap();
        assert_eq!((m.seeds, m.wall_seconds), (3, 3.0));
        let mi = m.mean_impulse.expect("two seeds measured it");
        assert!((mi - 3e-6).abs() < 1e-18, "{mi}");
        // the spread of the two measured seeds: |a - b| / 2
        assert!((m.mean_impulse_stderr.unwrap() - 1e-6).abs() < 1e-18);
        // the rates, pressures and temperatures of all three seeds
        assert!((m.lid_collision_rate - 40.0 / 3.0).abs() < 1e-12);
        assert!((m.temperature - 2.0).abs() < 1e-15);
        // no seed measured it: not measured, with no error bar
        let none = BedObservables::combine(&[seed(0.0, 0.0, 1.0), seed(0.0, 0.0, 1.0)]).unwrap();
        assert_eq!(none.mean_impulse, None);
        assert!(none.mean_impulse_stderr.is_none());
    }

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
