//! `dashpot dem --scene FILE.toml [--json] [--out DIR]`: a soft-sphere DEM run of a scene.

use crate::dem::scene::SceneFile;
use crate::dem::{Engine, Laws};
use crate::registry::Registry;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;

/// `dashpot dem`.
#[derive(Args, Debug)]
pub struct DemArgs {
    /// The scene (TOML; see `examples/dem/` and the `dem::scene` docs).
    #[arg(long, required_unless_present = "bed", conflicts_with = "bed")]
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
    /// Young's modulus of the disks (Pa); default steel, 2e11.
    #[arg(long, allow_hyphen_values = true)]
    pub young: Option<f64>,
    /// Poisson's ratio; default 0.3.
    #[arg(long, allow_hyphen_values = true)]
    pub poisson: Option<f64>,
    /// The step (s); default: the law's contact time at the largest impact speed / 50.
    #[arg(long, allow_hyphen_values = true)]
    pub dt: Option<f64>,
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
    let file = SceneFile::parse(&text).with_context(|| format!("in {}", path.display()))?;
    match file.dimension()? {
        2 => run_dim::<2>(reg, a, path, &file),
        _ => run_dim::<3>(reg, a, path, &file),
    }
}

/// `dem --bed` is `bed --engine dem` with the same values: its arguments are handed to that
/// command's parser and run by it, so both take the same checks, defaults and output.
fn run_bed(reg: &Registry, b: &DemBedArgs, json: bool) -> Result<()> {
    #[derive(clap::Parser)]
    struct BedCommand {
        #[command(flatten)]
        bed: crate::cli::bed::BedArgs,
    }
    let layers = b.layers.context("--bed needs --layers N")?;
    let freq = b.freq.context("--bed needs --freq HZ")?;
    let law = b
        .law
        .clone()
        .context("--bed needs --law NAME (a contact law, e.g. hsd)")?;
    let mut argv: Vec<String> = vec!["dashpot dem --bed".into(), "--engine".into(), "dem".into()];
    let mut put = |flag: &str, value: String| {
        argv.push(flag.into());
        argv.push(value);
    };
    put("--layers", layers.to_string());
    put("--freq", freq.to_string());
    put("--law", law);
    b.set.iter().for_each(|s| put("--set", s.clone()));
    if let Some(t) = &b.tangential {
        put("--tangential", t.clone());
    }
    b.tset.iter().for_each(|s| put("--tset", s.clone()));
    for (flag, v) in [("--young", b.young), ("--poisson", b.poisson), ("--dt", b.dt)] {
        if let Some(v) = v {
            put(flag, v.to_string());
        }
    }
    put("--gravity", b.gravity.to_string());
    put("--transient", b.transient.to_string());
    put("--cycles", b.cycles.to_string());
    put("--seed", b.seed.to_string());
    if json {
        argv.push("--json".into());
    }
    let cmd = <BedCommand as clap::Parser>::try_parse_from(&argv)
        .map_err(|e| crate::cli::UsageError(e.to_string()))?;
    crate::cli::bed::bed(reg, &cmd.bed)
}

fn run_dim<const D: usize>(
    reg: &Registry,
    a: &DemArgs,
    path: &std::path::Path,
    file: &SceneFile,
) -> Result<()> {
    let scene = file
        .scene::<D>()
        .with_context(|| format!("in {}", path.display()))?;
    let (mut e, energy_initial) = scene_engine(reg, file, &scene)?;
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
    if a.check {
        return print_check(&e, path, &file.law.name, a.json);
    }
    eprintln!("{line}");
    if let Some(w) = c.warning() {
        eprintln!("warning: {w}");
    }
    // (an estimate: the run steps while t + dt/2 < duration, one step fewer whenever the
    // fraction of duration / dt is below 1/2; the last frame is written at the end regardless)
    let total_steps = (scene.duration / c.dt).ceil() as u64;
    // frame k: the trajectory's frame and with --png its picture
    let frame = |e: &Engine<D>, w: &mut crate::output::AtomicFile, k: u64| -> Result<()> {
        crate::dem::xyz::write_frame(e, w)?;
        if let (true, Some(dir)) = (a.png, &a.out) {
            frame_png(e, dir, k, &file.law.name)?;
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
        frame(&e, &mut w, 0)?;
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
    // the steps to the next progress tick, frame or the end, as one block
    let next_frame = std::cell::Cell::new(1u64);
    let framing = traj.is_some() && frames > 0;
    e.run_with_stops(
        scene.duration,
        &mut |s| {
            let next_tick = (s / every + 1) * every;
            if framing {
                next_tick.min((next_frame.get() * total_steps).div_ceil(frames))
            } else {
                next_tick
            }
        },
        &mut |e| -> Result<()> {
            if e.steps() % every == 0 {
                pb.set_position(e.steps());
            }
            if let Some(w) = traj.as_mut() {
                let k = next_frame.get();
                if frames > 0 && e.steps() * frames >= k * total_steps {
                    frame(e, w, k)?;
                    next_frame.set(k + 1);
                }
            }
            Ok(())
        },
    )
    .with_context(|| format!("at t = {:.6e} s, step {}", e.time(), e.steps()))?;
    // the last frame, if the run ended short of the step it was placed at
    if let (Some(w), true) = (traj.as_mut(), framing && next_frame.get() <= frames) {
        frame(&e, w, next_frame.get())?;
    }
    pb.finish_and_clear();
    let wall = wall0.elapsed().as_secs_f64();
    if let Some(w) = traj {
        w.commit().context("writing the trajectory")?;
    }
    let state = final_json(reg, file, &e, energy_initial, wall)?;
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
            [&file.tangential, &file.rolling, &file.twisting]
                .iter()
                .filter_map(|t| t.as_ref().map(|t| format!(" + {}", t.name)))
                .collect::<String>()
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

/// The engine of a scene as `dashpot dem` runs it: the laws of `file` (`[law]`, `[tangential]`,
/// `[rolling]`, `[twisting]`) from `reg`, bound to the scene's material, energy accounting on;
/// and the energy at the start (J: kinetic, gravity and elastic), which `dem --json` reports.
pub fn scene_engine<const D: usize>(
    reg: &Registry,
    file: &SceneFile,
    scene: &crate::dem::scene::Scene<D>,
) -> Result<(Engine<D>, f64)> {
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
    let table =
        |t: &Option<crate::dem::scene::LawTable>| t.as_ref().map(|t| (t.name.clone(), t.param_values()));
    let (roll, twist) = (table(&file.rolling), table(&file.twisting));
    let laws = laws
        .with_rotation(
            reg,
            roll.as_ref().map(|(n, p)| (n.as_str(), p.as_slice())),
            twist.as_ref().map(|(n, p)| (n.as_str(), p.as_slice())),
            &scene.config.material,
        )
        .context("[rolling] / [twisting]")?;
    let mut cfg = scene.config.clone();
    cfg.energy = true;
    let e = Engine::new(cfg, &scene.bodies, scene.walls.clone(), laws)?;
    let energy_initial = e.energy().total() + e.elastic().iter().sum::<f64>();
    Ok((e, energy_initial))
}

/// What `dashpot dem --json` prints after a run of `file` on `e` (made by [`scene_engine`],
/// which gave `energy_initial`, J): the final state, the laws and their provenance, the energy
/// balance, and the rates of `wall` seconds of wall-clock time.
pub fn final_json<const D: usize>(
    reg: &Registry,
    file: &SceneFile,
    e: &Engine<D>,
    energy_initial: f64,
    wall: f64,
) -> Result<serde_json::Value> {
    let mut state = e.state_json();
    state["law"] = serde_json::json!(file.law.name);
    state["tangential"] = serde_json::json!(file.tangential.as_ref().map(|t| t.name.clone()));
    state["rolling"] = serde_json::json!(file.rolling.as_ref().map(|t| t.name.clone()));
    state["twisting"] = serde_json::json!(file.twisting.as_ref().map(|t| t.name.clone()));
    let tables = [
        Some(&file.law),
        file.tangential.as_ref(),
        file.rolling.as_ref(),
        file.twisting.as_ref(),
    ];
    let provenance = tables
        .into_iter()
        .flatten()
        .map(|t| crate::output::Provenance::of(reg, &t.name, &t.param_values()).map(|p| p.json()))
        .collect::<Result<Vec<_>, _>>()?;
    state["provenance"] = serde_json::json!(provenance);
    state["energy_initial"] = serde_json::json!(energy_initial);
    state["elastic"] = serde_json::json!(e.elastic().iter().sum::<f64>());
    state["dissipated"] = dissipated_json(e);
    state["wall_seconds"] = serde_json::json!(wall);
    state["particle_steps_per_second"] =
        serde_json::json!(e.p.len() as f64 * e.steps() as f64 / wall.max(1e-9));
    Ok(state)
}

/// `dem --scene FILE --check`: what the run would start with (the checks have passed).
fn print_check<const D: usize>(e: &Engine<D>, path: &std::path::Path, law: &str, json: bool) -> Result<()> {
    let c = e.step_choice;
    if let Some(w) = c.warning() {
        eprintln!("warning: {w}");
    }
    let d = |f: fn(f64, f64) -> f64, start: f64| 2.0 * e.p.radius.iter().cloned().fold(start, f);
    let (dmin, dmax) = (d(f64::min, f64::INFINITY), d(f64::max, 0.0));
    if json {
        let v = serde_json::json!({
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
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("{}: every check passed (not run)", path.display());
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

/// The two axes a picture shows: x and y in 2D, x and z (the side view) in 3D.
fn view_axes(d: usize) -> (usize, usize) {
    (0, d - 1)
}

/// A picture of the particles (to scale) and the walls at the engine's time.
pub fn snapshot_panel<const D: usize>(e: &Engine<D>, title: &str) -> crate::plot::Panel {
    use crate::plot::{Mark, Panel, Series};
    let (ax, ay) = view_axes(D);
    let disks: Vec<(f64, f64, f64)> = (0..e.p.len())
        .map(|i| (e.p.pos[i][ax], e.p.pos[i][ay], e.p.radius[i]))
        .collect();
    let rmax = e.p.radius.iter().cloned().fold(0.0, f64::max);
    let (mut x0, mut x1, mut y0, mut y1) = disks.iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
        |(a, b, c, d), &(x, y, _)| (a.min(x), b.max(x), c.min(y), d.max(y)),
    );
    let dom = &e.config().domain;
    if dom.bounded || dom.periodic.iter().any(|&p| p) {
        (x0, x1) = (x0.min(dom.lo[ax]), x1.max(dom.hi[ax]));
        if dom.bounded {
            (y0, y1) = (y0.min(dom.lo[ay]), y1.max(dom.hi[ay]));
        }
    }
    let walls = e.wall_states();
    for w in &walls {
        // a wall across the view: include its point
        (x0, x1, y0, y1) = (
            x0.min(w.point[ax]),
            x1.max(w.point[ax]),
            y0.min(w.point[ay]),
            y1.max(w.point[ay]),
        );
    }
    if !(x0.is_finite() && y0.is_finite()) {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    let pad = 2.0 * rmax.max(1e-12);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let diag = ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
    let mut series = Vec::new();
    for w in &walls {
        let (nx, ny) = (w.normal[ax], w.normal[ay]);
        let n = (nx * nx + ny * ny).sqrt();
        if n < 0.5 {
            continue; // a wall facing out of the picture's plane
        }
        let (tx, ty) = (-ny / n, nx / n);
        let (px, py) = (w.point[ax], w.point[ay]);
        series.push(Series::new(
            "",
            vec![(px - tx * diag, py - ty * diag), (px + tx * diag, py + ty * diag)],
            Mark::Line,
            6,
        ));
    }
    Panel {
        title: title.to_string(),
        x_label: if D == 2 { "x (m)" } else { "x (m), side view" }.into(),
        y_label: if D == 2 { "y (m)" } else { "z (m)" }.into(),
        equal_aspect: true,
        x_range: Some((x0, x1)),
        y_range: Some((y0, y1)),
        disks,
        series,
        ..Default::default()
    }
}

fn frame_png<const D: usize>(e: &Engine<D>, dir: &std::path::Path, k: u64, law: &str) -> Result<()> {
    let p = snapshot_panel(
        e,
        &format!("{} {}D particles, {law}, t = {:.6e} s", e.p.len(), D, e.time()),
    );
    let (w, h) = match (p.x_range, p.y_range) {
        (Some((a, b)), Some((c, d))) => (b - a, d - c),
        _ => (1.0, 1.0),
    };
    let width = 1200u32;
    let height = ((width as f64 * h / w.max(1e-300)) as u32 + 120).clamp(240, 2400);
    crate::plot::Figure {
        panels: vec![p],
        columns: 1,
        panel_size: (width, height),
    }
    .save(dir, &format!("frame_{k:04}"))
    .with_context(|| format!("drawing frame {k} into {}", dir.display()))?;
    Ok(())
}

/// `dissipated` of `dem --json`: the energy each family's laws dissipated since the start (J),
/// `null` for a family whose law does not report it (a plugin of sdk 0.1 or 0.2), and the total
/// (`null` if any is).
fn dissipated_json<const D: usize>(e: &Engine<D>) -> serde_json::Value {
    let fam = |k: usize| (!e.unreported[k]).then_some(e.dissipated[k]);
    let total = (0..4).map(fam).sum::<Option<f64>>();
    serde_json::json!({
        "normal": fam(0), "tangential": fam(1), "rolling": fam(2), "twisting": fam(3), "total": total,
    })
}
