//! Scaling exponents: a grid of runs over layers n and frequencies f, in parallel, and the
//! least-squares exponents θ of X ∝ V^θ for X = P, T, Nc, ΔI at each n (the paper's Fig. 4).

use super::engine::{Bed, BedConfig, BedReport};
use super::observables::{fit_power_err, BedObservables, PowerFit};
use super::{BedError, Laws, Restitution};
use crate::bed::on_dem::{DemBed, DemBedReport};
use crate::dem::DemError;
use crate::output::{write_atomic, Provenance};
use crate::plot::{Mark, Panel, Series};
use crate::registry::Registry;
use anyhow::Result;
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
    /// Every n of `layers` with every f of `freqs` (Hz), each run `periods` = (transient,
    /// measured) periods.
    pub fn new(layers: &[f64], freqs: &[f64], (transient, cycles): (f64, f64)) -> Grid {
        Grid {
            layers: layers.to_vec(),
            freqs: freqs.to_vec(),
            transient,
            cycles,
        }
    }

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

/// The symbols of the four observables, in the order of [`ScalingRow::fits`].
pub const FIT_SYMBOLS: [&str; 4] = ["P", "T", "Nc", "ΔI"];

impl ScalingRow {
    /// θ of P, T, Nc and ΔI, in that order ([`FIT_SYMBOLS`]).
    pub fn fits(&self) -> [&Option<PowerFit>; 4] {
        [
            &self.pressure,
            &self.temperature,
            &self.lid_collision_rate,
            &self.mean_impulse,
        ]
    }
}

/// A run of either engine, for the exponent fits and the grid CSV: its observables, and the
/// engine's own columns.
pub trait Measured: std::ops::Deref<Target = BedObservables> {
    /// Share of collisions made elastic by the TC model (0 without one).
    fn tc_share(&self) -> f64;
    /// The engine's own CSV columns after the observables': their header, and a run's values.
    const CSV_EXTRA_HEADER: &'static str;
    /// See [`Measured::CSV_EXTRA_HEADER`].
    fn csv_extra(&self) -> String;
}

impl Measured for BedReport {
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
                            let (v, e) = r.fit_values()[k];
                            v.map(|v| (r.piston_speed, v, e))
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
    s.push_str(&format!(
        "{},{}\n",
        BedObservables::CSV_HEADER,
        R::CSV_EXTRA_HEADER
    ));
    for r in runs {
        s.push_str(&format!("{},{}\n", r.csv(), r.csv_extra()));
    }
    Ok(write_atomic(path, s.as_bytes())?)
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
        let fits = r.fits().map(c).join(",");
        s.push_str(&format!("{},{fits},{}\n", r.layers, r.tc_share));
    }
    Ok(write_atomic(path, s.as_bytes())?)
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
