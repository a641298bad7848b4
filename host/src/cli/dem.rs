//! `dashpot dem --scene FILE.toml [--json] [--out DIR]`: a soft-sphere DEM run of a scene.

use crate::dem::scene::SceneFile;
use crate::dem::{Engine, Laws};
use crate::registry::Registry;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// `dashpot dem`.
#[derive(Args, Debug)]
pub struct DemArgs {
    /// The scene (TOML; see `examples/dem/` and the `dem::scene` docs).
    #[arg(long)]
    pub scene: PathBuf,
    /// Print the final state as JSON (particles, dt, steps, time, energy, contacts, ...).
    #[arg(long)]
    pub json: bool,
    /// Write the trajectory (extended XYZ, for OVITO/ParaView/ASE) and the final state here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `dashpot dem`.
pub fn run(reg: &Registry, a: &DemArgs) -> Result<()> {
    let text = std::fs::read_to_string(&a.scene)
        .with_context(|| format!("reading --scene {}", a.scene.display()))?;
    let file = SceneFile::parse(&text).with_context(|| format!("in {}", a.scene.display()))?;
    match file.dimension()? {
        2 => run_dim::<2>(reg, a, &file),
        _ => run_dim::<3>(reg, a, &file),
    }
}

fn run_dim<const D: usize>(reg: &Registry, a: &DemArgs, file: &SceneFile) -> Result<()> {
    let scene = file
        .scene::<D>()
        .with_context(|| format!("in {}", a.scene.display()))?;
    let normal = file.law.param_values();
    let tang = file
        .tangential
        .as_ref()
        .map(|t| (t.name.as_str(), t.param_values()));
    let laws = Laws::from_registry(
        reg,
        (&file.law.name, &normal),
        tang.as_ref().map(|(n, p)| (*n, p.as_slice())),
        &scene.config.material,
    )
    .context("[law] / [tangential]")?;
    let mut e = Engine::new(scene.config.clone(), &scene.bodies, scene.walls.clone(), laws)?;
    let c = e.step_choice;
    let line = if c.given {
        format!(
            "dt = {:.4e} s (given; the contact time at {:.3} m/s is {:.4e} s: {:.1} steps per collision)",
            c.dt,
            c.impact_speed,
            c.collision_time,
            c.collision_time / c.dt
        )
    } else {
        format!(
            "dt = {:.4e} s = contact time {:.4e} s / {} (law '{}', smallest particle, impact speed {:.3} m/s)",
            c.dt, c.collision_time, scene.config.steps_per_collision, file.law.name, c.impact_speed
        )
    };
    eprintln!("{line}");
    let total_steps = (scene.duration / c.dt).ceil() as u64;
    let mut traj = None;
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating --out {}", dir.display()))?;
        let p = dir.join("trajectory.xyz");
        let f = std::fs::File::create(&p).with_context(|| format!("creating {}", p.display()))?;
        let mut w = std::io::BufWriter::new(f);
        crate::dem::xyz::write_frame(&e, &mut w)?;
        traj = Some(w);
    }
    let frames = if a.out.is_some() {
        scene.snapshots.max(1)
    } else {
        0
    } as u64;
    let pb = progress(total_steps);
    let wall0 = std::time::Instant::now();
    let every = (total_steps / 200).max(1);
    let mut next_frame = 1u64;
    while e.time() + 0.5 * e.dt() < scene.duration {
        e.step()
            .with_context(|| format!("at t = {:.6e} s, step {}", e.time(), e.steps()))?;
        if e.steps() % every == 0 {
            pb.set_position(e.steps());
        }
        if let Some(w) = traj.as_mut() {
            if frames > 0 && e.steps() * frames >= next_frame * total_steps {
                crate::dem::xyz::write_frame(&e, w)?;
                next_frame += 1;
            }
        }
    }
    pb.finish_and_clear();
    let wall = wall0.elapsed().as_secs_f64();
    if let Some(mut w) = traj {
        w.flush()?;
    }
    let mut state = e.state_json();
    state["law"] = serde_json::json!(file.law.name);
    state["tangential"] = serde_json::json!(file.tangential.as_ref().map(|t| t.name.clone()));
    state["wall_seconds"] = serde_json::json!(wall);
    state["particle_steps_per_second"] =
        serde_json::json!(e.p.len() as f64 * e.steps() as f64 / wall.max(1e-9));
    if let Some(dir) = &a.out {
        crate::output::write_atomic(
            &dir.join("final.json"),
            serde_json::to_string_pretty(&state)?.as_bytes(),
        )?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&state)?);
    } else {
        let en = e.energy();
        println!(
            "{} {}D particles, law {}{}",
            e.p.len(),
            D,
            file.law.name,
            file.tangential
                .as_ref()
                .map(|t| format!(" + {}", t.name))
                .unwrap_or_default()
        );
        println!(
            "t = {:.6e} s after {} steps of {:.4e} s ({wall:.2} s wall, {:.3e} particle-steps/s)",
            e.time(),
            e.steps(),
            e.dt(),
            e.p.len() as f64 * e.steps() as f64 / wall.max(1e-9)
        );
        println!(
            "energy: {:.6e} J (translational {:.6e}, rotational {:.6e}, gravity {:.6e})",
            en.total(),
            en.translational,
            en.rotational,
            en.gravity
        );
        println!(
            "contacts now: {} ({} pairs, {} with walls); neighbour rebuilds: {}",
            e.contacts(),
            e.pairs.len(),
            e.wall_contacts.len(),
            e.rebuilds()
        );
        if let Some(dir) = &a.out {
            println!(
                "wrote {} and {}",
                dir.join("trajectory.xyz").display(),
                dir.join("final.json").display()
            );
        }
    }
    Ok(())
}

fn progress(len: u64) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let pb = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(s) =
        ProgressStyle::with_template("dem [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})")
    {
        pb.set_style(s);
    }
    pb
}
