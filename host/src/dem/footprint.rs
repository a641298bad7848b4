//! The DEM engine's memory, from a run's configuration, before anything is allocated.
//!
//! A run's peak is the engine's arrays (particles, the integrator's, the neighbour list, the
//! memory order's second buffers), its contacts (each family's history, double-buffered, and
//! the gathering's scratch), what the caller keeps beside it (the scene's bodies, a scene file's
//! particle tables, the final state as JSON) and the process itself. Sizes are taken from the
//! engine's own types ([`std::mem::size_of`]) and the laws' own history widths, so the estimate
//! follows the configuration (dimension, laws, energy accounting, reordering).
//!
//! The contacts at the peak are those of a dense pile (coordination 6 in 3D, 4 in 2D: the
//! isostatic packings a pile settles into) times the share of the pile that has packed by the end
//! of the run ([`packed_share`]: under gravity, a loose pile packs from the floor up), or the
//! contacts counted on a sample of the run's own steps, whichever is larger. Measured against the
//! peak resident memory of real runs in docs/dem.md ("Before a run").

use super::contacts::{gather_chunk_classes, nearest_first};
use super::integrator::EngineConfig;
use super::species::{LawSet, SpeciesLaws};
use super::state::{spin_len, Body, VecD};
use super::Laws;
use crate::budget::{check_memory_against, largest_fitting, rss, Memory, Need, Refused};
use crate::laws::{HeatConduction, RollingResistance, TangentialForce, TwistingResistance};
use dashpot_sdk::{HeatFlow, NormalContext};
use std::mem::size_of;

/// A DEM run's shape: what its memory depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct Footprint {
    /// Particles.
    pub particles: usize,
    /// Dimension (2 or 3).
    pub dim: usize,
    /// Walls.
    pub walls: usize,
    /// History slots per contact of the normal, tangential, rolling and twisting laws between
    /// particles (`None`: no such law).
    pub slots: [Option<usize>; 4],
    /// The same against walls.
    pub wall_slots: [Option<usize>; 4],
    /// Whether the laws report their energy (8 more arrays per contact).
    pub energy: bool,
    /// Per contact between particles and against walls: whether the normal law's contexts are
    /// kept (a tangential, rolling, twisting or heat law reads them), and whether the contacts
    /// conduct heat (a heat law: each contact's flow and the temperatures it read).
    pub extras: [Extras; 2],
    /// Whether the engine keeps an order of its own (second buffers of the particle arrays).
    pub reordered: bool,
    /// Pairs in the neighbour list now, if a list was built.
    pub listed: Option<usize>,
    /// Pair contacts counted on a sample of the run's steps, if one was run.
    pub sampled: Option<usize>,
    /// The share of a dense pile's contacts the run reaches at its peak, in [0, 1]
    /// ([`packed_share`]; 1: dense).
    pub packed: f64,
    /// How much further the neighbour list reaches than with the default skin: the volume
    /// ratio ((d_max + skin) / (d_max + 0.3 d_min))^D (1 at the default skin).
    pub reach_ratio: f64,
    /// What the caller keeps beside the engine (bytes): the scene's bodies, its file's tables.
    pub kept: f64,
    /// Whether the run ends by writing its final state as JSON (`--json`, `--out`).
    pub final_json: bool,
    /// The process's resident memory before the run (bytes): code, plugins, the caller's data.
    pub baseline: f64,
}

/// What one kind of contacts keeps beyond its families' forces and history (see
/// [`Footprint::extras`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Extras {
    /// The normal law's contexts (sdk 0.4), kept when another law of the contact reads them.
    pub contexts: bool,
    /// A heat law: each contact's heat flow and conductance, and the temperatures it read.
    pub heat: bool,
}

impl Extras {
    /// What a contact's tangential, rolling, twisting and heat laws make it keep.
    fn of(
        tangential: Option<&dyn TangentialForce>,
        rolling: Option<&dyn RollingResistance>,
        twisting: Option<&dyn TwistingResistance>,
        heat: Option<&dyn HeatConduction>,
    ) -> Extras {
        Extras {
            contexts: tangential.is_some_and(|l| l.reads_context())
                || rolling.is_some_and(|l| l.reads_context())
                || twisting.is_some_and(|l| l.reads_context())
                || heat.is_some_and(|l| l.reads_context()),
            heat: heat.is_some(),
        }
    }

    /// What the laws `set` make the contacts keep.
    fn of_set(set: &LawSet) -> Extras {
        Extras::of(
            set.tangential.as_deref(),
            set.rolling.as_deref(),
            set.twisting.as_deref(),
            set.heat.as_deref(),
        )
    }

    /// Both, if either kind of contacts keeps them.
    fn or(self, o: Extras) -> Extras {
        Extras {
            contexts: self.contexts || o.contexts,
            heat: self.heat || o.heat,
        }
    }

    /// Bytes per contact in one buffer: a context is three f64, a flow two, the temperatures two.
    fn bytes(self) -> usize {
        let mut b = 0;
        if self.contexts {
            b += size_of::<NormalContext>();
        }
        if self.heat {
            b += size_of::<HeatFlow>() + size_of::<[f64; 2]>();
        }
        b
    }
}

/// Pair contacts per particle in a dense pile (half the coordination number): 3D, 2D.
pub const PAIRS_PER_PARTICLE: [f64; 2] = [3.0, 2.0];

/// Neighbour-list pairs per particle in a dense pile with the default skin (0.3 of the smallest
/// diameter): the contacts and the near neighbours (measured: 5.5 in 3D, 3.2 in 2D).
pub const LISTED_PER_PARTICLE: [f64; 2] = [5.5, 3.2];

/// Bytes of the final state as JSON per particle (the serde_json tree of `dem --json`, and its
/// text), measured.
pub const FINAL_JSON_PER_PARTICLE: [f64; 2] = [2250.0, 1900.0];

/// The allocator's share beyond the bytes asked for: the contact arrays grow by doubling, in
/// blocks of tens of kilobytes per chunk of particles (measured).
pub const SLACK: f64 = 1.25;

fn of3(dim: usize) -> usize {
    if dim == 3 {
        0
    } else {
        1
    }
}

impl Footprint {
    /// The footprint of a run of `particles` between `walls` walls under `laws` with `cfg`,
    /// before the engine is built.
    pub fn of<const D: usize>(
        cfg: &EngineConfig<D>,
        laws: &Laws,
        particles: usize,
        walls: usize,
    ) -> Footprint {
        let r = &laws.rotation;
        let slots = [
            Some(laws.pair.history_slots()),
            laws.pair_tangential.as_ref().map(|l| l.history_slots()),
            r.pair_rolling.as_ref().map(|l| l.history_slots()),
            r.pair_twisting.as_ref().map(|l| l.history_slots()),
        ];
        let wall_slots = [
            Some(laws.wall.history_slots()),
            laws.wall_tangential.as_ref().map(|l| l.history_slots()),
            r.wall_rolling.as_ref().map(|l| l.history_slots()),
            r.wall_twisting.as_ref().map(|l| l.history_slots()),
        ];
        let extras = [
            Extras::of(
                laws.pair_tangential.as_deref(),
                r.pair_rolling.as_deref(),
                r.pair_twisting.as_deref(),
                r.pair_heat.as_deref(),
            ),
            Extras::of(
                laws.wall_tangential.as_deref(),
                r.wall_rolling.as_deref(),
                r.wall_twisting.as_deref(),
                r.wall_heat.as_deref(),
            ),
        ];
        let mut fp = Footprint::with_slots(cfg, slots, wall_slots, particles, walls, 1);
        fp.extras = extras;
        fp
    }

    /// [`Footprint::of`] a run of several species: each family's history as wide as its widest
    /// class (every contact is of one class; the widest bounds them all).
    pub fn of_species<const D: usize>(
        cfg: &EngineConfig<D>,
        laws: &SpeciesLaws,
        particles: usize,
        walls: usize,
    ) -> Footprint {
        let widest = |sets: &[LawSet]| {
            let mut w: [Option<usize>; 4] = [None; 4];
            for s in sets {
                let one = [
                    Some(s.normal.history_slots()),
                    s.tangential.as_ref().map(|l| l.history_slots()),
                    s.rolling.as_ref().map(|l| l.history_slots()),
                    s.twisting.as_ref().map(|l| l.history_slots()),
                ];
                for (a, b) in w.iter_mut().zip(one) {
                    *a = match (*a, b) {
                        (Some(x), Some(y)) => Some(x.max(y)),
                        (x, y) => x.or(y),
                    };
                }
            }
            w
        };
        let classes = laws.pair.len();
        let extras = |sets: &[LawSet]| {
            sets.iter()
                .map(Extras::of_set)
                .fold(Extras::default(), Extras::or)
        };
        let mut fp = Footprint::with_slots(
            cfg,
            widest(&laws.pair),
            widest(&laws.wall),
            particles,
            walls,
            classes,
        );
        fp.extras = [extras(&laws.pair), extras(&laws.wall)];
        fp
    }

    /// The footprint of contacts of `slots` history slots per family (normal, tangential,
    /// rolling, twisting; none: no such law), `wall_slots` against walls, the pair contacts in
    /// `classes` classes (which set the engine's chunks, [`gather_chunk_classes`]).
    fn with_slots<const D: usize>(
        cfg: &EngineConfig<D>,
        slots: [Option<usize>; 4],
        wall_slots: [Option<usize>; 4],
        particles: usize,
        walls: usize,
        classes: usize,
    ) -> Footprint {
        let chunk = gather_chunk_classes(particles, D, classes);
        let reordered =
            cfg.sort_from != usize::MAX && (particles >= cfg.sort_from || (D == 3 && nearest_first(chunk)));
        Footprint {
            particles,
            dim: D,
            walls,
            slots,
            wall_slots,
            energy: cfg.energy,
            extras: [Extras::default(); 2],
            reordered,
            listed: None,
            sampled: None,
            packed: 1.0,
            reach_ratio: 1.0,
            kept: 0.0,
            final_json: false,
            baseline: crate::budget::rss().now as f64,
        }
    }

    /// The least a run of `count` particles in dimension `dim` needs, whatever its laws and
    /// contacts: the bodies as a scene makes them, the start checks' neighbour search, and the
    /// engine's particle arrays (bytes). What a scene checks before it generates its particles.
    pub fn floor(count: f64, dim: usize) -> f64 {
        let (body, vec) = if dim == 3 {
            (size_of::<Body<3>>(), size_of::<VecD<3>>())
        } else {
            (size_of::<Body<2>>(), size_of::<VecD<2>>())
        };
        // two copies of the bodies while generated ones are appended; the start check's
        // positions, radii and cell arrays; the engine's particles and neighbour anchors
        let scene = 2 * body + vec + 8 + 8 + 8 + 8 + 4 + 4;
        count * (scene + per_particle(dim, false)) as f64
    }

    /// The skin of a run with particles of diameters `dmin` to `dmax` (m) and `skin` (m; the
    /// default if `None`): the footprint's [`Footprint::reach_ratio`].
    pub fn with_skin(mut self, dmin: f64, dmax: f64, skin: Option<f64>) -> Footprint {
        let default = dmax + 0.3 * dmin;
        let r = (dmax + skin.unwrap_or(0.3 * dmin)) / default;
        self.reach_ratio = if r.is_finite() {
            r.max(1.0).powi(self.dim as i32)
        } else {
            f64::INFINITY
        };
        self
    }

    /// All the pairs there are, N (N - 1) / 2.
    fn all_pairs(&self) -> f64 {
        let n = self.particles as f64;
        0.5 * n * (n - 1.0).max(0.0)
    }

    /// Pair contacts at the run's peak: the packed share of a dense pile's, or those counted
    /// on a sample if more.
    pub fn pair_contacts(&self) -> f64 {
        let dense = PAIRS_PER_PARTICLE[of3(self.dim)] * self.particles as f64 * self.packed;
        dense.max(self.sampled.unwrap_or(0) as f64).min(self.all_pairs())
    }

    /// Neighbour-list pairs at the run's peak: the packed share of a dense pile's (scaled by the
    /// skin's reach), or the pairs listed now if more; at most every pair.
    pub fn listed_pairs(&self) -> f64 {
        let dense =
            LISTED_PER_PARTICLE[of3(self.dim)] * self.particles as f64 * self.reach_ratio * self.packed;
        dense.max(self.listed.unwrap_or(0) as f64).min(self.all_pairs())
    }

    /// Wall contacts at the run's peak: a layer of particles on each wall.
    pub fn wall_contacts(&self) -> f64 {
        let n = self.particles as f64;
        let layer = n.powf((self.dim as f64 - 1.0) / self.dim as f64);
        (self.walls as f64 * 1.5 * layer).min(n)
    }

    /// The run's peak memory, by part.
    pub fn need(&self) -> Need {
        let n = self.particles as f64;
        let mut need = Need::new();
        need.holding(self.baseline);
        need.add("kept beside the engine", self.kept);
        let mut particles = per_particle(self.dim, self.reordered) as f64 * n;
        // the neighbour list's row starts, flags, wall candidates, and its build's cell arrays
        particles += n * (4.0 + 1.0 + 4.0 + 8.0 + 8.0 + 8.0 + 4.0 + 4.0 + 1.0);
        need.add("particles", particles);
        need.add("neighbour list", 2.0 * 4.0 * self.listed_pairs());
        let pair = contact_bytes(&self.slots, self.energy, self.reordered, self.extras[0]);
        let wall = contact_bytes(&self.wall_slots, self.energy, self.reordered, self.extras[1]);
        // each set's candidates (8 bytes a listed pair, in both buffers) and merge sources
        let scratch = 2.0 * 8.0 * self.listed_pairs() + 2.0 * 4.0 * self.pair_contacts();
        need.add(
            "contacts",
            SLACK * (pair * self.pair_contacts() + wall * self.wall_contacts() + scratch),
        );
        if self.final_json {
            need.add("final state as JSON", self.final_json_bytes());
        }
        need
    }

    /// The final state as JSON (bytes): what `--json` or `--out` adds at the end of a run.
    pub fn final_json_bytes(&self) -> f64 {
        FINAL_JSON_PER_PARTICLE[of3(self.dim)] * self.particles as f64
    }
}

/// The densest random packing's solid fraction: of spheres (3D), of disks (2D).
pub const DENSE_FRACTION: [f64; 2] = [0.64, 0.82];

/// The share of a dense pile's contacts a run of `duration` (s) reaches, for `bodies` under
/// `gravity` (m/s²): a loose pile packs from the floor up, each particle once it has fallen its
/// share of the pile's settling (the pile's height times one less its solid fraction over a
/// dense packing's), so by time t the share of the pile below g t² / 2 of settling has packed:
/// min(1, (t / t_pack)²), t_pack the time to fall the whole settling. Without gravity, or for a
/// pile already dense, 1 (nothing says it stays loose).
pub fn packed_share<const D: usize>(bodies: &[Body<D>], gravity: &VecD<D>, duration: f64) -> f64 {
    let g = gravity.norm();
    if bodies.is_empty() || g.is_nan() || g <= 0.0 {
        return 1.0;
    }
    let down = gravity / g;
    let dmax = bodies.iter().map(|b| b.diameter).fold(0.0, f64::max);
    // the bounding box of the centres, widened by the largest diameter
    let mut lo = VecD::<D>::repeat(f64::INFINITY);
    let mut hi = VecD::<D>::repeat(f64::NEG_INFINITY);
    for b in bodies {
        lo = lo.inf(&b.position);
        hi = hi.sup(&b.position);
    }
    let span = (hi - lo).add_scalar(dmax);
    let ball = |d: f64| {
        if D == 3 {
            std::f64::consts::PI / 6.0 * d.powi(3)
        } else {
            std::f64::consts::PI / 4.0 * d * d
        }
    };
    let solid: f64 = bodies.iter().map(|b| ball(b.diameter)).sum();
    let fraction = solid / span.iter().product::<f64>();
    let height: f64 = span.iter().zip(down.iter()).map(|(s, u)| s * u.abs()).sum();
    let settle = (1.0 - fraction / DENSE_FRACTION[of3(D)]).max(0.0) * height;
    if !(settle > 0.0 && settle.is_finite()) {
        return 1.0;
    }
    let t_pack = (2.0 * settle / g).sqrt();
    (duration / t_pack).powi(2).min(1.0)
}

/// Refuses `count` particles (`key` names the setting, e.g. `generate.count`) in dimension
/// `dim` if not even the least they need ([`Footprint::floor`]) fits in the memory available:
/// what a scene checks before it makes them. The message names the count, the memory needed and
/// available, and the largest count that would fit.
pub fn check_count(key: &str, count: usize, dim: usize) -> Result<(), Refused> {
    let mem = Memory::now();
    let mut need = Need::new();
    need.holding(rss().now as f64);
    need.add("the particles alone", Footprint::floor(count as f64, dim));
    let most = largest_fitting(mem.available as f64, |n| Footprint::floor(n, dim));
    check_memory_against(
        &format!("{key} = {count} particles"),
        &need,
        &mem,
        &format!("lower {key} to {most} at the very most (the particles alone, before their contacts)"),
    )
}

/// Bytes per particle of the engine's arrays: the particles (positions, velocities, forces;
/// spins and torques; radii, masses, moments of inertia), the integrator's (predicted
/// velocities, old accelerations, inverse masses and moments), the neighbour list's anchors;
/// with `reordered`, the memory order's second buffers and its numbering.
fn per_particle(dim: usize, reordered: bool) -> usize {
    let (vec, s) = if dim == 3 {
        (size_of::<VecD<3>>(), spin_len(3))
    } else {
        (size_of::<VecD<2>>(), spin_len(2))
    };
    let particles = 3 * vec + 2 * 8 * s + 3 * 8;
    let integrator = 2 * vec + 2 * 8;
    let anchors = vec;
    let order = if reordered {
        3 * vec + 2 * 8 * s + 3 * 8 + 4
    } else {
        0
    };
    particles + integrator + anchors + order
}

/// Bytes per contact of one kind (both buffers of the double-buffered sets): the keys, the
/// geometry (overlap, rate, mass, radius, normal, relative velocity), the forces, the flags,
/// each family's history (`slots`: normal, tangential, rolling, twisting), the rolling and
/// twisting arrays if either acts, the energy outputs (power and stored energy per family),
/// the reach, the sign of a reordered pile's pairs, and the contexts and heat flows (`extras`).
fn contact_bytes(slots: &[Option<usize>; 4], energy: bool, reordered: bool, extras: Extras) -> f64 {
    let hist: usize = slots.iter().flatten().sum();
    let mut b = 4 + 4 + 4 * 8 + 2 * 24 + 8 + 24 + 2 + 8 * hist + 8 + extras.bytes();
    if slots[2].is_some() || slots[3].is_some() {
        b += 24 + 8 + 24 + 8;
    }
    if energy {
        b += 8 * 8;
    }
    if reordered {
        b += 8;
    }
    2.0 * b as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp(dim: usize, particles: usize) -> Footprint {
        Footprint {
            particles,
            dim,
            walls: 1,
            slots: [Some(0), None, None, None],
            wall_slots: [Some(0), None, None, None],
            energy: false,
            extras: [Extras::default(); 2],
            reordered: false,
            listed: None,
            sampled: None,
            packed: 1.0,
            reach_ratio: 1.0,
            kept: 0.0,
            final_json: false,
            baseline: 0.0,
        }
    }

    /// The estimate grows with what the run keeps: more particles, history, energy outputs,
    /// rotation laws, the reordering's buffers, a final document; and it is linear in the count.
    #[test]
    fn the_estimate_follows_the_configuration() {
        let base = fp(3, 100_000).need().total();
        let twice = fp(3, 200_000).need().total();
        assert!((twice / base - 2.0).abs() < 0.05, "{base} {twice}");
        let more = |f: &dyn Fn(&mut Footprint)| {
            let mut x = fp(3, 100_000);
            f(&mut x);
            x.need().total()
        };
        assert!(more(&|x| x.slots[1] = Some(3)) > base);
        assert!(more(&|x| x.energy = true) > base);
        assert!(more(&|x| x.slots[2] = Some(3)) > more(&|x| x.slots[1] = Some(3)));
        assert!(more(&|x| x.reordered = true) > base);
        // contexts (24 B a contact and buffer), heat's flow and temperatures (32 B)
        let contexts = more(&|x| x.extras[0].contexts = true);
        let heat = more(&|x| x.extras[0].heat = true);
        let pairs = fp(3, 100_000).pair_contacts();
        assert!(
            (contexts - base - SLACK * 2.0 * 24.0 * pairs).abs() < 1.0,
            "{contexts} {base}"
        );
        assert!(
            (heat - base - SLACK * 2.0 * 32.0 * pairs).abs() < 1.0,
            "{heat} {base}"
        );
        assert!(more(&|x| x.final_json = true) > base + 1e8);
        assert!(fp(2, 100_000).need().total() < base);
        // a list longer than a dense pile's counts as it is
        assert!(more(&|x| x.listed = Some(10_000_000)) > base);
        // the floor is below the estimate, and an absurd count is past any machine
        assert!(Footprint::floor(1e5, 3) < base);
        assert!(Footprint::floor(1e12, 3) > 1e14);
    }
}
