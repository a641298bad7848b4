//! The engine and its step.
//!
//! Scheme: velocity Verlet (kick–drift–kick), second order and symplectic for conservative
//! forces, with two additions for dissipative contacts:
//!
//! - the overlap rate the normal law sees at the end of the step comes from a *predicted*
//!   end-of-step velocity rather than the half-step one, whose lag of dt/2 makes the dissipated
//!   energy first order in dt. The predictor is v(t + dt/2) + (dt/2)(2 a(t) − a(t − dt)): the
//!   acceleration extrapolated linearly to the step's end, second order (v(t) + dt·a(t), the
//!   first-order predictor, left an error of 1e-3 in the restitution at 50 steps per contact);
//! - the first and the last step of a contact take the mean force over the part of the step in
//!   contact ([`super::contacts::ContactSet::evaluate`]): the force switches on and off with a
//!   kink (HSD's damping grows as δ^{1/4}) that the step-end rule integrates only to dt^{5/4}.
//!
//! With them, a disk dropped on a floor under HSD bounces with ε to within 1.4e-4 at 50 steps
//! per contact whatever the phase of the first touch within a step (without: 4e-3 at worst,
//! 1.4e-3 at the test's phase). The tangential laws get the slip of the contact points over
//! the step (half-step v and ω), so that slip × dt is the step's tangential displacement
//! exactly (the Mindlin plugin's stated convention). Elastic and frictionless, between the first
//! and last steps of contacts the scheme is velocity Verlet.
//!
//! Time step: unless given, τ/`steps_per_collision` where τ is the contact time of the smallest
//! particle against an equal one and against a wall at the largest expected impact speed, found
//! by the two-body driver with the run's own law (so it is the law's stiffness that sets it).
//! A step, given or chosen, must resolve that contact by at least
//! [`MIN_STEPS_PER_COLLISION`] steps, below which the explicit scheme is unstable.

use super::cells::Neighbours;
use super::contacts::{gather_chunk_classes, nearest_first, parallel, Contacts};
use super::species::SpeciesLaws;
use super::state::{spin_len, to3, Body, Particles, Vec3, VecD};
use super::walls::{Wall, WallState};
use super::{DemError, Laws};
use rayon::prelude::*;

mod awake;
mod config;
mod forces;
mod heat;
mod kernels;
mod order;
mod pipeline;
mod snapshot;

pub use config::*;
use config::{collision_time, impact_speed, reach_bound};
use kernels::*;
pub use order::SORT_PERIOD;
pub use snapshot::EngineState;

/// A soft-sphere DEM run.
pub struct Engine<const D: usize> {
    /// The particles, in the user's numbering between calls (see [`Engine::user_index`] and
    /// [`Engine::advance_held`]). Between steps, velocities and spins may be edited freely;
    /// positions only followed by [`Engine::invalidate_neighbours`] (the neighbour list's
    /// staleness is tracked from the particles' speeds, so a particle moved by hand is not
    /// seen to have moved); radii, masses and moments of inertia are fixed at construction.
    pub p: Particles<D>,
    /// The walls.
    pub walls: Vec<Wall<D>>,
    laws: SpeciesLaws,
    /// Each particle's species, in the engine's order (empty: every particle is of species 0,
    /// the run has one).
    species: Vec<u8>,
    /// The wall of each surface (see [`Engine::wall_states`]).
    surface_wall: Vec<usize>,
    /// The class of species `s` against surface `k`, `surface_class[s * surfaces + k]` (the
    /// laws' wall classes, surface by surface; empty: one class).
    surface_class: Vec<u8>,
    /// Whether some wall moves (its work on the particles is then accounted).
    walls_move: bool,
    cfg: EngineConfig<D>,
    /// The step and how it was chosen.
    pub step_choice: StepChoice,
    dt: f64,
    t: f64,
    steps: u64,
    nb: Neighbours<D>,
    skin: f64,
    /// The largest reach of an adhesive normal law (m; 0 for others): the neighbour list reaches
    /// that much further.
    law_reach: f64,
    /// Particle-pair contacts of the last evaluation.
    pub pairs: Contacts,
    /// Particle–wall contacts of the last evaluation.
    pub wall_contacts: Contacts,
    vpred: Vec<VecD<D>>,
    /// Each particle's acceleration at the previous step (the predictor's extrapolation).
    aold: Vec<VecD<D>>,
    /// 1/m and 1/I of each particle (the kicks multiply: a division per component and particle
    /// was a tenth of a step). Masses and moments of inertia are fixed at construction.
    inv_mass: Vec<f64>,
    inv_inertia: Vec<f64>,
    /// Per chunk of contacts, the forces and torques on particles of later chunks (the
    /// partner j of a pair contact whose i is in the chunk), added after the chunks' own.
    overflow: Vec<Overflow<D>>,
    /// For each chunk of particles, the last chunk holding a pair partner of one of its
    /// particles (in the current neighbour list).
    reach: Vec<usize>,
    /// For each chunk of particles, the first chunk reaching it (see `reach`).
    back: Vec<usize>,
    /// For each chunk of particles, the time its drift and forces take (s; 0: not measured
    /// yet), learnt from the steps on several threads: where to cut the chunks between them.
    cost: Vec<f64>,
    /// Each chunk's time at the last such step (s).
    took: Vec<f64>,
    /// For each chunk of particles, a bound on their displacement since the list was built (m)
    /// (see [`kick_drift_chunk`]).
    moved: Vec<f64>,
    /// The last step's second half-kick is still to do ([`Engine::advance`]).
    pending_kick: bool,
    /// Impulse (N·s) given to each wall since the last reset (force on the wall × dt, summed).
    pub wall_impulse: Vec<VecD<D>>,
    /// Contact episodes with each wall since the last reset (first touches).
    pub wall_episodes: Vec<u64>,
    /// Particle-pair contact episodes since the start.
    pub pair_episodes: u64,
    /// Energy dissipated since the start (J) by the normal, tangential, rolling and twisting
    /// laws: each contact's reported power × dt, summed at every step (with
    /// [`EngineConfig::energy`]).
    pub dissipated: [f64; 4],
    /// The families whose law did not report its energy at some step (their share in
    /// [`Engine::dissipated`] is then incomplete).
    pub unreported: [bool; 4],
    /// The work the moving walls have done on the particles since the start (J): each wall
    /// contact's force on its particle · the wall's velocity at the contact × dt, summed at
    /// every step (with [`EngineConfig::energy`]; 0 while no wall moves). The books:
    /// initial + wall work = kinetic + gravity + elastic + dissipated.
    pub wall_work: f64,
    /// The engine's memory order (see [`Engine::user_index`]).
    order: order::Order<D>,
    /// Particles per chunk of contacts, the unit of parallel work ([`gather_chunk`] of the
    /// particle count).
    chunk: usize,
    /// Whether each particle's force sums the shares of earlier chunks' contacts nearest chunk
    /// first, else farthest first ([`nearest_first`] of the chunk).
    nearest_first: bool,
    /// Whether the steps run in parallel on a pool of several threads: [`parallel`] of the
    /// pile's size and chunk, but for the blocks of [`Engine::advance`] that [`awake::Pace`]
    /// runs on one thread.
    parallel: bool,
    /// Which of a parallel and a serial block is faster for this pile now.
    pace: awake::Pace,
    /// The temperatures, in a run with heat ([`Engine::with_heat`]).
    heat: Option<Box<heat::Thermal>>,
}

impl<const D: usize> Engine<D> {
    /// A run of `bodies` between `walls` under `laws`, all of the material
    /// [`EngineConfig::material`]; the step is chosen (or checked) here and the forces of the
    /// initial state evaluated.
    pub fn new(
        cfg: EngineConfig<D>,
        bodies: &[Body<D>],
        walls: Vec<Wall<D>>,
        laws: Laws,
    ) -> Result<Engine<D>, DemError> {
        let table = SpeciesLaws::single(laws, cfg.material);
        Engine::with_species(cfg, bodies, &[], walls, table)
    }

    /// A run of `bodies` of the species `species` (one per body, indices into `laws.species`;
    /// empty: every body of species 0) between `walls`, each contact under the laws of its
    /// class in `laws` (see [`crate::dem::species`]); each particle's mass and moment of
    /// inertia from its species' material ([`EngineConfig::material`] is not used). The step
    /// is chosen (or checked) against every class, and the forces of the initial state
    /// evaluated. A table of one species and one class of each kind runs exactly as
    /// [`Engine::new`].
    pub fn with_species(
        cfg: EngineConfig<D>,
        bodies: &[Body<D>],
        species: &[u8],
        walls: Vec<Wall<D>>,
        laws: SpeciesLaws,
    ) -> Result<Engine<D>, DemError> {
        if !(D == 2 || D == 3) {
            return Err(DemError::Invalid(format!("dimension = {D}: must be 2 or 3")));
        }
        laws.check(walls.len(), species, bodies.len())?;
        // (one species: no species array; several: one per particle)
        let species: Vec<u8> = match (laws.species.len(), species.is_empty()) {
            (1, _) => Vec::new(),
            (_, true) => vec![0; bodies.len()],
            (_, false) => species.to_vec(),
        };
        let materials: Vec<_> = laws.species.iter().map(|s| s.material).collect();
        for (k, b) in bodies.iter().enumerate() {
            if !(b.diameter.is_finite() && b.diameter > 0.0) {
                return Err(DemError::Invalid(format!(
                    "particle {k}: diameter = {} m is out of range: it must be finite and > 0",
                    b.diameter
                )));
            }
            let ok = b
                .position
                .iter()
                .chain(b.velocity.iter())
                .chain(b.angular_velocity.iter())
                .all(|x| x.is_finite());
            if !ok {
                return Err(DemError::Invalid(format!(
                    "particle {k}: position, velocity and angular_velocity must be finite"
                )));
            }
        }
        let law_reach = reach_bound(&laws, bodies)?;
        for (k, w) in walls.iter().enumerate() {
            w.validate()
                .map_err(|m| DemError::Invalid(format!("wall {k}: {m}")))?;
        }
        let surface_wall: Vec<usize> = walls
            .iter()
            .enumerate()
            .flat_map(|(k, w)| std::iter::repeat_n(k, w.surface_count()))
            .collect();
        let surface_class: Vec<u8> = if laws.wall_class.is_empty() {
            Vec::new()
        } else {
            let (n, nw) = (laws.species.len(), walls.len());
            (0..n)
                .flat_map(|s| surface_wall.iter().map(move |&w| (s, w)))
                .map(|(s, w)| laws.wall_class[s * nw + w])
                .collect()
        };
        let walls_move = walls.iter().any(Wall::moves);
        if !cfg.gravity.iter().all(|x| x.is_finite()) {
            return Err(DemError::Invalid("gravity must be finite".into()));
        }
        let p = Particles::of_species(bodies, &species, &materials);
        let dmin = p.radius.iter().cloned().fold(f64::INFINITY, f64::min) * 2.0;
        let dmax = p.radius.iter().cloned().fold(0.0, f64::max) * 2.0;
        let skin = cfg.skin.unwrap_or(0.3 * dmin);
        if !bodies.is_empty() && (skin.is_nan() || skin.is_infinite() || skin <= 0.0) {
            return Err(DemError::Invalid(format!(
                "skin = {skin} m is out of range: it must be finite and > 0"
            )));
        }
        for k in 0..D {
            if cfg.domain.periodic[k] || cfg.domain.bounded {
                let l = cfg.domain.length(k);
                if !(l.is_finite() && l > 0.0) {
                    return Err(DemError::Invalid(format!(
                        "box: length {l} m along axis {k} must be finite and > 0"
                    )));
                }
            }
            if cfg.domain.periodic[k] && cfg.domain.length(k) <= 2.0 * (dmax + skin) {
                return Err(DemError::Invalid(format!(
                    "box: the periodic length {} m along axis {k} must exceed twice the largest diameter plus the skin ({} m)",
                    cfg.domain.length(k),
                    2.0 * (dmax + skin)
                )));
            }
        }
        let step_choice = match cfg.dt {
            Some(dt) => {
                if !(dt.is_finite() && dt > 0.0) {
                    return Err(DemError::Invalid(format!(
                        "dt = {dt} s is out of range: it must be finite and > 0"
                    )));
                }
                let v = impact_speed(&cfg, &p, &walls);
                let tau = collision_time(&laws, D, &p, &species, v).unwrap_or(f64::NAN);
                if tau / dt < MIN_STEPS_PER_COLLISION {
                    return Err(DemError::Invalid(format!(
                        "dt = {dt:e} s is out of range: the contact time at the largest expected impact speed ({v:.3} m/s) is {tau:.4e} s, so the step resolves a collision in {:.2} steps, and the explicit step is unstable below {MIN_STEPS_PER_COLLISION} (a Hertz contact's deepest overlap); dt must be <= {:.4e} s (about {:.4e} s, 50 steps per collision, gives the restitution within 1e-3; a scene may give impact_speed if the impacts will be slower)",
                        tau / dt,
                        tau / MIN_STEPS_PER_COLLISION,
                        tau / 50.0
                    )));
                }
                StepChoice {
                    dt,
                    collision_time: tau,
                    impact_speed: v,
                    given: true,
                }
            }
            None => {
                check_steps_per_collision("steps_per_collision", cfg.steps_per_collision)
                    .map_err(DemError::Invalid)?;
                let v = impact_speed(&cfg, &p, &walls);
                let tau = if bodies.is_empty() {
                    1.0
                } else {
                    collision_time(&laws, D, &p, &species, v)?
                };
                StepChoice {
                    dt: tau / cfg.steps_per_collision,
                    collision_time: tau,
                    impact_speed: v,
                    given: false,
                }
            }
        };
        let nw = walls.len();
        let energy = cfg.energy;
        let chunk = gather_chunk_classes(bodies.len(), D, laws.pair.len());
        let pair_slots: Vec<_> = laws.pair.iter().map(|l| l.slots()).collect();
        let wall_slots: Vec<_> = laws.wall.iter().map(|l| l.slots()).collect();
        let mut e = Engine {
            vpred: p.vel.clone(),
            aold: vec![VecD::<D>::zeros(); p.len()],
            inv_mass: p.mass.iter().map(|m| 1.0 / m).collect(),
            inv_inertia: p.inertia.iter().map(|i| 1.0 / i).collect(),
            p,
            walls,
            laws,
            species,
            surface_wall,
            surface_class,
            walls_move,
            wall_work: 0.0,
            dt: step_choice.dt,
            step_choice,
            cfg,
            t: 0.0,
            steps: 0,
            nb: Neighbours::default(),
            skin,
            law_reach,
            pairs: Contacts::of_classes(pair_slots)
                .with_energy(energy)
                .with_reach(law_reach),
            wall_contacts: Contacts::of_classes(wall_slots)
                .with_energy(energy)
                .with_reach(law_reach),
            dissipated: [0.0; 4],
            unreported: [false; 4],
            overflow: Vec::new(),
            reach: Vec::new(),
            back: Vec::new(),
            cost: Vec::new(),
            took: Vec::new(),
            moved: Vec::new(),
            pending_kick: false,
            wall_impulse: vec![VecD::<D>::zeros(); nw],
            wall_episodes: vec![0; nw],
            pair_episodes: 0,
            order: order::Order::default(),
            chunk,
            nearest_first: nearest_first(chunk),
            parallel: parallel(bodies.len(), chunk),
            pace: awake::Pace::default(),
            heat: None,
        };
        e.order.due = e.sorts();
        e.check(false)?;
        e.rebuild();
        // the initial forces: a trial evaluation, its history discarded (nothing has happened yet)
        e.forces()?;
        e.pairs.clear_history();
        e.wall_contacts.clear_history();
        e.reset_wall_counters();
        e.dissipated = [0.0; 4];
        e.wall_work = 0.0;
        e.pair_episodes = e.pairs.len() as u64;
        let g = e.cfg.gravity;
        for i in 0..e.p.len() {
            e.aold[i] = e.p.force[i] / e.p.mass[i] + g;
        }
        e.leave_order();
        Ok(e)
    }

    /// Each particle's species in the engine's order (see [`Engine::user_index`]); empty in a
    /// run of one species.
    pub fn species(&self) -> &[u8] {
        &self.species
    }

    /// The species and the laws of every class of contacts.
    pub fn laws(&self) -> &SpeciesLaws {
        &self.laws
    }

    /// The step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The configuration.
    pub fn config(&self) -> &EngineConfig<D> {
        &self.cfg
    }

    /// Neighbour-list builds so far.
    pub fn rebuilds(&self) -> u64 {
        self.nb.builds
    }

    /// The neighbour-list skin (m).
    pub fn skin(&self) -> f64 {
        self.skin
    }

    /// Pairs in the neighbour list (closer than the skin at its last build).
    pub fn listed_pairs(&self) -> usize {
        self.nb.js.len()
    }

    /// Forces a neighbour-list rebuild at the next step (tests: history must survive it).
    pub fn invalidate_neighbours(&mut self) {
        self.nb.anchor.clear();
    }

    /// Zeroes the wall impulses and episode counts.
    pub fn reset_wall_counters(&mut self) {
        self.wall_impulse.iter_mut().for_each(|v| *v = VecD::<D>::zeros());
        self.wall_episodes.iter_mut().for_each(|v| *v = 0);
    }

    /// The walls' surfaces now (one per plane, cylinder or box seen from outside, one per face
    /// of a box holding the particles; see [`Engine::surface_wall`]).
    pub fn wall_states(&self) -> Vec<WallState<D>> {
        self.surfaces_at(self.t)
    }

    /// The walls' surfaces at time `t` (s).
    pub(super) fn surfaces_at(&self, t: f64) -> Vec<WallState<D>> {
        let mut out = Vec::with_capacity(self.surface_wall.len());
        for w in &self.walls {
            w.surfaces_into(t, &mut out);
        }
        out
    }

    /// The wall each surface of [`Engine::wall_states`] belongs to (the `j` of a wall contact
    /// is its surface).
    pub fn surface_wall(&self) -> &[usize] {
        &self.surface_wall
    }

    /// Rebuilds the neighbour list (wrapping positions into the box), with the chunks' reach
    /// and displacement bounds.
    fn rebuild(&mut self) {
        self.maybe_renumber();
        self.nb.build(
            &self.cfg.domain,
            &mut self.p.pos,
            &self.p.radius,
            self.skin + self.law_reach,
        );
        let walls = self.wall_states();
        self.nb
            .find_wall_candidates(&walls, &self.p.radius, self.law_reach);
        self.nb.chunk_reach(self.chunk, &mut self.reach);
        self.back.clear();
        self.back.extend(0..self.reach.len());
        for (k, &far) in self.reach.iter().enumerate().rev() {
            for m in k + 1..=far {
                self.back[m] = k;
            }
        }
        self.moved.clear();
        self.moved.resize(self.reach.len(), 0.0);
    }

    /// One step of `dt`.
    ///
    /// With a valid neighbour list, the step is one pass over the particles, chunk by chunk
    /// ([`Engine::drift_and_forces`]): each chunk's kicks and drift, then at once its contacts'
    /// forces, while its particles are still in cache. On the rare step where a particle has
    /// moved by more than half the skin since the list was built, the list is rebuilt and the
    /// forces are evaluated again ([`Engine::forces`]). The passes also sum the state, which
    /// is finite unless some coordinate is not (or the sum overflows: then the exact check
    /// tells), so neither the staleness test nor the state check costs a pass of its own.
    pub fn step(&mut self) -> Result<(), DemError> {
        self.enter_order();
        let done = self.step_with(false);
        self.leave_order();
        done
    }

    /// `k` steps of `dt`, the state at the end the same bit for bit as after `k` calls of
    /// [`Engine::step`]; between the steps, the second half-kick of one step is done in the
    /// same pass over the particles as the first half-kick and the drift of the next (one pass
    /// fewer per step; the state between the steps is not observable). Not in a bounded box,
    /// whose check for lost particles wants every step's end state: there, plain steps.
    ///
    /// On a pool of several threads, the pool's other threads wait for each step's parallel
    /// phase without sleeping through the block (see `awake.rs`): the same steps, without a
    /// wake-up per step.
    pub fn advance(&mut self, k: u64) -> Result<(), DemError> {
        self.enter_order();
        let done = self.advance_inside(k);
        self.leave_order();
        done
    }

    /// [`Engine::advance`] in the engine's order.
    ///
    /// On a pool of several threads the steps go in timed blocks, each run in parallel or on
    /// the calling thread alone as [`awake::Pace`] finds faster for this pile on this machine
    /// now: the same steps and bits either way (the chunks fix every sum's order).
    pub(super) fn advance_inside(&mut self, k: u64) -> Result<(), DemError> {
        let fuse = !self.cfg.domain.bounded;
        let can = parallel(self.p.len(), self.chunk);
        if !(k > 1 && can && rayon::current_num_threads() >= 2) {
            for s in 0..k {
                self.step_with(fuse && s + 1 < k)?;
            }
            return Ok(());
        }
        let mut s = 0;
        while s < k {
            let (parallel, steps) = self.pace.next(k - s);
            let (from, to) = (s, s + steps);
            let clock = std::time::Instant::now();
            self.parallel = parallel;
            let mut block = || -> Result<(), DemError> {
                for s in from..to {
                    self.step_with(fuse && s + 1 < k)?;
                }
                Ok(())
            };
            let done = if parallel {
                awake::with_pool_awake(block)
            } else {
                block()
            };
            self.parallel = can;
            done?;
            self.pace.record(parallel, clock.elapsed(), steps);
            s = to;
        }
        Ok(())
    }

    /// One step; with `defer`, the step ends before its second half-kick, which the next step
    /// does first ([`Engine::advance`]).
    fn step_with(&mut self, defer: bool) -> Result<(), DemError> {
        self.renumber_if_due();
        let pending = std::mem::take(&mut self.pending_kick);
        let dt = self.dt;
        let h = 0.5 * dt;
        let g = self.cfg.gravity;
        let n = self.p.len();
        if self.nb.anchor.len() == n {
            let pass = self.drift_and_forces(pending);
            if !pass.sum.is_finite() {
                // the last step's end state was not finite: name the particle (its coordinates
                // are one drift further on)
                self.check(true)?;
            }
            self.t += dt;
            self.steps += 1;
            if pass.stale {
                self.rebuild();
                self.forces()?;
            } else {
                self.finish_forces(pass.result, true)?;
            }
        } else {
            // no list (after [`Engine::invalidate_neighbours`]): the kicks and the drift of every
            // particle, then the list, then the forces
            let c = self.chunk;
            let cs = c * spin_len(D);
            let sum = {
                let p = &mut self.p;
                let shared = Shared::without_anchors(&p.force, &p.torque, &self.inv_mass, &self.inv_inertia);
                let run = |(k, ((((x, v), w), vp), ao)): KickDriftChunk<'_, D>| {
                    let s = shared.chunk(k * c, x.len());
                    kick_drift_chunk(&s, pending, g, h, dt, x, v, w, vp, ao, &mut 0.0, 0.0).1
                };
                // the same chain by std's chunks or rayon's
                macro_rules! drift_all {
                    ($chunks_mut:ident) => {
                        p.pos
                            .$chunks_mut(c)
                            .zip(p.vel.$chunks_mut(c))
                            .zip(p.omega.$chunks_mut(cs))
                            .zip(self.vpred.$chunks_mut(c))
                            .zip(self.aold.$chunks_mut(c))
                            .enumerate()
                            .map(run)
                            .sum::<f64>()
                    };
                }
                if !self.parallel {
                    drift_all!(chunks_mut)
                } else {
                    drift_all!(par_chunks_mut)
                }
            };
            if !sum.is_finite() {
                self.check(true)?;
            }
            self.t += dt;
            self.steps += 1;
            self.rebuild();
            self.forces()?;
        }
        self.conduct();
        if defer {
            self.pending_kick = true;
            return Ok(());
        }
        let c = self.chunk;
        let sum = {
            let p = &mut self.p;
            let shared = Shared::without_anchors(&p.force, &p.torque, &self.inv_mass, &self.inv_inertia);
            let pos = &p.pos;
            let run = |(k, (v, w)): (usize, (&mut [VecD<D>], &mut [f64]))| {
                let a = k * c;
                kick_chunk(&shared.chunk(a, v.len()), &pos[a..a + v.len()], g, h, v, w)
            };
            let cs = c * spin_len(D);
            let chunks = p.vel.chunks_mut(c).zip(p.omega.chunks_mut(cs)).enumerate();
            if !self.parallel {
                chunks.map(run).sum::<f64>()
            } else {
                p.vel
                    .par_chunks_mut(c)
                    .zip(p.omega.par_chunks_mut(cs))
                    .enumerate()
                    .map(run)
                    .sum::<f64>()
            }
        };
        if sum.is_finite() && !self.cfg.domain.bounded {
            return Ok(());
        }
        self.check(true)
    }

    /// How many steps, at most `limit`, a run to time `t_end` (s) takes from now: steps are
    /// taken while t + dt/2 < `t_end`, t summed step by step as the steps sum it.
    pub fn steps_to(&self, t_end: f64, limit: u64) -> u64 {
        let (mut k, mut t) = (0u64, self.t);
        while k < limit && t + 0.5 * self.dt < t_end {
            t += self.dt;
            k += 1;
        }
        k
    }

    /// Runs until time `t_end` (s), calling `progress(t)` every `every` steps.
    pub fn run_until(
        &mut self,
        t_end: f64,
        every: u64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<(), DemError> {
        self.run_with_stops(
            t_end,
            &mut |s| s.checked_div(every).map_or(u64::MAX, |q| (q + 1) * every),
            &mut |e| {
                if every > 0 && e.steps % every == 0 {
                    progress(e.t);
                }
                Ok(())
            },
        )
    }

    /// Runs until time `t_end` (s) in blocks of [`Engine::advance`]: each block ends at the step
    /// count `next_stop(steps)` gives (or at `t_end`), and `at_stop(self)` is called after it
    /// (a progress tick, a frame of output).
    pub fn run_with_stops<E: From<DemError>>(
        &mut self,
        t_end: f64,
        next_stop: &mut dyn FnMut(u64) -> u64,
        at_stop: &mut dyn FnMut(&Self) -> Result<(), E>,
    ) -> Result<(), E> {
        while self.t + 0.5 * self.dt < t_end {
            let limit = next_stop(self.steps).saturating_sub(self.steps).max(1);
            self.advance(self.steps_to(t_end, limit))?;
            at_stop(self)?;
        }
        Ok(())
    }

    /// The mean over particles of `to3(v)` (m/s): a helper for observables.
    pub fn mean_velocity(&self) -> Vec3 {
        let n = self.p.len().max(1) as f64;
        self.p.vel.iter().map(to3).sum::<Vec3>() / n
    }
}
