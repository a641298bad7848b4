//! `figures collide`, sdk 0.3's families: a JKR impact's force–overlap loop against the
//! quasi-static JKR curve, and a sphere's rolling stop against rigid-body mechanics.

use crate::collide::rolling::{roll, RollingSpec};
use crate::collide::two_body::{collide, Options, PairLaw};
use crate::plot::{Figure, Mark, Panel, Series};
use crate::registry::Registry;
use anyhow::{Context, Result};
use dashpot_sdk::{EndCriterion, Pair, ParamValue, Particle};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

/// Writes the JKR loop and the rolling stop into `out` (when their plugins are there) and
/// returns the markdown report.
pub fn families_figures(reg: &Registry, out: &Path) -> Result<String> {
    let mut md = String::new();
    let have = |n: &str| reg.find(n).is_ok();
    if have("jkr") {
        jkr_loop(reg, out, &mut md)?;
    } else {
        writeln!(md, "\n(The JKR loop needs the plugin jkr, not found.)\n")?;
    }
    if have("hsd") && have("mindlin") && have("rolling-sds") {
        rolling_stop(reg, out, &mut md)?;
    } else {
        writeln!(
            md,
            "\n(The rolling stop needs the plugins hsd, mindlin and rolling-sds.)\n"
        )?;
    }
    Ok(md)
}

/// A 1 mm silica-like sphere (ρ = 2500 kg/m³, E = 70 GPa, ν = 0.2) against a wall, w = 0.1 J/m².
fn jkr_loop(reg: &Registry, out: &Path, md: &mut String) -> Result<()> {
    let p = Particle {
        diameter: 1e-3,
        density: 2500.0,
        young: 7e10,
        poisson: 0.2,
    };
    let pair = Pair::wall(&p)?;
    let w = 0.1;
    let params = [ParamValue::new("w", w)];
    let law = reg.contact("jkr", &params)?;
    let (r, e) = (pair.radius, pair.young);
    // Thornton & Ning's critical speed, and two impacts on either side of it
    let vc = 1.84 * (w.powi(5) / (p.density.powi(3) * e * e * r.powi(5))).powf(1.0 / 6.0);
    let opt = Options {
        record: true,
        max_step_fraction: 0.002,
        ..Options::default()
    };
    let mut series = Vec::new();
    let mut lines = Vec::new();
    for (k, factor) in [0.7, 1.5].into_iter().enumerate() {
        let b = PairLaw::bind(&law, &pair, p.poisson)?;
        let c = collide(&b, pair.mass, factor * vc, EndCriterion::Overlap, &opt)
            .with_context(|| format!("jkr at {factor} v_c"))?;
        let pts: Vec<(f64, f64)> = c
            .trajectory
            .iter()
            .map(|s| (s.delta * 1e9, s.force * 1e6))
            .collect();
        let what = if c.stuck {
            "sticks".to_string()
        } else {
            format!("rebounds, e = {:.4}", c.restitution)
        };
        lines.push(format!("v0 = {factor} v_c: {what}"));
        series.push(Series::new(
            format!("impact at {factor} v_c ({what})"),
            pts,
            Mark::Line,
            k,
        ));
    }
    // the quasi-static JKR curve, parametric in the contact radius a
    let a0 = (9.0 * PI * w * r * r / (2.0 * e)).cbrt();
    // from rupture (a = a0/6^{2/3}) up, the stable branch under displacement control
    let a_c = a0 / 6f64.powf(2.0 / 3.0);
    let curve: Vec<(f64, f64)> = (0..=200)
        .map(|i| {
            let a = a_c + (1.05 * a0 - a_c) * i as f64 / 200.0;
            let delta = a * a / r - (2.0 * PI * w * a / e).sqrt();
            let f = 4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a.powi(3)).sqrt();
            (delta * 1e9, f * 1e6)
        })
        .collect();
    series.push(Series::new("JKR, quasi-static", curve, Mark::Dashed, 2));
    Figure::single(Panel {
        title: format!("JKR impacts, 1 mm sphere on a wall, w = {w} J/m² (v_c = {vc:.3e} m/s)"),
        x_label: "overlap δ (nm)".into(),
        y_label: "normal force F (µN)".into(),
        series,
        ..Default::default()
    })
    .save(out, "jkr_force_overlap_loop")?;
    writeln!(
        md,
        "\n**JKR force–overlap loop** (`jkr_force_overlap_loop.png`): a 1 mm sphere (ρ = 2500 kg/m³, \
         E = 70 GPa, ν = 0.2) on a wall, w = {w} J/m²; Thornton & Ning's critical speed \
         1.84 (w⁵/(ρ³E*²R*⁵))^{{1/6}} = {vc:.4e} m/s; {}. The contact forms at touch (F jumps to \
         −(8/9) of the pull-off force (3/2)πwR = {:.4e} N) and, on rebound, follows the JKR curve \
         to the rupture separation.\n",
        lines.join("; "),
        1.5 * PI * w * r
    )?;
    Ok(())
}

/// The 1 cm MCC sphere rolling on a wall against `rolling-sds` (μ_r = 0.1).
fn rolling_stop(reg: &Registry, out: &Path, md: &mut String) -> Result<()> {
    let p = Particle::MCC;
    let mats = Pair::wall(&p)?.materials(p.poisson)?;
    let n = reg.contact("hsd", &[ParamValue::new("eps", 0.5)])?.bind(&mats)?;
    let t = reg
        .tangential("mindlin", &[ParamValue::new("mu", 0.5)])?
        .bind(&mats)?;
    let mu_r = 0.1;
    let rl = reg
        .rolling("rolling-sds", &[ParamValue::new("mu", mu_r)])?
        .bind(&mats)?;
    let (m, r, v0, g) = (p.mass(), p.radius(), 0.05, 9.81);
    let spec = RollingSpec {
        mass: m,
        radius: r,
        inertia: 0.4 * m * r * r,
        v0,
        gravity: g,
        steps: 50,
    };
    let s = roll(&n, &t, &rl, &spec, 50)?;
    let a = 5.0 / 7.0 * mu_r * g;
    let run: Vec<(f64, f64)> = s.samples.iter().map(|q| (q[0], q[2])).collect();
    let exact: Vec<(f64, f64)> = (0..=50)
        .map(|i| {
            let tt = v0 / a * i as f64 / 50.0;
            (tt, v0 - a * tt)
        })
        .collect();
    Figure::single(Panel {
        title: format!("A 1 cm sphere rolling on a wall, rolling-sds μ_r = {mu_r}"),
        x_label: "time (s)".into(),
        y_label: "speed of the centre (m/s)".into(),
        series: vec![
            Series::new("hsd + mindlin + rolling-sds", run, Mark::Line, 0),
            Series::new("v0 − (5/7) μ_r g t", exact, Mark::Circles, 1),
        ],
        ..Default::default()
    })
    .save(out, "rolling_stop")?;
    writeln!(
        md,
        "\n**Rolling stop** (`rolling_stop.png`): a 1 cm MCC sphere launched at {v0} m/s rolling \
         without slip on a wall (hsd ε = 0.5, mindlin μ = 0.5, rolling-sds μ_r = {mu_r}) stops after \
         {:.5} s and {:.5e} m; rigid-body mechanics: (5/7) μ_r g gives {:.5} s and {:.5e} m.\n",
        s.stop_time,
        s.stop_distance,
        v0 / a,
        v0 * v0 / (2.0 * a)
    )?;
    Ok(())
}
