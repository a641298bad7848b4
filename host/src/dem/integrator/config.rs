//! The engine's configuration and the choice of its step: the contact time of the run's own law
//! at the largest expected impact speed, and the bounds on steps per collision.

use crate::collide::{collide, Options, PairLaw};
use crate::dem::cells::Domain;
use crate::dem::contacts::SERIAL_BELOW;
use crate::dem::species::SpeciesLaws;
use crate::dem::state::{Body, Material, Particles, VecD};
use crate::dem::walls::Wall;
use crate::dem::DemError;
use crate::laws::NormalLaw;
use dashpot_sdk::EndCriterion;
use rayon::prelude::*;

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
    /// Whether the laws report each contact's dissipated power and stored elastic energy
    /// (sdk 0.3), summed by family into [`super::Engine::dissipated`] (default false: the
    /// laws are called without those outputs).
    pub energy: bool,
    /// From how many particles on the engine keeps them in an order of its own, by neighbour
    /// cell (see [`super::Engine::user_index`]): in 3D [`SORT_FROM`] by default, in 2D never
    /// (`usize::MAX`: a 2D pile numbered row by row has its neighbours within a row's length
    /// in memory, in cache already, and the reordering cost more than it gained on the
    /// benchmarks' 10⁶-disk pile); 0: always. A 3D pile of small chunks (1,024 to 4,095
    /// particles, [`crate::dem::contacts::gather_chunk`]) keeps an order of its own whatever
    /// the count, in slabs (see `integrator/order.rs`), unless this is `usize::MAX` (never).
    /// What a user sees is numbered as given either way.
    pub sort_from: usize,
    /// Steps between two reorderings (default [`super::SORT_PERIOD`], at least 1).
    pub sort_period: u64,
}

/// The default of [`EngineConfig::sort_from`] in 3D: below this many particles a pile's arrays
/// sit in the caches whatever their order, and the reordering would cost without paying.
pub const SORT_FROM: usize = 16_384;

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
            energy: false,
            sort_from: if D == 3 { SORT_FROM } else { usize::MAX },
            sort_period: super::SORT_PERIOD,
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

/// The largest impact speed expected (m/s): the given one, or twice the largest initial surface
/// speed plus the largest wall speed plus the speed of a free fall across the extent of the
/// particles and walls (at least 0.01 m/s).
pub(super) fn impact_speed<const D: usize>(
    cfg: &EngineConfig<D>,
    p: &Particles<D>,
    walls: &[Wall<D>],
) -> f64 {
    if let Some(v) = cfg.impact_speed {
        return v;
    }
    let vmax = (0..p.len())
        .map(|i| p.vel[i].norm() + p.angular_velocity(i).norm() * p.radius[i])
        .fold(0.0, f64::max);
    // (a rotating plane's speed: at the particles' farthest from its axis)
    let reach = |c: &VecD<D>| p.pos.iter().map(|x| (x - c).norm()).fold(0.0, f64::max);
    let wmax = walls
        .iter()
        .map(|w| w.peak_speed(w.spin.map_or(0.0, |s| reach(&s.center))))
        .fold(0.0, f64::max);
    let g = cfg.gravity.norm();
    let mut extent = 0.0f64;
    if g > 0.0 {
        let gh = cfg.gravity / g;
        let hs: Vec<f64> = p
            .pos
            .iter()
            .map(|x| x.dot(&gh))
            .chain(walls.iter().flat_map(|w| w.heights(&gh)))
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

/// The shortest contact time (s) at impact speed `v` (m/s), by the two-body driver with the
/// run's own laws: for each pair of species present, their smallest particles against each
/// other (two of one species: the smallest against an equal one), and each species' smallest
/// particle against each class of walls it can meet (every wall class of the table when it
/// has one class, even without walls).
pub(super) fn collision_time<const D: usize>(
    laws: &SpeciesLaws,
    dim: usize,
    p: &Particles<D>,
    species: &[u8],
    v: f64,
) -> Result<f64, DemError> {
    let n = laws.species.len();
    // each species' smallest diameter (m), from its radii as the engine keeps them
    let mut rmin = vec![f64::INFINITY; n];
    for (k, &r) in p.radius.iter().enumerate() {
        let s = species.get(k).map_or(0, |&s| s as usize);
        rmin[s] = rmin[s].min(r);
    }
    let present: Vec<usize> = (0..n).filter(|&s| rmin[s].is_finite()).collect();
    let of = |s: usize| {
        let d = rmin[s] * 2.0;
        let (m, _) = laws.species[s].material.mass_inertia(dim, d);
        (m, 0.5 * d)
    };
    let mut runs: Vec<(&dyn NormalLaw, f64, f64)> = Vec::new();
    for (x, &a) in present.iter().enumerate() {
        for &b in &present[x..] {
            let law = &*laws.pair[laws.pair_class(a as u8, b as u8)].normal;
            let ((ma, ra), (mb, rb)) = (of(a), of(b));
            if a == b {
                runs.push((law, 0.5 * ma, 0.5 * ra));
            } else {
                runs.push((law, ma * mb / (ma + mb), ra * rb / (ra + rb)));
            }
        }
    }
    let walls = if laws.wall_class.is_empty() {
        1
    } else {
        laws.wall_class.len() / n
    };
    for &s in &present {
        let (m, r) = of(s);
        let mut seen = Vec::new();
        for w in 0..walls {
            let c = laws.wall_class(s as u8, w, walls);
            if !seen.contains(&c) {
                seen.push(c);
                runs.push((&*laws.wall[c].normal, m, r));
            }
        }
    }
    let mut tau = f64::INFINITY;
    for (law, mass, radius) in runs {
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

/// The largest reach (m) of the run's normal laws: how far beyond touching an adhesive law
/// (JKR) keeps a contact, from a contact formed at touch between the largest particles (the
/// reach grows with the radius), with a margin of 1.5; 0 for laws that are not adhesive.
pub(super) fn reach_bound<const D: usize>(laws: &SpeciesLaws, bodies: &[Body<D>]) -> Result<f64, DemError> {
    let Some(d) = bodies.iter().map(|b| b.diameter).reduce(f64::max) else {
        return Ok(0.0);
    };
    // each class's law, with the material of a species it acts on (its mass hardly matters)
    let n = laws.species.len();
    let walls = laws.wall_class.len() / n;
    let first_of = |class: usize, pairs: bool| -> usize {
        (0..n)
            .find(|&a| {
                if pairs {
                    (0..n).any(|b| laws.pair_class(a as u8, b as u8) == class)
                } else {
                    (0..walls.max(1)).any(|w| laws.wall_class(a as u8, w, walls) == class)
                }
            })
            .unwrap_or(0)
    };
    let classes = laws
        .pair
        .iter()
        .enumerate()
        .map(|(c, l)| (&l.normal, first_of(c, true)))
        .chain(
            laws.wall
                .iter()
                .enumerate()
                .map(|(c, l)| (&l.normal, first_of(c, false))),
        );
    let mut bound = 0.0f64;
    for (law, s) in classes {
        let p = laws.species[s].material.particle(d);
        let mut h = vec![0.0; law.history_slots()];
        let (mut f, mut reach) = ([0.0], [0.0]);
        law.force_batch_with(
            dashpot_sdk::NormalBatch {
                delta: &[1e-9 * d],
                rate: &[0.0],
                mass: &[p.mass()],
                radius: &[0.5 * d],
                slots: h.len(),
                history: &mut h,
                force: &mut f,
            },
            Some(&mut reach),
            crate::laws::EnergyOut::none(),
        )?;
        bound = bound.max(reach[0]);
    }
    Ok(1.5 * bound)
}

impl<const D: usize> super::Engine<D> {
    /// The exact state check, particle by particle: the first non-finite particle (velocities
    /// and spins too if `velocities_too`), or in a bounded box the first one outside it. The
    /// steps call it only when their running sums were not finite, or in a bounded box.
    pub(super) fn check(&self, velocities_too: bool) -> Result<(), DemError> {
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
                    i: self.user_index(i),
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
                i: self.user_index(i),
                t: self.t,
                pos: fmt(&p.pos[i]),
                axis,
                lo: dom.lo[axis],
                hi: dom.hi[axis],
            });
        }
        Ok(())
    }
}
