//! The step as one pass over the particles: each chunk's kicks and drift, then at once the
//! forces of its contacts, while the chunk's particles are still in cache.
//!
//! From 10⁵ particles on, a step is bound by memory traffic, not arithmetic. Done as two passes
//! (every drift, then every force), the second pass reads each particle's state again from
//! main memory and writes its force and torque into lines long evicted. Here the chunks are
//! taken in *reverse* order: a chunk's pair contacts have their partner j > i in the same
//! chunk or a later one, which has therefore already drifted; the gathering reads the chunk
//! that was just drifted and the one before it from cache, and the scatter writes forces the
//! drift has just read.
//!
//! In parallel, the chunks are cut into contiguous ranges, one per thread, each range one task,
//! run by the same thread at every step where it can ([`map_ranked`]): a 3D pile of a few
//! thousand particles fits in a core's cache, and a range taken by another thread at the next
//! step would first have to move its particles' state over from the other core. The cut
//! follows each chunk's measured cost (its drift's time and its forces', learnt step after
//! step, [`learn_costs`]; before any, its particles, listed pairs and contacts), so that the
//! ranges take the same time; it moves no result. A range's last chunks reach partners in
//! the next ranges' first chunks (their *head*: the chunks up to the farthest chunk any earlier
//! range reaches, from the neighbour list), which must have drifted before those forces are
//! evaluated. So each task drifts its own head first, and a task whose last chunks need a head
//! not drifted yet drifts it itself (whoever comes first); each range then runs its own reverse
//! sweep over the chunks outside its head. A task that finds a head it needs being drifted by
//! another does not wait: it drifts its own next chunks meanwhile, and once the head is done
//! evaluates the forces it put off, from the last chunk down as always (it waits only when it
//! has nothing left to drift). A pile of small chunks is numbered so that heads are short
//! (`order.rs`). Last, each task adds to its chunks the shares of the earlier chunks' contacts
//! that were left for it (see below), waiting where needed for an earlier range's chunk to be
//! done (the earlier range evaluates its last chunks, those that reach this range, first).
//! There is no serial phase: besides those waits for a head or a chunk, the pool's threads wait
//! for each other only at the end of the pass. The result does not depend on the cut nor on who drifts a
//! head: each chunk's drift and forces are the same arithmetic in any order, and each
//! particle's force sums the shares of the earlier chunks' contacts in one order fixed by the
//! chunks alone.
//!
//! That order: a chunk's contacts sum their forces into the chunk's own particles, and their
//! partners j beyond the chunk get their *shares* after the forces of j's own chunk. In a pile
//! of [`GATHER_CHUNK`](crate::dem::contacts::GATHER_CHUNK)s (from 4,096 particles on) the shares come chunk by chunk from the
//! farthest chunk to the nearest, each chunk's kept in a list ([`Overflow`]) until the end of
//! the pass. In a pile of small chunks (3D, 1,024 to 4,095 particles, [`crate::dem::contacts::
//! gather_chunk`]), from the nearest to the farthest: since a range is swept from its last
//! chunk down, a chunk's partners in later chunks of the same range have then just received
//! the shares of the chunks between, and get theirs at once; only the shares for later ranges
//! wait in lists, and the sweep of a single range (one thread) keeps none.
//!
//! If a drift finds the list stale (a particle has moved by more than half the skin since it
//! was built), the remaining gatherings are skipped, every chunk still drifts, and the step
//! rebuilds the list and evaluates the forces again; the history of the previous step is
//! intact, since gatherings write only the spare contact sets.
//!
//! The heads are what the pipelining costs: they drift apart from their gathering. In a pile
//! numbered row by row, a chunk reaches one or two chunks further, and a range's head is one
//! chunk. Where the numbering does not follow space (a box periodic along the numbering's slow
//! axis, or particles long mixed), a chunk may reach far, whole ranges become heads, and the
//! step degrades towards two passes (every drift, then every force): the same result, at the
//! speed of the two passes.
//!
//! The particle arrays are shared between the tasks through [`Parts`], whose slices the
//! schedule keeps apart. A head's state (to do, busy, done) is taken by one task with a
//! compare-and-swap; that task alone then writes the head's positions, velocities, spins,
//! predicted velocities, previous accelerations and displacement bounds, and publishes them
//! with the state "done" (release), which every reader of the head waits for (acquire). Task
//! r writes that state of its own chunks outside its head, and forces, torques, contact sets,
//! share lists and timings only of its own chunks, those of its head after the head is done
//! (a drift reads them). It reads the state of its own chunks already drifted and of the heads
//! it has waited for, which nobody writes any more in the pass, and an earlier range's share
//! lists once that range has flagged their chunk done (release, acquire).

use super::awake::{map_ranked, spin_until, OnDrop};
use super::{add_shares, chunk_forces, kick_drift_chunk, ChunkContext, Engine, Overflow, Shared};
use crate::dem::contacts::ClassMap;
use crate::dem::contacts::{ContactSet, View};
use crate::dem::state::spin_len;
use crate::dem::DemError;
use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::time::Instant;

/// A particle array shared by the tasks of [`Engine::drift_and_forces`], each
/// taking slices of it that the schedule (see the module doc) keeps apart from every other
/// task's: no element is written by one task while another holds a slice over it.
struct Parts<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: a `Parts` hands out slices of a `&mut [T]` borrowed for its lifetime; the slices are
// kept disjoint between threads by the schedule of `drift_and_forces`, which is what sending
// `&mut [T]` parts to other threads requires.
unsafe impl<T: Send + Sync> Send for Parts<'_, T> {}
// SAFETY: as above.
unsafe impl<T: Send + Sync> Sync for Parts<'_, T> {}

impl<'a, T> Parts<'a, T> {
    fn new(v: &'a mut [T]) -> Parts<'a, T> {
        Parts {
            ptr: v.as_mut_ptr(),
            len: v.len(),
            _borrow: PhantomData,
        }
    }

    /// The elements `r`, to read.
    ///
    /// # Safety
    /// No slice from [`Parts::get_mut`] over any of them may be alive meanwhile.
    unsafe fn get(&self, r: Range<usize>) -> &[T] {
        assert!(r.start <= r.end && r.end <= self.len, "Parts::get out of bounds");
        // SAFETY: in bounds (checked), within the borrowed slice; no writer (the caller)
        unsafe { std::slice::from_raw_parts(self.ptr.add(r.start), r.end - r.start) }
    }

    /// The elements `r`, to write.
    ///
    /// # Safety
    /// No other slice over any of them may be alive meanwhile.
    #[allow(clippy::mut_from_ref)]
    unsafe fn get_mut(&self, r: Range<usize>) -> &mut [T] {
        assert!(
            r.start <= r.end && r.end <= self.len,
            "Parts::get_mut out of bounds"
        );
        // SAFETY: in bounds (checked), within the borrowed slice; exclusive (the caller)
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(r.start), r.end - r.start) }
    }
}

/// `v` cut into consecutive parts of the lengths `cuts[r + 1] − cuts[r]`.
fn cut<'a, T>(mut v: &'a mut [T], cuts: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(cuts.len().saturating_sub(1));
    for w in cuts.windows(2) {
        let (a, b) = std::mem::take(&mut v).split_at_mut(w[1] - w[0]);
        out.push(a);
        v = b;
    }
    out
}

/// What a pipelined pass found.
pub(super) struct Pass {
    /// The neighbour list went stale: rebuild it and evaluate the forces again.
    pub stale: bool,
    /// The sum of the last step's end state when a second half-kick was pending (finite
    /// unless some coordinate is not), else 0; its rounding depends on which tasks drifted
    /// the heads, so only its finiteness means anything.
    pub sum: f64,
    /// The first error of the chunks' force evaluations, in chunk order (meaningless if stale).
    pub result: Result<(), DemError>,
}

/// One range's share of the chunk-owned data: new pair and wall contact sets of its chunks
/// (each chunk's classes in a row).
type RangeItems<'a> = (usize, (&'a mut [ContactSet], &'a mut [ContactSet]));

/// How fast the chunks' measured costs follow each step's times (see [`learn_costs`]).
const COST_RATE: f64 = 0.1;

/// The chunks' costs `cost` (s; 0: none measured yet) after a pass whose chunks took `took` (s,
/// each chunk's drift and forces): each moved by [`COST_RATE`] towards its new time, a time over
/// twice the cost so far taken as twice it (a thread held up once by the machine moves the cut
/// a little). Where to cut the chunks between the threads follows these costs; no result does.
fn learn_costs(cost: &mut [f64], took: &[f64]) {
    for (c, &t) in cost.iter_mut().zip(took) {
        *c = if *c > 0.0 {
            *c + COST_RATE * (t.min(2.0 * *c) - *c)
        } else {
            t
        };
    }
}

/// A head not drifted yet, being drifted, drifted.
const HEAD_TODO: u8 = 0;
const HEAD_BUSY: u8 = 1;
const HEAD_DONE: u8 = 2;

impl<const D: usize> Engine<D> {
    /// The first half-kick and the drift of every particle (after the last step's second
    /// half-kick when `pending`) and the contacts' forces at the new positions, chunk by chunk
    /// in one pass (see the module doc), with the list valid at the start. The forces are
    /// left for [`Engine::finish_forces`] to complete unless the pass found the list stale.
    pub(super) fn drift_and_forces(&mut self, pending: bool) -> Pass {
        let n = self.p.len();
        let c = self.chunk;
        let chunks = n.div_ceil(c);
        let dt = self.dt;
        let (h, g) = (0.5 * dt, self.cfg.gravity);
        let t_end = self.t + dt;
        let ws = self.surfaces_at(t_end);
        if let Some(th) = self.heat.as_deref_mut() {
            th.prepare(t_end, &self.surface_wall);
        }
        // one range per thread, each range run by the same thread at every step where it can
        // (its particles' state then stays in that core's cache: see the module doc); one
        // thread, one range
        let threads = rayon::current_num_threads();
        let tasks = if !self.parallel || threads == 1 {
            1
        } else {
            threads.clamp(1, chunks.max(1))
        };
        // range r: chunks cuts[r]..cuts[r + 1]; its head: cuts[r]..head[r] (one range, no
        // head: no allocation, for the small piles whose steps take microseconds)
        let (one_cut, one_head) = ([0, chunks], [0]);
        let (mut cut_v, mut head_v, mut prefix) = (Vec::new(), Vec::new(), Vec::<f64>::new());
        if tasks > 1 {
            // cut where the work is even: a chunk's work is counted as its particles, its listed
            // pairs and its contacts of the last step (weights ~ their costs in a step)
            let (start, pairs, walls) = (&self.nb.start, &self.pairs, &self.wall_contacts);
            // (a chunk's contacts: those of its sets, one per class)
            let held = |c: &crate::dem::contacts::Contacts, k: usize| -> usize {
                let nc = c.classes();
                c.chunks
                    .get(k * nc..(k + 1) * nc)
                    .map_or(0, |s| s.iter().map(ContactSet::len).sum())
            };
            self.cost.resize(chunks, 0.0);
            let measured = self.cost.iter().all(|&t| t > 0.0);
            prefix.reserve(chunks + 1);
            prefix.push(0.0);
            for k in 0..chunks {
                // the chunk's measured cost, or before any, its counted work: its particles,
                // its listed pairs and its contacts of the last step (a contact costs some 16
                // particles' worth of pass 1: measured range by range)
                let w = if measured {
                    self.cost[k]
                } else {
                    let r = k * c..((k + 1) * c).min(n);
                    let listed = (start[r.end] - start[r.start]) as usize;
                    let touching = held(pairs, k) + held(walls, k);
                    (4 * r.len() + listed + 16 * touching) as f64
                };
                prefix.push(prefix[k] + w);
            }
            cut_v = vec![0; tasks + 1];
            cut_v[tasks] = chunks;
            for r in 1..tasks {
                let at = prefix.partition_point(|&w| w < prefix[chunks] * r as f64 / tasks as f64);
                // at least one chunk in every range
                cut_v[r] = at.clamp(cut_v[r - 1] + 1, chunks - (tasks - r));
            }
            head_v = vec![0usize; tasks];
            let mut reached = 0usize;
            for r in 0..tasks {
                let (a, b) = (cut_v[r], cut_v[r + 1]);
                head_v[r] = reached.clamp(a, b);
                let far = self.reach[a..b].iter().map(|&k| k + 1).max().unwrap_or(0);
                reached = reached.max(far);
            }
        }
        let (cuts, head): (&[usize], &[usize]) = if tasks > 1 {
            (&cut_v, &head_v)
        } else {
            (&one_cut, &one_head)
        };
        self.overflow.resize_with(chunks, Overflow::default);
        let (pc, wc) = (self.pairs.classes(), self.wall_contacts.classes());
        let (prev_p, next_p) = self.pairs.buffers(chunks);
        let (prev_w, next_w) = self.wall_contacts.buffers(chunks);
        let p = &mut self.p;
        let (radius, mass) = (&p.radius[..], &p.mass[..]);
        let (im, ii, anchor) = (&self.inv_mass[..], &self.inv_inertia[..], &self.nb.anchor[..]);
        let skin = self.nb.skin;
        let pos = Parts::new(&mut p.pos);
        let vel = Parts::new(&mut p.vel);
        let omega = Parts::new(&mut p.omega);
        let vpred = Parts::new(&mut self.vpred);
        let aold = Parts::new(&mut self.aold);
        let force = Parts::new(&mut p.force);
        let torque = Parts::new(&mut p.torque);
        let moved = Parts::new(&mut self.moved);
        self.took.resize(chunks, 0.0);
        let took = Parts::new(&mut self.took);
        let overflow = Parts::new(&mut self.overflow);
        let particles = |k: usize| k * c..((k + 1) * c).min(n);
        // the same particles' spins and torques
        let spins = |r: &Range<usize>| r.start * spin_len(D)..r.end * spin_len(D);
        // the drift of chunk k; the caller owns chunk k (see the module doc)
        let drift = |k: usize| -> (bool, f64) {
            let r = particles(k);
            // SAFETY: chunk k's state, force and torque are this task's alone (the schedule)
            unsafe {
                let s = Shared {
                    force: force.get(r.clone()),
                    torque: torque.get(spins(&r)),
                    im: &im[r.clone()],
                    ii: &ii[r.clone()],
                    anchor: &anchor[r.clone()],
                };
                kick_drift_chunk(
                    &s,
                    pending,
                    g,
                    h,
                    dt,
                    pos.get_mut(r.clone()),
                    vel.get_mut(r.clone()),
                    omega.get_mut(spins(&r)),
                    vpred.get_mut(r.clone()),
                    aold.get_mut(r),
                    &mut moved.get_mut(k..k + 1)[0],
                    skin,
                )
            }
        };
        let ctx = ChunkContext {
            dom: &self.cfg.domain,
            nb: &self.nb,
            walls: &ws,
            laws: &self.laws,
            map: ClassMap {
                species: self.laws.species.len(),
                walls: ws.len(),
                pair: &self.laws.pair_class,
                wall: &self.surface_class,
            },
            dt,
            edges: self.cfg.edge_means,
            heat: self.heat.as_deref().map(|th| th.view()),
        };
        let species = &self.species[..];
        let (reach, back) = (&self.reach, &self.back);
        let uid = (!self.order.uid.is_empty()).then_some(&self.order.uid[..]);
        let nearest_first = self.nearest_first;
        // the forces of chunk k of the range ending before chunk `end`, whose particles and
        // partners have drifted (nearest first, the shares of its partners in later chunks of
        // the range are added at once, else they all wait for the end)
        let forces =
            |k: usize, end: usize, np: &mut [ContactSet], nw: &mut [ContactSet]| -> Result<(), DemError> {
                let r = particles(k);
                let w = r.start..particles(reach[k]).end;
                let sink = r.start..if nearest_first {
                    particles(end - 1).end
                } else {
                    r.end
                };
                // SAFETY: chunks k..=reach[k] have drifted and no task writes their state now;
                // chunk k's overflow, and the force and torque of chunk k and of the later chunks
                // of its range (which have drifted), are this task's alone (the schedule)
                unsafe {
                    let view = View {
                        base: r.start,
                        pos: pos.get(w.clone()),
                        vpred: vpred.get(w.clone()),
                        vel: vel.get(w.clone()),
                        omega: omega.get(spins(&w)),
                        radius: &radius[w.clone()],
                        mass: &mass[w.clone()],
                        uid: uid.map(|u| &u[w.clone()]),
                        species: species.get(w).unwrap_or(&[]),
                    };
                    chunk_forces(
                        &ctx,
                        r.clone(),
                        &view,
                        (&prev_p[k * pc..(k + 1) * pc], np),
                        (&prev_w[k * wc..(k + 1) * wc], nw),
                        force.get_mut(sink.clone()),
                        torque.get_mut(spins(&sink)),
                        c,
                        &mut overflow.get_mut(k..k + 1)[0],
                    )
                }
            };
        let stale = AtomicBool::new(false);
        // every range's head: drifted by the first task that needs it (its own range's, or an
        // earlier range's whose last chunks reach it), the others waiting until it is done;
        // each chunk's forces and overflow: done (or given up, the list being stale) (one
        // range: no head, no flags, no allocation)
        let (heads, chunk_done): (Vec<AtomicU8>, Vec<AtomicBool>) = if tasks > 1 {
            (
                (0..tasks)
                    .map(|r| AtomicU8::new(if head[r] > cuts[r] { HEAD_TODO } else { HEAD_DONE }))
                    .collect(),
                (0..chunks).map(|_| AtomicBool::new(false)).collect(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        // makes sure head `r` has drifted (`wait`), or only tries to (None: another task is
        // drifting it); the drift's sum if this task drifted it
        let try_head = |r: usize, wait: bool| -> Option<f64> {
            let state = &heads[r];
            if state
                .compare_exchange(HEAD_TODO, HEAD_BUSY, Ordering::Acquire, Ordering::Acquire)
                .is_ok()
            {
                // "done" however the drift ends: a panic must reach the caller, not leave the
                // other tasks waiting
                let _done = OnDrop(|| state.store(HEAD_DONE, Ordering::Release));
                let (mut st, mut sum) = (false, 0.0);
                for k in cuts[r]..head[r] {
                    let (s, x) = drift(k);
                    st |= s;
                    sum += x;
                }
                if st {
                    stale.store(true, Ordering::Relaxed);
                }
                return Some(sum);
            }
            if !wait {
                return (state.load(Ordering::Acquire) == HEAD_DONE).then_some(0.0);
            }
            spin_until(|| state.load(Ordering::Acquire) == HEAD_DONE);
            Some(0.0)
        };
        // each range's task: its own head first (the previous range's last chunks wait for
        // it); then its chunks from the last, each drifted (outside its head) and its forces
        // evaluated, the heads of the later ranges it reaches made sure of before the first
        // forces; then, unless the list went stale, its chunks' shares of the earlier chunks'
        // contacts added chunk by chunk in order, waiting for an earlier range's chunk to be
        // done where needed
        let sweep = |(r, (np, nw)): RangeItems<'_>| {
            let (a, b) = (cuts[r], cuts[r + 1]);
            // every chunk of the range marked done however the task ends
            let _done = OnDrop(|| {
                for f in chunk_done.get(a..b).unwrap_or(&[]) {
                    f.store(true, Ordering::Release);
                }
            });
            let mut sum = 0.0;
            if tasks > 1 {
                sum += try_head(r, true).unwrap_or(0.0);
            }
            let far = reach[a..b].iter().copied().max().unwrap_or(0);
            // the later ranges whose heads this range's chunks reach (ranges r + 1.. start at
            // cuts[r + 1..tasks]), made sure of before the first forces
            let reached = (r + 1..tasks).take_while(|&q| cuts[q] <= far);
            let mut later_heads = tasks == 1 || reached.clone().next().is_none();
            let mut st = false;
            let mut first_err: Result<(), DemError> = Ok(());
            // the chunks from `due` on have their forces evaluated; those between the chunk
            // drifted last and `due` wait for the later heads (a head being drifted by another
            // task: this one drifts its own next chunks meanwhile, the forces still evaluated
            // from the last chunk down, in the same order)
            let mut due = b;
            for k in (a..b).rev() {
                // (timed on several threads: the drift's time and the forces', not the waits)
                if k >= head[r] {
                    let clock = (tasks > 1).then(Instant::now);
                    let (s, x) = drift(k);
                    sum += x;
                    if s {
                        st = true;
                        stale.store(true, Ordering::Relaxed);
                    }
                    if let Some(t) = clock {
                        // SAFETY: chunk k's entry is this task's alone (the schedule)
                        unsafe { took.get_mut(k..k + 1)[0] = t.elapsed().as_secs_f64() };
                    }
                } else if tasks > 1 {
                    // SAFETY: as above
                    unsafe { took.get_mut(k..k + 1)[0] = 0.0 };
                }
                if st || stale.load(Ordering::Relaxed) {
                    continue;
                }
                if !later_heads {
                    // while own chunks are left to drift, a head another task is drifting is
                    // not waited for: the forces are put off
                    let more = k > head[r].max(a);
                    let mut ready = true;
                    for q in reached.clone() {
                        match try_head(q, !more) {
                            Some(x) => sum += x,
                            None => ready = false,
                        }
                    }
                    if !ready {
                        continue;
                    }
                    later_heads = true;
                }
                for k in (k..due).rev() {
                    let clock = (tasks > 1).then(Instant::now);
                    let (q, u) = ((k - a) * pc, (k - a) * wc);
                    if let Err(e) = forces(k, b, &mut np[q..q + pc], &mut nw[u..u + wc]) {
                        first_err = Err(e);
                    }
                    if let Some(t) = clock {
                        // SAFETY: chunk k's entry is this task's alone (the schedule)
                        unsafe { took.get_mut(k..k + 1)[0] += t.elapsed().as_secs_f64() };
                    }
                    if let Some(f) = chunk_done.get(k) {
                        f.store(true, Ordering::Release);
                    }
                }
                due = k;
            }
            if st || stale.load(Ordering::Relaxed) {
                return (sum, first_err);
            }
            for (m, &first) in back.iter().enumerate().take(b).skip(a) {
                let r = particles(m);
                // the shares of chunk k for chunk m (unless added at once), its forces done
                let add = |k: usize| {
                    if reach[k] < m || (nearest_first && k >= a) {
                        return;
                    }
                    if k < a {
                        spin_until(|| chunk_done[k].load(Ordering::Acquire));
                    }
                    // SAFETY: chunk k's forces are done (its own range's, or flagged done):
                    // nobody writes its overflow any more; chunk m's force and torque are
                    // this task's alone
                    unsafe {
                        let shares = overflow.get(k..k + 1)[0].to(m - k - 1);
                        add_shares::<D>(
                            shares,
                            r.start,
                            force.get_mut(r.clone()),
                            torque.get_mut(spins(&r)),
                        );
                    }
                };
                if nearest_first {
                    (first..m).rev().for_each(add);
                } else {
                    (first..m).for_each(add);
                }
            }
            (sum, first_err)
        };
        let (mut sum, mut result) = (0.0, Ok(()));
        if tasks > 1 {
            let scaled = |n: usize| cuts.iter().map(|&k| k * n).collect::<Vec<usize>>();
            let ranges: Vec<RangeItems<'_>> = cut(next_p, &scaled(pc))
                .into_iter()
                .zip(cut(next_w, &scaled(wc)))
                .enumerate()
                .collect();
            for (x, res) in map_ranked(ranges, sweep) {
                sum += x;
                if result.is_ok() {
                    result = res;
                }
            }
            if !stale.load(Ordering::Relaxed) {
                learn_costs(&mut self.cost, &self.took);
            }
        } else {
            (sum, result) = sweep((0, (next_p, next_w)));
        }
        Pass {
            stale: stale.load(Ordering::Relaxed),
            sum,
            result,
        }
    }
}
