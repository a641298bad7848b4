//! Scaling exponents: a grid of runs over layers n and frequencies f, in parallel, and the
//! least-squares exponents θ of X ∝ V^θ for X = P, T, Nc, ΔI at each n (the paper's Fig. 4).

use super::engine::{Bed, BedConfig, BedReport};
use super::observables::{fit_power_err, PowerFit};
use super::{BedError, Laws, Restitution};
use crate::bed::on_dem::{DemBed, DemBedReport};
use crate::dem::DemError;
use crate::output::{write_atomic, Provenance};
use crate::plot::{Mark, Panel, Series};
use crate::registry::Registry;
use anyhow::{Context, Result};
use dashpot_sdk::ParamValue;
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// A grid of runs: every n with every f, each `transient` periods then `cycles` measured.
#[derive(Debug, Clone)]
pub struct Grid {
    /// Layers n.
    pub layers: Vec<f64>,
    /// Frequencies f (Hz).
    pub freqs: Vec<f64>,
    /// Transient periods.
    pub transient: f64,
    /// Measured periods.
    pub cycles: f64,
}

impl Grid {
    /// Number of runs.
    pub fn len(&self) -> usize {
        self.layers.len() * self.freqs.len()
    }

    /// True if the grid has no run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The (n, f) of run `k` (row-major: n outer).
    pub fn point(&self, k: usize) -> (f64, f64) {
        (
            self.layers[k / self.freqs.len()],
            self.freqs[k % self.freqs.len()],
        )
    }
}

/// Runs every point of `grid` in parallel (rayon) with the configuration `cfg(n, f)`; `tick` is
/// called after each run. Results in grid order (n outer, f inner).
pub fn run_grid<R: Restitution>(
    laws: &Laws<R>,
    cfg: &(dyn Fn(f64, f64) -> BedConfig + Sync),
    grid: &Grid,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<BedReport>, BedError> {
    let jobs = (0..grid.len()).map(|k| (k, ())).collect();
    run_points(grid, jobs, tick, |n, f, ()| {
        Bed::new(
            cfg(n, f),
            Laws {
                disk: &laws.disk,
                wall: &laws.wall,
            },
        )
        .and_then(|mut bed| bed.run_protocol(grid.transient, grid.cycles, &mut |_| {}))
    })
}

/// An error of one run of several, which can say which run it was (the error kind kept).
pub trait InRun {
    /// This error, as that of the run `point`.
    fn in_run(self, point: String) -> Self;
}

impl InRun for BedError {
    fn in_run(self, point: String) -> Self {
        BedError::InRun {
            point,
            error: Box::new(self),
        }
    }
}

impl InRun for DemError {
    fn in_run(self, point: String) -> Self {
        DemError::InRun {
            point,
            error: Box::new(self),
        }
    }
}

/// Runs `run(n, f, job)` for each `(k, job)` at the grid's point k, in parallel (rayon), the
/// longest runs first (many disks, low frequency: more simulated time) for load balance;
/// `tick` is called after each run. Results in grid order; an error stops the lot, and names
/// its grid point.
fn run_points<J: Send, T: Send, E: Send + InRun>(
    grid: &Grid,
    mut jobs: Vec<(usize, J)>,
    tick: &(dyn Fn() + Sync),
    run: impl Fn(f64, f64, J) -> Result<T, E> + Sync,
) -> Result<Vec<T>, E> {
    let cost = |k: usize| {
        let (n, f) = grid.point(k);
        n / f
    };
    jobs.sort_by(|a, b| cost(b.0).total_cmp(&cost(a.0)));
    let mut done: Vec<(usize, T)> = jobs
        .into_par_iter()
        .map(|(k, job)| {
            let (n, f) = grid.point(k);
            let r = run(n, f, job).map_err(|e| e.in_run(format!("n = {n}, f = {f} Hz")))?;
            tick();
            Ok((k, r))
        })
        .collect::<Result<Vec<_>, E>>()?;
    done.sort_by_key(|(k, _)| *k);
    Ok(done.into_iter().map(|(_, r)| r).collect())
}

/// The four exponents at one n.
#[derive(Debug, Clone, Serialize)]
pub struct ScalingRow {
    /// Layers n.
    pub layers: f64,
    /// θ of the lid pressure P.
    pub pressure: Option<PowerFit>,
    /// θ of the temperature T.
    pub temperature: Option<PowerFit>,
    /// θ of the lid collision rate Nc.
    pub lid_collision_rate: Option<PowerFit>,
    /// θ of the mean impulse ΔI.
    pub mean_impulse: Option<PowerFit>,
    /// Largest TC share of collisions over the frequencies at this n.
    pub tc_share: f64,
}

/// What the exponent fits need from a run, of either engine.
pub trait Measured {
    /// Piston peak speed V (m/s).
    fn speed(&self) -> f64;
    /// (P, its standard error), (T, ...), (Nc, ...), (ΔI, ...); `None` where not measured (ΔI
    /// without lid collisions).
    fn observables(&self) -> [(Option<f64>, Option<f64>); 4];
    /// (P, its standard error): always measured.
    fn pressure(&self) -> (f64, Option<f64>) {
        let (p, e) = self.observables()[0];
        (p.unwrap_or(0.0), e)
    }
    /// Share of collisions made elastic by the TC model (0 without one).
    fn tc_share(&self) -> f64;
    /// The grid CSV's columns common to both engines, in order: n, f, V, P, Nc, ΔI, T and the
    /// piston pressure, each with its standard error.
    fn csv_common(&self) -> String;
    /// The engine's own CSV columns after those: their header, and a run's values.
    const CSV_EXTRA_HEADER: &'static str;
    /// See [`Measured::CSV_EXTRA_HEADER`].
    fn csv_extra(&self) -> String;
}

/// The methods of [`Measured`] both engines' reports share, from their fields (named alike):
/// the speed, the observables and the common CSV columns.
macro_rules! measured_common {
    () => {
        fn speed(&self) -> f64 {
            self.piston_speed
        }
        fn observables(&self) -> [(Option<f64>, Option<f64>); 4] {
            [
                (Some(self.pressure), self.pressure_stderr),
                (Some(self.temperature), self.temperature_stderr),
                (
                    Some(self.lid_collision_rate),
                    self.lid_collision_rate_stderr,
                ),
                (self.mean_impulse, self.mean_impulse_stderr),
            ]
        }
        fn csv_common(&self) -> String {
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
    };
}

/// The header of [`Measured::csv_common`].
const CSV_COMMON_HEADER: &str = "layers,freq_hz,piston_speed_m_s,pressure_n_m,pressure_stderr,lid_collision_rate_per_s,lid_collision_rate_stderr,mean_impulse_n_s,mean_impulse_stderr,temperature_j,temperature_stderr,piston_pressure_n_m,piston_pressure_stderr";

impl Measured for BedReport {
    measured_common!();
    fn tc_share(&self) -> f64 {
        self.tc_share
    }
    const CSV_EXTRA_HEADER: &'static str = "events,collisions,tc_share,max_overlap_m,wall_s";
    fn csv_extra(&self) -> String {
        format!(
            "{},{},{:e},{:e},{:.3}",
            self.events, self.collisions, self.tc_share, self.max_overlap, self.wall_seconds
        )
    }
}

impl Measured for DemBedReport {
    measured_common!();
    fn tc_share(&self) -> f64 {
        0.0
    }
    const CSV_EXTRA_HEADER: &'static str = "young_pa,dt_s,collision_time_s,steps,wall_s";
    fn csv_extra(&self) -> String {
        format!(
            "{:e},{:e},{:e},{},{:.3}",
            self.young, self.dt, self.collision_time, self.steps, self.wall_seconds
        )
    }
}

/// Runs every point of `grid` on the DEM engine, in parallel (each run serial: a bed has fewer
/// disks than pay for threads), with `laws[k]` for run `k` and the bed `bed(n, f)`; `tick` is
/// called after each run. Results in grid order.
pub fn run_dem_grid(
    laws: Vec<crate::dem::Laws>,
    bed: &(dyn Fn(f64, f64) -> DemBed + Sync),
    grid: &Grid,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<DemBedReport>, DemError> {
    let jobs = laws.into_iter().enumerate().collect();
    run_points(grid, jobs, tick, |n, f, l| {
        bed(n, f).run(l, grid.transient, grid.cycles, &mut |_| {})
    })
}

/// Fits θ for each n of `grid` from the runs (in grid order).
pub fn fit_all<R: Measured>(grid: &Grid, runs: &[R]) -> Vec<ScalingRow> {
    let nf = grid.freqs.len();
    grid.layers
        .iter()
        .enumerate()
        .map(|(a, &n)| {
            let rs = &runs[a * nf..(a + 1) * nf];
            let fit = |k: usize| {
                fit_power_err(
                    &rs.iter()
                        .filter_map(|r| {
                            let (v, e) = r.observables()[k];
                            v.map(|v| (r.speed(), v, e))
                        })
                        .collect::<Vec<_>>(),
                )
            };
            ScalingRow {
                layers: n,
                pressure: fit(0),
                temperature: fit(1),
                lid_collision_rate: fit(2),
                mean_impulse: fit(3),
                tc_share: rs.iter().map(|r| r.tc_share()).fold(0.0, f64::max),
            }
        })
        .collect()
}

/// The provenance of the laws of a grid, as every command's results carry it
/// ([`Provenance`]): the law `name` with the parameters `params`, and the tangential law if
/// any.
pub fn provenance(
    reg: &Registry,
    name: &str,
    params: &[ParamValue],
    tangential: Option<(&str, &[ParamValue])>,
) -> Result<Vec<Provenance>> {
    let mut v = vec![Provenance::of(reg, name, params)?];
    if let Some((t, tp)) = tangential {
        v.push(Provenance::of(reg, t, tp)?);
    }
    Ok(v)
}

/// The provenance as the JSON of the other commands: `provenance` (the law) and, with a
/// tangential law, `tangential_provenance`.
pub fn provenance_json(prov: &[Provenance]) -> serde_json::Map<String, serde_json::Value> {
    let mut m = serde_json::Map::new();
    if let Some(p) = prov.first() {
        m.insert("provenance".into(), p.json());
    }
    if let Some(t) = prov.get(1) {
        m.insert("tangential_provenance".into(), t.json());
    }
    m
}

/// The provenance's `#` comment lines, put before a CSV header.
fn csv_comments(prov: &[Provenance]) -> String {
    prov.iter().map(Provenance::csv_comment).collect()
}

/// Writes every run of the grid as CSV, either engine's: the provenance of its laws as `#`
/// comment lines, then the common columns, then the engine's own.
pub fn write_grid_csv<R: Measured>(path: &Path, runs: &[R], prov: &[Provenance]) -> Result<()> {
    let mut s = csv_comments(prov);
    s.push_str(&format!("{CSV_COMMON_HEADER},{}\n", R::CSV_EXTRA_HEADER));
    for r in runs {
        s.push_str(&format!("{},{}\n", r.csv_common(), r.csv_extra()));
    }
    write_atomic(path, s.as_bytes()).with_context(|| format!("cannot write {}", path.display()))
}

/// Writes the exponents as CSV (theta and max |residual| of each observable), after the
/// provenance of the laws as `#` comment lines.
pub fn write_fit_csv(path: &Path, rows: &[ScalingRow], prov: &[Provenance]) -> Result<()> {
    let mut s = csv_comments(prov);
    s.push_str("layers,theta_p,theta_p_stderr,resid_p,theta_t,theta_t_stderr,resid_t,theta_nc,theta_nc_stderr,resid_nc,theta_di,theta_di_stderr,resid_di,tc_share\n");
    let c = |f: &Option<PowerFit>| match f {
        Some(f) => format!(
            "{},{},{}",
            f.theta,
            f.theta_stderr.map(|e| e.to_string()).unwrap_or_default(),
            f.max_residual
        ),
        None => ",,".to_string(),
    };
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{}\n",
            r.layers,
            c(&r.pressure),
            c(&r.temperature),
            c(&r.lid_collision_rate),
            c(&r.mean_impulse),
            r.tc_share
        ));
    }
    write_atomic(path, s.as_bytes()).with_context(|| format!("cannot write {}", path.display()))
}

/// θ(n) for the four observables; points whose fit is not a power law (a residual ≥ 0.25, the
/// paper's rule) are left out.
pub fn theta_panel(rows: &[ScalingRow], title: &str) -> Panel {
    fn pick(rows: &[ScalingRow], f: fn(&ScalingRow) -> Option<PowerFit>) -> Vec<(f64, f64)> {
        rows.iter()
            .filter_map(|r| f(r).filter(|p| p.is_power_law()).map(|p| (r.layers, p.theta)))
            .collect()
    }
    let mut series = Vec::new();
    type Pick = fn(&ScalingRow) -> Option<PowerFit>;
    let which: [(&str, Pick); 4] = [
        ("T", |r| r.temperature),
        ("Nc", |r| r.lid_collision_rate),
        ("ΔI", |r| r.mean_impulse),
        ("P", |r| r.pressure),
    ];
    for (k, (name, f)) in which.into_iter().enumerate() {
        let pts = pick(rows, f);
        series.push(Series::new(name, pts.clone(), Mark::Line, k));
        series.push(Series::new("", pts, Mark::Circles, k));
        let bars: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                f(r).filter(|p| p.is_power_law())
                    .and_then(|p| p.theta_stderr.map(|e| (r.layers, p.theta, e)))
            })
            .collect();
        series.extend(error_bars(&bars, k));
    }
    let xmax = rows.iter().map(|r| r.layers).fold(1.0, f64::max);
    Panel {
        title: title.to_string(),
        x_label: "n (layers)".into(),
        y_label: "θ".into(),
        x_range: Some((0.0, xmax * 1.05)),
        y_range: Some((-0.5, 2.5)),
        series,
        ..Default::default()
    }
}

/// Vertical error bars of ± one standard error at (x, y, e), as short line series.
pub fn error_bars(points: &[(f64, f64, f64)], color: usize) -> Vec<Series> {
    points
        .iter()
        .filter(|p| p.2.is_finite() && p.2 > 0.0)
        .map(|&(x, y, e)| Series::new("", vec![(x, y - e), (x, y + e)], Mark::Line, color))
        .collect()
}
