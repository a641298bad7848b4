//! The engine's memory order: from [`EngineConfig::sort_from`] particles on, the particles are
//! renumbered along a Morton (Z-order) curve through the cells of the neighbour grid, at the
//! first neighbour-list build and then every [`EngineConfig::sort_period`] steps (at a build
//! forced then), so that particles close in space are close in memory: a contact's partners,
//! and the chunks' neighbours, are then mostly in cache, whatever order the user gave (a large
//! pile generated layer by layer has a particle's neighbours above and below a whole layer
//! away in memory).
//!
//! A 3D pile of small chunks (1,024 to 4,095 particles, [`crate::dem::contacts::gather_chunk`])
//! sits in the caches in any order; what its order decides is how its step shares out between
//! threads, which take contiguous ranges of chunks (`pipeline.rs`). Its cells go slab by slab
//! along its longest axis (a periodic one counted at half its length: it is cut twice), in
//! Morton order within a slab, the slabs folded about a periodic seam ([`slab_rank`]). Two
//! ranges then meet at a plane (two planes, across a fold), and a range's last chunks reach
//! only the next range's first few: the *head* that range drifts before the others may
//! evaluate the forces across the cut. Along a Morton curve, or in a pile numbered layer by
//! layer whose layers have mixed as it fell, they reach most of the next range, which the other
//! thread must then drift before any of its forces (measured on the 3D pile of the benchmarks:
//! heads of 2.4 chunks of 8 instead of 6, BENCHMARKS.md).
//!
//! The renumbering is invisible from outside: between the engine's calls the particle arrays
//! ([`Engine::p`]) are in the user's order, in the same buffers after every call (so views of
//! them stay valid). Each [`Engine::step`] and [`Engine::advance`] permutes them into the
//! engine's order at its start and back at its end ([`Engine::advance_held`] leaves them in
//! the engine's order for the next such call). Inside, every per-particle array and the
//! contacts (their keys and histories, [`crate::dem::contacts::Contacts::renumber`]) follow
//! each renumbering. A pair contact is presented to the laws from the partner the user
//! numbered first ([`crate::dem::contacts::View::uid`]), so the laws get the same numbers in
//! either order; only the order in which a particle's contact forces are summed differs
//! (rounding). The order is a function of the positions at the steps it is made (multiples of
//! the period) and of the previous order, never of the threads, of the other builds of the
//! list, or of how the steps are split into calls: a run stays the same bit for bit on any
//! number of threads, with the list rebuilt at any steps, stepped one by one or in blocks.
//!
//! [`EngineConfig::sort_from`]: super::EngineConfig::sort_from
//! [`EngineConfig::sort_period`]: super::EngineConfig::sort_period

use super::Engine;
use crate::dem::cells::Domain;
use crate::dem::state::{spin_len, VecD};
use crate::dem::DemError;
use rayon::prelude::*;

/// The default of [`super::EngineConfig::sort_period`]: the particles are renumbered every
/// this many steps (and at the start): the order decays only as particles travel cells, while
/// a renumbering costs about two builds of the list (LAMMPS's `atom_modify sort` renumbers
/// every 1000 steps by default too).
pub const SORT_PERIOD: u64 = 1000;

/// Where the particles are, as far as the engine's order goes.
#[derive(Debug, Clone, Default)]
pub(super) struct Order<const D: usize> {
    /// The user's number of each particle of the engine (empty: the same numbers).
    pub(super) uid: Vec<u32>,
    /// Whether [`Engine::p`] is in the engine's order now (inside a step), else the user's.
    pub(super) inside: bool,
    /// The next neighbour-list build renumbers the particles.
    pub(super) due: bool,
    /// The other order's buffers of the particle arrays (the user's inside a step, the
    /// engine's outside), swapped with [`Engine::p`]'s at each crossing: so the arrays a user
    /// sees are the same buffers after every call, and a crossing is one pass over them.
    /// Positions, velocities, forces.
    vecs: [Vec<VecD<D>>; 3],
    /// Spins and torques.
    spins: [Vec<f64>; 2],
    /// Radii, masses, moments of inertia: fixed, so only swapped, never permuted at a
    /// crossing.
    pub(super) fixed: [Vec<f64>; 3],
}

impl<const D: usize> Engine<D> {
    /// The user's number of the engine's particle `k`: the contacts ([`Engine::pairs`],
    /// [`Engine::wall_contacts`]) number particles in the engine's own order (see
    /// `integrator/order.rs`); everything else is in the user's.
    pub fn user_index(&self, k: usize) -> usize {
        self.order.uid.get(k).map_or(k, |&u| u as usize)
    }

    /// `k` steps as [`Engine::advance`], the particle arrays left in the engine's order at the
    /// end (see [`Engine::user_index`]) for the next call of this one: a reordered pile steps
    /// on without permuting its arrays into the user's order and back at every call, which
    /// costs over half a step (70-90 ns per sphere there and back in 3D, against some 120 ns
    /// per sphere-step at 10⁶ spheres). Until
    /// [`Engine::to_user_order`] (which every other stepping call also ends with), [`Engine::p`]
    /// is in the engine's order: read nothing of it meanwhile.
    pub fn advance_held(&mut self, k: u64) -> Result<(), DemError> {
        self.enter_order();
        self.advance_inside(k)
    }

    /// The particle arrays back in the user's order after [`Engine::advance_held`] (nothing to
    /// do otherwise).
    pub fn to_user_order(&mut self) {
        self.leave_order();
    }

    /// The particle arrays into the engine's order (at the start of a step).
    pub(super) fn enter_order(&mut self) {
        if self.order.uid.is_empty() || self.order.inside {
            return;
        }
        self.cross(true);
    }

    /// The particle arrays back into the user's order (at the end of a step).
    pub(super) fn leave_order(&mut self) {
        if self.order.inside {
            self.cross(false);
        }
    }

    /// Into the engine's order (`into`) or out of it: each moving array permuted into the
    /// other buffer, which then becomes [`Engine::p`]'s; the fixed ones swapped.
    fn cross(&mut self, into: bool) {
        let (o, p) = (&mut self.order, &mut self.p);
        o.inside = into;
        let s = spin_len(D);
        for (v, spare) in [&mut p.pos, &mut p.vel, &mut p.force]
            .into_iter()
            .zip(&mut o.vecs)
        {
            permute_into(v, spare, &o.uid, 1, into);
            std::mem::swap(v, spare);
        }
        for (v, spare) in [&mut p.omega, &mut p.torque].into_iter().zip(&mut o.spins) {
            permute_into(v, spare, &o.uid, s, into);
            std::mem::swap(v, spare);
        }
        for (v, other) in [&mut p.radius, &mut p.mass, &mut p.inertia]
            .into_iter()
            .zip(&mut o.fixed)
        {
            std::mem::swap(v, other);
        }
        self.cross_heat(into);
    }

    /// Whether this run keeps its own order.
    pub(super) fn sorts(&self) -> bool {
        let n = self.p.len();
        n >= 2 && (n >= self.cfg.sort_from || (self.nearest_first && self.cfg.sort_from != usize::MAX))
    }

    /// At the start of a step: if it is a renumbering's (see the module doc), the list is
    /// dropped, and its build renumbers the particles.
    pub(super) fn renumber_if_due(&mut self) {
        if self.steps > 0 && self.steps % self.cfg.sort_period.max(1) == 0 && self.sorts() {
            self.order.due = true;
            self.nb.anchor.clear();
        }
    }

    /// At a neighbour-list build (positions wrapped): renumbers the particles if it is due,
    /// every per-particle array and the contacts with them.
    pub(super) fn maybe_renumber(&mut self) {
        let n = self.p.len();
        if !std::mem::take(&mut self.order.due) || !self.sorts() {
            return;
        }
        // the cells of wrapped positions (the list's build wraps them too, on every rebuild)
        let dom = &self.cfg.domain;
        self.p.pos.iter_mut().for_each(|x| dom.wrap(x));
        let rmax = self.p.radius.iter().cloned().fold(0.0, f64::max);
        let perm = morton_order(
            &self.cfg.domain,
            &self.p.pos,
            2.0 * rmax + self.skin + self.law_reach,
            self.nearest_first,
        );
        if self.order.uid.is_empty() {
            // the first renumbering: the user's fixed arrays kept aside as they are
            self.order.uid = (0..n as u32).collect();
            let p = &self.p;
            self.order.fixed = [p.radius.clone(), p.mass.clone(), p.inertia.clone()];
            self.order.inside = true;
        }
        // the new particle k is the old perm[k]
        let p = &mut self.p;
        gather(&mut p.pos, &perm, 1);
        gather(&mut p.vel, &perm, 1);
        gather(&mut p.omega, &perm, spin_len(D));
        gather(&mut p.radius, &perm, 1);
        gather(&mut p.mass, &perm, 1);
        gather(&mut p.inertia, &perm, 1);
        gather(&mut p.force, &perm, 1);
        gather(&mut p.torque, &perm, spin_len(D));
        gather(&mut self.vpred, &perm, 1);
        gather(&mut self.aold, &perm, 1);
        gather(&mut self.inv_mass, &perm, 1);
        gather(&mut self.inv_inertia, &perm, 1);
        gather(&mut self.order.uid, &perm, 1);
        if !self.species.is_empty() {
            gather(&mut self.species, &perm, 1);
        }
        self.gather_heat(&perm);
        let mut new_of = vec![0u32; n];
        for (k, &o) in perm.iter().enumerate() {
            new_of[o as usize] = k as u32;
        }
        self.pairs.renumber(&new_of, true, self.chunk);
        self.wall_contacts.renumber(&new_of, false, self.chunk);
    }
}

/// `v` ← `v[perm[k]]` for each element `k` (of `stride` values), in place.
pub(super) fn gather<T: Copy>(v: &mut [T], perm: &[u32], stride: usize) {
    let old = v.to_vec();
    for (k, &o) in perm.iter().enumerate() {
        let o = o as usize;
        v[k * stride..(k + 1) * stride].copy_from_slice(&old[o * stride..(o + 1) * stride]);
    }
}

/// `dst` ← `src` permuted: into the engine's order (`into`: `dst[k]` ← `src[uid[k]]`) or out
/// of it (`dst[uid[k]]` ← `src[k]`), elements of `stride` values.
pub(super) fn permute_into<T: Copy>(src: &[T], dst: &mut Vec<T>, uid: &[u32], stride: usize, into: bool) {
    if dst.len() != src.len() {
        // (the first crossing: the buffer made; every element is written below)
        *dst = src.to_vec();
    }
    for (k, &u) in uid.iter().enumerate() {
        let (u, k) = (u as usize * stride, k * stride);
        if into {
            dst[k..k + stride].copy_from_slice(&src[u..u + stride]);
        } else {
            dst[u..u + stride].copy_from_slice(&src[k..k + stride]);
        }
    }
}

/// The particles at `pos` in the Morton order of their cells of side `size` (m) (a grid over
/// the box along periodic axes, over the particles' extent along the others), ties in the
/// current order: the new particle `k` is `perm[k]`. With `slabs`, the cells are taken slab by
/// slab along the pile's longest axis, in Morton order within each slab (see [`slab_rank`]).
pub(super) fn morton_order<const D: usize>(
    dom: &Domain<D>,
    pos: &[VecD<D>],
    size: f64,
    slabs: bool,
) -> Vec<u32> {
    let bits = if D == 2 { 31 } else { 63 / D as u32 };
    let mut lo = [0.0; D];
    let mut cell = [size; D];
    let mut cells = [0u64; D];
    for k in 0..D {
        let (a, b) = if dom.periodic[k] {
            (dom.lo[k], dom.hi[k])
        } else {
            pos.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x[k]), b.max(x[k]))
            })
        };
        lo[k] = a;
        // no more cells along an axis than the key holds
        let most = (1u64 << bits) as f64;
        if (b - a) / size > most {
            cell[k] = (b - a) / most;
        }
        let n = ((b - a) / cell[k]).ceil();
        cells[k] = if n >= 1.0 { (n as u64).min(1u64 << bits) } else { 1 };
    }
    // the slabs' axis: the longest, a periodic one counted at half its length (it is cut twice)
    let slab = slabs.then(|| {
        (0..D)
            .max_by(|&i, &j| {
                let len = |k: usize| cells[k] as f64 / if dom.periodic[k] { 2.0 } else { 1.0 };
                len(i).total_cmp(&len(j))
            })
            .unwrap_or(0)
    });
    let top = (1u64 << bits) - 1;
    let key = |x: &VecD<D>| -> u64 {
        let q = |k: usize| {
            let q = ((x[k] - lo[k]) / cell[k]).floor();
            // (NaN: cell 0)
            if q >= 0.0 {
                (q as u64).min(top)
            } else {
                0
            }
        };
        match slab {
            None => (0..D).fold(0u64, |code, k| code | spread::<D>(q(k)) << k),
            Some(s) => {
                // the slab's place, then the other axes' Morton code (one axis in 2D: its cell)
                let rank = slab_rank(q(s).min(cells[s] - 1), cells[s], dom.periodic[s]);
                let (a, b) = ((s + 1) % D, (s + 2) % D);
                if D == 3 {
                    rank << (2 * bits) | spread::<2>(q(a.min(b))) | spread::<2>(q(a.max(b))) << 1
                } else {
                    rank << bits | q(a)
                }
            }
        }
    };
    let mut keyed: Vec<(u64, u32)> = pos
        .par_iter()
        .enumerate()
        .map(|(i, x)| (key(x), i as u32))
        .collect();
    // the keys are distinct (the index breaks ties): the result is one, on any threads
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The place of slab `q` of `n` along the slabs' axis. Along an open axis, the slabs in order.
/// Along a periodic one, folded about the seam: 0, n − 1, 1, n − 2, 2, … so that the slabs on
/// either side of the seam are neighbours in memory too, and a slab's neighbours are at most
/// three places away.
fn slab_rank(q: u64, n: u64, periodic: bool) -> u64 {
    if !periodic {
        return q;
    }
    let back = n - 1 - q;
    2 * q.min(back) + u64::from(q > back)
}

/// The bits [`spread`] keeps of a coordinate, then its steps (shift, mask), widest first: in 2D
/// bit b goes to bit 2b, in 3D to bit 3b.
const SPREAD_2D: (u64, [(u32, u64); 5]) = (
    0xffff_ffff,
    [
        (16, 0x0000_ffff_0000_ffff),
        (8, 0x00ff_00ff_00ff_00ff),
        (4, 0x0f0f_0f0f_0f0f_0f0f),
        (2, 0x3333_3333_3333_3333),
        (1, 0x5555_5555_5555_5555),
    ],
);
const SPREAD_3D: (u64, [(u32, u64); 5]) = (
    0x1f_ffff,
    [
        (32, 0x1f_0000_0000_ffff),
        (16, 0x1f_0000_ff00_00ff),
        (8, 0x100f_00f0_0f00_f00f),
        (4, 0x10c3_0c30_c30c_30c3),
        (2, 0x1249_2492_4924_9249),
    ],
);

/// The bits of `q` spread `D` apart (bit b to bit D·b): one coordinate of a Morton code (21
/// bits in 3D, 31 in 2D).
fn spread<const D: usize>(q: u64) -> u64 {
    let (keep, steps) = if D == 2 { SPREAD_2D } else { SPREAD_3D };
    steps
        .iter()
        .fold(q & keep, |x, &(shift, mask)| (x | (x << shift)) & mask)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_ranks_are_a_permutation_with_neighbours_close() {
        for n in 1..40u64 {
            for periodic in [false, true] {
                let ranks: Vec<u64> = (0..n).map(|q| slab_rank(q, n, periodic)).collect();
                let mut sorted = ranks.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "n = {n}, periodic {periodic}");
                // each slab and its neighbour (across the seam too, if periodic)
                let pairs = if periodic { n } else { n - 1 };
                for q in 0..pairs {
                    let (a, b) = (ranks[q as usize], ranks[((q + 1) % n) as usize]);
                    let most = if periodic { 3 } else { 1 };
                    assert!(a.abs_diff(b) <= most, "n = {n}: slabs {q}, {} at {a}, {b}", q + 1);
                }
            }
        }
    }

    /// A box of 12 × 4 cells, periodic in x and y, one particle a cell in 3 layers: the slabs
    /// go along x (12 cells, counted as 6, against 4 along y counted as 2 and the particles' 2
    /// along z), folded about the seam, and each slab's 12 particles come together.
    #[test]
    fn a_small_pile_is_ordered_slab_by_slab_along_its_longest_axis() {
        let dom = Domain::<3> {
            lo: VecD::<3>::zeros(),
            hi: VecD::<3>::new(12.0, 4.0, 10.0),
            periodic: [true, true, false],
            bounded: false,
        };
        let mut pos = Vec::new();
        for z in 0..3 {
            for y in 0..4 {
                for x in 0..12 {
                    pos.push(VecD::<3>::new(x as f64 + 0.5, y as f64 + 0.5, z as f64 + 0.5));
                }
            }
        }
        let perm = morton_order(&dom, &pos, 1.0, true);
        let slab_of = |k: usize| pos[perm[k] as usize][0].floor() as u64;
        for (k, chunk) in (0..perm.len()).collect::<Vec<_>>().chunks(12).enumerate() {
            for &i in chunk {
                assert_eq!(slab_rank(slab_of(i), 12, true), k as u64, "particle {i}");
            }
        }
        // without slabs: the Morton order, whose first eight particles fill the corner's
        // 2 × 2 × 2 cells
        let perm = morton_order(&dom, &pos, 1.0, false);
        for &i in &perm[..8] {
            let x = pos[i as usize];
            assert!(x[0] < 2.0 && x[1] < 2.0 && x[2] < 2.0, "{x:?}");
        }
    }
}
