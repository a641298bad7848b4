//! `dashpot sweep`: collisions over a grid of impact speeds and law parameters, each parameter
//! set's speeds run as restitution curves.

use super::args::LawArgs;
use super::collide::{check_v0, IntegrationArgs};
use super::grid::parse_grid;
use crate::collide::lanes::{collide_many, MAX_LANES};
use crate::collide::two_body::{Collision, Options, PairLaw};
use crate::output::write_atomic;
use crate::registry::Registry;
use anyhow::{Context, Result};
use clap::Args;
use dashpot_sdk::{EndCriterion, MaterialPair, Pair, ParamValue};
use rayon::prelude::*;
use std::path::PathBuf;

/// `dashpot sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// Impact speeds (m/s): START:STOP:COUNT[:log|lin] or a list, e.g. 1e-3:10:41.
    #[arg(long, default_value = "1e-3:10:41")]
    pub v0: String,
    /// Also vary a law parameter: NAME=GRID (repeatable; the sweep is the full product).
    #[arg(long, value_name = "NAME=GRID")]
    pub vary: Vec<String>,
    #[command(flatten)]
    pub integration: IntegrationArgs,
    /// Output CSV file.
    #[arg(long, default_value = "sweep.csv")]
    pub out: PathBuf,
}

/// One row of a sweep.
#[derive(Debug, Clone)]
pub struct SweepRow {
    /// The parameters of this collision.
    pub params: Vec<ParamValue>,
    /// The collision.
    pub collision: Collision,
}

/// What a sweep runs: one law on one pair, over impact speeds and parameter grids.
#[derive(Debug, Clone)]
pub struct SweepSpec<'a> {
    /// The contact law.
    pub law: &'a str,
    /// Its fixed parameters.
    pub base: &'a [ParamValue],
    /// The pair.
    pub pair: &'a Pair,
    /// Its effective moduli.
    pub materials: &'a MaterialPair,
    /// Impact speeds (m/s).
    pub v0s: &'a [f64],
    /// Parameters varied over grids (the sweep is the full product).
    pub varied: &'a [(String, Vec<f64>)],
    /// End of contact.
    pub end: EndCriterion,
    /// Integrator settings.
    pub options: Options,
}

/// The rows of a sweep over `v0s` impact speeds and the `varied` grids (their product), refused
/// before anything is allocated if they would not fit in the memory available: each row keeps
/// its parameters and its collision until the CSV is written, and its CSV line.
pub fn check_size(
    v0s: usize,
    varied: &[(String, Vec<f64>)],
    base: usize,
) -> Result<usize, crate::budget::Refused> {
    let combos: f64 = varied.iter().map(|(_, g)| g.len() as f64).product();
    let rows = combos * v0s as f64;
    let params = (base + varied.len()) as f64;
    let per_row = (std::mem::size_of::<SweepRow>() + 2 * std::mem::size_of::<Option<SweepRow>>()) as f64
        + params * (std::mem::size_of::<ParamValue>() as f64 + 24.0)
        + 200.0;
    let mut need = crate::budget::Need::new();
    need.holding(crate::budget::rss().now as f64);
    need.add("the rows", rows * per_row);
    let grids: Vec<String> = std::iter::once(format!("{v0s} impact speeds"))
        .chain(varied.iter().map(|(n, g)| format!("{} values of {n}", g.len())))
        .collect();
    crate::budget::check_memory(
        &format!("the sweep of {rows:.0} collisions ({})", grids.join(" x ")),
        &need,
        "fewer grid points (--v0 COUNT, --vary grids), or several sweeps",
    )?;
    Ok(rows as usize)
}

/// Runs collisions over the product of `v0s` and `varied` grids in parallel, with a progress bar
/// on stderr when it is a terminal.
pub fn sweep(reg: &Registry, spec: &SweepSpec<'_>) -> Result<Vec<SweepRow>> {
    let (name, base, pair, v0s, varied, end, opt) = (
        spec.law,
        spec.base,
        spec.pair,
        spec.v0s,
        spec.varied,
        spec.end,
        &spec.options,
    );
    check_size(v0s.len(), varied, base.len())?;
    let mut combos: Vec<Vec<ParamValue>> = vec![base.to_vec()];
    for (n, g) in varied {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                g.iter().map(move |&v| {
                    let mut c = c.clone();
                    match c.iter_mut().find(|p| p.name == n.as_str()) {
                        Some(p) => p.value = v,
                        None => c.push(ParamValue::new(n, v)),
                    }
                    c
                })
            })
            .collect();
    }
    // validate every parameter set once, before the long run
    for c in &combos {
        reg.contact(name, c)?.bind(spec.materials)?;
    }
    // tasks: each parameter set's speeds in runs of up to MAX_LANES, run as a restitution curve
    // (its collisions in lockstep, each the bits of `collide` alone), the runs in parallel
    let tasks: Vec<(usize, &[f64])> = (0..combos.len())
        .flat_map(|i| v0s.chunks(MAX_LANES).map(move |c| (i, c)))
        .collect();
    let pb = crate::progress::Progress::new((combos.len() * v0s.len()) as u64, "sweep", "collisions", false);
    let runs: Vec<Vec<SweepRow>> = tasks
        .par_iter()
        .map(|&(i, speeds)| -> Result<Vec<SweepRow>> {
            let law = PairLaw::new(
                reg.contact(name, &combos[i])?.bind(spec.materials)?,
                pair.mass,
                pair.radius,
            );
            let curve = collide_many(&law, pair.mass, speeds, end, opt);
            pb.inc(speeds.len() as u64);
            curve
                .into_iter()
                .zip(speeds)
                .map(|(c, &v0)| {
                    let c = c.with_context(|| format!("collision at v0 = {v0} m/s with {:?}", combos[i]))?;
                    Ok(SweepRow {
                        params: combos[i].clone(),
                        collision: c,
                    })
                })
                .collect()
        })
        .collect::<Result<_>>()?;
    let rows: Vec<SweepRow> = runs.into_iter().flatten().collect();
    pb.finish();
    Ok(rows)
}

/// `dashpot sweep`.
pub fn run_sweep(reg: &Registry, a: &SweepArgs) -> Result<()> {
    let sel = a.law.resolve()?;
    let v0s = parse_grid(&a.v0)?;
    for &v in &v0s {
        check_v0(v)?;
    }
    let mut varied = Vec::new();
    for spec in &a.vary {
        let (n, g) = spec
            .split_once('=')
            .with_context(|| format!("--vary expects NAME=GRID, got '{spec}'"))?;
        varied.push((n.trim().to_string(), parse_grid(g)?));
    }
    let opt = a.integration.options()?;
    let end = a.integration.end_for(reg, &sel.name)?;
    let prov = sel.provenance(reg)?;
    let rows = sweep(
        reg,
        &SweepSpec {
            law: &sel.name,
            base: &sel.params,
            pair: &sel.pair,
            materials: &sel.materials,
            v0s: &v0s,
            varied: &varied,
            end,
            options: opt,
        },
    )?;
    let names: Vec<String> = rows
        .first()
        .map(|r| r.params.iter().map(|p| p.name.to_string()).collect())
        .unwrap_or_default();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["law".to_string()];
    header.extend(names.iter().cloned());
    header.extend(
        [
            "v0_m_per_s",
            "end",
            "restitution",
            "contact_time_s",
            "max_overlap_m",
            "max_overlap_time_s",
        ]
        .map(String::from),
    );
    w.write_record(&header)?;
    for r in &rows {
        let c = &r.collision;
        let mut rec = vec![sel.name.clone()];
        rec.extend(r.params.iter().map(|p| p.value.to_string()));
        rec.extend([
            c.v0.to_string(),
            c.end.as_str().to_string(),
            c.restitution.to_string(),
            c.contact_time.to_string(),
            c.max_overlap.to_string(),
            c.max_overlap_time.to_string(),
        ]);
        w.write_record(&rec)?;
    }
    let csv = [prov.csv_comment().into_bytes(), w.into_inner().context("csv")?].concat();
    write_atomic(&a.out, &csv)?;
    println!("wrote {} collisions to {}", rows.len(), a.out.display());
    Ok(())
}
