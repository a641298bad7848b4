//! `dashpot dem --scene FILE.toml [--json] [--out DIR]`: a soft-sphere DEM run of a scene;
//! `--checkpoint-every` and `--restart FILE` (see [`super::dem_checkpoint`]).

use super::dem_checkpoint::{
    default_path, parse_scene, trajectory_frames, Checkpoints, Every, Interrupted, Resume,
};
use crate::dem::checkpoint::Checkpoint;
use crate::dem::scene::SceneFile;
use crate::dem::Engine;
use crate::registry::Registry;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

/// `dashpot dem`.
#[derive(Args, Debug)]
pub struct DemArgs {
    /// The scene (TOML; see `examples/dem/` and the `dem::scene` docs).
    #[arg(long, required_unless_present_any = ["bed", "restart"], conflicts_with = "bed")]
    pub scene: Option<PathBuf>,
    /// McNamara & Falcon's vibrated bed on the DEM engine instead of a scene.
    #[command(flatten)]
    pub bed: DemBedArgs,
    /// Print the final state as JSON (particles, dt, steps, time, energy, contacts, ...).
    #[arg(long)]
    pub json: bool,
    /// Write the trajectory (extended XYZ, for OVITO/ParaView/ASE) and the final state here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw each trajectory frame as a picture, frame_NNNN.png (and .svg), into --out:
    /// the particles to scale and the walls (2D: the x–y plane; 3D: the side view x–z, y
    /// into the page).
    #[arg(long, requires = "out")]
    pub png: bool,
    /// Check the scene and stop before the first step: every check of the file and of the start
    /// state (overlaps, the box, the packing, the laws, the step), then the step chosen, the
    /// contact time, the particle count and size range. Exits non-zero if a check fails.
    #[arg(long, requires = "scene")]
    pub check: bool,
    /// The limits of a long run (`--max-hours`).
    #[command(flatten)]
    pub limits: crate::cli::budget::LimitArgs,
    /// Write a checkpoint (the whole state, to resume with --restart) every STEPS steps (e.g.
    /// 5000) or every so much wall-clock time (90s, 10min, 2h). Ctrl-C (or SIGTERM) writes one
    /// in any case: the step under way ends, the checkpoint is written, and the run stops
    /// (exit status 130) saying where it is.
    #[arg(long, value_name = "STEPS|TIME", allow_hyphen_values = true, conflicts_with_all = ["bed", "check"])]
    pub checkpoint_every: Option<Every>,
    /// The checkpoint file, replaced at each checkpoint (default: the --restart file, else
    /// DIR/checkpoint.dpck with --out DIR, else SCENE.dpck in the current directory).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["bed", "check"])]
    pub checkpoint: Option<PathBuf>,
    /// Resume the run a checkpoint was written by: it ends bit for bit as the run would have
    /// without the stop. The checkpoint holds its scene (--scene, if given, must be the same);
    /// its laws are loaded again and must be the same plugins' versions.
    #[arg(long, value_name = "CHECKPOINT", conflicts_with_all = ["bed", "check"])]
    pub restart: Option<PathBuf>,
}

/// `dashpot dem --bed ...`: the vibrated bed of McNamara & Falcon with contact laws (the same
/// run as `dashpot bed --engine dem`, with the paper's geometry).
#[derive(Args, Debug)]
pub struct DemBedArgs {
    /// Run the vibrated bed (the event-driven bed's geometry) with contact laws.
    #[arg(long)]
    pub bed: bool,
    /// Number of layers n (N = n L/d disks).
    #[arg(long, requires = "bed", allow_hyphen_values = true)]
    pub layers: Option<f64>,
    /// Piston frequency f (Hz).
    #[arg(long, requires = "bed", allow_hyphen_values = true)]
    pub freq: Option<f64>,
    /// The contact law (see `dashpot laws`).
    #[arg(long, requires = "bed")]
    pub law: Option<String>,
    /// A contact-law parameter NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE", requires = "bed")]
    pub set: Vec<String>,
    /// A tangential law (friction), e.g. mindlin.
    #[arg(long, requires = "bed")]
    pub tangential: Option<String>,
    /// A tangential-law parameter NAME=VALUE (repeatable), e.g. mu=0.3.
    #[arg(long = "tset", value_name = "NAME=VALUE", requires = "bed")]
    pub tset: Vec<String>,
    /// The disks' material and the step.
    #[command(flatten)]
    pub disks: crate::cli::bed::DiskArgs,
    /// Gravity (m/s²).
    #[arg(long, default_value_t = 9.8, allow_hyphen_values = true)]
    pub gravity: f64,
    /// Transient periods (not measured).
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true)]
    pub transient: f64,
    /// Measured periods.
    #[arg(long, default_value_t = 200.0, allow_hyphen_values = true)]
    pub cycles: f64,
    /// Seed of the initial state.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `dashpot dem`.
pub fn run(reg: &Registry, a: &DemArgs) -> Result<()> {
    crate::budget::check_max_hours(a.limits.max_hours)?;
    if let Some(r) = &a.restart {
        let r = Resume::read(r)?;
        return match r.header.dimension {
            2 => resume_dim::<2>(reg, a, r),
            _ => resume_dim::<3>(reg, a, r),
        };
    }
    let Some(path) = &a.scene else {
        if a.check {
            // (clap lets `requires = "scene"` pass when --scene conflicts with a given --bed)
            return Err(crate::cli::UsageError(
                "--check checks a scene: give --scene FILE (dem --bed has no scene to check)".into(),
            )
            .into());
        }
        return run_bed(reg, &a.bed, a.json);
    };
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading --scene {}", path.display()))?;
    let file = parse_scene(&text, path)?;
    match file.dimension()? {
        2 => run_dim::<2>(reg, a, path, &text, &file, None),
        _ => run_dim::<3>(reg, a, path, &text, &file, None),
    }
}

/// `dem --restart FILE` of a run in `D` dimensions: the checkpoint's scene (or `--scene`,
/// which must be the same), run from the checkpoint's state on.
fn resume_dim<const D: usize>(reg: &Registry, a: &DemArgs, r: Resume) -> Result<()> {
    let given = match &a.scene {
        Some(p) => Some((
            std::fs::read_to_string(p).with_context(|| format!("reading --scene {}", p.display()))?,
            p.clone(),
        )),
        None => None,
    };
    let ck = r.decode::<D>(given.as_ref().map(|(t, p)| (t.as_str(), p.as_path())))?;
    let path = given.map_or_else(|| r.path.clone(), |(_, p)| p);
    let text = ck.scene.clone();
    let file = parse_scene(&text, &path)?;
    if file.dimension()? != D {
        anyhow::bail!(
            "{}: its header says {D} dimensions, its scene {}: it cannot be resumed from",
            r.path.display(),
            file.dimension()?
        );
    }
    run_dim::<D>(reg, a, &path, &text, &file, Some((r, ck)))
}

/// `dem --bed` is `bed --engine dem` with the same values: the same experiment, checked and run
/// by the same code.
fn run_bed(reg: &Registry, b: &DemBedArgs, json: bool) -> Result<()> {
    use crate::bed::spec::{BedEngine, BedSpec, LawChoice};
    use crate::cli::bed::{dem_tangential, param_values};
    let layers = b.layers.context("--bed needs --layers N")?;
    let freq = b.freq.context("--bed needs --freq HZ")?;
    let law = b
        .law
        .as_deref()
        .context("--bed needs --law NAME (a contact law, e.g. hsd)")?;
    let spec = BedSpec {
        config: crate::bed::BedConfig {
            gravity: b.gravity,
            seed: b.seed,
            ..crate::bed::BedConfig::paper(layers, freq)
        },
        young: b.disks.young,
        poisson: b.disks.poisson,
        engine: BedEngine::Dem {
            law: LawChoice::new(law, param_values(&b.set)?),
            tangential: dem_tangential(b.tangential.as_deref(), &b.tset)?,
            rolling: None,
            dt: b.disks.dt,
            steps_per_collision: None,
        },
        transient: b.transient,
        cycles: b.cycles,
        seeds: 1,
    };
    let out = crate::cli::bed::BedOutput {
        json,
        ..Default::default()
    };
    if let Some(v) = crate::cli::bed::run(reg, &spec, out, &|_| {})? {
        println!("{}", serde_json::to_string_pretty(&v)?);
    }
    Ok(())
}

fn run_dim<const D: usize>(
    reg: &Registry,
    a: &DemArgs,
    path: &std::path::Path,
    text: &str,
    file: &SceneFile,
    resume: Option<(Resume, Checkpoint<D>)>,
) -> Result<()> {
    let mut scene = file
        .scene::<D>()
        .with_context(|| format!("in {}", path.display()))?;
    scene.plan.resolve_names(reg);
    // (the setup --check times: the scene's particles, the engine)
    let started = std::time::Instant::now();
    let (mut e, mut energy_initial, fp) = scene_engine_sized(reg, file, &scene)?;
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
            c.dt, c.collision_time, scene.config.steps_per_collision, scene.plan.law_names(), c.impact_speed
        )
    };
    // steps past any machine's reach are refused before the first (and under --check)
    let total_steps = crate::cli::budget::check_run_steps(&e, scene.duration)?;
    crate::cli::budget::check_least_hours(total_steps, e.p.len(), a.limits.max_hours)?;
    let frames = if a.out.is_some() {
        scene.snapshots.max(1)
    } else {
        0
    } as u64;
    if a.check {
        let setup = started.elapsed().as_secs_f64();
        let mut fp = fp;
        // (--json here is the check's own output; the run's final document is counted apart)
        fp.final_json = a.out.is_some();
        let est = crate::cli::budget::estimate(
            &mut e,
            fp,
            scene.duration,
            setup,
            frames,
            std::time::Duration::from_secs(2),
        )?;
        crate::budget::check_hours(
            &format!("the run of {total_steps} steps of {} particles", e.p.len()),
            est.total_seconds(),
            "estimated from a timed sample of its steps",
            a.limits.max_hours,
        )?;
        return print_check(&e, path, &scene, a.json, &est);
    }
    eprintln!("{line}");
    if let Some(w) = c.warning() {
        eprintln!("warning: {w}");
    }
    let ck_path = a
        .checkpoint
        .clone()
        .unwrap_or_else(|| default_path(a.restart.as_deref(), a.out.as_deref(), a.scene.as_deref()));
    let mut cks = Checkpoints::new(reg, &scene.plan, D as u32, text, ck_path, a.checkpoint_every)?;
    // trajectory frames the checkpoint's run had written
    let mut resumed_frames = None;
    if let Some((r, ck)) = resume {
        energy_initial = ck.energy_initial;
        resumed_frames = Some(ck.frames);
        r.restore(ck, cks.hash(), &mut e)?;
        eprintln!(
            "resumed from {} at t = {:.6e} s, step {}",
            r.path.display(),
            e.time(),
            e.steps()
        );
    }
    cks.start(energy_initial, e.steps());
    eprintln!(
        "checkpoints: {}{} (Ctrl-C writes one and stops)",
        cks.path.display(),
        match a.checkpoint_every {
            Some(Every::Steps(n)) => format!(" every {n} steps"),
            Some(Every::Wall(d)) => format!(" every {:.0} s of wall-clock time", d.as_secs_f64()),
            None => String::new(),
        }
    );
    // (an estimate: the run steps while t + dt/2 < duration, one step fewer whenever the
    // fraction of duration / dt is below 1/2; the last frame is written at the end regardless)
    let total_steps = (scene.duration / c.dt).ceil() as u64;
    // frame k: the trajectory's frame and with --png its picture
    let frame = |e: &Engine<D>, w: &mut crate::output::AtomicFile, k: u64| -> Result<()> {
        crate::dem::xyz::write_frame(e, w)?;
        if let (true, Some(dir)) = (a.png, &a.out) {
            frame_png(e, dir, k, &scene.plan.law_names())?;
        }
        Ok(())
    };
    let mut traj = None;
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating --out {}", dir.display()))?;
        let p = dir.join("trajectory.xyz");
        // (it appears at its name when the run has ended well: a failed run leaves none)
        let mut w =
            crate::output::AtomicFile::create(&p).with_context(|| format!("creating {}", p.display()))?;
        match resumed_frames {
            None => frame(&e, &mut w, 0)?,
            Some(k) => {
                // the frames of the run before the checkpoint, if the trajectory holds them
                let before = std::fs::read_to_string(&p).ok();
                match before.filter(|t| trajectory_frames(t, e.p.len()) == k) {
                    Some(t) => std::io::Write::write_all(&mut w, t.as_bytes())?,
                    None => eprintln!(
                        "warning: {} does not hold the {k} frames written before the checkpoint: it is replaced by the frames from t = {:.6e} s on",
                        p.display(),
                        e.time()
                    ),
                }
            }
        }
        traj = Some(w);
    }
    let frames = if a.out.is_some() {
        scene.snapshots.max(1)
    } else {
        0
    } as u64;
    // frames written so far: the start's and those whose steps have passed
    let frames_done = |steps: u64| {
        (steps * frames)
            .checked_div(total_steps)
            .map_or(0, |k| k.min(frames))
            + 1
    };
    let pb = crate::output::progress_bar(total_steps, "dem");
    pb.set_message("steps");
    let wall0 = std::time::Instant::now();
    // blocks of steps of about progress::TICK each (the bar moves, Ctrl-C is seen, the pace is
    // judged against --max-hours), cut at the frames and checkpoints; a run's bits do not
    // depend on its blocks
    let pace = std::cell::RefCell::new(crate::progress::Pace::new());
    let mut limit = crate::cli::budget::PaceLimit::new(a.limits.max_hours);
    let last_stop = std::cell::Cell::new(e.steps());
    let first_step = e.steps();
    let next_frame = std::cell::Cell::new(frames_done(e.steps()));
    let framing = traj.is_some() && frames > 0;
    let cks = std::cell::RefCell::new(cks);
    let ran = e.run_with_stops(
        scene.duration,
        &mut |s| {
            let next_tick = s.saturating_add(pace.borrow().block());
            let next = next_tick.min(cks.borrow().next_stop(s));
            if framing {
                next.min((next_frame.get() * total_steps).div_ceil(frames))
            } else {
                next
            }
        },
        &mut |e| -> Result<()> {
            pace.borrow_mut().done(e.steps() - last_stop.replace(e.steps()));
            pb.set_position(e.steps());
            limit.check(
                e.steps() - first_step,
                total_steps.saturating_sub(first_step),
                wall0.elapsed().as_secs_f64(),
            )?;
            if let Some(w) = traj.as_mut() {
                let k = next_frame.get();
                if frames > 0 && e.steps() * frames >= k * total_steps {
                    frame(e, w, k)?;
                    next_frame.set(k + 1);
                }
            }
            let mut ck = cks.borrow_mut();
            if ck.interrupted() {
                ck.write(e, next_frame.get())?;
                return Err(Interrupted(format!(
                    "interrupted at t = {:.6e} s, step {}: the checkpoint {} holds the run; resume it with `dashpot dem --restart {}`",
                    e.time(),
                    e.steps(),
                    ck.path.display(),
                    ck.path.display()
                ))
                .into());
            }
            if ck.due(e.steps()) {
                ck.write(e, next_frame.get())?;
            }
            Ok(())
        },
    );
    if let Err(err) = ran {
        if err.is::<Interrupted>() {
            pb.finish_and_clear();
            // the frames up to the checkpoint, which the resumed run goes on from
            if let Some(w) = traj {
                w.commit().context("writing the trajectory")?;
            }
            return Err(err);
        }
        return Err(err.context(format!("at t = {:.6e} s, step {}", e.time(), e.steps())));
    }
    let cks = cks.into_inner();
    // the last frame, if the run ended short of the step it was placed at
    if let (Some(w), true) = (traj.as_mut(), framing && next_frame.get() <= frames) {
        frame(&e, w, next_frame.get())?;
    }
    pb.finish();
    if let Some(w) = e.heat_books().and_then(|b| b.warning()) {
        eprintln!("warning: {w}");
    }
    let wall = wall0.elapsed().as_secs_f64();
    if let Some(w) = traj {
        w.commit()?;
    }
    // (the final state as JSON only where it goes: a large pile's costs more than its engine)
    let state = if a.json || a.out.is_some() {
        Some(final_json(reg, file, &scene.plan, &e, energy_initial, wall)?)
    } else {
        None
    };
    if let (Some(dir), Some(state)) = (&a.out, &state) {
        crate::output::write_atomic(
            &dir.join("final.json"),
            serde_json::to_string_pretty(state)?.as_bytes(),
        )?;
    }
    if let (true, Some(state)) = (a.json, &state) {
        println!("{}", serde_json::to_string_pretty(state)?);
    } else {
        let en = e.energy();
        println!("{} {}D particles, {}", e.p.len(), D, laws_line(&scene.plan));
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
        if cks.written > 0 {
            println!(
                "checkpoints written: {} (the last to {})",
                cks.written,
                cks.path.display()
            );
        }
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

/// The engine of a scene as `dashpot dem` runs it: the laws of every class of contacts (the
/// scene's `[law]`, `[tangential]`, `[rolling]`, `[twisting]` and `[[pair]]` tables) from
/// `reg`, bound to their materials, energy accounting as the scene says (on unless
/// `energy = false`); and the energy at the start (J: kinetic, gravity and elastic), which
/// `dem --json` reports.
pub fn scene_engine<const D: usize>(
    reg: &Registry,
    file: &SceneFile,
    scene: &crate::dem::scene::Scene<D>,
) -> Result<(Engine<D>, f64)> {
    scene_engine_sized(reg, file, scene).map(|(e, en, _)| (e, en))
}

/// [`scene_engine`], and the run's memory footprint, checked against the memory available
/// before the engine is built (a run that cannot fit is refused, naming what it needs).
pub fn scene_engine_sized<const D: usize>(
    reg: &Registry,
    file: &SceneFile,
    scene: &crate::dem::scene::Scene<D>,
) -> Result<(Engine<D>, f64, crate::dem::footprint::Footprint)> {
    let laws = scene.plan.bind(reg)?;
    let fp = crate::cli::budget::scene_footprint(scene, &laws);
    crate::cli::budget::check_scene_memory(file, scene, &laws)?;
    let mut e = Engine::with_species(
        scene.config.clone(),
        &scene.bodies,
        &scene.species,
        scene.walls.clone(),
        laws,
    )?;
    if let Some(h) = &scene.heat {
        e = e.with_heat(h.clone())?;
    }
    let energy_initial = e.energy().total() + e.elastic().iter().sum::<f64>();
    Ok((e, energy_initial, fp))
}

/// The laws of a run in one line: `law hsd + mindlin`, or with several classes
/// `laws by pair: powder–powder jkr; powder–beads hsd; ...`.
fn laws_line(plan: &crate::dem::scene::PairPlan) -> String {
    if plan.pair.len() == 1 && plan.wall.len() <= 1 && plan.wall.iter().all(|w| w.laws == plan.pair[0].laws) {
        return format!("law {}", plan.pair[0].laws.names());
    }
    let each = plan
        .pair
        .iter()
        .chain(&plan.wall)
        .map(|c| format!("{} {}", c.label, c.laws.names()))
        .collect::<Vec<_>>()
        .join("; ");
    format!("laws by pair: {each}")
}

/// What `dashpot dem --json` prints after a run of `file` on `e` (made by [`scene_engine`],
/// which gave `energy_initial`, J): the final state, the laws and their provenance, the energy
/// balance, and the rates of `wall` seconds of wall-clock time.
pub fn final_json<const D: usize>(
    reg: &Registry,
    file: &SceneFile,
    plan: &crate::dem::scene::PairPlan,
    e: &Engine<D>,
    energy_initial: f64,
    wall: f64,
) -> Result<serde_json::Value> {
    let mut state = e.state_json();
    state["law"] = serde_json::json!(file.law.as_ref().map(|t| t.name.clone()));
    state["tangential"] = serde_json::json!(file.tangential.as_ref().map(|t| t.name.clone()));
    state["rolling"] = serde_json::json!(file.rolling.as_ref().map(|t| t.name.clone()));
    state["twisting"] = serde_json::json!(file.twisting.as_ref().map(|t| t.name.clone()));
    state["heat_law"] = serde_json::json!(file.heat.as_ref().map(|t| t.name.clone()));
    if plan.named || plan.pair.len() > 1 || plan.wall.len() > 1 {
        // the species and every class of contacts with its laws; each particle's species
        state["pairs"] = plan.json();
        if plan.named {
            let names = e.particle_species();
            if let Some(parts) = state["particles"].as_array_mut() {
                for (p, s) in parts.iter_mut().zip(names) {
                    p["species"] = serde_json::json!(plan.species[s as usize].name);
                }
            }
        }
    }
    let provenance = plan
        .tables()
        .into_iter()
        .map(|t| crate::output::Provenance::of(reg, &t.name, &t.param_values()).map(|p| p.json()))
        .collect::<Result<Vec<_>, _>>()?;
    state["provenance"] = serde_json::json!(provenance);
    // without the accounting (`energy = false`) the laws were not asked: null, not zeros
    let on = e.config().energy;
    state["energy_initial"] = serde_json::json!(on.then_some(energy_initial));
    state["elastic"] = serde_json::json!(on.then(|| e.elastic().iter().sum::<f64>()));
    // the work of moving walls on the particles: initial + wall_work = energy + elastic +
    // dissipated
    state["wall_work"] = serde_json::json!(on.then_some(e.wall_work));
    state["dissipated"] = if on {
        dissipated_json(e)
    } else {
        serde_json::Value::Null
    };
    state["wall_seconds"] = serde_json::json!(wall);
    state["particle_steps_per_second"] =
        serde_json::json!(e.p.len() as f64 * e.steps() as f64 / wall.max(1e-9));
    Ok(state)
}

/// `dem --scene FILE --check`: what the run would start with (the checks have passed): the
/// step, the particles, the species, every class of contacts with its laws, the walls; and
/// the estimate of the run (steps, peak memory, wall time).
fn print_check<const D: usize>(
    e: &Engine<D>,
    path: &std::path::Path,
    scene: &crate::dem::scene::Scene<D>,
    json: bool,
    est: &crate::cli::budget::RunEstimate,
) -> Result<()> {
    let c = e.step_choice;
    if let Some(w) = c.warning() {
        eprintln!("warning: {w}");
    }
    let plan = &scene.plan;
    let law = plan.law_names();
    let d = |f: fn(f64, f64) -> f64, start: f64| 2.0 * e.p.radius.iter().cloned().fold(start, f);
    let (dmin, dmax) = (d(f64::min, f64::INFINITY), d(f64::max, 0.0));
    let mut count = vec![0usize; plan.species.len()];
    for &s in &scene.species {
        count[s as usize] += 1;
    }
    let walls: Vec<String> = scene.walls.iter().map(|w| w.describe()).collect();
    if json {
        let mut v = serde_json::json!({
            "scene": path.display().to_string(),
            "checks": "passed",
            "dimension": D,
            "law": law,
            "dt": c.dt,
            "dt_given": c.given,
            "collision_time": c.collision_time,
            "impact_speed": c.impact_speed,
            "steps_per_collision": c.collision_time / c.dt,
            "particles": e.p.len(),
            "diameter_min": dmin,
            "diameter_max": dmax,
            "walls": e.walls.len(),
            "wall_shapes": walls,
            "estimate": est.json(),
        });
        let mut pairs = plan.json();
        for (s, n) in pairs["species"].as_array_mut().into_iter().flatten().zip(&count) {
            s["particles"] = serde_json::json!(n);
        }
        v["pairs"] = pairs;
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "{}: every check passed (not run): a timed sample of {} steps, nothing written",
        path.display(),
        est.sample_steps
    );
    println!(
        "dt = {:.4e} s{}; contact time {:.4e} s at {:.3} m/s (law '{law}'), {:.1} steps per collision",
        c.dt,
        if c.given { " (given)" } else { " (chosen)" },
        c.collision_time,
        c.impact_speed,
        c.collision_time / c.dt
    );
    println!(
        "{} {}D particles, diameters {dmin:.4e} .. {dmax:.4e} m; {} wall(s)",
        e.p.len(),
        D,
        e.walls.len()
    );
    if plan.named {
        for (s, n) in plan.species.iter().zip(&count) {
            let m = &s.material;
            println!(
                "species '{}': {n} particles, E = {:e} Pa, nu = {}, rho = {} kg/m^3",
                s.name, m.young, m.poisson, m.density
            );
        }
    }
    for c in &plan.pair {
        println!("particle pairs {}: {}", c.label, c.laws.described());
    }
    for c in &plan.wall {
        println!("wall pairs {}: {}", c.label, c.laws.described());
    }
    for (k, w) in walls.iter().enumerate() {
        println!("wall {k}: {w}");
    }
    est.lines().iter().for_each(|l| println!("{l}"));
    Ok(())
}

/// Frame `k` of the trajectory as a picture, `frame_NNNN.png` (and .svg) in `dir`.
fn frame_png<const D: usize>(e: &Engine<D>, dir: &std::path::Path, k: u64, law: &str) -> Result<()> {
    let title = format!("{} {}D particles, {law}, t = {:.6e} s", e.p.len(), D, e.time());
    crate::report::snapshot::Scene::dem(e)
        .figure(&title)
        .save(dir, &format!("frame_{k:04}"))
        .with_context(|| format!("drawing frame {k} into {}", dir.display()))?;
    Ok(())
}

/// `dissipated` of `dem --json`: the energy each family's laws dissipated since the start (J),
/// `null` for a family whose law does not report it (a law without `energy`, or a plugin of
/// sdk 0.1 or 0.2), and the total
/// (`null` if any is).
fn dissipated_json<const D: usize>(e: &Engine<D>) -> serde_json::Value {
    let fam = |k: usize| (!e.unreported[k]).then_some(e.dissipated[k]);
    let total = (0..4).map(fam).sum::<Option<f64>>();
    serde_json::json!({
        "normal": fam(0), "tangential": fam(1), "rolling": fam(2), "twisting": fam(3), "total": total,
    })
}
