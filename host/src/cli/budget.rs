//! Know before a DEM run: its memory checked before the engine is built, its step count before
//! the first step, its pace against `--max-hours` in its first seconds, and `--check`'s estimate
//! of steps, peak memory and wall time from a timed sample of the scene's own steps.

use crate::budget::{self, check_memory_against, largest_fitting, Memory, Need, Refused};
use crate::dem::footprint::Footprint;
use crate::dem::scene::{Scene, SceneFile};
use crate::dem::species::SpeciesLaws;
use crate::dem::state::Body;
use crate::dem::Engine;
use clap::Args;
use std::time::{Duration, Instant};

/// The limits of a long run.
#[derive(Args, Debug, Clone)]
pub struct LimitArgs {
    /// Refuse a run estimated to take longer than this many hours of wall time (estimated from
    /// the pace of its first seconds; `--check` prints the estimate).
    #[arg(long, value_name = "HOURS", default_value_t = budget::DEFAULT_MAX_HOURS, allow_hyphen_values = true)]
    pub max_hours: f64,
}

impl Default for LimitArgs {
    fn default() -> Self {
        LimitArgs {
            max_hours: budget::DEFAULT_MAX_HOURS,
        }
    }
}

/// Bytes a `[[particle]]` table of a scene file holds while the run lasts: its text and its
/// parsed table (measured).
pub const TABLE_BYTES: f64 = 400.0;

/// The footprint of the run of `scene` under `laws`: the engine's (its packed share from the
/// scene's gravity and duration, its skin), and the final state as JSON at the end; the
/// scene's bodies and tables are resident already (the footprint's baseline).
pub fn scene_footprint<const D: usize>(scene: &Scene<D>, laws: &SpeciesLaws) -> Footprint {
    let d = scene.bodies.iter().map(|b| b.diameter);
    let (dmin, dmax) = (d.clone().fold(f64::INFINITY, f64::min), d.fold(0.0, f64::max));
    let mut fp = Footprint::of_species(&scene.config, laws, scene.bodies.len(), scene.walls.len()).with_skin(
        dmin,
        dmax,
        scene.config.skin,
    );
    fp.packed = crate::dem::footprint::packed_share(&scene.bodies, &scene.config.gravity, scene.duration);
    // (the scene's bodies and tables are resident already: part of the baseline)
    fp.final_json = true;
    fp
}

/// Bytes the caller keeps beside the engine: `tables` scene-file tables, `bodies` bodies.
fn kept(tables: f64, bodies: f64, dim: usize) -> f64 {
    let body = if dim == 3 {
        std::mem::size_of::<Body<3>>()
    } else {
        std::mem::size_of::<Body<2>>()
    };
    tables * TABLE_BYTES + bodies * body as f64
}

/// Refuses the run of `scene` under `laws` if its peak memory (estimated) exceeds the memory
/// available, before the engine allocates: the message names the particles, the estimate by
/// part, the memory available, and how many particles would fit.
pub fn check_scene_memory<const D: usize>(
    file: &SceneFile,
    scene: &Scene<D>,
    laws: &SpeciesLaws,
) -> Result<(), Refused> {
    let fp = scene_footprint(scene, laws);
    let mem = Memory::now();
    let n = fp.particles as f64;
    let tables = file.particle_tables() as f64;
    // (a run of m particles: the engine's and, beyond those made already, their bodies)
    let made = kept(tables, n, D);
    let most = largest_fitting(mem.available as f64, |m| {
        let f = Footprint {
            particles: m as usize,
            ..fp.clone()
        };
        f.need().more() + kept(tables * m / n.max(1.0), m, D) - made
    });
    check_memory_against(
        &format!("the run of {} {D}D particles", fp.particles),
        &fp.need(),
        &mem,
        &format!(
            "about {most} particles would fit: fewer particles (generate.count, [[particle]]), or a machine with more memory (DASHPOT_MEMORY_AVAILABLE overrides the figure)"
        ),
    )
}

/// The steps of the run of `e` to `duration` (s), refused if absurd: the message names dt, how
/// it was chosen and what to change.
pub fn check_run_steps<const D: usize>(e: &Engine<D>, duration: f64) -> Result<u64, Refused> {
    let c = e.step_choice;
    let advice = if c.given {
        format!(
            "the given dt is far below the contact time ({:.4e} s at {:.3} m/s): give a larger dt, or a shorter duration",
            c.collision_time, c.impact_speed
        )
    } else {
        format!(
            "dt was chosen as the contact time {:.4e} s at {:.3} m/s / steps_per_collision = {}: a law or material far stiffer than meant (young, a stiffness k), or far too many steps per collision; or a shorter duration",
            c.collision_time,
            c.impact_speed,
            e.config().steps_per_collision
        )
    };
    budget::check_steps("the run", e.dt(), duration - e.time(), e.p.len(), &advice)
}

/// Refuses a run of `steps` steps of `particles` particles that could not end within
/// `max_hours` even at the fastest pace any machine steps
/// ([`budget::FASTEST_PARTICLE_STEPS_PER_SECOND`]).
pub fn check_least_hours(steps: u64, particles: usize, max_hours: f64) -> Result<(), Refused> {
    let least = steps as f64 * particles.max(1) as f64 / budget::FASTEST_PARTICLE_STEPS_PER_SECOND;
    budget::check_hours(
        &format!("the run of {steps} steps of {particles} particles"),
        least,
        &format!(
            "at least, at {:.0e} particle-steps/s",
            budget::FASTEST_PARTICLE_STEPS_PER_SECOND
        ),
        max_hours,
    )
}

/// The fewest steps a timed sample takes after its first block (a pile of a million particles
/// takes a few tenths of a second a step: a second would time two steps).
pub const SAMPLE_STEPS: u64 = 6;

/// Seconds per particle to build and write the final state as JSON (measured).
pub const FINAL_JSON_SECONDS_PER_PARTICLE: f64 = 1.2e-5;

/// What `--check` estimates of a run: its steps, its peak memory and its wall time.
#[derive(Debug, Clone)]
pub struct RunEstimate {
    /// Steps to the end.
    pub steps: u64,
    /// The step (s).
    pub dt: f64,
    /// The peak memory, by part.
    pub memory: Need,
    /// The memory available.
    pub available: Memory,
    /// This process's resident memory after the engine was built and the sample run (bytes).
    pub resident: u64,
    /// Wall time to read the scene and build the engine (s), measured.
    pub setup_seconds: f64,
    /// Steps of the timed sample.
    pub sample_steps: u64,
    /// Wall time per step (s), measured on the sample.
    pub step_seconds: f64,
    /// Frames of the trajectory to write, and the time of each (s), measured.
    pub frames: u64,
    /// Wall time to write one frame (s).
    pub frame_seconds: f64,
    /// Wall time of the final state (s), estimated, if the run writes it (`--out`).
    pub final_seconds: f64,
    /// What the final state as JSON would add, if the run did not count it: its memory (bytes)
    /// and its wall time (s) (`--json` prints it).
    pub json_extra: (f64, f64),
}

impl RunEstimate {
    /// The estimated wall time of the whole run (s).
    pub fn total_seconds(&self) -> f64 {
        self.setup_seconds
            + self.steps as f64 * self.step_seconds
            + self.frames as f64 * self.frame_seconds
            + self.final_seconds
    }

    /// The estimate as JSON.
    pub fn json(&self) -> serde_json::Value {
        let parts: serde_json::Map<String, serde_json::Value> = self
            .memory
            .parts
            .iter()
            .map(|(n, b)| (n.clone(), serde_json::json!(b)))
            .collect();
        serde_json::json!({
            "steps": self.steps,
            "dt": self.dt,
            "memory_bytes": self.memory.total(),
            "memory_parts": parts,
            "memory_available_bytes": self.available.available,
            "memory_available_source": self.available.source,
            "resident_bytes_after_sample": self.resident,
            "wall_seconds": self.total_seconds(),
            "setup_seconds": self.setup_seconds,
            "sample_steps": self.sample_steps,
            "seconds_per_step": self.step_seconds,
            "frames": self.frames,
            "seconds_per_frame": self.frame_seconds,
            "final_seconds": self.final_seconds,
            "memory_bytes_with_json": self.memory.total() + self.json_extra.0,
            "wall_seconds_with_json": self.total_seconds() + self.json_extra.1,
        })
    }

    /// The estimate as lines of text.
    pub fn lines(&self) -> Vec<String> {
        let mut v = vec![
            format!("steps: {} of {:.4e} s", self.steps, self.dt),
            format!(
                "peak memory: about {} ({} held before the run; {}); {} available ({}); {} resident now",
                budget::bytes(self.memory.total()),
                budget::bytes(self.memory.resident),
                self.memory.breakdown(),
                budget::bytes(self.available.available as f64),
                self.available.source,
                budget::bytes(self.resident as f64)
            ),
            format!(
                "wall time: about {} ({:.4e} s per step over a sample of {} steps on this machine now, setup {:.2} s{}; the pace changes as contacts form or part, and with the machine's load)",
                budget::seconds(self.total_seconds()),
                self.step_seconds,
                self.sample_steps,
                self.setup_seconds,
                if self.frames > 0 {
                    format!(", {} frames of {:.3} s", self.frames, self.frame_seconds)
                } else {
                    String::new()
                }
            ),
        ];
        if self.json_extra.0 > 0.0 {
            v.push(format!(
                "with --json: the final state adds about {} and {} at the end",
                budget::bytes(self.json_extra.0),
                budget::seconds(self.json_extra.1)
            ));
        }
        v
    }
}

/// The timed sample: blocks of steps of `e` as the run makes them ([`crate::progress::Pace`]:
/// what a call of the engine costs beyond its steps is then the run's) until `budget` of wall
/// time has passed and [`SAMPLE_STEPS`] steps after the first block, or `steps` steps are done;
/// the time per step of the blocks making the sample's second half (the first steps pay for
/// warming caches and the engine's learning of its pace).
fn sample_steps<const D: usize>(
    e: &mut Engine<D>,
    steps: u64,
    budget: Duration,
) -> Result<(u64, f64), crate::dem::DemError> {
    let clock = Instant::now();
    let mut blocks: Vec<(u64, f64)> = Vec::new();
    let mut pace = crate::progress::Pace::new();
    let mut done = 0u64;
    while done < steps && (clock.elapsed() < budget || done < 1 + SAMPLE_STEPS) {
        let k = pace.block().min(steps - done);
        let t = Instant::now();
        e.advance(k)?;
        pace.done(k);
        blocks.push((k, t.elapsed().as_secs_f64()));
        done += k;
    }
    let total: f64 = blocks.iter().map(|b| b.1).sum();
    let (mut n, mut t) = (0u64, 0.0);
    for &(k, s) in blocks.iter().rev() {
        n += k;
        t += s;
        if t >= 0.4 * total {
            break;
        }
    }
    Ok((done, if n > 0 { t / n as f64 } else { 0.0 }))
}

/// `--check`'s estimate of the run of `e` (just built, `setup_seconds` after the start) to
/// `duration` (s), with `frames` trajectory frames: runs a timed sample of its own steps (about
/// `budget` of wall time; the engine is left at the sample's end) and measures a frame's
/// writing.
pub fn estimate<const D: usize>(
    e: &mut Engine<D>,
    mut fp: Footprint,
    duration: f64,
    setup_seconds: f64,
    frames: u64,
    budget: Duration,
) -> anyhow::Result<RunEstimate> {
    let steps = check_run_steps(e, duration)?;
    let frame_seconds = if frames > 0 {
        let t = Instant::now();
        crate::dem::xyz::write_frame(e, &mut std::io::sink())?;
        t.elapsed().as_secs_f64()
    } else {
        0.0
    };
    let (sample, step_seconds) = sample_steps(e, steps, budget)?;
    let json_seconds = FINAL_JSON_SECONDS_PER_PARTICLE * e.p.len() as f64;
    fp.listed = Some(e.listed_pairs());
    fp.sampled = Some(e.pairs.len());
    Ok(RunEstimate {
        steps,
        dt: e.dt(),
        memory: fp.need(),
        available: Memory::now(),
        resident: budget::rss().now,
        setup_seconds,
        sample_steps: sample,
        step_seconds,
        frames,
        frame_seconds,
        final_seconds: if fp.final_json { json_seconds } else { 0.0 },
        json_extra: if fp.final_json {
            (0.0, 0.0)
        } else {
            (fp.final_json_bytes(), json_seconds)
        },
    })
}

/// The wall-time limit of a run checked from its pace: once `MEASURE` of wall time has passed
/// after the start of the steps (and until it has been checked once), the time the whole run
/// would take at the pace so far, refused past `max_hours`.
pub struct PaceLimit {
    max_hours: f64,
    checked: bool,
}

/// How long a run's pace is measured before [`PaceLimit`] judges it.
pub const MEASURE: Duration = Duration::from_secs(2);

impl PaceLimit {
    /// A limit of `max_hours`.
    pub fn new(max_hours: f64) -> PaceLimit {
        PaceLimit {
            max_hours,
            checked: false,
        }
    }

    /// After `done` of `total` steps in `elapsed` seconds: an error if the run would take more
    /// than the limit (checked once, after [`MEASURE`]).
    pub fn check(&mut self, done: u64, total: u64, elapsed: f64) -> Result<(), Refused> {
        if self.checked || elapsed < MEASURE.as_secs_f64() || done == 0 {
            return Ok(());
        }
        self.checked = true;
        let estimate = elapsed * total as f64 / done as f64;
        budget::check_hours(
            &format!("the run of {total} steps"),
            estimate,
            &format!(
                "at the pace of its first {done} steps, {:.3e} s each",
                elapsed / done as f64
            ),
            self.max_hours,
        )
    }
}
