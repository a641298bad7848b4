//! McNamara & Falcon's vibrated bed on the soft-sphere engine: the event-driven bed's geometry
//! (`crate::bed::BedConfig`: N = round(n L/d) disks of diameter d in a box of width L,
//! periodic sideways, a piston of two joined parabolas below, a fixed lid at A/2 + n d + (h − h0)),
//! but every contact is a contact law acting over time, with friction if a tangential law is
//! given. Steel disks by default (E = 200 GPa, ν = 0.3, ρ = 7800 kg/m³, the mass of a 2 mm steel
//! sphere, 3.27×10⁻⁵ kg, as the paper's); `young` softens them.
//!
//! Measured after the transient, as the event-driven bed does: the lid pressure P = I/(T L) from
//! the impulse I the lid received over the measured time T; the lid collision rate counted per
//! contact *episode* (a disk touching the lid, however long); the mean impulse per episode; the
//! temperature, the mean translational kinetic energy per disk sampled 64 times a period. The
//! statistical error of P is the standard error of its means over blocks of periods.

use super::scene::packing;
use super::state::{DiskMass, Material, VecD};
use super::walls::{Motion, Wall};
use super::{DemError, Domain, Engine, EngineConfig, Laws};
use crate::bed::piston::Piston;
use crate::bed::BedConfig;

/// The DEM bed's settings beyond the bed's geometry.
#[derive(Debug, Clone)]
pub struct DemBed {
    /// Geometry, frequency, gravity, seed (the event-driven bed's; `mass`, `tangential` and `tc`
    /// are not used: the mass comes from the material, friction from a tangential law, and a
    /// soft contact needs no TC model).
    pub bed: BedConfig,
    /// The disks' material (2D mass convention: a sphere's).
    pub material: Material,
    /// The step (s), or chosen from the law.
    pub dt: Option<f64>,
    /// Steps per collision when the step is chosen.
    pub steps_per_collision: f64,
}

/// What a DEM bed run measured (the event-driven bed's keys, plus the step).
#[derive(Debug, Clone, serde::Serialize)]
pub struct DemBedReport {
    /// Number of disks N.
    pub disks: usize,
    /// Lid height (m).
    pub lid: f64,
    /// Piston peak speed V = 4Af (m/s).
    pub piston_speed: f64,
    /// Measured time (s).
    pub measured_time: f64,
    /// Lid pressure P (N/m).
    pub pressure: f64,
    /// Standard error of P from block means (N/m).
    pub pressure_error: f64,
    /// Lid contact episodes per second (1/s).
    pub lid_collision_rate: f64,
    /// Mean impulse per lid episode (N·s).
    pub mean_impulse: f64,
    /// Mean translational kinetic energy per disk (J).
    pub temperature: f64,
    /// The step (s).
    pub dt: f64,
    /// The contact time the step was chosen from (s).
    pub collision_time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Young's modulus used (Pa).
    pub young: f64,
    /// Wall time (s).
    pub wall_seconds: f64,
}

impl DemBed {
    /// Steel disks in the paper's bed with `layers` layers at `freq` (Hz).
    pub fn paper(layers: f64, freq: f64) -> DemBed {
        DemBed {
            bed: BedConfig::paper(layers, freq),
            material: Material {
                disk_mass: DiskMass::Sphere,
                ..Material::STEEL
            },
            dt: None,
            steps_per_collision: 50.0,
        }
    }

    /// The engine at t = 0: disks on a jittered lattice above the piston (at its lowest), random
    /// velocities of magnitude `initial_speed`.
    pub fn engine(&self, laws: Laws) -> Result<Engine<2>, DemError> {
        let b = &self.bed;
        b.validate().map_err(|e| DemError::Invalid(e.to_string()))?;
        let n = b.disks();
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
                + (2.0 * b.gravity * (lid - bottom)).sqrt()
                + 2.0 * b.initial_speed,
        );
        cfg.domain = Domain {
            lo: VecD::<2>::new(0.0, bottom - b.amplitude - d),
            hi: VecD::<2>::new(b.width, lid + d),
            periodic: [true, false],
            bounded: true,
        };
        let piston = Wall {
            point: VecD::<2>::new(0.0, 0.0),
            normal: VecD::<2>::new(0.0, 1.0),
            motion: Motion::Piston(Piston::new(b.amplitude, b.freq)),
        };
        let lid_wall = Wall::fixed(VecD::<2>::new(0.0, lid), VecD::<2>::new(0.0, -1.0));
        Engine::new(cfg, &bodies, vec![piston, lid_wall], laws)
    }

    /// Runs `transient` periods, then measures over `cycles` periods.
    pub fn run(
        &self,
        laws: Laws,
        transient: f64,
        cycles: f64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<DemBedReport, DemError> {
        if !(transient.is_finite() && transient >= 0.0) {
            return Err(DemError::Invalid(format!(
                "transient = {transient} periods is out of range: must be >= 0"
            )));
        }
        if !(cycles.is_finite() && cycles >= 1.0) {
            return Err(DemError::Invalid(format!(
                "cycles = {cycles} periods is out of range: must be >= 1"
            )));
        }
        let clock = std::time::Instant::now();
        let mut e = self.engine(laws)?;
        let period = 1.0 / self.bed.freq;
        let every = ((period / e.dt()) as u64 / 64).max(1);
        e.run_until(transient * period, every, progress)?;
        e.reset_wall_counters();
        let t0 = e.time();
        let sample = period / 64.0;
        let mut next_sample = t0;
        let (mut ke, mut samples) = (0.0, 0u64);
        // block means of the lid impulse: about 20 blocks
        let blocks = (cycles.floor() as usize).clamp(1, 20);
        let block_len = cycles * period / blocks as f64;
        let mut block_impulse = Vec::with_capacity(blocks);
        let mut last = 0.0;
        let end = t0 + cycles * period;
        while e.time() + 0.5 * e.dt() < end {
            e.step()?;
            if e.time() >= next_sample {
                ke += e.temperature();
                samples += 1;
                next_sample += sample;
            }
            if e.time() >= t0 + (block_impulse.len() + 1) as f64 * block_len - 0.5 * e.dt()
                && block_impulse.len() < blocks
            {
                let now = e.wall_impulse[1].y;
                block_impulse.push(now - last);
                last = now;
            }
            if e.steps() % every == 0 {
                progress(e.time());
            }
        }
        let tm = e.time() - t0;
        let w = self.bed.width;
        let impulse = e.wall_impulse[1].y;
        let episodes = e.wall_episodes[1];
        let pressure = impulse / (tm * w);
        let pb: Vec<f64> = block_impulse.iter().map(|i| i / (block_len * w)).collect();
        let k = pb.len() as f64;
        let mean = pb.iter().sum::<f64>() / k;
        let var = if k > 1.0 {
            pb.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (k - 1.0)
        } else {
            f64::NAN
        };
        Ok(DemBedReport {
            disks: e.p.len(),
            lid: self.bed.lid(),
            piston_speed: Piston::new(self.bed.amplitude, self.bed.freq).peak_speed(),
            measured_time: tm,
            pressure,
            pressure_error: (var / k).sqrt(),
            lid_collision_rate: episodes as f64 / tm,
            mean_impulse: if episodes > 0 {
                impulse / episodes as f64
            } else {
                0.0
            },
            temperature: if samples > 0 { ke / samples as f64 } else { 0.0 },
            dt: e.dt(),
            collision_time: e.step_choice.collision_time,
            steps: e.steps(),
            young: self.material.young,
            wall_seconds: clock.elapsed().as_secs_f64(),
        })
    }
}
