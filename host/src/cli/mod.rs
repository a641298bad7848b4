//! The `dashpot` command line.

pub mod args;
pub mod bed;
pub mod budget;
pub mod calibrate_data;
pub mod collide;
pub mod collide_heat;
pub mod dem;
pub mod dem_checkpoint;
pub mod grid;
pub mod roll;
pub mod sweep;

pub use args::{LawArgs, ParticleArgs, Selection, UsageError};

use crate::registry::{Registry, SearchPath};
use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand};
use dashpot_sdk::{Contact, LawKind};
use serde_json::json;
use std::path::PathBuf;

/// dashpot: contact and restitution laws for granular collisions, loaded as plugins at run time.
#[derive(Parser, Debug)]
#[command(name = "dashpot", version, about, long_about = None)]
pub struct Cli {
    #[command(flatten)]
    pub plugins: PluginArgs,
    #[command(subcommand)]
    pub command: Command,
}

/// Where to find plugins. The built-in laws (the plugins beside the dashpot executable) are
/// always loaded unless `--no-default-plugins` is given; plugins named here come first, so a law
/// name they share with a built-in one shadows it (with a warning when it is used).
#[derive(Args, Debug, Clone, Default)]
pub struct PluginArgs {
    /// Directory to search for plugin libraries (repeatable; searched after --plugin files,
    /// before DASHPOT_PLUGIN_PATH and the built-in plugins, which stay loaded).
    #[arg(long = "plugin-dir", global = true, value_name = "DIR")]
    pub plugin_dirs: Vec<PathBuf>,
    /// A plugin library to load by path (repeatable; loaded first, before any directory is
    /// searched; the built-in laws stay loaded). A relative path is relative to the current
    /// directory.
    #[arg(long = "plugin", global = true, value_name = "FILE")]
    pub plugin_files: Vec<PathBuf>,
    /// Do not load the built-in plugins (those beside the dashpot executable): only --plugin,
    /// --plugin-dir and DASHPOT_PLUGIN_PATH.
    #[arg(long = "no-default-plugins", global = true)]
    pub no_default_plugins: bool,
}

impl PluginArgs {
    /// Loads the registry.
    pub fn registry(&self) -> Result<Registry> {
        let mut sp = SearchPath::standard(self.plugin_dirs.clone(), self.plugin_files.clone());
        sp.use_default = !self.no_default_plugins;
        Ok(Registry::discover(&sp)?)
    }
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// List every law found: name, kind, plugin file, version and parameter schema.
    Laws {
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Show one law's documentation and parameters.
    Law {
        /// The law's name.
        name: String,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate a law once: a contact law's force F(δ, δ̇) or a restitution law's r(v).
    Eval(EvalArgs),
    /// Integrate one head-on collision under a contact law: restitution, contact time, maximum overlap.
    Collide(crate::cli::collide::CollideArgs),
    /// Collisions over a grid of impact speeds and law parameters, in parallel, to CSV.
    Sweep(crate::cli::sweep::SweepArgs),
    /// The law parameters that reproduce a measured restitution (and contact time).
    Calibrate(crate::cli::collide::CalibrateArgs),
    /// Reproduce a paper's figures (PNG, SVG, CSV and a markdown report) into a folder.
    #[command(subcommand)]
    Figures(FigureSet),
    /// The main job: reproduce what the drivers can so far from the two papers, into a folder.
    Reproduce {
        /// Output folder (created if needed).
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Tiny driver runs (seconds, for tests): the numbers are noisy, the pipeline complete.
        #[arg(long)]
        quick: bool,
    },
    /// The vibrated bed of McNamara & Falcon (2005): one event-driven run, lid pressure and more.
    Bed(crate::cli::bed::BedArgs),
    /// Scaling exponents θ of the vibrated bed over a grid of layers and frequencies.
    Scaling(crate::cli::bed::ScalingArgs),
    /// Soft-sphere DEM: a scene of disks or spheres, every contact through the contact laws.
    Dem(crate::cli::dem::DemArgs),
}

/// Which figures.
#[derive(Subcommand, Debug)]
pub enum FigureSet {
    /// Antypov & Elliott Figs. 1–3 and the Kuwabara–Kono ε(v0) under both end criteria.
    Collide {
        /// Output folder (created if needed).
        #[arg(long, default_value = "results/collide")]
        out: PathBuf,
    },
    #[command(flatten)]
    Bed(crate::cli::bed::FiguresCommand),
}

/// `dashpot eval`.
#[derive(Args, Debug)]
pub struct EvalArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// Overlap δ (m), for a contact law.
    #[arg(long, allow_hyphen_values = true)]
    pub delta: Option<f64>,
    /// Overlap rate δ̇ (m/s, > 0 approaching), for a contact law.
    #[arg(long, allow_hyphen_values = true)]
    pub rate: Option<f64>,
    /// Normal impact speed v (m/s), for a restitution law.
    #[arg(long, allow_hyphen_values = true)]
    pub speed: Option<f64>,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the CLI; returns the process exit code.
pub fn run() -> std::process::ExitCode {
    use std::io::Write as _;
    use std::process::ExitCode;
    let cli = Cli::parse();
    // a failed print (a full disk, a closed pipe) is an error, not a crash
    match crate::output::catch_print_failures(|| dispatch(cli)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            let _ = writeln!(std::io::stderr(), "error: {e:#}");
            let usage = e.chain().any(|c| c.is::<UsageError>());
            // (130: stopped by Ctrl-C, as a shell reports SIGINT; a DEM run writes a checkpoint)
            let stopped = e
                .chain()
                .any(|c| c.is::<crate::progress::Interrupted>() || c.is::<dem_checkpoint::Interrupted>());
            ExitCode::from(if usage {
                2
            } else if stopped {
                130
            } else {
                1
            })
        }
        // the reader has gone (`dashpot laws | head -1`): the shell's code for SIGPIPE, quietly
        Err(f) if f.broken_pipe => ExitCode::from(141),
        Err(f) => {
            let _ = writeln!(std::io::stderr(), "error: {}", f.message);
            ExitCode::from(1)
        }
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    let reg = cli.plugins.registry()?;
    match cli.command {
        Command::Laws { json } => laws(&reg, json),
        Command::Law { name, json } => law(&reg, &name, json),
        Command::Eval(a) => eval(&reg, &a),
        Command::Collide(a) => crate::cli::collide::run_collide(&reg, &a),
        Command::Sweep(a) => crate::cli::sweep::run_sweep(&reg, &a),
        Command::Calibrate(a) => crate::cli::collide::run_calibrate(&reg, &a),
        Command::Figures(FigureSet::Collide { out }) => {
            let md = crate::report::collide::collide_figures(&reg, &out)?;
            crate::output::write_atomic(&out.join("collide.md"), md.as_bytes())?;
            println!("{md}\nwrote figures and {}", out.join("collide.md").display());
            Ok(())
        }
        Command::Figures(FigureSet::Bed(c)) => crate::cli::bed::figures(&reg, &c),
        Command::Reproduce { out, quick } => crate::reproduce::run(&reg, &out, quick),
        Command::Bed(a) => crate::cli::bed::bed(&reg, &a),
        Command::Scaling(a) => crate::cli::bed::scaling(&reg, &a),
        Command::Dem(a) => crate::cli::dem::run(&reg, &a),
    }
}

/// The JSON description of a law, as `dashpot laws --json` prints it.
pub use crate::output::law_json;

fn laws(reg: &Registry, json_out: bool) -> Result<()> {
    if json_out {
        let v: Vec<_> = reg.laws.iter().map(|l| law_json(reg, &l.info)).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({ "laws": v, "notes": reg.notes }))?
        );
        return Ok(());
    }
    for e in &reg.refused {
        eprintln!("warning: {e}");
    }
    if reg.laws.is_empty() {
        bail!(
            "no plugins found; searched: {}. Build them with `cargo build --release` or pass --plugin-dir.",
            reg.searched
                .iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    for l in &reg.laws {
        let p = &reg.plugins[l.plugin];
        println!("{}  [{}]  {}", l.info.name, l.info.kind.as_str(), l.info.summary);
        println!(
            "    plugin: {} ({} {})",
            p.path
                .file_name()
                .map(|f| f.to_string_lossy().to_string())
                .unwrap_or_default(),
            p.name,
            p.version
        );
        for s in l.info.params.iter() {
            let def = default_text(s);
            println!(
                "    {:<6} [{}] {}, range {}: {}",
                s.name, s.unit, def, s.range, s.doc
            );
        }
    }
    for n in &reg.notes {
        println!("note: {n}");
    }
    Ok(())
}

fn law(reg: &Registry, name: &str, json_out: bool) -> Result<()> {
    let (e, p) = reg.find(name)?;
    if json_out {
        println!("{}", serde_json::to_string_pretty(&law_json(reg, &e.info))?);
        return Ok(());
    }
    let i = &e.info;
    println!("{} ({} law)", i.name, i.kind.as_str());
    println!(
        "plugin: {} ({} {}, sdk {})",
        p.path.display(),
        p.name,
        p.version,
        p.sdk_version
    );
    if let Some(c) = i.end_criterion {
        println!("calibrated for contact ending by: {}", c.as_str());
    }
    println!("\n{}\n", i.summary);
    println!("{}\n", textwrap(i.doc.as_str(), 96));
    println!("parameters:");
    for s in i.params.iter() {
        let def = default_text(s);
        println!(
            "  {} [{}]  {}; valid {}\n      {}",
            s.name, s.unit, def, s.range, s.doc
        );
    }
    Ok(())
}

/// A parameter's default as `dashpot laws` and `dashpot law` print it.
fn default_text(s: &dashpot_sdk::ParamSpec) -> String {
    match s.default {
        Some(v) => format!("default {v}"),
        None => "derived if unset".to_string(),
    }
}

fn textwrap(s: &str, width: usize) -> String {
    let mut out = String::new();
    let mut line = 0;
    for w in s.split_whitespace() {
        if line > 0 && line + 1 + w.chars().count() > width {
            out.push('\n');
            line = 0;
        } else if line > 0 {
            out.push(' ');
            line += 1;
        }
        out.push_str(w);
        line += w.chars().count();
    }
    out
}

pub fn finite(name: &str, unit: &str, v: f64) -> Result<f64> {
    if !v.is_finite() {
        bail!("--{name} = {v} {unit} is not a finite number");
    }
    Ok(v)
}

fn eval(reg: &Registry, a: &EvalArgs) -> Result<()> {
    let sel = a.law.resolve()?;
    let (name, params, pair, partner) = (&sel.name, &sel.params, sel.pair, &sel.partner);
    let (entry, _) = reg.find(name)?;
    let prov = sel.provenance(reg)?;
    let (params_json, pair_json) = (prov.params_json(), sel.pair_json());
    match entry.info.kind {
        LawKind::Contact => {
            if a.speed.is_some() {
                bail!("'{name}' is a contact law: give --delta and --rate, not --speed");
            }
            let (Some(delta), Some(rate)) = (a.delta, a.rate) else {
                bail!("'{name}' is a contact law: give both --delta (overlap, m) and --rate (overlap rate, m/s)");
            };
            let delta = finite("delta", "m", delta)?;
            let rate = finite("rate", "m/s", rate)?;
            let law = reg.contact(name, params)?;
            let bound = law.bind(&sel.materials)?;
            let mut history = vec![0.0; bound.history_slots()];
            let contact = Contact {
                delta,
                rate,
                mass: pair.mass,
                radius: pair.radius,
            };
            let coeffs = bound.coefficients(pair.mass, pair.radius)?;
            let finite_for = |p: &[dashpot_sdk::ParamValue]| {
                reg.contact(name, p)
                    .and_then(|l| l.bind(&sel.materials))
                    .and_then(|b| b.coefficients(pair.mass, pair.radius))
                    .is_ok_and(|c| c.iter().all(|c| c.value.is_finite()))
            };
            crate::checks::finite_coefficients(
                name,
                params,
                &entry.info.params,
                pair.mass,
                pair.radius,
                &coeffs,
                Some(&finite_for),
            )?;
            let force = bound.force(contact, &mut history)?;
            if a.json {
                let c: serde_json::Map<String, serde_json::Value> = coeffs
                    .iter()
                    .map(|c| (c.name.to_string(), json!(c.value)))
                    .collect();
                println!(
                    "{}",
                    serde_json::to_string_pretty(&json!({
                        "law": name, "kind": "contact", "plugin": prov.plugin_file,
                        "params": params_json, "pair": pair_json, "coefficients": c,
                        "delta": delta, "rate": rate, "force": force, "provenance": prov.json(),
                    }))?
                );
            } else {
                for l in prov.lines() {
                    println!("{l}");
                }
                println!(
                    "pair: {partner}: m_eff = {:.6e} kg, r_eff = {:.6e} m, E_eff = {:.6e} Pa",
                    pair.mass, pair.radius, pair.young
                );
                for c in &coeffs {
                    println!(
                        "  {:<13} = {:<14.8e} [{}]  {}",
                        c.name.as_str(),
                        c.value,
                        c.unit,
                        c.doc
                    );
                }
                println!("F(delta = {delta:e} m, rate = {rate:e} m/s) = {force:.10e} N");
            }
        }
        LawKind::Tangential => {
            bail!(
                "'{name}' is a tangential law: it acts together with a contact law, in \
                 `dashpot collide --law NORMAL --tangential {name} --angle DEG`"
            );
        }
        LawKind::Rolling | LawKind::Twisting => {
            bail!(
                "'{name}' is a {} law: it acts together with a contact law on a contact's \
                 rotation; `dashpot eval` evaluates contact and restitution laws only",
                entry.info.kind.as_str()
            );
        }
        LawKind::Heat => {
            bail!(
                "'{name}' is a heat law: it conducts heat through a contact whose radius a contact law \
                 reports; `dashpot eval` evaluates contact and restitution laws only (`dashpot law {name}` \
                 describes it)"
            );
        }
        LawKind::Restitution => {
            if a.delta.is_some() || a.rate.is_some() {
                bail!("'{name}' is a restitution law: give --speed, not --delta/--rate");
            }
            let speed = a.speed.with_context(|| {
                format!("'{name}' is a restitution law: give --speed (impact speed, m/s)")
            })?;
            let speed = finite("speed", "m/s", speed)?;
            if speed < 0.0 {
                bail!("--speed = {speed} m/s is out of range: an impact speed must be >= 0");
            }
            let law = reg.restitution(name, params)?;
            let r = law.bind(&pair)?.restitution(speed)?;
            if a.json {
                println!(
                    "{}",
                    serde_json::to_string_pretty(&json!({
                        "law": name, "kind": "restitution", "plugin": prov.plugin_file,
                        "params": params_json, "pair": pair_json, "speed": speed, "restitution": r,
                        "provenance": prov.json(),
                    }))?
                );
            } else {
                for l in prov.lines() {
                    println!("{l}");
                }
                println!("r(v = {speed} m/s) = {r:.10}");
            }
        }
    }
    Ok(())
}
