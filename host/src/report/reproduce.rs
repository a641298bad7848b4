//! The main job: reproduce the two papers' results with the laws loaded as plugins.
//!
//! It reproduces what the laws give directly: the closed forms of Antypov & Elliott (eqs. 8, 9,
//! 10, 17, 21, 25) for the paper's MCC granule, and the restitution curve of McNamara & Falcon
//! (eq. 1, their Fig. 1); then the vibrated bed of McNamara & Falcon (Figs. 2-4, on a reduced
//! grid, [`crate::report::bed::Size::reproduce`]).

use crate::collide::PairLaw;
use crate::output::law_json;
use crate::output::write_atomic;
use crate::registry::Registry;
use anyhow::{Context, Result};
use dashpot_sdk::{Pair, ParamValue, Particle};
use std::fmt::Write as _;
use std::path::Path;

fn coeff(c: &[dashpot_sdk::Coefficient], name: &str) -> f64 {
    c.iter()
        .find(|c| c.name == name)
        .map(|c| c.value)
        .unwrap_or(f64::NAN)
}

/// The laws the report is made of.
pub const REQUIRED: [&str; 5] = ["lsd", "hsd", "kuwabara-kono", "mcnamara-falcon", "constant"];

/// Writes `report.md`, `laws.json` and CSV tables into `out`; `quick`: tiny driver runs.
pub fn run(reg: &Registry, out: &Path, quick: bool) -> Result<()> {
    // the papers need these laws: without one, the report would be incomplete, not a result
    let missing: Vec<&str> = REQUIRED
        .iter()
        .copied()
        .filter(|n| reg.find(n).is_err())
        .collect();
    if !missing.is_empty() {
        anyhow::bail!(
            "reproduce needs the built-in laws {}, but {} not found (searched: {}){}. Build them \
             with `cargo build --release`, and do not pass --no-default-plugins; plugins given \
             with --plugin, --plugin-dir or DASHPOT_PLUGIN_PATH are loaded in addition to them",
            REQUIRED.join(", "),
            if missing.len() == 1 {
                format!("'{}' was", missing[0])
            } else {
                format!(
                    "{} were",
                    missing
                        .iter()
                        .map(|m| format!("'{m}'"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            },
            reg.searched
                .iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
            reg.refused_note()
        );
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut md = String::new();
    writeln!(md, "# dashpot: reproduction report\n")?;
    writeln!(
        md,
        "Every number below was computed by the law plugins loaded at run time (`dashpot laws`), \
         by dashpot {} (dashpot-sdk {}).\n",
        env!("CARGO_PKG_VERSION"),
        dashpot_sdk::abi::ABI_VERSION
    )?;

    // ---- laws ----
    eprintln!("reproduce: the laws loaded");
    writeln!(
        md,
        "## Laws loaded\n\n| law | kind | plugin | sdk | file | parameters |\n|---|---|---|---|---|---|"
    )?;
    for l in &reg.laws {
        let p = &reg.plugins[l.plugin];
        let params: Vec<String> = l
            .info
            .params
            .iter()
            .map(|s| format!("{} [{}] in {}", s.name, s.unit, s.range))
            .collect();
        writeln!(
            md,
            "| {} | {} | {} {} | {} | `{}` | {} |",
            l.info.name,
            l.info.kind.as_str(),
            p.name,
            p.version,
            p.sdk_version,
            p.path.display(),
            params.join("; ")
        )?;
    }
    for n in &reg.notes {
        writeln!(md, "\nNote: {n}.")?;
    }
    for s in reg
        .shadowed
        .iter()
        .filter(|s| REQUIRED.contains(&s.name.as_str()))
    {
        eprintln!(
            "warning: law '{}' is taken from {}; it shadows the one in {}",
            s.name,
            s.used.display(),
            s.hidden.display()
        );
    }
    let laws: Vec<_> = reg.laws.iter().map(|l| law_json(reg, &l.info)).collect();
    write_atomic(
        &out.join("laws.json"),
        serde_json::to_string_pretty(&laws)?.as_bytes(),
    )?;

    // ---- Antypov & Elliott: MCC granule ----
    eprintln!("reproduce: Antypov & Elliott, closed forms, Figs. 1-3 and the statements");
    let mcc = Particle::MCC;
    let pair = Pair::spheres(&mcc, &mcc)?;
    writeln!(
        md,
        "\n## Antypov & Elliott (2011): the damped Hertz spring, MCC granule\n\n\
         Two identical spheres, d = {} m, ρ = {} kg/m³, E = {} Pa, ν = {}: m_eff = {:.6e} kg, \
         r_eff = {:.6e} m, E_eff = {:.6e} Pa.\n",
        mcc.diameter, mcc.density, mcc.young, mcc.poisson, pair.mass, pair.radius, pair.young
    )?;
    if reg.find("lsd").is_ok() && reg.find("hsd").is_ok() {
        writeln!(
            md,
            "| ε | LSD k (N/m) | LSD γ (1/s) (eq. 8) | LSD τ (s) | LSD δ_max at v0 = 1 m/s (m) (eq. 21) | τ(ε)/τ(1) (eq. 25) | HSD α(ε) (eq. 17) | HSD K (N/m^1.5) (eq. 9) |\n|---|---|---|---|---|---|---|---|"
        )?;
        let mut csv = String::from("eps,alpha_hsd,gamma_lsd_per_s,tau_lsd_s,tau_ratio_lsd\n");
        let tau1 = {
            let b = reg.contact("lsd", &[ParamValue::new("eps", 1.0)])?;
            let b = PairLaw::bind(&b, &pair, mcc.poisson)?;
            coeff(&b.coefficients()?, "contact_time")
        };
        for eps in [0.01, 0.1, 0.3, 0.54, 0.7, 0.9, 0.99, 1.0] {
            let lsd = PairLaw::bind(
                &reg.contact("lsd", &[ParamValue::new("eps", eps)])?,
                &pair,
                mcc.poisson,
            )?;
            let hsd = PairLaw::bind(
                &reg.contact("hsd", &[ParamValue::new("eps", eps)])?,
                &pair,
                mcc.poisson,
            )?;
            let (lc, hc) = (lsd.coefficients()?, hsd.coefficients()?);
            let (k, g, tau, w0) = (
                coeff(&lc, "k"),
                coeff(&lc, "gamma"),
                coeff(&lc, "contact_time"),
                coeff(&lc, "w0"),
            );
            let w1 = (w0 * w0 - g * g).sqrt();
            let dmax = if g > 0.0 {
                1.0 / w0 * (-(g / w1) * (w1 / g).atan()).exp()
            } else {
                1.0 / w0
            };
            writeln!(
                md,
                "| {eps} | {k:.5e} | {g:.5e} | {tau:.5e} | {dmax:.5e} | {:.6} | {:.6} | {:.5e} |",
                tau / tau1,
                coeff(&hc, "alpha"),
                coeff(&hc, "K")
            )?;
            writeln!(csv, "{eps},{},{g},{tau},{}", coeff(&hc, "alpha"), tau / tau1)?;
        }
        write_atomic(&out.join("antypov_elliott_closed_forms.csv"), csv.as_bytes())?;
        writeln!(md)?;
        md.push_str(&crate::report::collide::collide_figures(reg, out)?);
        md.push_str(&crate::ae_statements::report(reg)?);
    } else {
        writeln!(md, "(the lsd and hsd plugins were not found)\n")?;
    }

    // ---- McNamara & Falcon: r(v) ----
    eprintln!("reproduce: McNamara & Falcon, r(v) (Fig. 1)");
    writeln!(
        md,
        "## McNamara & Falcon (2005): restitution against impact speed (eq. 1, Fig. 1)\n"
    )?;
    if reg.find("mcnamara-falcon").is_ok() {
        let law = reg.restitution("mcnamara-falcon", &[])?.bind(&pair)?;
        writeln!(
            md,
            "r0 = 0.95, v_y = 0.3 m/s (stainless steel).\n\n| v (m/s) | r(v) |\n|---|---|"
        )?;
        for v in [0.0, 0.001, 0.01, 0.1, 0.3, 1.0, 3.0, 10.0] {
            writeln!(md, "| {v} | {:.6} |", law.restitution(v)?)?;
        }
        let n = 241;
        let speeds: Vec<f64> = (0..n)
            .map(|i| 10f64.powf(-3.0 + 4.0 * i as f64 / (n - 1) as f64))
            .collect();
        let mut r = vec![0.0; n];
        law.restitution_batch(&speeds, &mut r)?;
        let mut csv = String::from("speed_m_per_s,restitution\n");
        for (v, r) in speeds.iter().zip(&r) {
            writeln!(csv, "{v:.6e},{r:.9}")?;
        }
        write_atomic(&out.join("mcnamara_falcon_fig1.csv"), csv.as_bytes())?;
        use crate::plot::{Figure, Mark, Panel, Series};
        Figure::single(Panel {
            title: "McNamara & Falcon (2005) Fig. 1: r(v), r0 = 0.95, vy = 0.3 m/s".into(),
            x_label: "impact speed v (m/s)".into(),
            y_label: "coefficient of restitution r".into(),
            log_x: true,
            y_range: Some((0.0, 1.05)),
            series: vec![
                Series::new(
                    "mcnamara-falcon plugin",
                    speeds.iter().copied().zip(r.iter().copied()).collect(),
                    Mark::Line,
                    0,
                ),
                Series::new("v = vy", vec![(0.3, 0.0), (0.3, 1.05)], Mark::Dashed, 7),
                Series::new("r = r0", vec![(1e-3, 0.95), (10.0, 0.95)], Mark::Dashed, 6),
            ],
            ..Default::default()
        })
        .save(out, "mcnamara_falcon_fig1")?;
        writeln!(
            md,
            "\nThe paper states r(1 m/s) ≈ 0.7; the plugin gives {:.4}. The full curve (their Fig. 1) is \
             `mcnamara_falcon_fig1.png` (and `.svg`, `.csv`).",
            law.restitution(1.0)?
        )?;
    } else {
        writeln!(md, "(the mcnamara-falcon plugin was not found)")?;
    }

    // ---- McNamara & Falcon: the vibrated bed (Figs. 2-4) ----
    writeln!(md, "\n## McNamara & Falcon (2005): the vibrated bed\n")?;
    if reg.find("mcnamara-falcon").is_ok() && reg.find("constant").is_ok() {
        let bed_dir = out.join("bed");
        let size = if quick {
            crate::report::bed::Size::tiny()
        } else {
            crate::report::bed::Size::reproduce()
        };
        eprintln!(
            "reproduce: the vibrated bed, Figs. 2-4 and the other statements (size {})",
            size.name
        );
        let bed_md = crate::report::bed::run(reg, &bed_dir, &size)?;
        write_atomic(&bed_dir.join("report.md"), bed_md.as_bytes())?;
        // the bed report's sections, one level down
        for line in bed_md.lines().skip(1) {
            if line.starts_with('#') {
                writeln!(md, "#{line}")?;
            } else {
                writeln!(md, "{line}")?;
            }
        }
        writeln!(
            md,
            "\nFigures and CSV files in `bed/`. This is a reduced grid (a few minutes on two \
             cores); `dashpot figures bed --out DIR` runs the paper's."
        )?;
    } else {
        writeln!(md, "(the mcnamara-falcon and constant plugins are needed)")?;
    }
    write_atomic(&out.join("report.md"), md.as_bytes())?;
    println!("{md}");
    println!("wrote {}/report.md, laws.json and CSV tables", out.display());
    Ok(())
}
