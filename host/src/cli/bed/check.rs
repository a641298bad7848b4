//! `dashpot bed --check`: the disks, the peak memory and the wall time of a bed run, estimated
//! from a timed sample of the bed's own run on this machine; and the pace of a bed run judged
//! against `--max-hours`.

use crate::bed::engine::Bed;
use crate::bed::spec::{BedEngine, BedSpec};
use crate::bed::Laws;
use crate::budget::{self, Memory, Need};
use crate::dem::footprint::Footprint;
use crate::registry::Registry;
use anyhow::Result;
use std::time::{Duration, Instant};

/// How long the sample of a bed runs (wall time).
pub const SAMPLE: Duration = Duration::from_secs(1);

/// What `bed --check` estimates.
#[derive(Debug, Clone)]
pub struct BedEstimate {
    /// Disks.
    pub disks: usize,
    /// Simulated time of one seed's protocol (s).
    pub simulated: f64,
    /// Seeds, and how many run at once.
    pub seeds: usize,
    /// Runs at once (the thread pool's width).
    pub at_once: usize,
    /// DEM steps per seed (none on the event-driven engine).
    pub steps: Option<u64>,
    /// Peak memory, by part.
    pub memory: Need,
    /// The memory available.
    pub available: Memory,
    /// Simulated time of the sample (s) and its wall time (s).
    pub sample: (f64, f64),
    /// Wall time per simulated second of the measured periods, if they run otherwise than the
    /// transient (the DEM bed steps one step at a time there, to sample its observables).
    pub measured_pace: Option<f64>,
    /// The transient's share of the simulated time.
    pub transient_share: f64,
    /// Wall time to set a run up (s), measured: building it (twice on the DEM engine, which
    /// builds one to print the step first).
    pub setup_seconds: f64,
}

impl BedEstimate {
    /// Wall time of the whole run (s): the seeds in waves of `at_once`, each at the sample's
    /// pace.
    pub fn total_seconds(&self) -> f64 {
        let waves = self.seeds.div_ceil(self.at_once.max(1)) as f64;
        let pace = self.sample.1 / self.sample.0.max(1e-300);
        let measured = self.measured_pace.unwrap_or(pace);
        let (t, m) = (self.transient_share, 1.0 - self.transient_share);
        self.setup_seconds + waves * self.simulated * (t * pace + m * measured)
    }

    /// As JSON.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "disks": self.disks,
            "simulated_seconds": self.simulated,
            "seeds": self.seeds,
            "steps": self.steps,
            "memory_bytes": self.memory.total(),
            "memory_available_bytes": self.available.available,
            "memory_available_source": self.available.source,
            "sample_simulated_seconds": self.sample.0,
            "sample_wall_seconds": self.sample.1,
            "wall_seconds": self.total_seconds(),
        })
    }

    /// As lines of text.
    pub fn lines(&self) -> Vec<String> {
        let mut v = vec![format!(
            "bed: {} disks, {:.4} s simulated per seed, {} seed(s){}",
            self.disks,
            self.simulated,
            self.seeds,
            self.steps
                .map(|s| format!(", {s} DEM steps each"))
                .unwrap_or_default()
        )];
        v.push(format!(
            "peak memory: about {} ({}); {} available ({})",
            budget::bytes(self.memory.total()),
            self.memory.breakdown(),
            budget::bytes(self.available.available as f64),
            self.available.source
        ));
        v.push(format!(
            "wall time: about {} (a sample of {:.4} s simulated took {:.3} s on this machine now; the pace changes as the bed leaves its initial state, and with the machine's load)",
            budget::seconds(self.total_seconds()),
            self.sample.0,
            self.sample.1
        ));
        v
    }
}

/// The estimate of the bed `spec` (checked): builds one run, runs it for about [`SAMPLE`] of
/// wall time, and scales.
pub fn estimate(reg: &Registry, spec: &BedSpec) -> Result<BedEstimate> {
    spec.validate()?;
    let clock = Instant::now();
    let cfg = spec.config;
    let period = 1.0 / cfg.freq;
    let simulated = (spec.transient + spec.cycles) * period;
    let at_once = spec.seeds.min(rayon::current_num_threads().max(1));
    let disks = cfg.disks();
    match &spec.engine {
        BedEngine::Event { .. } => {
            let laws = spec.restitution_laws(reg)?;
            let laws = Laws {
                disk: &laws.disk,
                wall: &laws.wall,
            };
            let mut bed = Bed::new(cfg, laws)?;
            let setup = clock.elapsed().as_secs_f64();
            // simulated time in doubling slices until the budget is spent
            let (t0, w0) = (bed.now(), Instant::now());
            let mut slice = period / 64.0;
            let mut half = (t0, w0);
            while w0.elapsed() < SAMPLE && bed.now() - t0 < simulated {
                let end = (bed.now() + slice).min(t0 + simulated);
                bed.run_until(end, &mut |_| {})?;
                if w0.elapsed() < SAMPLE / 2 {
                    half = (bed.now(), Instant::now());
                }
                slice *= 2.0;
            }
            let sample = (bed.now() - half.0, half.1.elapsed().as_secs_f64());
            Ok(BedEstimate {
                disks,
                simulated,
                seeds: spec.seeds,
                at_once,
                steps: None,
                memory: budget::bed_need(disks as f64, at_once as f64, 0.0),
                available: Memory::now(),
                sample: if sample.0 > 0.0 {
                    sample
                } else {
                    (bed.now() - t0, w0.elapsed().as_secs_f64())
                },
                measured_pace: None,
                transient_share: spec.transient / (spec.transient + spec.cycles),
                setup_seconds: setup,
            })
        }
        BedEngine::Dem { .. } => {
            let dem = spec.dem_bed(cfg);
            let laws = spec.dem_laws(reg, &dem.material)?;
            let mut fp = Footprint::of(&crate::dem::EngineConfig::<2>::new(dem.material), &laws, disks, 2);
            let mut e = dem.engine(laws)?;
            let setup = clock.elapsed().as_secs_f64();
            let steps = budget::check_steps("the DEM bed", e.dt(), simulated, disks, "")?;
            // the transient in blocks (as the run steps it), then single steps (as the measured
            // periods step, sampling the observables), each for half the sample
            let half = SAMPLE / 2;
            let transient = ((spec.transient * period / e.dt()) as u64).min(steps);
            let (blocks, single) = {
                let w0 = Instant::now();
                let (mut done, mut k) = (0u64, 1u64);
                while done < transient && w0.elapsed() < half {
                    let k_now = k.min(transient - done);
                    e.advance(k_now)?;
                    done += k_now;
                    k *= 2;
                }
                let blocks = (done, w0.elapsed().as_secs_f64());
                let w1 = Instant::now();
                let mut one = 0u64;
                while done + one < steps && (w1.elapsed() < half || one == 0) {
                    e.step()?;
                    let _ = e.temperature();
                    one += 1;
                }
                (blocks, (one, w1.elapsed().as_secs_f64()))
            };
            let dt = e.dt();
            fp.listed = Some(e.listed_pairs());
            fp.sampled = Some(e.pairs.len());
            let one = fp.need();
            let mut memory = Need::new();
            memory.holding(one.resident);
            memory.add("the runs at once", at_once as f64 * one.more());
            Ok(BedEstimate {
                disks,
                simulated,
                seeds: spec.seeds,
                at_once,
                steps: Some(steps),
                memory,
                available: Memory::now(),
                // (no transient: the measured periods' pace for both)
                sample: if blocks.0 > 0 {
                    (blocks.0 as f64 * dt, blocks.1)
                } else {
                    (single.0 as f64 * dt, single.1)
                },
                measured_pace: (single.0 > 0).then(|| single.1 / (single.0 as f64 * dt)),
                transient_share: spec.transient / (spec.transient + spec.cycles),
                setup_seconds: 2.0 * setup,
            })
        }
    }
}

/// `dashpot bed --check`: prints the estimate (or returns it as the `--json` document).
pub fn check(
    reg: &Registry,
    spec: &BedSpec,
    json: bool,
    max_hours: f64,
) -> Result<Option<serde_json::Value>> {
    let est = estimate(reg, spec)?;
    budget::check_hours(
        "the bed run",
        est.total_seconds(),
        "estimated from a timed sample of its run",
        max_hours,
    )?;
    if json {
        return Ok(Some(
            serde_json::json!({ "checks": "passed", "estimate": est.json() }),
        ));
    }
    println!("every check passed (not run: a timed sample, nothing written)");
    est.lines().iter().for_each(|l| println!("{l}"));
    Ok(None)
}

/// The `--max-hours` limit of a bed run, judged from its progress: once [`crate::cli::budget::MEASURE`]
/// of wall time has passed, the wall time the whole protocol (`simulated` seconds per seed) would
/// take at the pace so far; past `max_hours`, [`PaceWatch::tick`] unwinds with the refusal, which
/// [`watch`] turns back into an error.
pub struct PaceWatch {
    started: Instant,
    simulated: f64,
    max_hours: f64,
    judged: std::sync::atomic::AtomicBool,
}

impl PaceWatch {
    /// A watch over a run of `simulated` seconds (simulated time) per seed, `waves` seeds one
    /// after the other (the seeds in parallel, as many at once as threads).
    pub fn new(simulated: f64, waves: f64, max_hours: f64) -> PaceWatch {
        PaceWatch {
            started: Instant::now(),
            simulated: simulated * waves.max(1.0),
            max_hours,
            judged: std::sync::atomic::AtomicBool::new(false),
        }
    }

    /// A run has reached simulated time `t` (s).
    pub fn tick(&self, t: f64) {
        use std::sync::atomic::Ordering;
        let wall = self.started.elapsed();
        if wall < crate::cli::budget::MEASURE || t <= 0.0 || self.judged.swap(true, Ordering::Relaxed) {
            return;
        }
        let estimate = wall.as_secs_f64() * self.simulated / t;
        if let Err(r) = budget::check_hours(
            &format!("the bed run of {:.4e} s simulated", self.simulated),
            estimate,
            &format!("at the pace of its first {t:.4e} s simulated"),
            self.max_hours,
        ) {
            std::panic::resume_unwind(Box::new(r));
        }
    }
}

/// Runs `f`, which calls [`PaceWatch::tick`] from its progress; a refusal unwound from there
/// becomes this error.
pub fn watch<T>(f: impl FnOnce() -> Result<T>) -> Result<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => match p.downcast::<budget::Refused>() {
            Ok(r) => Err((*r).into()),
            Err(p) => std::panic::resume_unwind(p),
        },
    }
}
