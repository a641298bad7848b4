//! `dashpot figures bed`: McNamara & Falcon's Figs. 2 b–d, 3 and 4 a–d, and a report that
//! compares each with the paper's statements, backed by the numbers.

use crate::bed::engine::{BedConfig, BedReport};
use crate::bed::scaling::{provenance, run_grid, Grid, Measured};
use crate::bed::{bed_particle, resolve_for, DynRestitution, LawChoice, Laws};
use crate::output::progress_bar;
use crate::output::Provenance;
use crate::plot::{Mark, Panel, Series, PALETTE};
use crate::registry::Registry;
use anyhow::{Context, Result};
use dashpot_sdk::ParamValue;
use std::fmt::Write as _;
use std::path::Path;

mod dem;
mod figs;
pub use dem::*;
use figs::*;

/// The TC time (s) used with the constant laws in the figures (off for r(v), which needs none).
pub const FIGURE_TC: f64 = 1e-5;

/// How big the figures' runs are.
#[derive(Debug, Clone)]
pub struct Size {
    /// Name shown in the report.
    pub name: &'static str,
    /// Fig. 2: layers.
    pub fig2_layers: Vec<f64>,
    /// Fig. 2: frequencies (Hz).
    pub fig2_freqs: Vec<f64>,
    /// Fig. 2: transient and measured periods.
    pub fig2_periods: (f64, f64),
    /// Fig. 3: transient periods, then 10 snapshots one period apart. The cluster of r = 0.7
    /// needs several hundred periods to gather.
    pub fig3_transient: f64,
    /// Fig. 4: layers.
    pub fig4_layers: Vec<f64>,
    /// Fig. 4: frequencies (Hz).
    pub fig4_freqs: Vec<f64>,
    /// Fig. 4: transient and measured periods.
    pub fig4_periods: (f64, f64),
    /// The other statements of the paper (Secs. III A–C).
    pub statements: crate::bed::statements::StatementSize,
}

fn steps(a: f64, b: f64, k: usize) -> Vec<f64> {
    (0..k).map(|i| a + (b - a) * i as f64 / (k - 1) as f64).collect()
}

impl Size {
    /// The paper's grids: Fig. 2 with f = 10…30 Hz by 2 Hz over 11 values of n (100 periods
    /// after 50), Fig. 4 with 7 values of n and 11 frequencies (200 periods after 50).
    pub fn paper() -> Size {
        Size {
            name: "paper",
            fig2_layers: vec![0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0],
            fig2_freqs: steps(10.0, 30.0, 11),
            fig2_periods: (50.0, 100.0),
            fig3_transient: 1000.0,
            fig4_layers: vec![0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0],
            fig4_freqs: steps(10.0, 30.0, 11),
            fig4_periods: (50.0, 200.0),
            statements: crate::bed::statements::StatementSize::standard(),
        }
    }

    /// A quick look (about a minute on two cores).
    pub fn quick() -> Size {
        Size {
            name: "quick",
            fig2_layers: vec![0.25, 0.5, 1.0, 2.0, 3.0, 5.0],
            fig2_freqs: vec![10.0, 20.0, 30.0],
            fig2_periods: (10.0, 20.0),
            fig3_transient: 300.0,
            fig4_layers: vec![0.5, 1.0, 2.0, 3.0],
            fig4_freqs: steps(10.0, 30.0, 5),
            fig4_periods: (10.0, 30.0),
            statements: crate::bed::statements::StatementSize::tiny(),
        }
    }

    /// Tiny runs for tests of the pipeline (seconds; the numbers are noisy).
    pub fn tiny() -> Size {
        Size {
            name: "tiny",
            fig2_layers: vec![0.5, 1.0, 2.0],
            fig2_freqs: vec![10.0, 30.0],
            fig2_periods: (2.0, 4.0),
            fig3_transient: 3.0,
            fig4_layers: vec![0.5, 2.0],
            fig4_freqs: vec![10.0, 20.0, 30.0],
            fig4_periods: (2.0, 4.0),
            statements: crate::bed::statements::StatementSize::tiny(),
        }
    }

    /// The size `dashpot reproduce` uses (about 150 CPU s, so a minute or two on two cores):
    /// the paper's values of n, fewer frequencies for Fig. 2 and shorter runs.
    pub fn reproduce() -> Size {
        Size {
            name: "reproduce",
            fig2_freqs: steps(10.0, 30.0, 6),
            fig2_periods: (30.0, 60.0),
            fig4_periods: (30.0, 100.0),
            ..Size::paper()
        }
    }
}

type Plug = Laws<DynRestitution>;

fn law(reg: &Registry, name: &str, params: &[ParamValue]) -> Result<Plug> {
    let c = BedConfig::paper(1.0, 20.0);
    let law = LawChoice::new(name, params.to_vec());
    Ok(resolve_for(reg, &law, &bed_particle(c.diameter, c.mass))?)
}

/// The three laws of the paper: r(v) (eq. 1), r = 0.95, r = 0.7, and their provenance (for
/// the CSV files).
struct Three {
    rv: Plug,
    r95: Plug,
    r70: Plug,
    prov: [Vec<Provenance>; 3],
}

fn refs(l: &Plug) -> Laws<&DynRestitution> {
    Laws {
        disk: &l.disk,
        wall: &l.wall,
    }
}

fn cfg_for(constant: bool, gravity: f64) -> impl Fn(f64, f64) -> BedConfig + Sync {
    move |n, f| BedConfig {
        gravity,
        tc: constant.then_some(FIGURE_TC),
        ..BedConfig::paper(n, f)
    }
}

fn grid_runs(l: &Plug, constant: bool, gravity: f64, grid: &Grid, what: &str) -> Result<Vec<BedReport>> {
    let pb = progress_bar(grid.len() as u64, what);
    let r = run_grid(&refs(l), &cfg_for(constant, gravity), grid, &|| pb.inc(1))
        .with_context(|| what.to_string())?;
    pb.finish_and_clear();
    Ok(r)
}

/// Runs everything, writes the figures and CSV files into `out`, returns the report (markdown).
pub fn run(reg: &Registry, out: &Path, size: &Size) -> Result<String> {
    run_only(reg, out, size, &[])
}

/// Like [`run`], for the figures listed in `only` (2, 3, 4; empty: all).
pub fn run_only(reg: &Registry, out: &Path, size: &Size, only: &[u8]) -> Result<String> {
    let want = |k: u8| only.is_empty() || only.contains(&k);
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let laws = Three {
        rv: law(reg, "mcnamara-falcon", &[])?,
        r95: law(reg, "constant", &[ParamValue::new("r", 0.95)])?,
        r70: law(reg, "constant", &[ParamValue::new("r", 0.7)])?,
        prov: [
            provenance(reg, "mcnamara-falcon", &[], None)?,
            provenance(reg, "constant", &[ParamValue::new("r", 0.95)], None)?,
            provenance(reg, "constant", &[ParamValue::new("r", 0.7)], None)?,
        ],
    };
    let clock = std::time::Instant::now();
    let mut md = String::new();
    writeln!(
        md,
        "# McNamara & Falcon (2005), vibrated bed: Figs. 2 b–d, 3, 4 a–d\n\n\
         Size `{}`. Disks d = 2 mm, m = 3.27e-5 kg, L = 0.2 m, A = 25 mm, h − h0 = 15 mm with \
         h0 = n d, smooth disks. r(v) is the `mcnamara-falcon` plugin (r0 = 0.95, v_y = 0.3 m/s), \
         constant r the `constant` plugin; constant-r runs use the TC model with t_c = {} s \
         (its share of collisions is listed), r(v) runs none. Every number below is from \
         these runs; the CSV files beside this report hold them all.\n",
        size.name, FIGURE_TC
    )?;
    let stage = |s: &str| eprintln!("figures bed ({}): {s}", size.name);
    if want(2) {
        stage("Fig. 2, P(n) for r(v), r = 0.95, r = 0.7");
        let t = std::time::Instant::now();
        fig2(&laws, out, size, &mut md)?;
        writeln!(md, "Fig. 2 wall time: {:.0} s.\n", t.elapsed().as_secs_f64())?;
    }
    if want(3) {
        stage("Fig. 3, snapshots at n = 3, f = 30 Hz");
        let t = std::time::Instant::now();
        fig3(&laws, out, size, &mut md)?;
        writeln!(md, "Fig. 3 wall time: {:.0} s.\n", t.elapsed().as_secs_f64())?;
    }
    if want(4) {
        stage("Fig. 4, the exponents θ(n), four panels");
        let t = std::time::Instant::now();
        fig4(&laws, out, size, &mut md)?;
        writeln!(
            md,
            "Fig. 4 wall time: {:.0} s ({} runs).\n",
            t.elapsed().as_secs_f64(),
            4 * size.fig4_layers.len() * size.fig4_freqs.len()
        )?;
    }
    if want(5) {
        stage("the other statements (g, headroom, h0, L, r_t, A/10 with 10 f)");
        let t = std::time::Instant::now();
        md.push_str(&crate::bed::statements::run(
            &laws.rv,
            &laws.r95,
            FIGURE_TC,
            &size.statements,
        )?);
        writeln!(md, "Statements wall time: {:.0} s.\n", t.elapsed().as_secs_f64())?;
    }
    stage("done");
    Ok(with_wall_time(md, clock))
}

fn pressure_panel<R: Measured>(title: &str, grid: &Grid, runs: &[R]) -> Panel {
    let nf = grid.freqs.len();
    let series = grid
        .freqs
        .iter()
        .enumerate()
        .flat_map(|(k, f)| {
            let pts: Vec<(f64, f64)> = grid
                .layers
                .iter()
                .enumerate()
                .map(|(a, &n)| (n, runs[a * nf + k].pressure))
                .collect();
            let c = PALETTE.len() + (k * 15) / (nf.max(2) - 1);
            let bars: Vec<(f64, f64, f64)> = grid
                .layers
                .iter()
                .enumerate()
                .filter_map(|(a, &n)| {
                    let r = &runs[a * nf + k];
                    r.pressure_stderr.map(|e| (n, r.pressure, e))
                })
                .collect();
            let mut s = vec![
                Series::new(format!("f = {f:.0} Hz"), pts.clone(), Mark::Line, c),
                Series::new("", pts, Mark::Circles, c),
            ];
            s.extend(crate::bed::scaling::error_bars(&bars, c));
            s
        })
        .collect();
    Panel {
        title: title.to_string(),
        x_label: "n (layers)".into(),
        y_label: "P (N/m)".into(),
        series,
        ..Default::default()
    }
}

/// The rows of a table of three sets of [`peaks`]: f, then for each set the n of the largest
/// pressure and P(last n)/P(max).
fn peak_rows(md: &mut String, [a, b, c]: [&[(f64, f64, f64)]; 3]) -> std::fmt::Result {
    use std::fmt::Write as _;
    for k in 0..a.len() {
        writeln!(
            md,
            "| {:.0} | {} | {:.2} | {} | {:.2} | {} | {:.2} |",
            a[k].0, a[k].1, a[k].2, b[k].1, b[k].2, c[k].1, c[k].2
        )?;
    }
    Ok(())
}

/// For each frequency: the n of the largest pressure, and P(last n)/P(max).
fn peaks<R: Measured>(grid: &Grid, runs: &[R]) -> Vec<(f64, f64, f64)> {
    let nf = grid.freqs.len();
    grid.freqs
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let p: Vec<f64> = (0..grid.layers.len())
                .map(|a| runs[a * nf + k].pressure)
                .collect();
            let (am, pm) = p
                .iter()
                .enumerate()
                .fold((0, f64::MIN), |acc, (a, &v)| if v > acc.1 { (a, v) } else { acc });
            (f, grid.layers[am], p[p.len() - 1] / pm)
        })
        .collect()
}

/// The report `md` ended with its total wall time since `clock` and the threads it ran on.
fn with_wall_time(mut md: String, clock: std::time::Instant) -> String {
    md.push_str(&format!(
        "\nTotal wall time: {:.0} s on {} threads.\n",
        clock.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    ));
    md
}
