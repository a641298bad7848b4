//! Contacts gathered each step into arrays (structure of arrays, what the laws' batch calls
//! take), and their history carried from step to step.
//!
//! A contact is keyed by `(i, j)`: two particles with `i < j`, or particle `i` and wall `j`.
//! The contacts are kept in chunks by their particle `i`: chunk `c` holds those of particles
//! `c·C .. (c+1)·C` for the pile's chunk size `C` ([`gather_chunk`]), in key order (particle
//! by particle, partners sorted). Particle indices never change, so a contact stays in its chunk for life: its
//! history is found in the same chunk of the previous step, also in key order, by a merge
//! (one cursor moving forward through the previous set), and each chunk is gathered, evaluated and
//! scattered as one parallel task that touches no other chunk's contacts (see
//! [`super::integrator::Engine`]). A contact that is new starts from zero history; one that is
//! gone is not carried over (dropped at separation). Neither a neighbour-list rebuild nor a
//! periodic wrap touches the history.
//!
//! Each chunk is double-buffered ([`Contacts`]): the step's contacts are written into the
//! spare set while the previous step's are read, then the two are swapped, so a step allocates
//! nothing once the arrays have grown to the pile's size.

use super::state::VecD;
use super::DemError;
use crate::laws::{EnergyOut, NormalLaw, TangentialForce};
use dashpot_sdk::{HeatFlow, NormalBatch, NormalContext, TangentialBatch};
use std::ops::Range;

mod classes;
mod edges;
mod gather;
mod pair_geometry;
mod renumber;
mod rotation;
mod saved;

pub use classes::{gather_pair_classes, gather_wall_classes};
use edges::{step_edge_means, EdgeScratch, Edges};
pub use rotation::Rotating;

/// The particle state a gathering reads: particles `base..base + pos.len()`, each array
/// indexed by particle number minus `base` (the engine hands a chunk the particles its
/// contacts can reach, and no more: other chunks' particles may be moving meanwhile).
#[derive(Debug, Clone, Copy)]
pub struct View<'a, const D: usize> {
    /// The first particle of the view.
    pub base: usize,
    /// Positions (m).
    pub pos: &'a [VecD<D>],
    /// Predicted end-of-step velocities (m/s), for the overlap rates.
    pub vpred: &'a [VecD<D>],
    /// The step's (half-step) velocities (m/s), for the contact points' slip.
    pub vel: &'a [VecD<D>],
    /// The step's angular velocities (rad/s), laid out as [`super::state::Particles::omega`].
    pub omega: &'a [f64],
    /// Radii (m).
    pub radius: &'a [f64],
    /// Masses (kg).
    pub mass: &'a [f64],
    /// The user's number of each particle when the engine keeps its own order (see
    /// [`super::integrator::Engine::user_index`]), `None` when the two are the same. A pair
    /// contact is presented to the laws from the partner the user numbered first, so that
    /// the laws see the same contact (and keep the same history) whatever the order.
    pub uid: Option<&'a [u32]>,
    /// Each particle's species (see [`super::species`]); empty when every particle is of
    /// species 0.
    pub species: &'a [u8],
}

/// How a chunk's contacts are sorted into their classes' sets ([`Contacts`]): the class of
/// each pair of species and of each species against each wall (see
/// [`super::species::SpeciesLaws`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct ClassMap<'a> {
    /// Species in the run.
    pub species: usize,
    /// Walls in the run.
    pub walls: usize,
    /// The class of the pair of species `(a, b)`: `pair[a * species + b]` (empty: one class).
    pub pair: &'a [u8],
    /// The class of species `s` against wall `w`: `wall[s * walls + w]` (empty: one class).
    pub wall: &'a [u8],
}

/// One chunk of one kind of contacts (particle pairs, or particles against walls), structure
/// of arrays.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactSet {
    /// First partner: a particle.
    pub i: Vec<u32>,
    /// Second partner: a particle (j > i) or a wall index.
    pub j: Vec<u32>,
    /// Overlaps δ (m).
    pub delta: Vec<f64>,
    /// Overlap rates (m/s), > 0 approaching.
    pub rate: Vec<f64>,
    /// Effective masses (kg).
    pub mass: Vec<f64>,
    /// Effective radii (m).
    pub radius: Vec<f64>,
    /// Unit normals from j to i.
    pub normal: Vec<[f64; 3]>,
    /// Velocities of i's contact point relative to j's (m/s).
    pub vrel: Vec<[f64; 3]>,
    /// Pairs in the engine's own order (see [`View::uid`]): −1 where the laws see the contact
    /// from j (the partner the user numbered first: `normal`, `vrel`, the forces and the
    /// history are then j's), +1 where from i; empty when the engine keeps the user's order.
    pub sign: Vec<f64>,
    /// Normal-law history, `slots_n` per contact.
    pub hist_n: Vec<f64>,
    /// Tangential-law history, `slots_t` per contact.
    pub hist_t: Vec<f64>,
    /// Normal history slots per contact.
    pub slots_n: usize,
    /// Tangential history slots per contact.
    pub slots_t: usize,
    /// Normal forces (N), > 0 repulsive.
    pub fnorm: Vec<f64>,
    /// Tangential forces on i (N).
    pub ftan: Vec<[f64; 3]>,
    /// Whether each contact formed this step (its first touch).
    pub fresh: Vec<bool>,
    /// Whether each contact's force was last taken as the rest of the contact (see
    /// [`ContactSet::evaluate`]: the step predicted to be its last); carried over.
    pub last: Vec<bool>,
    /// Rolling- and twisting-law history slots per contact (sdk 0.3); `None`: no such law,
    /// and the rotational arrays below stay empty.
    pub slots_r: Option<usize>,
    /// Twisting-law history slots per contact.
    pub slots_w: Option<usize>,
    /// Rolling-law history.
    pub hist_r: Vec<f64>,
    /// Twisting-law history.
    pub hist_w: Vec<f64>,
    /// Rolling velocities R_eff (ω_i − ω_j) × n̂ (m/s).
    pub vroll: Vec<[f64; 3]>,
    /// Twisting rates (ω_i − ω_j)·n̂ (rad/s).
    pub twist: Vec<f64>,
    /// Rolling-resistance forces (N): the torque on i is R_eff n̂ × F, on j its opposite.
    pub froll: Vec<[f64; 3]>,
    /// Twisting torques about n̂ on i (N·m), on j their opposite.
    pub mtwist: Vec<f64>,
    /// The normal law's contexts (sdk 0.4), one per contact while a tangential, rolling,
    /// twisting or heat law of the run reads them (see [`ContactSet::evaluate`]); empty otherwise.
    #[serde(skip)]
    pub context: Vec<NormalContext>,
    /// Each contact's heat flow (W) into the partner the laws see it from (`i`, or `j` where
    /// [`ContactSet::sign`] is −1; the other partner gets its negative) and conductance
    /// (W/K) at the last evaluation of a run with temperatures and a heat law for this class
    /// (see `integrator/heat.rs`); empty otherwise.
    #[serde(skip)]
    pub flow: Vec<HeatFlow>,
    /// Scratch of the heat law's call: each contact's temperatures as its laws see it
    /// (`[T_i, T_j]`, or `[T_j, T_i]` where [`ContactSet::sign`] is −1; K).
    #[serde(skip)]
    pub pair_t: Vec<[f64; 2]>,
    /// Whether the laws are asked for their energy outputs.
    pub energy: bool,
    /// The largest reach of the normal law (m; 0 for a law that is not adhesive): contacts are
    /// kept beyond touching while δ ≥ −reach of their own (see [`ContactSet::reach`]).
    pub reach_bound: f64,
    /// Each contact's reach after its last force call (m), kept when `reach_bound` > 0.
    pub reach: Vec<f64>,
    /// Dissipated power of each contact (W), by family: normal, tangential, rolling, twisting.
    pub power: [Vec<f64>; 4],
    /// Elastic energy stored in each contact (J), by family.
    pub elastic: [Vec<f64>; 4],
    /// The families whose law did not report its energy at the last evaluation.
    pub unreported: [bool; 4],
    /// The contacts' dissipated power summed by family at the last evaluation (W; with
    /// `energy`), block by block as the laws wrote it (while it is in cache).
    pub power_sum: [f64; 4],
    /// The elastic energy the tangential, rolling and twisting springs of the previous step's
    /// contacts that ended held, and an adhesive normal law's (J, by family), with `energy`:
    /// dissipated at the gathering that dropped them (the contact that held it is gone).
    pub dropped: [f64; 4],
    /// The contacts of the previous step that ended holding spring energy: their particles
    /// (`i`, `j` as [`ContactSet::i`], [`ContactSet::j`]) and that energy (J), with `energy`.
    pub ended: Vec<(u32, u32, f64)>,
    /// The chunk's first particle.
    pub first: usize,
    /// Contacts of this set that were not in the previous one (first touches this step).
    pub formed: usize,
    /// Scratch of the gathering: the candidate pairs (or particles, `j` unused, for walls).
    #[serde(skip)]
    cand: Vec<(u32, u32)>,
    /// Scratch of a gathering into several classes' sets: every class's candidates, before
    /// they are sorted into their sets (kept by the chunk's first set).
    #[serde(skip)]
    split: Vec<(u32, u32)>,
    /// Scratch of a gathering into several classes' sets: each candidate's class (kept by the
    /// chunk's first set).
    #[serde(skip)]
    class_of: Vec<u8>,
    /// Scratch of the walls' gathering: each particle's largest overlap with a wall (m).
    #[serde(skip)]
    scratch: Vec<f64>,
    /// Scratch of the merge: each contact's index in the previous set.
    #[serde(skip)]
    src: Vec<u32>,
    /// Scratch of the first- and last-step means.
    #[serde(skip)]
    edge: EdgeScratch,
}

/// The overlap beyond which a run is refused, as a fraction of the smaller radius.
pub const MAX_OVERLAP: f64 = 0.5;

/// Contacts per law call.
pub const LAW_CHUNK: usize = 1024;

/// Particles per chunk of contacts (the unit of parallel work), but in the 3D piles of
/// [`SMALL_FROM`] to [`FULL_CHUNK_FROM`] particles ([`gather_chunk`]).
pub const GATHER_CHUNK: usize = 2048;

/// Particles per chunk of contacts in a pile of `n` particles in `dim` dimensions: a 3D pile of
/// [`SMALL_FROM`] particles to fewer than [`FULL_CHUNK_FROM`] is cut into [`SMALL_CHUNKS`]
/// chunks (a multiple of 64 particles, at least [`MIN_CHUNK`]), so that two or more threads
/// share its step out; every other pile takes [`GATHER_CHUNK`]s. In 2D, a disk has a third of a
/// sphere's contacts and work, and a small pile's step would pay its chunks' fixed costs (some
/// 4,000 instructions a chunk: 8 % of a 2,000-disk step in 16 chunks) for a step of tens of
/// microseconds. A function of the pile alone, never of the threads: the chunks fix the order
/// in which forces are summed, and so a run's bits.
pub fn gather_chunk(n: usize, dim: usize) -> usize {
    if dim == 3 && (SMALL_FROM..FULL_CHUNK_FROM).contains(&n) {
        n.div_ceil(SMALL_CHUNKS).next_multiple_of(64).max(MIN_CHUNK)
    } else {
        GATHER_CHUNK
    }
}

/// [`gather_chunk`] for a run whose pair contacts fall into `classes` classes (pairs of species
/// with their own laws, see [`crate::dem::species`]): a small pile's chunks then hold `classes`
/// times the particles (at most [`GATHER_CHUNK`]), so that each class's batch calls and arrays
/// are as long as those of a run of one class (a chunk's contacts split into `classes` sets of
/// a third as many each made every batch call's fixed cost and every array's first touch count
/// three times as often). One class: [`gather_chunk`].
pub fn gather_chunk_classes(n: usize, dim: usize, classes: usize) -> usize {
    let c = gather_chunk(n, dim);
    if classes > 1 && c < GATHER_CHUNK {
        (c * classes).min(GATHER_CHUNK)
    } else {
        c
    }
}

/// Whether a pile of chunks of `chunk` particles ([`gather_chunk`]) sums each particle's
/// shares of the earlier chunks' contacts nearest chunk first (small chunks: a chunk's contacts
/// then add their partners' shares at once when those are the same thread's), or farthest
/// first ([`GATHER_CHUNK`]s: the order the engine has always summed them in, so that such a
/// pile keeps its bits).
pub fn nearest_first(chunk: usize) -> bool {
    chunk < GATHER_CHUNK
}

/// Whether a pile of `n` particles in chunks of `chunk` steps in parallel on a pool of several
/// threads: from [`SERIAL_BELOW`] particles on, or in small chunks (fewer chunks share out
/// badly: two 2,048-particle chunks with a dependency between them ran slower on two threads
/// than on one).
pub fn parallel(n: usize, chunk: usize) -> bool {
    n >= SERIAL_BELOW || nearest_first(chunk)
}

/// Chunks of a small 3D pile (see [`gather_chunk`]).
pub const SMALL_CHUNKS: usize = 16;

/// The smallest chunk (particles) (see [`gather_chunk`]).
pub const MIN_CHUNK: usize = 128;

/// The batch of a law of the contact's motion, `motion_batch!(Batch { set[a..b], dt,
/// normal_force: SLICE, input: ARRAY, history / slots => output: ARRAY })`, on contacts
/// `a..b` of contact set `set`: the step `dt` (s), the geometry every such law reads (unit
/// normals, the normal forces (N) given, overlaps, masses, radii), the law's own input array,
/// its history of `slots` values a contact and its output array, with the normal law's contexts
/// of the contacts when the laws read them ([`contexts`]). For the tangential and
/// rolling laws (`velocity: ARRAY => force: ARRAY`, [`dashpot_sdk::VectorBatch`]) and the
/// twisting law (`rate: ARRAY => torque: ARRAY`, [`dashpot_sdk::TwistingBatch`]). A macro
/// rather than a method: the batch borrows the set's arrays one by one, some shared and some
/// mutably, where a method would borrow the whole set.
macro_rules! motion_batch {
    ($ty:ident {
        $set:ident[$a:ident..$b:ident], $dt:ident, normal_force: $fnorm:expr,
        $input:ident: $inputs:ident, $history:ident / $slots:ident => $output:ident: $outputs:ident
    }) => {
        $ty {
            dt: $dt,
            normal: &$set.normal[$a..$b],
            $input: &$set.$inputs[$a..$b],
            normal_force: $fnorm,
            delta: &$set.delta[$a..$b],
            mass: &$set.mass[$a..$b],
            radius: &$set.radius[$a..$b],
            context: contexts(&$set.context, $a..$b),
            slots: $slots,
            history: &mut $set.$history[$a * $slots..$b * $slots],
            $output: &mut $set.$outputs[$a..$b],
        }
    };
}
use motion_batch;

/// The energy outputs of contacts `r` of family `k` (0 normal, 1 tangential, 2 rolling, 3
/// twisting: the index into [`ContactSet::power`] and [`ContactSet::elastic`]); none unless
/// `energy` (the arrays are then sized for every contact).
#[inline(always)]
fn family_out<'v>(
    energy: bool,
    power: &'v mut [Vec<f64>; 4],
    elastic: &'v mut [Vec<f64>; 4],
    k: usize,
    r: Range<usize>,
) -> EnergyOut<'v> {
    if energy {
        EnergyOut {
            power: Some(&mut power[k][r.clone()]),
            elastic: Some(&mut elastic[k][r]),
        }
    } else {
        EnergyOut::none()
    }
}

/// The sum of `x` in four interleaved partial sums added pairwise at the end: the same bits on
/// every run (the order is fixed), in a loop the compiler vectorises, where a plain sum is one
/// chain of additions each waiting on the last.
fn sum4(x: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let mut quads = x.chunks_exact(4);
    for q in &mut quads {
        for k in 0..4 {
            acc[k] += q[k];
        }
    }
    let rest: f64 = quads.remainder().iter().sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + rest
}

/// The normal contexts of contacts `r` of a set whose contexts are `all` ([`ContactSet::context`])
/// for the laws of the contact's motion: those the normal law reported, or none (the defaults)
/// when no law of the run reads them.
#[inline]
fn contexts(all: &[NormalContext], r: Range<usize>) -> &[NormalContext] {
    if all.is_empty() {
        &[]
    } else {
        &all[r]
    }
}

impl ContactSet {
    /// Adds family `k`'s power on contacts `r`, just written by its law, to
    /// [`ContactSet::power_sum`] (with `energy`).
    fn add_power(&mut self, k: usize, r: Range<usize>) {
        if self.energy {
            self.power_sum[k] += sum4(&self.power[k][r]);
        }
    }

    /// An empty set for laws keeping `slots_n` and `slots_t` history values.
    pub fn new(slots_n: usize, slots_t: usize) -> ContactSet {
        ContactSet {
            slots_n,
            slots_t,
            ..Default::default()
        }
    }

    /// The set for rolling and twisting laws of `slots_r` and `slots_w` history slots (`None`:
    /// no such law).
    pub fn with_rotation(mut self, slots_r: Option<usize>, slots_w: Option<usize>) -> ContactSet {
        self.slots_r = slots_r;
        self.slots_w = slots_w;
        self
    }

    /// Whether a rolling or twisting law acts (the rotational arrays are kept).
    #[inline]
    pub fn rotational(&self) -> bool {
        self.slots_r.is_some() || self.slots_w.is_some()
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.i.len()
    }

    /// No contacts.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// Sizes every array for `count` contacts (keeping their room: once grown to a pile's
    /// contacts, no step allocates; only new elements are written, and the gathering then
    /// writes every contact's values by index).
    fn size(&mut self, count: usize) {
        self.i.resize(count, 0);
        self.j.resize(count, 0);
        self.delta.resize(count, 0.0);
        self.rate.resize(count, 0.0);
        self.mass.resize(count, 0.0);
        self.radius.resize(count, 0.0);
        self.normal.resize(count, [0.0; 3]);
        self.vrel.resize(count, [0.0; 3]);
        if !self.sign.is_empty() {
            self.sign.resize(count, 1.0);
        }
        self.hist_n.resize(count * self.slots_n, 0.0);
        self.hist_t.resize(count * self.slots_t, 0.0);
        self.fnorm.resize(count, 0.0);
        self.ftan.resize(count, [0.0; 3]);
        self.fresh.resize(count, false);
        self.last.resize(count, false);
        if self.energy {
            for v in self.power.iter_mut().chain(self.elastic.iter_mut()) {
                v.resize(count, 0.0);
            }
        }
        if self.reach_bound > 0.0 {
            self.reach.resize(count, 0.0);
        }
        if self.rotational() {
            let (sr, sw) = (self.slots_r.unwrap_or(0), self.slots_w.unwrap_or(0));
            self.hist_r.resize(count * sr, 0.0);
            self.hist_w.resize(count * sw, 0.0);
            self.vroll.resize(count, [0.0; 3]);
            self.twist.resize(count, 0.0);
            self.froll.resize(count, [0.0; 3]);
            self.mtwist.resize(count, 0.0);
        }
    }

    /// Calls the laws on every contact of the set (in batches of [`LAW_CHUNK`]): normal forces,
    /// then tangential forces (which need them), histories advanced in place over `dt` (s).
    ///
    /// The first and the last step of a contact (normal laws without history): velocity Verlet
    /// sums the force at the step ends, each standing for the step around it, a rule whose
    /// error at a kink (the force switching on at first touch and off at separation, with
    /// terms in δ^{1/4} or √δ in the damping) is of order dt^{5/4}, not dt². So at a first
    /// touch the force is replaced by the mean over the step of the law along the overlap
    /// extrapolated linearly back to first touch (δ from 0 to δ + δ̇ dt/2); at a step predicted
    /// to be the contact's last (δ + δ̇ dt − F dt²/2m ≤ 0) by the mean over what is left of the
    /// contact (δ from δ − δ̇ dt/2 down to 0), and a contact that was so predicted but still
    /// overlaps by less than |δ̇| dt/2 at the next step adds nothing more. The means are
    /// 5-point Gauss–Legendre rules in u with δ = D u⁴, exact for Hertz and HSD, one extra
    /// batch call per batch that has such contacts. A law with history (Thornton, Walton–Braun)
    /// keeps the step-end rule, as does every law when `edge_means` is false.
    pub fn evaluate(
        &mut self,
        normal: &dyn NormalLaw,
        tangential: Option<&dyn TangentialForce>,
        rotation: Rotating<'_>,
        dt: f64,
        edge_means: bool,
    ) -> Result<(), DemError> {
        let n = self.len();
        let (sn, st) = (self.slots_n, self.slots_t);
        // a law with history would see its history advanced by the extra calls: plain rule
        let edges = edge_means && sn == 0;
        // the normal law's contexts only when a law of the contact's motion reads them
        let reads = tangential.is_some_and(|t| t.reads_context())
            || rotation.rolling.is_some_and(|l| l.reads_context())
            || rotation.twisting.is_some_and(|l| l.reads_context())
            || rotation.context;
        self.context
            .resize(if reads { n } else { 0 }, NormalContext::default());
        self.unreported = [false; 4];
        self.power_sum = [0.0; 4];
        let mut a = 0;
        while a < n {
            let b = (a + LAW_CHUNK).min(n);
            let f = &mut self.fnorm[a..b];
            let nb = NormalBatch {
                delta: &self.delta[a..b],
                rate: &self.rate[a..b],
                mass: &self.mass[a..b],
                radius: &self.radius[a..b],
                slots: sn,
                history: &mut self.hist_n[a * sn..b * sn],
                force: &mut *f,
            };
            if reads {
                let out = family_out(self.energy, &mut self.power, &mut self.elastic, 0, a..b);
                let reach = (self.reach_bound > 0.0).then(|| &mut self.reach[a..b]);
                let written = normal.force_batch_context(nb, reach, &mut self.context[a..b], out)?;
                self.unreported[0] |= self.energy && !written;
            } else if self.energy || self.reach_bound > 0.0 {
                let out = family_out(self.energy, &mut self.power, &mut self.elastic, 0, a..b);
                let reach = (self.reach_bound > 0.0).then(|| &mut self.reach[a..b]);
                let written = normal.force_batch_with(nb, reach, out)?;
                self.unreported[0] |= self.energy && !written;
            } else {
                normal.force_batch(nb)?;
            }
            if edges {
                step_edge_means(
                    normal,
                    Edges {
                        delta: &self.delta[a..b],
                        rate: &self.rate[a..b],
                        mass: &self.mass[a..b],
                        radius: &self.radius[a..b],
                        fresh: &self.fresh[a..b],
                    },
                    &mut self.last[a..b],
                    f,
                    dt,
                    &mut self.edge,
                )?;
            }
            if let Some(t) = tangential {
                let mut tb = motion_batch!(TangentialBatch {
                    self[a..b], dt, normal_force: &*f,
                    velocity: vrel, hist_t / st => force: ftan
                });
                // (the contexts only to a law that reads them, as to the rolling and twisting)
                if !t.reads_context() {
                    tb.context = &[];
                }
                if self.energy {
                    let out = family_out(true, &mut self.power, &mut self.elastic, 1, a..b);
                    self.unreported[1] |= !t.force_batch_with(tb, out)?;
                    self.add_power(1, a..b);
                } else {
                    t.force_batch(tb)?;
                }
            }
            if self.rotational() {
                self.evaluate_rotation(&rotation, a..b, dt)?;
            }
            self.add_power(0, a..b);
            a = b;
        }
        Ok(())
    }
}

/// The history slots per contact of one class of contacts' laws: normal, tangential, and the
/// rolling and twisting laws' (`None`: no such law).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Slots {
    /// Normal-law history slots.
    pub n: usize,
    /// Tangential-law history slots (0 without a tangential law).
    pub t: usize,
    /// Rolling-law history slots.
    pub r: Option<usize>,
    /// Twisting-law history slots.
    pub w: Option<usize>,
}

/// One kind of contacts of a run (particle pairs, or particles against walls), in chunks of
/// particles ([`gather_chunk`], see the module doc), each double-buffered, and within each
/// chunk one set per *class* of contacts (a pair of species, or a species and a kind of wall,
/// with the same laws: [`crate::dem::species::SpeciesLaws`]): chunk `k`'s set of class `c` is
/// `chunks[k * classes + c]`. Each class has its own laws' history widths. A scene of one
/// species has one class: one set per chunk.
#[derive(Debug, Clone, Default)]
pub struct Contacts {
    /// The sets of the last evaluation, chunk by chunk in particle order, each chunk's classes
    /// in order.
    pub chunks: Vec<ContactSet>,
    /// The sets being written.
    spare: Vec<ContactSet>,
    /// Each class's history slots (at least one class).
    slots: Vec<Slots>,
    energy: bool,
    reach_bound: f64,
}

impl Contacts {
    /// No contacts yet, of one class whose laws keep `slots_n` and `slots_t` history values.
    pub fn new(slots_n: usize, slots_t: usize) -> Contacts {
        Contacts::of_classes(vec![Slots {
            n: slots_n,
            t: slots_t,
            ..Slots::default()
        }])
    }

    /// No contacts yet, of the classes whose laws keep `slots` history values (one entry per
    /// class, at least one).
    pub fn of_classes(slots: Vec<Slots>) -> Contacts {
        assert!(!slots.is_empty(), "at least one class of contacts");
        Contacts {
            slots,
            ..Default::default()
        }
    }

    /// The contacts of rolling and twisting laws of `slots_r` and `slots_w` history slots
    /// (`None`: no such law), for a set of one class.
    pub fn with_rotation(mut self, slots_r: Option<usize>, slots_w: Option<usize>) -> Contacts {
        self.slots[0].r = slots_r;
        self.slots[0].w = slots_w;
        self
    }

    /// The contacts of normal laws that reach `bound` (m) beyond touching at most.
    pub fn with_reach(mut self, bound: f64) -> Contacts {
        self.reach_bound = bound;
        self
    }

    /// The contacts with (`on`) or without the laws' energy outputs.
    pub fn with_energy(mut self, on: bool) -> Contacts {
        self.energy = on;
        self
    }

    /// Classes of contacts (sets per chunk).
    pub fn classes(&self) -> usize {
        self.slots.len()
    }

    /// Each class's history slots.
    pub fn slots(&self) -> &[Slots] {
        &self.slots
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.chunks.iter().map(ContactSet::len).sum()
    }

    /// No contacts.
    pub fn is_empty(&self) -> bool {
        self.chunks.iter().all(ContactSet::is_empty)
    }

    /// Contacts that formed at the last evaluation (first touches).
    pub fn formed(&self) -> usize {
        self.chunks.iter().map(|c| c.formed).sum()
    }

    /// Contacts whose last evaluation took the rest of the contact (see
    /// [`ContactSet::evaluate`]).
    pub fn predicted_last(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| c.last.iter().filter(|&&l| l).count())
            .sum()
    }

    /// Every contact's history set to zero (the engine's trial evaluation at construction).
    pub fn clear_history(&mut self) {
        for c in &mut self.chunks {
            c.hist_n.iter_mut().for_each(|h| *h = 0.0);
            c.hist_t.iter_mut().for_each(|h| *h = 0.0);
            c.hist_r.iter_mut().for_each(|h| *h = 0.0);
            c.hist_w.iter_mut().for_each(|h| *h = 0.0);
        }
    }

    /// An empty set of class `class`.
    fn make(&self, class: usize) -> ContactSet {
        let s = self.slots[class];
        ContactSet {
            energy: self.energy,
            reach_bound: self.reach_bound,
            ..ContactSet::new(s.n, s.t).with_rotation(s.r, s.w)
        }
    }

    /// The previous sets and the spare ones to write, of `chunks` chunks (each chunk's
    /// [`Contacts::classes`] sets in a row; created as needed).
    pub fn buffers(&mut self, chunks: usize) -> (&[ContactSet], &mut [ContactSet]) {
        let nc = self.classes();
        for v in [0, 1] {
            let len = if v == 0 {
                self.chunks.len()
            } else {
                self.spare.len()
            };
            let want = chunks * nc;
            let made: Vec<ContactSet> = (len..want).map(|k| self.make(k % nc)).collect();
            let sets = if v == 0 { &mut self.chunks } else { &mut self.spare };
            sets.truncate(want);
            sets.extend(made);
        }
        (&self.chunks, &mut self.spare)
    }

    /// The spare sets, now written, become the current ones.
    pub fn swap(&mut self) {
        std::mem::swap(&mut self.chunks, &mut self.spare);
    }
}

/// From this many particles on, chunks of contacts are [`GATHER_CHUNK`] particles (see
/// [`gather_chunk`]).
pub const FULL_CHUNK_FROM: usize = 4096;

/// From this many particles on, a 3D pile is cut into small chunks (see [`gather_chunk`]).
pub const SMALL_FROM: usize = 1024;

/// Below this many particles the engine runs serially (but a pile of small chunks, see
/// [`parallel`]): rayon's dispatch per parallel loop costs more than a few thousand particles'
/// work (a 50-disk bed ran at 175 µs per step).
pub const SERIAL_BELOW: usize = 4096;
