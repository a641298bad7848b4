//! McNamara & Falcon's vibrated bed on the soft-sphere engine: the event-driven bed's geometry
//! (`crate::bed::BedConfig`: N = round(n L/d) disks of diameter d in a box of width L,
//! periodic sideways, a piston of two joined parabolas below, a fixed lid at A/2 + n d + (h − h0)),
//! but every contact is a contact law acting over time, with friction if a tangential law is
//! given. Steel disks by default (E = 200 GPa, ν = 0.3, ρ = 7800 kg/m³, the mass of a 2 mm steel
//! sphere, 3.27×10⁻⁵ kg, as the paper's); `young` softens them.
//!
//! Measured after the transient, as the event-driven bed does, under the same JSON keys: the lid
//! pressure P = I/(T L) from the impulse I the lid received over the measured time T; the lid
//! collision rate counted per contact *episode* (a disk touching the lid, however long); the mean
//! impulse per episode; the temperature, the mean translational kinetic energy per disk sampled
//! 64 times a period; the piston pressure. Each one's statistical error (`*_stderr`) is the
//! standard error of its values over blocks of periods (up to 20 blocks), or, over independent
//! seeds, of the seeds' values ([`DemBedReport::combine`]).
//!
//! The disks' mass is the bed's `mass` (the density follows from it), so that the event-driven
//! bed's `from:LAW` tables and this engine bind the laws to the same particle.

use crate::bed::engine::SAMPLES_PER_PERIOD;
use crate::bed::observables::{measured_report, stderr_of, BedObservables};
use crate::bed::BedConfig;
use crate::dem::scene::packing;
use crate::dem::state::{DiskMass, Material, VecD};
use crate::dem::walls::{Motion, Wall};
use crate::dem::{DemError, Domain, Engine, EngineConfig, Laws};
use crate::piston::Piston;

/// The error for a measuring window of `cycles` periods of `period` (s) in `blocks` blocks
/// whose blocks are shorter than a step `dt` (s).
fn too_short(cycles: f64, period: f64, blocks: usize, dt: f64) -> DemError {
    DemError::Invalid(format!(
        "cycles = {cycles} periods ({:e} s in {blocks} blocks) is too short: each block must span at least one step of dt = {dt:e} s",
        cycles * period
    ))
}

/// The DEM bed's settings beyond the bed's geometry.
#[derive(Debug, Clone)]
pub struct DemBed {
    /// Geometry, frequency, gravity, mass, seed (the event-driven bed's; `tangential` and `tc`
    /// must be unset: friction comes from a tangential law, and a soft contact needs no TC model).
    pub bed: BedConfig,
    /// The disks' material (2D mass convention: a sphere's; density from the bed's mass).
    pub material: Material,
    /// The step (s), or chosen from the law.
    pub dt: Option<f64>,
    /// Steps per collision when the step is chosen.
    pub steps_per_collision: f64,
}

/// What a DEM bed run measured ([`BedObservables`], under the event-driven bed's JSON keys and
/// read through `report.pressure`, ...), and the step it took.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DemBedReport {
    /// The observables (their JSON keys at the report's top level).
    #[serde(flatten)]
    pub measured: BedObservables,
    /// Lid contact episodes counted.
    pub lid_episodes: u64,
    /// The step (s).
    pub dt: f64,
    /// The contact time at `impact_speed` the step was chosen from (s).
    pub collision_time: f64,
    /// The impact speed the contact time was computed at (m/s).
    pub impact_speed: f64,
    /// Whether the step was given (`--dt`) rather than chosen.
    pub dt_given: bool,
    /// Steps taken (per seed).
    pub steps: u64,
    /// Young's modulus used (Pa).
    pub young: f64,
    /// Poisson's ratio used.
    pub poisson: f64,
    /// Density of the disks (kg/m³), from the bed's mass.
    pub density: f64,
}

measured_report!(DemBedReport);

impl DemBedReport {
    /// The mean of independent runs ([`BedObservables::combine`]), lid episodes summed (one run:
    /// itself).
    pub fn combine(runs: &[DemBedReport]) -> Option<DemBedReport> {
        let mut r = runs.first()?.clone();
        r.measured = BedObservables::combine(runs.iter().map(|r| &r.measured))?;
        r.lid_episodes = runs.iter().map(|r| r.lid_episodes).sum();
        Some(r)
    }
}

impl DemBed {
    /// Steel disks in the paper's bed with `layers` layers at `freq` (Hz).
    pub fn paper(layers: f64, freq: f64) -> DemBed {
        DemBed::new(BedConfig::paper(layers, freq), None, None)
    }

    /// The bed `bed` with disks of Young's modulus `young` (Pa; default steel, 2×10¹¹) and
    /// Poisson's ratio `poisson` (default 0.3), of the bed's mass (the density follows).
    pub fn new(bed: BedConfig, young: Option<f64>, poisson: Option<f64>) -> DemBed {
        let d = bed.diameter;
        DemBed {
            material: Material {
                young: young.unwrap_or(crate::bed::STEEL_YOUNG),
                poisson: poisson.unwrap_or(crate::bed::STEEL_POISSON),
                density: bed.mass / (std::f64::consts::PI / 6.0 * d * d * d),
                disk_mass: DiskMass::Sphere,
            },
            bed,
            dt: None,
            steps_per_collision: 50.0,
        }
    }

    /// Checks the bed for soft disks: its configuration, and neither rough disks nor the TC
    /// model (the event-driven engine's: friction comes from a tangential law, and a soft
    /// contact needs no TC model).
    pub fn check(&self) -> Result<(), crate::bed::BedError> {
        let b = &self.bed;
        b.validate()?;
        let bad = |s: String| Err(crate::bed::BedError::Invalid(s));
        if let Some(rt) = b.tangential {
            return bad(format!(
                "tangential restitution r_t = {rt} is the event-driven engine's rough-disk model: the DEM bed takes a tangential law (e.g. mindlin) instead"
            ));
        }
        if let Some(tc) = b.tc {
            return bad(format!(
                "--tc {tc} is the event-driven engine's TC model: soft contacts need none, leave it unset with the DEM engine"
            ));
        }
        Ok(())
    }

    /// The engine at t = 0: disks on a jittered lattice above the piston (at its lowest), random
    /// velocities of magnitude `initial_speed`.
    pub fn engine(&self, laws: Laws) -> Result<Engine<2>, DemError> {
        let b = &self.bed;
        self.check().map_err(|e| DemError::Invalid(e.to_string()))?;
        let n = b.disks();
        // (before the disks are made: a bed past the machine's memory is refused)
        crate::dem::footprint::check_count("the bed's disks N = n L/d", n, 2)
            .map_err(|e| DemError::Invalid(format!("{e}; lower --layers")))?;
        let d = b.diameter;
        let bottom = -0.5 * b.amplitude;
        let lid = b.lid();
        let bodies = packing::<2>(
            n,
            d,
            d,
            VecD::<2>::new(0.0, bottom + 0.01 * d),
            VecD::<2>::new(b.width, lid - 0.01 * d),
            b.initial_speed,
            b.seed,
        )
        .map_err(|e| DemError::Invalid(e.to_string()))?;
        let mut cfg = EngineConfig::<2>::new(self.material);
        cfg.gravity = VecD::<2>::new(0.0, -b.gravity);
        cfg.dt = self.dt;
        cfg.steps_per_collision = self.steps_per_collision;
        // the fastest impacts: a disk meeting the piston at its peak speed after falling the box
        cfg.impact_speed = Some(
            2.0 * Piston::new(b.amplitude, b.freq).peak_speed()
                + (2.0 * b.gravity.abs() * (lid - bottom)).sqrt()
                + 2.0 * b.initial_speed,
        );
        cfg.domain = Domain {
            lo: VecD::<2>::new(0.0, bottom - b.amplitude - d),
            hi: VecD::<2>::new(b.width, lid + d),
            periodic: [true, false],
            bounded: true,
        };
        let piston = Wall::plane(
            VecD::<2>::new(0.0, 0.0),
            VecD::<2>::new(0.0, 1.0),
            Motion::Piston(Piston::new(b.amplitude, b.freq)),
        );
        let lid_wall = Wall::fixed(VecD::<2>::new(0.0, lid), VecD::<2>::new(0.0, -1.0));
        Engine::new(cfg, &bodies, vec![piston, lid_wall], laws)
    }

    /// Runs `transient` periods, then measures over `cycles` periods; `progress(t)` is called
    /// with the simulated time every 1/64 period or so.
    pub fn run(
        &self,
        laws: Laws,
        transient: f64,
        cycles: f64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<DemBedReport, DemError> {
        BedConfig::check_protocol(transient, cycles).map_err(|e| DemError::Invalid(e.to_string()))?;
        let clock = std::time::Instant::now();
        let mut e = self.engine(laws)?;
        let period = 1.0 / self.bed.freq;
        // a step count past any machine's reach is refused before the first step
        crate::budget::check_steps(
            "the DEM bed",
            e.dt(),
            (transient + cycles) * period,
            e.p.len(),
            "a stiffer material than meant (--young), a far smaller --dt or too many --steps-per-collision, or a protocol (--transient, --cycles, --freq) far longer than meant",
        )
        .map_err(|r| DemError::Invalid(r.0))?;
        // block sums: time, lid impulse, piston impulse, lid episodes, kinetic energy, samples
        let blocks = (cycles.floor() as usize).clamp(1, 20);
        let block_len = cycles * period / blocks as f64;
        if block_len < e.dt() {
            return Err(too_short(cycles, period, blocks, e.dt()));
        }
        let every = ((period / e.dt()) as u64 / 64).max(1);
        e.run_until(transient * period, every, progress)?;
        e.reset_wall_counters();
        let t0 = e.time();
        let sample = period / SAMPLES_PER_PERIOD as f64;
        let mut next_sample = t0;
        let mut rows: Vec<[f64; 6]> = Vec::with_capacity(blocks);
        let (mut lid0, mut pis0, mut ep0, mut tb0) = (0.0, 0.0, 0u64, t0);
        for b in 0..blocks {
            let end = t0 + (b + 1) as f64 * block_len;
            let (mut ke, mut samples) = (0.0, 0.0);
            while e.time() + 0.5 * e.dt() < end {
                e.step()?;
                if e.time() >= next_sample {
                    ke += e.temperature();
                    samples += 1.0;
                    next_sample += sample;
                }
                if e.steps() % every == 0 {
                    progress(e.time());
                }
            }
            let (lid, pis, ep) = (e.wall_impulse[1].y, -e.wall_impulse[0].y, e.wall_episodes[1]);
            rows.push([
                e.time() - tb0,
                lid - lid0,
                pis - pis0,
                (ep - ep0) as f64,
                ke,
                samples,
            ]);
            (lid0, pis0, ep0, tb0) = (lid, pis, ep, e.time());
        }
        let tm = e.time() - t0;
        // a block that took no step would give 0/0 rates
        if rows.iter().any(|r| r[0] <= 0.0 || r[0].is_nan()) {
            return Err(too_short(cycles, period, blocks, e.dt()));
        }
        let w = self.bed.width;
        let sum = |k: usize| rows.iter().map(|r| r[k]).sum::<f64>();
        let (impulse, piston, episodes, ke, samples) = (sum(1), sum(2), sum(3), sum(4), sum(5));
        let se =
            |f: &dyn Fn(&[f64; 6]) -> Option<f64>| stderr_of(&rows.iter().filter_map(f).collect::<Vec<_>>());
        let c = e.step_choice;
        let wall = clock.elapsed().as_secs_f64();
        Ok(DemBedReport {
            measured: BedObservables {
                config: self.bed,
                disks: e.p.len(),
                lid: self.bed.lid(),
                piston_speed: Piston::new(self.bed.amplitude, self.bed.freq).peak_speed(),
                measured_time: tm,
                pressure: impulse / (tm * w),
                lid_collision_rate: episodes / tm,
                mean_impulse: (episodes > 0.0).then(|| impulse / episodes),
                temperature: if samples > 0.0 { ke / samples } else { 0.0 },
                pressure_stderr: se(&|r| Some(r[1] / (r[0] * w))),
                lid_collision_rate_stderr: se(&|r| Some(r[3] / r[0])),
                mean_impulse_stderr: se(&|r| (r[3] > 0.0).then(|| r[1] / r[3])),
                temperature_stderr: se(&|r| (r[5] > 0.0).then(|| r[4] / r[5])),
                piston_pressure: piston / (tm * w),
                piston_pressure_stderr: se(&|r| Some(r[2] / (r[0] * w))),
                seeds: 1,
                wall_seconds: wall,
                wall_per_simulated_second: wall / e.time().max(1e-300),
            },
            lid_episodes: episodes as u64,
            dt: e.dt(),
            collision_time: c.collision_time,
            impact_speed: c.impact_speed,
            dt_given: c.given,
            steps: e.steps(),
            young: self.material.young,
            poisson: self.material.poisson,
            density: self.material.density,
        })
    }
}
