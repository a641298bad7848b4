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

use super::cells::{Domain, Neighbours};
use super::contacts::{ContactSet, Contacts, View, GATHER_CHUNK, SERIAL_BELOW};
use super::state::{from3, set_spin, spin, spin_len, to3, Body, Material, Particles, Vec3, VecD};
use super::walls::{Wall, WallState};
use super::{DemError, Laws};
use crate::collide::{collide, Options, PairLaw};
use dashpot_sdk::EndCriterion;
use rayon::prelude::*;

mod awake;
mod pipeline;

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

/// The second half-kick of one particle (acceleration `a`, angular acceleration `al`), its end
/// state added to the running sums `sx` (position and velocity) and `sw` (spin), whose
/// finiteness is the state check.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn end_kick<const D: usize>(
    a: VecD<D>,
    al: Vec3,
    h: f64,
    x: &VecD<D>,
    v: &mut VecD<D>,
    w: &mut Vec3,
    sx: &mut VecD<D>,
    sw: &mut Vec3,
) {
    *v += a * h;
    *w += al * h;
    *sx += x + *v;
    *sw += *w;
}

/// One chunk's task in [`Engine::forces`]: chunk index, (previous, next) pair contacts,
/// (previous, next) wall contacts, the chunk's forces and torques, its overflow.
type ChunkTask<'a, const D: usize> = (
    usize,
    (
        (
            (
                (&'a ContactSet, &'a mut ContactSet),
                (&'a ContactSet, &'a mut ContactSet),
            ),
            (&'a mut [VecD<D>], &'a mut [f64]),
        ),
        &'a mut Vec<(u32, VecD<D>, Vec3)>,
    ),
);

/// Sums the forces and torques of one chunk's pair contacts `pairs` and wall contacts `walls`
/// into the chunk's particles (`f`, `tq`: particles `pairs.first..pairs.first + f.len()`,
/// torques as [`Particles::torque`]), zeroed first; `radius` holds the radii from the chunk's
/// first particle on (to its farthest partner). A pair partner beyond the chunk gets its force
/// and torque through `overflow` (force on i, torque on j).
fn scatter_chunk<const D: usize>(
    pairs: &ContactSet,
    walls: &ContactSet,
    radius: &[f64],
    f: &mut [VecD<D>],
    tq: &mut [f64],
    overflow: &mut Vec<(u32, VecD<D>, Vec3)>,
) {
    f.iter_mut().for_each(|v| *v = VecD::<D>::zeros());
    tq.iter_mut().for_each(|v| *v = 0.0);
    overflow.clear();
    let (first, len) = (pairs.first, f.len());
    for m in 0..pairs.len() {
        let (i, j) = (pairs.i[m] as usize - first, pairs.j[m] as usize);
        let nv = Vec3::from(pairs.normal[m]);
        let ft = Vec3::from(pairs.ftan[m]);
        let fi = from3::<D>(&(nv * pairs.fnorm[m] + ft));
        let nxf = nv.cross(&ft);
        f[i] += fi;
        add_spin::<D>(tq, i, &-(nxf * radius[i]));
        let jl = j - first;
        let tj = -(nxf * radius[jl]);
        if jl < len {
            f[jl] -= fi;
            add_spin::<D>(tq, jl, &tj);
        } else {
            overflow.push((j as u32, fi, tj));
        }
    }
    for m in 0..walls.len() {
        let i = walls.i[m] as usize - first;
        let nv = Vec3::from(walls.normal[m]);
        let ft = Vec3::from(walls.ftan[m]);
        f[i] += from3::<D>(&(nv * walls.fnorm[m] + ft));
        add_spin::<D>(tq, i, &-(nv.cross(&ft) * radius[i]));
    }
}

/// Adds `v` to spin `i` of the flat array `w` (a − b is a + (−b) in floating point: adding the
/// negation is subtracting).
#[inline(always)]
fn add_spin<const D: usize>(w: &mut [f64], i: usize, v: &Vec3) {
    let s = spin::<D>(w, i) + v;
    set_spin::<D>(w, i, &s);
}

/// What every chunk's force evaluation shares: the box, the neighbour list, the walls' states,
/// the laws, the step (s) and whether contacts' first and last steps take mean forces.
struct ChunkContext<'a, const D: usize> {
    dom: &'a Domain<D>,
    nb: &'a Neighbours<D>,
    walls: &'a [WallState<D>],
    laws: &'a Laws,
    dt: f64,
    edges: bool,
}

/// The forces of the chunk of particles `range`: its pair and wall contacts gathered from
/// `view` (history from the chunk's previous sets `pairs.0` and `walls.0` into the new ones
/// `pairs.1` and `walls.1`), the laws called on them, and the forces and torques summed into
/// the chunk's `f` and `tq` (see [`scatter_chunk`], which fills `overflow`).
#[allow(clippy::too_many_arguments)]
fn chunk_forces<const D: usize>(
    ctx: &ChunkContext<'_, D>,
    range: std::ops::Range<usize>,
    view: &View<'_, D>,
    pairs: (&ContactSet, &mut ContactSet),
    walls: (&ContactSet, &mut ContactSet),
    f: &mut [VecD<D>],
    tq: &mut [f64],
    overflow: &mut Vec<(u32, VecD<D>, Vec3)>,
) -> Result<(), DemError> {
    let ((pp, np), (pw, nw)) = (pairs, walls);
    np.gather_pairs(pp, range.clone(), ctx.dom, ctx.nb, view)?;
    nw.gather_walls(pw, range.clone(), ctx.walls, view)?;
    let laws = ctx.laws;
    np.evaluate(&*laws.pair, laws.pair_tangential.as_deref(), ctx.dt, ctx.edges)?;
    nw.evaluate(&*laws.wall, laws.wall_tangential.as_deref(), ctx.dt, ctx.edges)?;
    let radius = &view.radius[range.start - view.base..];
    scatter_chunk(np, nw, radius, f, tq, overflow);
    Ok(())
}

/// The arrays the kick loops read, whole or one chunk's part.
struct Shared<'a, const D: usize> {
    force: &'a [VecD<D>],
    /// Torques, [`spin_len`]`(D)` per particle.
    torque: &'a [f64],
    im: &'a [f64],
    ii: &'a [f64],
    /// The positions at the neighbour list's build, or empty (no valid list).
    anchor: &'a [VecD<D>],
}

impl<'a, const D: usize> Shared<'a, D> {
    /// Forces, torques, inverse masses and moments of inertia, no anchors (no staleness test).
    fn without_anchors(
        force: &'a [VecD<D>],
        torque: &'a [f64],
        im: &'a [f64],
        ii: &'a [f64],
    ) -> Shared<'a, D> {
        Shared {
            force,
            torque,
            im,
            ii,
            anchor: &[],
        }
    }

    /// The part of particles `a..a + len`.
    fn chunk(&self, a: usize, len: usize) -> Shared<'a, D> {
        let b = a + len;
        Shared {
            force: &self.force[a..b],
            torque: &self.torque[a * spin_len(D)..b * spin_len(D)],
            im: &self.im[a..b],
            ii: &self.ii[a..b],
            anchor: if self.anchor.is_empty() {
                &[]
            } else {
                &self.anchor[a..b]
            },
        }
    }
}

/// One chunk's item in the kick–drift loop: chunk index, positions, velocities, spins,
/// predicted velocities, previous accelerations.
type KickDriftChunk<'a, const D: usize> = (
    usize,
    (
        (
            ((&'a mut [VecD<D>], &'a mut [VecD<D>]), &'a mut [f64]),
            &'a mut [VecD<D>],
        ),
        &'a mut [VecD<D>],
    ),
);

/// The unit roundoff of f64 (2⁻⁵³).
const ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// The first half-kick and the drift of one chunk of particles (gravity `g`, half step `h`,
/// step `dt`), preceded by the last step's second half-kick when `pending` (the same force
/// and the same two additions as the separate loops, so the same bits, in one pass over the
/// particles instead of two). Returns whether a particle has moved by more than half the
/// list's `skin` (m) since the anchors (the list is stale; never without anchors) and, when
/// `pending`, the sum of every coordinate of the last step's end state (finite unless one of
/// them is not; else 0).
///
/// `moved` (m) bounds the displacement of the chunk's particles since the anchors: the chunk's
/// largest speed × `dt` is added each step (with the roundoff of the drift's sums), and the
/// displacements themselves are read only once the bound nears half the skin (then `moved`
/// becomes their largest). So the anchors are read in a few steps of a list's life, not in
/// every one, and the test says stale exactly when a displacement exceeds half the skin.
/// Positions are wrapped only when the list is built, so the plain difference is the
/// displacement. A NaN displacement is never stale: the state check reports it.
#[allow(clippy::too_many_arguments)]
fn kick_drift_chunk<const D: usize>(
    s: &Shared<'_, D>,
    pending: bool,
    g: VecD<D>,
    h: f64,
    dt: f64,
    pos: &mut [VecD<D>],
    vel: &mut [VecD<D>],
    omega: &mut [f64],
    vpred: &mut [VecD<D>],
    aold: &mut [VecD<D>],
    moved: &mut f64,
    skin: f64,
) -> (bool, f64) {
    let n = pos.len();
    let ns = n * spin_len(D);
    let (force, torque, im, ii) = (&s.force[..n], &s.torque[..ns], &s.im[..n], &s.ii[..n]);
    let (vel, omega, vpred, aold) = (&mut vel[..n], &mut omega[..ns], &mut vpred[..n], &mut aold[..n]);
    let (mut sx, mut sw) = (VecD::<D>::zeros(), Vec3::zeros());
    // the largest squared speed of the drift and squared distance from the origin after it
    let (mut v2max, mut x2max) = (0.0f64, 0.0f64);
    // (`pending` is the same for the whole loop: the compiler makes two loops of it)
    for i in 0..n {
        let (a, al) = (force[i] * im[i] + g, spin::<D>(torque, i) * ii[i]);
        let mut w = spin::<D>(omega, i);
        if pending {
            end_kick(a, al, h, &pos[i], &mut vel[i], &mut w, &mut sx, &mut sw);
        }
        kick_drift_one(
            a,
            al,
            h,
            dt,
            &mut pos[i],
            &mut vel[i],
            &mut w,
            &mut vpred[i],
            &mut aold[i],
        );
        set_spin::<D>(omega, i, &w);
        let (v2, x2) = (vel[i].norm_squared(), pos[i].norm_squared());
        v2max = if v2 > v2max { v2 } else { v2max };
        x2max = if x2 > x2max { x2 } else { x2max };
    }
    let sum = sx.sum() + sw.sum();
    if s.anchor.len() != n {
        return (false, sum);
    }
    // |fl(x + fl(v dt)) − (x + v dt)| ≤ u (|x + v dt| + |v dt|), each component
    *moved += v2max.sqrt() * dt * (1.0 + 4.0 * ROUNDOFF) + 2.0 * ROUNDOFF * x2max.sqrt();
    // (the displacements' own rounding is far below the margin of 0.49 against 0.5)
    if *moved <= 0.49 * skin {
        return (false, sum);
    }
    let anchor = &s.anchor[..n];
    let mut worst = 0.0f64;
    for i in 0..n {
        let d2 = (pos[i] - anchor[i]).norm_squared();
        worst = if d2 > worst { d2 } else { worst };
    }
    *moved = worst.sqrt();
    (worst > 0.25 * skin * skin, sum)
}

/// The second half-kick of one chunk of particles at positions `pos`; returns the sum of every
/// position, velocity and spin coordinate, finite unless one of them is not.
fn kick_chunk<const D: usize>(
    s: &Shared<'_, D>,
    pos: &[VecD<D>],
    g: VecD<D>,
    h: f64,
    vel: &mut [VecD<D>],
    omega: &mut [f64],
) -> f64 {
    let n = vel.len();
    let ns = n * spin_len(D);
    let (force, torque, im, ii) = (&s.force[..n], &s.torque[..ns], &s.im[..n], &s.ii[..n]);
    let (pos, omega) = (&pos[..n], &mut omega[..ns]);
    // component-wise running sums: no horizontal add per particle
    let (mut sx, mut sw) = (VecD::<D>::zeros(), Vec3::zeros());
    for i in 0..n {
        let (a, al) = (force[i] * im[i] + g, spin::<D>(torque, i) * ii[i]);
        let mut w = spin::<D>(omega, i);
        end_kick(a, al, h, &pos[i], &mut vel[i], &mut w, &mut sx, &mut sw);
        set_spin::<D>(omega, i, &w);
    }
    sx.sum() + sw.sum()
}

/// The fewest steps per collision (τ/dt, τ the contact time at the largest expected impact
/// speed) a run accepts. Velocity Verlet is stable for an undamped spring of angular frequency ω
/// only while ω dt < 2. A linear spring's contact lasts π/ω, so its limit is π/2 ≈ 1.57 steps
/// per collision; a Hertz contact stiffens with overlap (ω² = (3/2) K δ^{1/2}/m), and at its
/// deepest overlap ω = 1.37 v/δ_max while τ = 2.94 δ_max/v, so its limit is 2.0. Below it the
/// contact gains energy step by step. It is a floor, not a guarantee: damping taken from the
/// explicit velocity narrows the stable range further (for a linear dashpot, to
/// ω dt < 2(√(1 + ζ²) − ζ) at damping ratio ζ), and well above it the restitution is still off
/// (about 50 steps per collision give it within 1e-3; [`StepChoice::warning`] speaks up below
/// [`WARN_STEPS_PER_COLLISION`]).
pub const MIN_STEPS_PER_COLLISION: f64 = 2.0;

/// Below this many steps per collision a given step draws a warning ([`StepChoice::warning`]).
pub const WARN_STEPS_PER_COLLISION: f64 = 10.0;

/// Checks a steps-per-collision setting called `name` (the chosen step is τ/k): the message
/// names the value and the range.
pub fn check_steps_per_collision(name: &str, k: f64) -> Result<(), String> {
    if k.is_finite() && k >= MIN_STEPS_PER_COLLISION {
        return Ok(());
    }
    Err(format!(
        "{name} = {k} is out of range: it must be >= {MIN_STEPS_PER_COLLISION} (below, the explicit step is unstable at a Hertz contact's deepest overlap)"
    ))
}

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

impl StepChoice {
    /// What a user should hear about a given step: that it resolves a collision in fewer than
    /// [`WARN_STEPS_PER_COLLISION`] steps, or that the contact time could not be computed (the
    /// two-body driver failed with this law), so the step went unchecked. None for a chosen
    /// step or a well-resolved one.
    pub fn warning(&self) -> Option<String> {
        if !self.given {
            return None;
        }
        let k = self.collision_time / self.dt;
        if !k.is_finite() {
            return Some(format!(
                "the contact time at {:.3} m/s could not be computed with this law: the step dt = {:.4e} s is not checked against it",
                self.impact_speed, self.dt
            ));
        }
        (k < WARN_STEPS_PER_COLLISION).then(|| {
            format!(
                "{k:.1} steps per collision at {:.3} m/s: the contacts are barely resolved, and the restitution is off by 1e-3 or more (about {:.4e} s, 50 steps per collision, resolves it)",
                self.impact_speed,
                self.collision_time / 50.0
            )
        })
    }
}

/// A soft-sphere DEM run.
pub struct Engine<const D: usize> {
    /// The particles. Between steps, velocities and spins may be edited freely; positions only
    /// followed by [`Engine::invalidate_neighbours`] (the neighbour list's staleness is tracked
    /// from the particles' speeds, so a particle moved by hand is not seen to have moved).
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
    /// partner j of a pair contact whose i is in the chunk), added after the parallel part.
    overflow: Vec<Vec<(u32, VecD<D>, Vec3)>>,
    /// For each chunk of particles, the last chunk holding a pair partner of one of its
    /// particles (in the current neighbour list).
    reach: Vec<usize>,
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
            pairs: Contacts::new(sn, st),
            wall_contacts: Contacts::new(swn, swt),
            overflow: Vec::new(),
            reach: Vec::new(),
            moved: Vec::new(),
            pending_kick: false,
            wall_impulse: vec![VecD::<D>::zeros(); nw],
            wall_episodes: vec![0; nw],
            pair_episodes: 0,
        };
        e.check(false)?;
        e.rebuild();
        // the initial forces: a trial evaluation, its history discarded (nothing has happened yet)
        e.forces()?;
        e.pairs.clear_history();
        e.wall_contacts.clear_history();
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

    /// The walls' planes now.
    pub fn wall_states(&self) -> Vec<WallState<D>> {
        self.walls.iter().map(|w| w.at(self.t)).collect()
    }

    /// Gathers the contacts at the current positions and predicted velocities, calls the laws,
    /// and sums forces and torques into the particles.
    ///
    /// The particles are cut into chunks of [`GATHER_CHUNK`]; each chunk is one task, run in
    /// parallel: it gathers its particles' pair and wall contacts (history from the same chunk
    /// of the last step), calls the laws on them, and sums the forces into its own particles'
    /// slice of the force and torque arrays ([`chunk_forces`]). A pair partner j beyond the
    /// chunk gets its share afterwards, chunk by chunk in order ([`Engine::finish_forces`]).
    /// The sums therefore run in one fixed order whatever the number of threads, and a run is
    /// bit for bit the same on one core or many. (The steps themselves do this work chunk by
    /// chunk right after each chunk's drift: [`Engine::drift_and_forces`].)
    fn forces(&mut self) -> Result<(), DemError> {
        let ws = self.wall_states();
        let n = self.p.len();
        let chunks = n.div_ceil(GATHER_CHUNK);
        self.overflow.resize_with(chunks, Vec::new);
        let (prev_p, next_p) = self.pairs.buffers(chunks);
        let (prev_w, next_w) = self.wall_contacts.buffers(chunks);
        let p = &mut self.p;
        let view = View {
            base: 0,
            pos: &p.pos,
            vpred: &self.vpred,
            vel: &p.vel,
            omega: &p.omega,
            radius: &p.radius,
            mass: &p.mass,
        };
        let ctx = ChunkContext {
            dom: &self.cfg.domain,
            nb: &self.nb,
            walls: &ws,
            laws: &self.laws,
            dt: self.dt,
            edges: self.cfg.edge_means,
        };
        let work = |(c, ((((pp, np), (pw, nw)), (f, tq)), ov)): ChunkTask<'_, D>| {
            let range = c * GATHER_CHUNK..(c * GATHER_CHUNK + f.len());
            chunk_forces(&ctx, range, &view, (pp, np), (pw, nw), f, tq, ov)
        };
        let force = &mut p.force;
        let torque = &mut p.torque;
        let overflow = &mut self.overflow;
        // the first error in chunk order, whatever the threads did
        // the same chain of zips, by std's iterators or rayon's (method names given)
        macro_rules! tasks {
            ($iter:ident, $iter_mut:ident, $chunks_mut:ident) => {
                prev_p
                    .$iter()
                    .zip(next_p.$iter_mut())
                    .zip(prev_w.$iter().zip(next_w.$iter_mut()))
                    .zip(
                        force
                            .$chunks_mut(GATHER_CHUNK)
                            .zip(torque.$chunks_mut(GATHER_CHUNK * spin_len(D))),
                    )
                    .zip(overflow.$iter_mut())
                    .enumerate()
                    .map(work)
                    .collect()
            };
        }
        let results: Vec<Result<(), DemError>> = if n < SERIAL_BELOW {
            tasks!(iter, iter_mut, chunks_mut)
        } else {
            tasks!(par_iter, par_iter_mut, par_chunks_mut)
        };
        self.finish_forces(results.into_iter().collect())
    }

    /// The serial end of a force evaluation whose chunks gave `results` (the first error in
    /// chunk order): a contact test that met a NaN reports the particle whose state is not
    /// finite; else the new contacts become the current ones, the partners beyond each chunk
    /// get their forces (chunk by chunk, in order), and the walls' impulses and episodes and
    /// the pair episodes are counted.
    fn finish_forces(&mut self, results: Result<(), DemError>) -> Result<(), DemError> {
        results.map_err(|e| match self.check(true) {
            Err(nf @ DemError::NonFinite { .. }) => nf,
            _ => e,
        })?;
        self.pairs.swap();
        self.wall_contacts.swap();
        let p = &mut self.p;
        for ov in &self.overflow {
            for &(j, f, t) in ov {
                p.force[j as usize] -= f;
                add_spin::<D>(&mut p.torque, j as usize, &t);
            }
        }
        for w in &self.wall_contacts.chunks {
            for m in 0..w.len() {
                let nv = Vec3::from(w.normal[m]);
                let fi = nv * w.fnorm[m] + Vec3::from(w.ftan[m]);
                let k = w.j[m] as usize;
                self.wall_impulse[k] -= from3::<D>(&fi) * self.dt;
                if w.fresh[m] {
                    self.wall_episodes[k] += 1;
                }
            }
        }
        self.pair_episodes += self.pairs.formed() as u64;
        Ok(())
    }

    /// Rebuilds the neighbour list (wrapping positions into the box), with the chunks' reach
    /// and displacement bounds.
    fn rebuild(&mut self) {
        self.nb
            .build(&self.cfg.domain, &mut self.p.pos, &self.p.radius, self.skin);
        self.nb.chunk_reach(GATHER_CHUNK, &mut self.reach);
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
        self.step_with(false)
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
        let fuse = !self.cfg.domain.bounded;
        let parallel = k > 1 && self.p.len() >= SERIAL_BELOW;
        let mut block = || {
            for s in 0..k {
                self.step_with(fuse && s + 1 < k)?;
            }
            Ok(())
        };
        if parallel {
            awake::with_pool_awake(block)
        } else {
            block()
        }
    }

    /// One step; with `defer`, the step ends before its second half-kick, which the next step
    /// does first ([`Engine::advance`]).
    fn step_with(&mut self, defer: bool) -> Result<(), DemError> {
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
                self.finish_forces(pass.result)?;
            }
        } else {
            // no list (after [`Engine::invalidate_neighbours`]): the kicks and the drift of every
            // particle, then the list, then the forces
            let c = GATHER_CHUNK;
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
                if n < SERIAL_BELOW {
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
        if defer {
            self.pending_kick = true;
            return Ok(());
        }
        let c = GATHER_CHUNK;
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
            if n < SERIAL_BELOW {
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

    /// The exact state check, particle by particle: the first non-finite particle (velocities
    /// and spins too if `velocities_too`), or in a bounded box the first one outside it. The
    /// steps call it only when their running sums were not finite, or in a bounded box.
    fn check(&self, velocities_too: bool) -> Result<(), DemError> {
        let p = &self.p;
        let dom = &self.cfg.domain;
        let bad_at = |&i: &usize| {
            let fin = p.pos[i].iter().all(|x| x.is_finite())
                && (!velocities_too
                    || (p.vel[i].iter().all(|x| x.is_finite())
                        && p.angular_velocity(i).iter().all(|x| x.is_finite())));
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
                || !p.angular_velocity(i).iter().all(|x| x.is_finite())
            {
                return Err(DemError::NonFinite {
                    i,
                    t: self.t,
                    pos: fmt(&p.pos[i]),
                    vel: fmt(&p.vel[i]),
                    spin: format!("{:?}", p.angular_velocity(i).as_slice()),
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
        .map(|i| p.vel[i].norm() + p.angular_velocity(i).norm() * p.radius[i])
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
