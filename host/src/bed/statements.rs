//! McNamara & Falcon's statements beyond Figs. 2–4 (their Secs. III A–C), each judged against
//! the runs' standard errors: the pressure on the lower wall, the maximum of P(n) at g = 0 and
//! g > 9.8, the headroom h − h0, the box width L, the tangential restitution, A/10 with 10 f,
//! and both readings of h0.
//!
//! Every sweep is P(n) at one frequency (20 Hz, V = 2 m/s) over the same n, a run per n, with
//! standard errors by batch means. A maximum "holds" when P peaks at 0.5 ≤ n ≤ 2 and the last n
//! lies more than 2 σ below the peak (σ the two runs' errors combined).

use super::engine::{BedConfig, BedReport};
use super::scaling::{run_grid, Grid};
use super::{DynRestitution, Laws};
use crate::output::progress_bar;
use anyhow::{Context, Result};
use std::fmt::Write as _;

/// The sizes of the statement sweeps.
#[derive(Debug, Clone)]
pub struct StatementSize {
    /// Layers n of every P(n) sweep.
    pub layers: Vec<f64>,
    /// Transient and measured periods.
    pub periods: (f64, f64),
}

impl StatementSize {
    /// For `reproduce` and `figures bed`: n from 0.25 to 4, 30 periods after 20.
    pub fn standard() -> StatementSize {
        StatementSize {
            layers: vec![0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0],
            periods: (20.0, 30.0),
        }
    }

    /// For tests of the pipeline.
    pub fn tiny() -> StatementSize {
        StatementSize {
            layers: vec![0.5, 1.0, 2.0],
            periods: (2.0, 4.0),
        }
    }
}

const F: f64 = 20.0;

fn sweep(
    law: &Laws<DynRestitution>,
    size: &StatementSize,
    what: &str,
    cfg: &(dyn Fn(f64) -> BedConfig + Sync),
) -> Result<Vec<BedReport>> {
    let grid = Grid::new(&size.layers, &[F], size.periods);
    let pb = progress_bar(grid.len() as u64, what);
    let l = Laws {
        disk: &law.disk,
        wall: &law.wall,
    };
    let r = run_grid(&l, &|n, _| cfg(n), &grid, &|| pb.inc(1)).with_context(|| what.to_string())?;
    pb.finish_and_clear();
    Ok(r)
}

/// (n at the maximum, whether P(last n) is more than 2 σ below the maximum, the drop in σ).
fn maximum(runs: &[BedReport]) -> (f64, bool, f64) {
    let (am, _) =
        runs.iter().enumerate().fold(
            (0, f64::MIN),
            |a, (k, r)| if r.pressure > a.1 { (k, r.pressure) } else { a },
        );
    let (top, last) = (&runs[am], &runs[runs.len() - 1]);
    let s = (top.pressure_stderr.unwrap_or(0.0).powi(2) + last.pressure_stderr.unwrap_or(0.0).powi(2))
        .sqrt()
        .max(1e-300);
    let drop = (top.pressure - last.pressure) / s;
    (top.config.layers, drop > 2.0, drop)
}

/// How P(n) ends after its maximum, in words: "falls 2.3 σ by the last n", or, when the maximum
/// is the last n, that it does not fall (not "falls 0.0 σ").
fn fall(runs: &[BedReport]) -> String {
    let (at, _, drop) = maximum(runs);
    fall_text(runs.last().is_some_and(|r| r.config.layers == at), drop)
}

/// [`fall`]'s words for a maximum at the last n (`at_last`) or a drop of `drop` σ after it.
fn fall_text(at_last: bool, drop: f64) -> String {
    if at_last {
        "does not fall: its maximum is at the last n".to_string()
    } else {
        format!("falls {drop:.1} σ by the last n")
    }
}

fn row(runs: &[BedReport]) -> String {
    runs.iter()
        .map(|r| match r.pressure_stderr {
            Some(e) => format!("{:.3} ± {:.3}", r.pressure, e),
            None => format!("{:.3}", r.pressure),
        })
        .collect::<Vec<_>>()
        .join(" | ")
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "**holds**"
    } else {
        "**does not hold**"
    }
}

/// Runs the sweeps with r(v) (`rv`) and r = 0.95 (`r95`, TC at `tc` s) and returns the report
/// section (markdown), a progress line per sweep on stderr.
pub fn run(
    rv: &Laws<DynRestitution>,
    r95: &Laws<DynRestitution>,
    tc: f64,
    size: &StatementSize,
) -> Result<String> {
    let mut md = String::new();
    let ns = &size.layers;
    let head = format!(
        "| sweep | {} |\n|---|{}",
        ns.iter()
            .map(|n| format!("P (N/m), n = {n}"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(ns.len())
    );
    writeln!(
        md,
        "## McNamara & Falcon: the other statements (Secs. III A–C)\n\n\
         P(n) at f = {F} Hz (V = 2 m/s), {} periods measured after {}, ± one standard error \
         (batch means). A maximum of P(n) counts when P peaks at 0.5 ≤ n ≤ 2 and P at n = {} is \
         more than 2 σ below the peak; this rule was fixed before the runs.\n",
        size.periods.1,
        size.periods.0,
        ns[ns.len() - 1]
    )?;
    let paper = |n: f64| BedConfig::paper(n, F);
    let stage = |s: &str| eprintln!("  statements: {s}");
    // the paper's bed at each n with one change
    let varied = |what: &str, change: &(dyn Fn(&mut BedConfig) + Sync)| {
        sweep(rv, size, what, &|n| {
            let mut c = paper(n);
            change(&mut c);
            c
        })
    };

    stage("r(v) at g = 9.8, 0 and 20 m/s²");
    let g98 = sweep(rv, size, "r(v), g = 9.8", &|n| paper(n))?;
    let g0 = varied("r(v), g = 0", &|c| c.gravity = 0.0)?;
    let g20 = varied("r(v), g = 20", &|c| c.gravity = 20.0)?;
    writeln!(md, "{head}")?;
    for (name, runs) in [
        ("r(v), g = 9.8", &g98),
        ("r(v), g = 0", &g0),
        ("r(v), g = 20 m/s²", &g20),
    ] {
        writeln!(md, "| {name} | {} |", row(runs))?;
    }
    // the lower wall
    let mut worst = 0.0f64;
    for r in g98.iter().chain(&g20) {
        let c = &r.config;
        let expect = r.pressure + r.disks as f64 * c.mass * c.gravity / c.width;
        let s = (r.piston_pressure_stderr.unwrap_or(0.0).powi(2) + r.pressure_stderr.unwrap_or(0.0).powi(2))
            .sqrt()
            .max(1e-300);
        worst = worst.max((r.piston_pressure - expect).abs() / s);
    }
    let (m0, ok0, _) = maximum(&g0);
    let (m20, ok20, _) = maximum(&g20);
    writeln!(
        md,
        "\n- \"The time averaged pressure on the lower wall is just P plus the weight of the \
         particles N m g/L\" (momentum): the piston's pressure (collisions and disks riding on \
         it) against P + N m g/L in the {} runs at g = 9.8 and 20: the largest difference is \
         {worst:.2} σ: {}.\n\
         - \"This maximum pressure is not due to gravity because it also appears in simulations \
         with g = 0\": with g = 0, P peaks at n = {m0} and {}: {}.\n\
         - \"The maximum persists when g is increased above 9.8 m/s²\": with g = 20 m/s², P \
         peaks at n = {m20} and {}: {}.",
        g98.len() + g20.len(),
        verdict(worst < 3.0),
        fall(&g0),
        verdict(ok0 && (0.5..=2.0).contains(&m0)),
        fall(&g20),
        verdict(ok20 && (0.5..=2.0).contains(&m20)),
    )?;

    stage("headroom h − h0 = 5, 15, 50 mm and both readings of h0");
    let mut hs = Vec::new();
    for h in [0.005, 0.05] {
        hs.push((h, varied(&format!("r(v), h - h0 = {h}"), &|c| c.headroom = h)?));
    }
    // the lid stays h − h0 = 15 mm above a bed at rest 0.9 n d high
    let h09 = varied("r(v), h0 = 0.9 n d", &|c| {
        c.headroom = 0.015 - 0.1 * c.layers * 0.002
    })?;
    writeln!(md, "\n{head}")?;
    writeln!(md, "| h − h0 = 5 mm | {} |", row(&hs[0].1))?;
    writeln!(md, "| h − h0 = 15 mm | {} |", row(&g98))?;
    writeln!(md, "| h − h0 = 50 mm | {} |", row(&hs[1].1))?;
    writeln!(md, "| h0 = 0.9 n d (h − h0 = 15 mm) | {} |", row(&h09))?;
    let (m5, ok5, _) = maximum(&hs[0].1);
    let (m15, ok15, _) = maximum(&g98);
    let (m50, ok50, _) = maximum(&hs[1].1);
    let peak = |r: &[BedReport]| r.iter().map(|r| r.pressure).fold(f64::MIN, f64::max);
    let (mh, okh, _) = maximum(&h09);
    writeln!(
        md,
        "\n- Headroom, 5 ≤ h − h0 ≤ 50 mm: \"increasing h − h0 shifts the maximum towards \
         smaller values of n and decreases in amplitude\": the peak is at n = {m15} (15 mm) and \
         n = {m50} (50 mm), P_max {:.3} → {:.3} N/m: {}. \"The maximum disappears\" at 5 mm: \
         here P peaks at n = {m5} and {}: {}.\n\
         - h0, both readings (the paper does not define it): with h0 = n d the maximum is at \
         n = {m15} ({}); with h0 = 0.9 n d (a random 2D packing) at n = {mh} and {} \
         ({}). The conclusion does not depend on the reading: {}.",
        peak(&g98),
        peak(&hs[1].1),
        verdict(m50 <= m15 && peak(&hs[1].1) < peak(&g98) && ok50),
        fall(&hs[0].1),
        verdict(!(ok5 && (0.5..=2.0).contains(&m5))),
        if ok15 { "a maximum" } else { "no maximum" },
        fall(&h09),
        if okh { "a maximum" } else { "no maximum" },
        verdict(ok15 == okh),
    )?;

    stage("box width L = 10 and 40 cm");
    let l10 = varied("r(v), L = 10 cm", &|c| c.width = 0.1)?;
    let l40 = varied("r(v), L = 40 cm", &|c| c.width = 0.4)?;
    writeln!(md, "\n{head}")?;
    writeln!(md, "| L = 10 cm | {} |", row(&l10))?;
    writeln!(md, "| L = 20 cm | {} |", row(&g98))?;
    writeln!(md, "| L = 40 cm | {} |", row(&l40))?;
    let dev = |a: &[BedReport]| {
        a.iter()
            .zip(&g98)
            .map(|(x, y)| {
                let s = (x.pressure_stderr.unwrap_or(0.0).powi(2) + y.pressure_stderr.unwrap_or(0.0).powi(2))
                    .sqrt();
                (
                    (x.pressure - y.pressure).abs() / y.pressure,
                    (x.pressure - y.pressure).abs() / s.max(1e-300),
                )
            })
            .fold((0.0f64, 0.0f64), |a, b| (a.0.max(b.0), a.1.max(b.1)))
    };
    let ((r10, s10), (r40, s40)) = (dev(&l10), dev(&l40));
    writeln!(
        md,
        "\n- \"None of this paper's results depend significantly on L\" (L = 10 and 40 cm, n = \
         N d/L fixed): largest relative change of P against L = 20 cm {:.0} % ({s10:.1} σ) at \
         10 cm and {:.0} % ({s40:.1} σ) at 40 cm; the maximum of P(n) is at n = {} and {}: {} \
         (judged on the maximum, the paper's result; \"significantly\" is not quantified).",
        100.0 * r10,
        100.0 * r40,
        maximum(&l10).0,
        maximum(&l40).0,
        verdict(maximum(&l10).1 && maximum(&l40).1 && r10 < 0.2 && r40 < 0.2),
    )?;

    stage("tangential restitution, r = 0.95");
    let mut rts = Vec::new();
    for rt in [None, Some(0.9), Some(0.0)] {
        rts.push((
            rt,
            sweep(r95, size, &format!("r = 0.95, r_t = {rt:?}"), &|n| BedConfig {
                tangential: rt,
                tc: Some(tc),
                ..paper(n)
            })?,
        ));
    }
    writeln!(md, "\n{head}")?;
    for (rt, runs) in &rts {
        let name = match rt {
            None => "r = 0.95, smooth (r_t = −1)".to_string(),
            Some(v) => format!("r = 0.95, r_t = {v}"),
        };
        writeln!(md, "| {name} | {} |", row(runs))?;
    }
    let change = |a: &[BedReport], b: &[BedReport]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x.pressure - y.pressure).abs() / y.pressure)
            .fold(0.0f64, f64::max)
    };
    let flat = |r: &[BedReport]| {
        let tail: Vec<f64> = r
            .iter()
            .filter(|r| r.config.layers >= 2.0)
            .map(|r| r.pressure)
            .collect();
        let (lo, hi) = tail
            .iter()
            .fold((f64::MAX, f64::MIN), |a, &p| (a.0.min(p), a.1.max(p)));
        (hi - lo) / hi
    };
    let (c09, f0, fs) = (change(&rts[1].1, &rts[0].1), flat(&rts[2].1), flat(&rts[0].1));
    writeln!(
        md,
        "\n- Tangential restitution, r = 0.95 (TC t_c = {tc} s): \"when |r_t| is close to one, the \
         P vs. n curves are almost unchanged\": r_t = 0.9 changes P by at most {:.0} % against \
         smooth disks: {}. \"When r_t is close to 0, the curves become nearly flat for n > 2\": \
         over n ≥ 2, P varies by {:.0} % with r_t = 0 against {:.0} % for smooth disks: {}.",
        100.0 * c09,
        verdict(c09 < 0.15),
        100.0 * f0,
        100.0 * fs,
        verdict(f0 < fs && f0 < 0.25),
    )?;

    stage("A/10 with 10 f");
    let ns_v: Vec<f64> = vec![1.0, 2.0];
    let grid = |f: f64| Grid {
        layers: ns_v.clone(),
        freqs: vec![f],
        transient: size.periods.0 * f / F,
        cycles: size.periods.1 * f / F,
    };
    let l = Laws {
        disk: &rv.disk,
        wall: &rv.wall,
    };
    let base = run_grid(&l, &|n, f| BedConfig::paper(n, f), &grid(10.0), &|| {})?;
    let fast = run_grid(
        &l,
        &|n, f| BedConfig {
            amplitude: 0.0025,
            ..BedConfig::paper(n, f)
        },
        &grid(100.0),
        &|| {},
    )?;
    let ch: Vec<String> = base
        .iter()
        .zip(&fast)
        .map(|(a, b)| {
            format!(
                "n = {}: {:.3} ± {:.3} → {:.3} ± {:.3} N/m ({:+.0} %)",
                a.config.layers,
                a.pressure,
                a.pressure_stderr.unwrap_or(f64::NAN),
                b.pressure,
                b.pressure_stderr.unwrap_or(f64::NAN),
                100.0 * (b.pressure / a.pressure - 1.0)
            )
        })
        .collect();
    let worst_v = base
        .iter()
        .zip(&fast)
        .map(|(a, b)| (b.pressure / a.pressure - 1.0).abs())
        .fold(0.0f64, f64::max);
    writeln!(
        md,
        "- \"Multiplying the frequency by 10 while dividing A by 10 ... changes the pressure only \
         by about 20 %\" (V = 1 m/s, Γ 10 times larger; r(v), same protocol in periods): {}: \
         {} (about 20 % read as at most 30 %).\n",
        ch.join("; "),
        verdict(worst_v < 0.3),
    )?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_maximum_at_the_last_n_is_said_not_to_fall() {
        assert_eq!(
            super::fall_text(true, 0.0),
            "does not fall: its maximum is at the last n"
        );
        assert_eq!(super::fall_text(false, 2.345), "falls 2.3 σ by the last n");
    }
}
