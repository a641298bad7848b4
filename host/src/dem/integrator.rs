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

use super::cells::{Domain, Neighbours};
use super::contacts::{ContactSet, SERIAL_BELOW};
use super::state::{from3, to3, Body, Material, Particles, Vec3, VecD};
use super::walls::{Wall, WallState};
use super::{DemError, Laws};
use crate::collide::{collide, Options, PairLaw};
use dashpot_sdk::EndCriterion;
use rayon::prelude::*;

/// One particle's item in the kick–drift loop: index, position, velocity, spin, predicted
/// velocity, previous acceleration.
/// The first half-kick and the drift of one particle, with its acceleration `a` (m/s²) and
/// angular acceleration `al` (rad/s²); `vp` gets the second-order predicted velocity at the end
/// of the step, `ao` keeps `a` for the next prediction.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn kick_drift_one<const D: usize>(
    a: VecD<D>,
    al: Vec3,
    h: f64,
    dt: f64,
    x: &mut VecD<D>,
    v: &mut VecD<D>,
    w: &mut Vec3,
    vp: &mut VecD<D>,
    ao: &mut VecD<D>,
) {
    *v += a * h;
    *x += *v * dt;
    *w += al * h;
    *vp = *v + (a * 2.0 - *ao) * h;
    *ao = a;
}

type KickDrift<'a, const D: usize> = (
    usize,
    (
        (
            ((&'a mut VecD<D>, &'a mut VecD<D>), &'a mut Vec3),
            &'a mut VecD<D>,
        ),
        &'a mut VecD<D>,
    ),
);

/// Run settings.
#[derive(Debug, Clone)]
pub struct EngineConfig<const D: usize> {
    /// Gravity (m/s²).
    pub gravity: VecD<D>,
    /// The time step (s); `None`: chosen from the laws (see the module doc).
    pub dt: Option<f64>,
    /// Steps per collision when the step is chosen (default 50).
    pub steps_per_collision: f64,
    /// The largest impact speed expected (m/s); `None`: estimated from the initial state, the
    /// walls' motion and free fall across the particles' extent.
    pub impact_speed: Option<f64>,
    /// The neighbour-list skin (m); `None`: 0.3 of the smallest diameter.
    pub skin: Option<f64>,
    /// The box.
    pub domain: Domain<D>,
    /// The particles' material.
    pub material: Material,
    /// Whether a contact's first and last step take the mean force over the part of the step in
    /// contact (default true; off: the plain step-end rule, for measuring what it changes).
    pub edge_means: bool,
}

impl<const D: usize> EngineConfig<D> {
    /// Defaults: no gravity, step chosen at 50 steps per collision, open unbounded box.
    pub fn new(material: Material) -> EngineConfig<D> {
        EngineConfig {
            gravity: VecD::<D>::zeros(),
            dt: None,
            steps_per_collision: 50.0,
            impact_speed: None,
            skin: None,
            domain: Domain {
                lo: VecD::<D>::zeros(),
                hi: VecD::<D>::zeros(),
                periodic: [false; D],
                bounded: false,
            },
            material,
            edge_means: true,
        }
    }
}

/// How the step was chosen (printed by the CLI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StepChoice {
    /// The step (s).
    pub dt: f64,
    /// The shortest contact time τ at `impact_speed` (s) (particle pair or particle–wall).
    pub collision_time: f64,
    /// The impact speed τ was computed at (m/s).
    pub impact_speed: f64,
    /// Whether the step was given rather than chosen.
    pub given: bool,
}

/// A soft-sphere DEM run.
pub struct Engine<const D: usize> {
    /// The particles.
    pub p: Particles<D>,
    /// The walls.
    pub walls: Vec<Wall<D>>,
    laws: Laws,
    cfg: EngineConfig<D>,
    /// The step and how it was chosen.
    pub step_choice: StepChoice,
    dt: f64,
    t: f64,
    steps: u64,
    nb: Neighbours<D>,
    skin: f64,
    /// Particle-pair contacts of the last evaluation.
    pub pairs: ContactSet,
    /// Particle–wall contacts of the last evaluation.
    pub wall_contacts: ContactSet,
    vpred: Vec<VecD<D>>,
    /// Each particle's acceleration at the previous step (the predictor's extrapolation).
    aold: Vec<VecD<D>>,
    /// 1/m and 1/I of each particle (the kicks multiply: a division per component and particle
    /// was a tenth of a step). Masses and moments of inertia are fixed at construction.
    inv_mass: Vec<f64>,
    inv_inertia: Vec<f64>,
    bufs: Vec<(Vec<VecD<D>>, Vec<Vec3>)>,
    /// Impulse (N·s) given to each wall since the last reset (force on the wall × dt, summed).
    pub wall_impulse: Vec<VecD<D>>,
    /// Contact episodes with each wall since the last reset (first touches).
    pub wall_episodes: Vec<u64>,
    /// Particle-pair contact episodes since the start.
    pub pair_episodes: u64,
}

impl<const D: usize> Engine<D> {
    /// A run of `bodies` between `walls` under `laws`; the step is chosen (or checked) here and the
    /// forces of the initial state evaluated.
    pub fn new(
        cfg: EngineConfig<D>,
        bodies: &[Body<D>],
        walls: Vec<Wall<D>>,
        laws: Laws,
    ) -> Result<Engine<D>, DemError> {
        if !(D == 2 || D == 3) {
            return Err(DemError::Invalid(format!("dimension = {D}: must be 2 or 3")));
        }
        let mat = cfg.material;
        mat.particle(1.0)
            .validate()
            .map_err(|e| DemError::Invalid(format!("material: {}", e.message)))?;
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
        for (k, w) in walls.iter().enumerate() {
            if !(w.normal.iter().all(|x| x.is_finite()) && (w.normal.norm() - 1.0).abs() < 1e-9) {
                return Err(DemError::Invalid(format!(
                    "wall {k}: normal must be a finite unit vector"
                )));
            }
        }
        if !cfg.gravity.iter().all(|x| x.is_finite()) {
            return Err(DemError::Invalid("gravity must be finite".into()));
        }
        let p = Particles::new(bodies, &mat);
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
                let tau = collision_time(&laws, &mat, D, dmin, v).unwrap_or(f64::NAN);
                StepChoice {
                    dt,
                    collision_time: tau,
                    impact_speed: v,
                    given: true,
                }
            }
            None => {
                if !(cfg.steps_per_collision.is_finite() && cfg.steps_per_collision >= 1.0) {
                    return Err(DemError::Invalid(format!(
                        "steps_per_collision = {} is out of range: it must be >= 1",
                        cfg.steps_per_collision
                    )));
                }
                let v = impact_speed(&cfg, &p, &walls);
                let tau = if bodies.is_empty() {
                    1.0
                } else {
                    collision_time(&laws, &mat, D, dmin, v)?
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
        let (sn, st) = (
            laws.pair.history_slots(),
            laws.pair_tangential.as_ref().map_or(0, |t| t.history_slots()),
        );
        let (swn, swt) = (
            laws.wall.history_slots(),
            laws.wall_tangential.as_ref().map_or(0, |t| t.history_slots()),
        );
        let mut e = Engine {
            vpred: p.vel.clone(),
            aold: vec![VecD::<D>::zeros(); p.len()],
            inv_mass: p.mass.iter().map(|m| 1.0 / m).collect(),
            inv_inertia: p.inertia.iter().map(|i| 1.0 / i).collect(),
            p,
            walls,
            laws,
            dt: step_choice.dt,
            step_choice,
            cfg,
            t: 0.0,
            steps: 0,
            nb: Neighbours::default(),
            skin,
            pairs: ContactSet::new(sn, st),
            wall_contacts: ContactSet::new(swn, swt),
            bufs: Vec::new(),
            wall_impulse: vec![VecD::<D>::zeros(); nw],
            wall_episodes: vec![0; nw],
            pair_episodes: 0,
        };
        e.check(false)?;
        e.nb.build(&e.cfg.domain, &mut e.p.pos, &e.p.radius, e.skin);
        // the initial forces: a trial evaluation, its history discarded (nothing has happened yet)
        e.forces()?;
        e.pairs
            .hist_n
            .iter_mut()
            .chain(e.pairs.hist_t.iter_mut())
            .for_each(|h| *h = 0.0);
        e.wall_contacts
            .hist_n
            .iter_mut()
            .chain(e.wall_contacts.hist_t.iter_mut())
            .for_each(|h| *h = 0.0);
        e.reset_wall_counters();
        e.pair_episodes = e.pairs.len() as u64;
        let g = e.cfg.gravity;
        for i in 0..e.p.len() {
            e.aold[i] = e.p.force[i] / e.p.mass[i] + g;
        }
        Ok(e)
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

    /// Forces a neighbour-list rebuild at the next step (tests: history must survive it).
    pub fn invalidate_neighbours(&mut self) {
        self.nb.anchor.clear();
    }

    /// Zeroes the wall impulses and episode counts.
    pub fn reset_wall_counters(&mut self) {
        self.wall_impulse.iter_mut().for_each(|v| *v = VecD::<D>::zeros());
        self.wall_episodes.iter_mut().for_each(|v| *v = 0);
    }

    /// The walls' planes now.
    pub fn wall_states(&self) -> Vec<WallState<D>> {
        self.walls.iter().map(|w| w.at(self.t)).collect()
    }

    /// Gathers the contacts at the current positions and predicted velocities, calls the laws,
    /// and sums forces and torques into the particles.
    fn forces(&mut self) -> Result<(), DemError> {
        let ws = self.wall_states();
        let p = &self.p;
        self.pairs.gather_pairs(
            &self.cfg.domain,
            &self.nb,
            &p.pos,
            &self.vpred,
            &p.vel,
            &p.omega,
            &p.radius,
            &p.mass,
        )?;
        self.wall_contacts
            .gather_walls(&ws, &p.pos, &self.vpred, &p.vel, &p.omega, &p.radius, &p.mass)?;
        self.pairs.evaluate(
            &*self.laws.pair,
            self.laws.pair_tangential.as_deref(),
            self.dt,
            self.cfg.edge_means,
        )?;
        self.wall_contacts.evaluate(
            &*self.laws.wall,
            self.laws.wall_tangential.as_deref(),
            self.dt,
            self.cfg.edge_means,
        )?;
        self.scatter();
        Ok(())
    }

    fn scatter(&mut self) {
        let n = self.p.len();
        let threads = rayon::current_num_threads();
        let c = &self.pairs;
        let parts = if threads > 1 && c.len() >= 8192 {
            threads
        } else {
            1
        };
        while self.bufs.len() + 1 < parts {
            self.bufs.push((Vec::new(), Vec::new()));
        }
        let per = c.len().div_ceil(parts).max(1);
        let mut targets: Vec<(&mut [VecD<D>], &mut [Vec3])> = Vec::with_capacity(parts);
        targets.push((&mut self.p.force, &mut self.p.torque));
        for b in self.bufs.iter_mut().take(parts - 1) {
            b.0.resize(n, VecD::<D>::zeros());
            b.1.resize(n, Vec3::zeros());
            targets.push((&mut b.0, &mut b.1));
        }
        let radius = &self.p.radius;
        let accumulate = |k: usize, (f, tq): (&mut [VecD<D>], &mut [Vec3])| {
            f.iter_mut().for_each(|v| *v = VecD::<D>::zeros());
            tq.iter_mut().for_each(|v| *v = Vec3::zeros());
            for m in k * per..((k + 1) * per).min(c.len()) {
                let (i, j) = (c.i[m] as usize, c.j[m] as usize);
                let nv = Vec3::from(c.normal[m]);
                let ft = Vec3::from(c.ftan[m]);
                let fi = from3::<D>(&(nv * c.fnorm[m] + ft));
                f[i] += fi;
                f[j] -= fi;
                let nxf = nv.cross(&ft);
                tq[i] -= nxf * radius[i];
                tq[j] -= nxf * radius[j];
            }
        };
        if parts == 1 {
            let t = targets.pop().expect("one target");
            accumulate(0, t);
        } else {
            targets
                .into_par_iter()
                .enumerate()
                .for_each(|(k, t)| accumulate(k, t));
            let bufs = &self.bufs[..parts - 1];
            self.p
                .force
                .par_iter_mut()
                .zip(self.p.torque.par_iter_mut())
                .enumerate()
                .for_each(|(i, (f, tq))| {
                    for b in bufs {
                        *f += b.0[i];
                        *tq += b.1[i];
                    }
                });
        }
        let w = &self.wall_contacts;
        for m in 0..w.len() {
            let i = w.i[m] as usize;
            let nv = Vec3::from(w.normal[m]);
            let ft = Vec3::from(w.ftan[m]);
            let fi = nv * w.fnorm[m] + ft;
            self.p.force[i] += from3::<D>(&fi);
            self.p.torque[i] -= nv.cross(&ft) * self.p.radius[i];
            let k = w.j[m] as usize;
            self.wall_impulse[k] -= from3::<D>(&fi) * self.dt;
            if w.fresh[m] {
                self.wall_episodes[k] += 1;
            }
        }
        self.pair_episodes += c.formed as u64;
        if D == 2 {
            self.p.torque.iter_mut().for_each(|t| {
                t.x = 0.0;
                t.y = 0.0;
            });
        }
    }

    /// One step of `dt`.
    pub fn step(&mut self) -> Result<(), DemError> {
        let dt = self.dt;
        let h = 0.5 * dt;
        let g = self.cfg.gravity;
        {
            let p = &mut self.p;
            let (pos, vel, omega) = (&mut p.pos, &mut p.vel, &mut p.omega);
            let (force, torque) = (&p.force, &p.torque);
            let (im, ii) = (&self.inv_mass, &self.inv_inertia);
            let kick_drift = |(i, ((((x, v), w), vp), ao)): KickDrift<'_, D>| {
                kick_drift_one(force[i] * im[i] + g, torque[i] * ii[i], h, dt, x, v, w, vp, ao);
            };
            let n = pos.len();
            if n < SERIAL_BELOW {
                // a plain indexed loop over equal-length slices: inlined and vectorised
                let (force, torque, im, ii) = (&force[..n], &torque[..n], &im[..n], &ii[..n]);
                let (vel, omega) = (&mut vel[..n], &mut omega[..n]);
                let (vpred, aold) = (&mut self.vpred[..n], &mut self.aold[..n]);
                for i in 0..n {
                    kick_drift_one(
                        force[i] * im[i] + g,
                        torque[i] * ii[i],
                        h,
                        dt,
                        &mut pos[i],
                        &mut vel[i],
                        &mut omega[i],
                        &mut vpred[i],
                        &mut aold[i],
                    );
                }
            } else {
                pos.par_iter_mut()
                    .zip(vel.par_iter_mut())
                    .zip(omega.par_iter_mut())
                    .zip(self.vpred.par_iter_mut())
                    .zip(self.aold.par_iter_mut())
                    .enumerate()
                    .for_each(kick_drift);
            }
        }
        self.t += dt;
        self.steps += 1;
        if self.nb.stale(&self.cfg.domain, &self.p.pos) {
            self.nb
                .build(&self.cfg.domain, &mut self.p.pos, &self.p.radius, self.skin);
        }
        self.forces()?;
        {
            let p = &mut self.p;
            let (vel, omega) = (&mut p.vel, &mut p.omega);
            let (force, torque) = (&p.force, &p.torque);
            let (im, ii) = (&self.inv_mass, &self.inv_inertia);
            let kick = |(i, (v, w)): (usize, (&mut VecD<D>, &mut Vec3))| {
                *v += (force[i] * im[i] + g) * h;
                *w += torque[i] * ii[i] * h;
            };
            let n = vel.len();
            if n < SERIAL_BELOW {
                let (force, torque, im, ii) = (&force[..n], &torque[..n], &im[..n], &ii[..n]);
                let omega = &mut omega[..n];
                for i in 0..n {
                    vel[i] += (force[i] * im[i] + g) * h;
                    omega[i] += torque[i] * ii[i] * h;
                }
            } else {
                vel.par_iter_mut()
                    .zip(omega.par_iter_mut())
                    .enumerate()
                    .for_each(kick);
            }
        }
        self.check(true)
    }

    /// Runs until time `t_end` (s), calling `progress(t)` every `every` steps.
    pub fn run_until(
        &mut self,
        t_end: f64,
        every: u64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<(), DemError> {
        while self.t + 0.5 * self.dt < t_end {
            self.step()?;
            if every > 0 && self.steps % every == 0 {
                progress(self.t);
            }
        }
        Ok(())
    }

    fn check(&self, velocities_too: bool) -> Result<(), DemError> {
        let p = &self.p;
        let dom = &self.cfg.domain;
        // the common case in one branch-free pass: a sum of every coordinate is finite unless
        // one of them is not (or the sum overflows, which only takes the exact scan below)
        if !dom.bounded && p.len() < SERIAL_BELOW {
            // one running sum per component: independent chains, not one long one
            let mut s = [0.0f64; 4];
            for (k, x) in p.pos.iter().enumerate() {
                s[k % 4] += x.sum();
            }
            if velocities_too {
                for (k, (v, w)) in p.vel.iter().zip(&p.omega).enumerate() {
                    s[k % 4] += v.sum() + w.sum();
                }
            }
            if ((s[0] + s[1]) + (s[2] + s[3])).is_finite() {
                return Ok(());
            }
        }
        let bad_at = |&i: &usize| {
            let fin = p.pos[i].iter().all(|x| x.is_finite())
                && (!velocities_too
                    || (p.vel[i].iter().all(|x| x.is_finite()) && p.omega[i].iter().all(|x| x.is_finite())));
            if !fin {
                return true;
            }
            dom.bounded
                && (0..D).any(|k| !dom.periodic[k] && (p.pos[i][k] < dom.lo[k] || p.pos[i][k] > dom.hi[k]))
        };
        let bad = if p.len() < SERIAL_BELOW {
            (0..p.len()).find(bad_at)
        } else {
            (0..p.len()).into_par_iter().find_first(bad_at)
        };
        if let Some(i) = bad {
            let fmt = |v: &VecD<D>| format!("{:?}", v.as_slice());
            if !p.pos[i].iter().chain(p.vel[i].iter()).all(|x| x.is_finite())
                || !p.omega[i].iter().all(|x| x.is_finite())
            {
                return Err(DemError::NonFinite {
                    i,
                    t: self.t,
                    pos: fmt(&p.pos[i]),
                    vel: fmt(&p.vel[i]),
                });
            }
            let axis = (0..D)
                .find(|&k| p.pos[i][k] < dom.lo[k] || p.pos[i][k] > dom.hi[k])
                .unwrap_or(0);
            return Err(DemError::Lost {
                i,
                t: self.t,
                pos: fmt(&p.pos[i]),
                axis,
                lo: dom.lo[axis],
                hi: dom.hi[axis],
            });
        }
        Ok(())
    }

    /// The mean over particles of `to3(v)` (m/s): a helper for observables.
    pub fn mean_velocity(&self) -> Vec3 {
        let n = self.p.len().max(1) as f64;
        self.p.vel.iter().map(to3).sum::<Vec3>() / n
    }
}

/// The largest impact speed expected (m/s): the given one, or twice the largest initial surface
/// speed plus the largest wall speed plus the speed of a free fall across the extent of the
/// particles and walls (at least 0.01 m/s).
fn impact_speed<const D: usize>(cfg: &EngineConfig<D>, p: &Particles<D>, walls: &[Wall<D>]) -> f64 {
    if let Some(v) = cfg.impact_speed {
        return v;
    }
    let vmax = (0..p.len())
        .map(|i| p.vel[i].norm() + p.omega[i].norm() * p.radius[i])
        .fold(0.0, f64::max);
    let wmax = walls.iter().map(|w| w.motion.peak_speed()).fold(0.0, f64::max);
    let g = cfg.gravity.norm();
    let mut extent = 0.0f64;
    if g > 0.0 {
        let gh = cfg.gravity / g;
        let hs: Vec<f64> = p
            .pos
            .iter()
            .map(|x| x.dot(&gh))
            .chain(walls.iter().map(|w| w.point.dot(&gh)))
            .collect();
        let (a, b) = hs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| {
            (a.min(h), b.max(h))
        });
        if a.is_finite() {
            extent = b - a;
        }
    }
    (2.0 * vmax + 2.0 * wmax + (2.0 * g * extent).sqrt()).max(0.01)
}

/// The shortest contact time (s) at impact speed `v` (m/s): particles of diameter `d` (m) against
/// each other and against a wall, by the two-body driver with the run's own laws.
fn collision_time(laws: &Laws, mat: &Material, dim: usize, d: f64, v: f64) -> Result<f64, DemError> {
    let (m, _) = mat.mass_inertia(dim, d);
    let r = 0.5 * d;
    let mut tau = f64::INFINITY;
    for (law, mass, radius) in [(&*laws.pair, 0.5 * m, 0.5 * r), (&*laws.wall, m, r)] {
        let c = collide(
            &PairLaw::new(law, mass, radius),
            mass,
            v,
            EndCriterion::Overlap,
            &Options::default(),
        )
        .map_err(|e| DemError::Timestep(format!("law '{}' at v = {v} m/s: {e}", law.name())))?;
        tau = tau.min(c.contact_time);
    }
    Ok(tau)
}
