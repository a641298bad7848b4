//! `dashpot scaling` and `dashpot figures bed`.

use super::*;
use crate::bed::spec::{BedEngine, BedSpec};
use crate::bed::{scaling, Laws};
use crate::output::progress_bar;
use crate::output::write_atomic;
use crate::plot::Figure;
use crate::registry::Registry;
use anyhow::{bail, Context, Result};

/// `dashpot scaling`.
pub fn scaling(reg: &Registry, a: &ScalingArgs) -> Result<()> {
    let freqs = parse_range(&a.freqs)?;
    if a.layers.is_empty() {
        bail!("--layers: give at least one number of layers");
    }
    let spec = a.phys.spec(a.layers[0], freqs[0], 1)?;
    // every n and every f of the grid checked (at the first f and the first n)
    let points = a
        .layers
        .iter()
        .map(|&n| (n, freqs[0]))
        .chain(freqs.iter().map(|&f| (a.layers[0], f)));
    for (n, f) in points {
        BedSpec {
            config: spec.at(n, f),
            ..spec.clone()
        }
        .validate()?;
    }
    crate::budget::check_max_hours(a.limits.max_hours)?;
    let grid = scaling::Grid {
        layers: a.layers.clone(),
        freqs,
        transient: spec.transient,
        cycles: spec.cycles,
    };
    // the grid's slowest run (most layers, lowest frequency: the most disks over the longest
    // protocol), timed for a moment, bounds every run; they run in waves of the thread pool
    let (most, lowest) = (
        grid.layers.iter().copied().fold(f64::MIN, f64::max),
        grid.freqs.iter().copied().fold(f64::MAX, f64::min),
    );
    let slowest = BedSpec {
        config: spec.at(most, lowest),
        ..spec.clone()
    };
    let est = super::check::estimate(reg, &slowest)?;
    let waves = grid.len().div_ceil(rayon::current_num_threads().max(1)) as f64;
    crate::budget::check_hours(
        "the scaling grid",
        waves * est.total_seconds(),
        "estimated from a timed sample of its slowest run",
        a.limits.max_hours,
    )?;
    let prov = scaling_provenance(reg, &spec)?;
    let pb = progress_bar(grid.len() as u64, "scaling (runs)");
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
    let grid_csv = a.out.join("grid.csv");
    let (rows, law) = match &spec.engine {
        BedEngine::Event { restitution } => {
            let laws = spec.restitution_laws(reg)?;
            let laws = Laws {
                disk: &laws.disk,
                wall: &laws.wall,
            };
            let runs = scaling::run_grid(&laws, &|n, f| spec.at(n, f), &grid, &|| pb.inc(1))?;
            scaling::write_grid_csv(&grid_csv, &runs, &prov)?;
            (scaling::fit_all(&grid, &runs), restitution.name.clone())
        }
        BedEngine::Dem { law, tangential, .. } => {
            let mat = spec.dem_bed(spec.config).material;
            let laws = (0..grid.len())
                .map(|_| spec.dem_laws(reg, &mat))
                .collect::<Result<Vec<_>>>()?;
            let runs =
                scaling::run_dem_grid(laws, &|n, f| spec.dem_bed(spec.at(n, f)), &grid, &|| pb.inc(1))?;
            scaling::write_grid_csv(&grid_csv, &runs, &prov)?;
            let law = format!(
                "DEM {}{}, E = {:.3e} Pa",
                law.name,
                tangential
                    .as_ref()
                    .map(|t| format!(" + {} {}", t.name, a.phys.tset.join(" ")))
                    .unwrap_or_default(),
                mat.young
            );
            (scaling::fit_all(&grid, &runs), law)
        }
    };
    pb.finish_and_clear();
    scaling::write_fit_csv(&a.out.join("scaling.csv"), &rows, &prov)?;
    let title = format!(
        "θ(n): {} {}, g = {} m/s²",
        law,
        a.phys.set.join(" "),
        a.phys.gravity
    );
    Figure::single(scaling::theta_panel(&rows, &title)).save(&a.out, "theta")?;
    if a.json {
        let mut v = scaling::provenance_json(&prov);
        v.insert("exponents".into(), serde_json::to_value(&rows)?);
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!(
            "scaling exponents θ of X ∝ V^θ, least squares of ln X on ln V over {} frequencies (max |residual| in ln units)",
            grid.freqs.len()
        );
        println!(
            "{:>6} {:>16} {:>16} {:>16} {:>16}",
            "n", "θ_P", "θ_T", "θ_Nc", "θ_ΔI"
        );
        for r in &rows {
            let c = |f: &Option<crate::bed::observables::PowerFit>| match f {
                Some(f) => format!("{:7.3} ({:.3})", f.theta, f.max_residual),
                None => "-".to_string(),
            };
            let fits = r.fits().map(|f| format!("{:>16}", c(f))).join(" ");
            println!("{:>6} {fits}", r.layers);
        }
        prov.iter().flat_map(|p| p.lines()).for_each(|l| println!("{l}"));
        println!(
            "wrote {}, {} and theta.png/.svg",
            a.out.join("scaling.csv").display(),
            a.out.join("grid.csv").display()
        );
    }
    Ok(())
}

/// The provenance of `dashpot scaling`'s laws: the restitution law (a contact law's own for
/// `from:NAME`), or on the DEM engine the contact law and the tangential law.
fn scaling_provenance(reg: &Registry, spec: &BedSpec) -> Result<Vec<crate::output::Provenance>> {
    let prov = match &spec.engine {
        BedEngine::Event { restitution: r } => {
            let name = r.name.strip_prefix(crate::bed::FROM_CONTACT).unwrap_or(&r.name);
            scaling::provenance(reg, name, &r.params, None)?
        }
        BedEngine::Dem { law, tangential, .. } => {
            let tangential = tangential.as_ref().map(|t| (t.name.as_str(), &t.params[..]));
            scaling::provenance(reg, &law.name, &law.params, tangential)?
        }
    };
    prov.iter().for_each(|p| p.warn_if_shadowed());
    Ok(prov)
}

/// `dashpot figures ...`.
pub fn figures(reg: &Registry, cmd: &FiguresCommand) -> Result<()> {
    match cmd {
        FiguresCommand::Bed {
            out,
            quick,
            only,
            engine,
            young,
        } => {
            let size = if *quick {
                crate::report::bed::Size::quick()
            } else {
                crate::report::bed::Size::paper()
            };
            let md = match engine {
                EngineKind::Event => crate::report::bed::run_only(reg, out, &size, only)?,
                EngineKind::Dem => {
                    if !(young.is_finite() && *young > 0.0) {
                        bail!("--young = {young} Pa is out of range: Young's modulus must be finite and > 0");
                    }
                    crate::report::bed::run_dem(reg, out, &size, *young, only)?
                }
            };
            write_atomic(&out.join("report.md"), md.as_bytes())?;
            println!("wrote {}", out.join("report.md").display());
            Ok(())
        }
    }
}
