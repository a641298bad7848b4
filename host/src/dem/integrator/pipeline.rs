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
//! In parallel, the chunks are cut into contiguous ranges, two per thread, of even work (by
//! particles, listed pairs and the last step's contacts), each range one task, taken in order
//! by whichever thread is free. A range's last chunks reach partners in the next ranges' first
//! chunks (their *head*: the chunks up to the farthest chunk any earlier range reaches, from
//! the neighbour list), which must have drifted before those forces are evaluated. So a head
//! is drifted by the first task that needs it, its own range's or an earlier one's, and the
//! others wait the few microseconds until it is done (a head is one chunk in a pile numbered
//! row by row); each range then runs its own reverse sweep over the chunks outside its head.
//! There is no serial phase: besides those few microseconds, the pool's threads wait for
//! each other only at the end of the pass. The result does not depend on the cut nor on who drifts a head: each chunk's
//! drift and forces are the same arithmetic in any order, and the forces on partners beyond a
//! chunk are added afterwards in chunk order ([`Engine::finish_forces`]).
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
//! r writes that state of its own chunks outside its head, and forces and torques only of its
//! own chunks, those of its head after the head is done (a drift reads them). It reads the
//! state of its own chunks already drifted and of the heads it has waited for, which nobody
//! writes any more in the pass.

use super::awake::{map_claimed, spin_until, OnDrop};
use super::{chunk_forces, kick_drift_chunk, ChunkContext, Engine, Shared, GATHER_CHUNK, SERIAL_BELOW};
use crate::dem::contacts::{ContactSet, View};
use crate::dem::state::{spin_len, Vec3, VecD};
use crate::dem::DemError;
use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};

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

/// One range's share of the chunk-owned data: new pair and wall contact sets and overflows of
/// its chunks.
type RangeItems<'a, const D: usize> = (
    usize,
    (
        (&'a mut [ContactSet], &'a mut [ContactSet]),
        &'a mut [Vec<(u32, VecD<D>, Vec3)>],
    ),
);

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
        let c = GATHER_CHUNK;
        let chunks = n.div_ceil(c);
        let dt = self.dt;
        let (h, g) = (0.5 * dt, self.cfg.gravity);
        let t_end = self.t + dt;
        let ws: Vec<_> = self.walls.iter().map(|w| w.at(t_end)).collect();
        // two ranges per thread, so that a thread held up (by the machine, or by a range denser
        // in contacts than its weight says) leaves its second range to another; one thread,
        // one range
        let threads = rayon::current_num_threads();
        let tasks = if n < SERIAL_BELOW || threads == 1 {
            1
        } else {
            (2 * threads).clamp(1, chunks.max(1))
        };
        // range r: chunks cuts[r]..cuts[r + 1]; its head: cuts[r]..head[r] (one range, no
        // head: no allocation, for the small piles whose steps take microseconds)
        let (one_cut, one_head) = ([0, chunks], [0]);
        let (mut cut_v, mut head_v) = (Vec::new(), Vec::new());
        if tasks > 1 {
            // cut where the work is even: a chunk's work is counted as its particles, its listed
            // pairs and its contacts of the last step (weights ~ their costs in a step)
            let (start, pairs, walls) = (&self.nb.start, &self.pairs.chunks, &self.wall_contacts.chunks);
            let mut prefix = Vec::with_capacity(chunks + 1);
            prefix.push(0usize);
            for k in 0..chunks {
                let r = k * c..((k + 1) * c).min(n);
                let listed = (start[r.end] - start[r.start]) as usize;
                // (a contact costs some 16 particles' worth of pass 1: measured range by range)
                let touching = pairs.get(k).map_or(0, |s| s.len()) + walls.get(k).map_or(0, |s| s.len());
                prefix.push(prefix[k] + 4 * r.len() + listed + 16 * touching);
            }
            cut_v = vec![0; tasks + 1];
            cut_v[tasks] = chunks;
            for r in 1..tasks {
                let at = prefix.partition_point(|&w| w < prefix[chunks] * r / tasks);
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
        self.overflow.resize_with(chunks, Vec::new);
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
            dt,
            edges: self.cfg.edge_means,
        };
        let reach = &self.reach;
        let uid = (!self.order.uid.is_empty()).then_some(&self.order.uid[..]);
        // the forces of chunk k, whose particles and partners have drifted
        let forces = |k: usize,
                      np: &mut ContactSet,
                      nw: &mut ContactSet,
                      ov: &mut Vec<(u32, VecD<D>, Vec3)>|
         -> Result<(), DemError> {
            let r = particles(k);
            let w = r.start..particles(reach[k]).end;
            // SAFETY: chunks k..=reach[k] have drifted and no task writes their state now;
            // chunk k's force and torque are this task's alone (the schedule)
            unsafe {
                let view = View {
                    base: r.start,
                    pos: pos.get(w.clone()),
                    vpred: vpred.get(w.clone()),
                    vel: vel.get(w.clone()),
                    omega: omega.get(spins(&w)),
                    radius: &radius[w.clone()],
                    mass: &mass[w.clone()],
                    uid: uid.map(|u| &u[w]),
                };
                chunk_forces(
                    &ctx,
                    r.clone(),
                    &view,
                    (&prev_p[k], np),
                    (&prev_w[k], nw),
                    force.get_mut(r.clone()),
                    torque.get_mut(spins(&r)),
                    ov,
                )
            }
        };
        let stale = AtomicBool::new(false);
        // every range's head: drifted by the first task that needs it (its own range's, or an
        // earlier range's whose last chunks reach it), the others waiting until it is done
        // (one range: no head, no allocation)
        let heads: Vec<AtomicU8> = if tasks > 1 {
            (0..tasks)
                .map(|r| AtomicU8::new(if head[r] > cuts[r] { HEAD_TODO } else { HEAD_DONE }))
                .collect()
        } else {
            Vec::new()
        };
        // makes sure head `r` has drifted; the drift's sum if this task drifted it
        let ensure_head = |r: usize| -> f64 {
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
                return sum;
            }
            spin_until(|| state.load(Ordering::Acquire) == HEAD_DONE);
            0.0
        };
        // each range's reverse sweep: first the heads of the later ranges its chunks reach,
        // then its chunks from the last, each drifted (outside its head) and its forces
        // evaluated; its own head is made sure of before the forces of the head's chunks
        let sweep = |(r, ((np, nw), ov)): RangeItems<'_, D>| {
            let (a, b) = (cuts[r], cuts[r + 1]);
            let mut sum = 0.0;
            let far = reach[a..b].iter().copied().max().unwrap_or(0);
            // (ranges r + 1.. start at cuts[r + 1..tasks])
            for (q, &start) in cuts.iter().enumerate().take(tasks).skip(r + 1) {
                if start > far {
                    break;
                }
                sum += ensure_head(q);
            }
            let mut st = false;
            let mut first_err: Result<(), DemError> = Ok(());
            for k in (a..b).rev() {
                if k >= head[r] {
                    let (s, x) = drift(k);
                    sum += x;
                    if s {
                        st = true;
                        stale.store(true, Ordering::Relaxed);
                    }
                } else if k + 1 == head[r] {
                    sum += ensure_head(r);
                }
                if st || stale.load(Ordering::Relaxed) {
                    continue;
                }
                if let Err(e) = forces(k, &mut np[k - a], &mut nw[k - a], &mut ov[k - a]) {
                    first_err = Err(e);
                }
            }
            (sum, first_err)
        };
        let (mut sum, mut result) = (0.0, Ok(()));
        if tasks > 1 {
            let ranges: Vec<RangeItems<'_, D>> = cut(next_p, cuts)
                .into_iter()
                .zip(cut(next_w, cuts))
                .zip(cut(&mut self.overflow, cuts))
                .enumerate()
                .collect();
            for (x, res) in map_claimed(ranges, sweep) {
                sum += x;
                if result.is_ok() {
                    result = res;
                }
            }
        } else {
            (sum, result) = sweep((0, ((next_p, next_w), &mut self.overflow)));
        }
        Pass {
            stale: stale.load(Ordering::Relaxed),
            sum,
            result,
        }
    }
}
