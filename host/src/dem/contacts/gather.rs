//! The gathering of a chunk's contacts: the pairs (and particle–wall contacts) in touch, their
//! geometry and relative velocities written into the set's arrays, then their history carried
//! over from the previous set by one merge over both sets' keys.
//!
//! Each stage is its own loop over the contacts (the candidates' geometry, then the merge, then
//! the rolling and twisting part when a scene has those laws): short loops with few live values
//! and no calls, which the compiler keeps in registers.

use super::pair_geometry::{pair_geometry, ContactValues, PairsOut};
use super::{ContactSet, View, MAX_OVERLAP};
use crate::dem::cells::{Domain, Images, Neighbours};
use crate::dem::state::{spin, to3, Vec3};
use crate::dem::walls::WallState;
use crate::dem::DemError;
use std::ops::Range;

/// A contact's key: particle `i` in the high half, its partner `j` in the low half (contacts
/// are kept in key order).
#[inline(always)]
fn key(i: u32, j: u32) -> u64 {
    ((i as u64) << 32) | j as u64
}

/// A contact new in this set (no index in the previous one).
const NEW: u32 = u32::MAX;

/// `dst` ← `src` for a contact's history slots (a plain copy of a few values: no call to
/// `memcpy` for three numbers).
#[inline(always)]
fn copy_slots(dst: &mut [f64], src: &[f64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

/// Each contact's `slots` history values in `hist`: those of its previous contact `src[k]` in
/// `old`, or zero for a new one ([`NEW`]); the common slot counts with their length known to
/// the compiler.
fn carry_slots(hist: &mut [f64], old: &[f64], src: &[u32], slots: usize) {
    #[inline(always)]
    fn each<const S: usize>(hist: &mut [f64], old: &[f64], src: &[u32]) {
        for (h, &m) in hist.chunks_exact_mut(S).zip(src) {
            let h: &mut [f64; S] = h.try_into().expect("S slots");
            *h = if m == NEW {
                [0.0; S]
            } else {
                let a = m as usize * S;
                old[a..a + S].try_into().expect("S slots")
            };
        }
    }
    match slots {
        0 => {}
        1 => each::<1>(hist, old, src),
        2 => each::<2>(hist, old, src),
        3 => each::<3>(hist, old, src),
        _ => {
            for (h, &m) in hist.chunks_exact_mut(slots).zip(src) {
                if m == NEW {
                    h.fill(0.0);
                } else {
                    copy_slots(h, &old[m as usize * slots..(m as usize + 1) * slots]);
                }
            }
        }
    }
}

/// Pass 1 of a pair gathering, over every listed pair of the particles of `range`: the pairs
/// in contact (or within `reach` (m) of it) written into `cand`, their count returned. Kept
/// without a branch per pair (one pair in six or so touches: a branch mispredicts too often);
/// a NaN distance is kept too, for the check of pass 2. The rows with no partner across a
/// periodic boundary (most) take the plain difference of positions (see
/// [`Neighbours::cross`]).
#[inline(never)]
pub(super) fn touching<const D: usize>(
    range: Range<usize>,
    nb: &Neighbours<D>,
    images: &Images<D>,
    view: &View<'_, D>,
    reach: f64,
    cand: &mut [(u32, u32)],
) -> usize {
    let mut count = 0;
    for i in range {
        count = if nb.cross[i] {
            touching_row::<D, true>(i, nb.of(i), images, view, reach, cand, count)
        } else {
            touching_row::<D, false>(i, nb.of(i), images, view, reach, cand, count)
        };
    }
    count
}

/// [`touching`] for row `i` (partners `js`), the candidates written into `cand` from `count`
/// on; the count after them returned. `IMAGE`: the minimum image of each difference.
#[inline(always)]
fn touching_row<const D: usize, const IMAGE: bool>(
    i: usize,
    js: &[u32],
    images: &Images<D>,
    view: &View<'_, D>,
    reach: f64,
    cand: &mut [(u32, u32)],
    mut count: usize,
) -> usize {
    let (base, pos, radius) = (view.base, view.pos, view.radius);
    let (xi, ri) = (pos[i - base], radius[i - base] + reach);
    for &j in js {
        let jl = j as usize - base;
        let d = if IMAGE {
            images.delta(&xi, &pos[jl])
        } else {
            xi - pos[jl]
        };
        let r2 = d.norm_squared();
        let sum = ri + radius[jl];
        cand[count] = (i as u32, j);
        count += usize::from((r2 < sum * sum) | r2.is_nan());
    }
    count
}

/// The elastic energy (J) of the motion families' springs (tangential, rolling, twisting; and
/// the normal law's, when it is adhesive) that `prev`'s contacts not carried over held, added to
/// `dropped` by family and listed in `ended` by contact: `src` lists the carried ones' indices in `prev`, in increasing order ([`NEW`]
/// for the new ones).
fn dropped_springs(prev: &ContactSet, src: &[u32], dropped: &mut [f64; 4], ended: &mut Vec<(u32, u32, f64)>) {
    // an adhesive normal law's contact ends at its reach, beyond touching, holding what its
    // adhesion hysteresis left in it; a contact of any other normal law ends at touch, where
    // its last step's mean force has given its energy back
    let from = if prev.reach_bound > 0.0 { 0 } else { 1 };
    let mut gone = |a: usize, b: usize| {
        for m in a..b.min(prev.len()) {
            let mut sum = 0.0;
            for (k, d) in dropped.iter_mut().enumerate().skip(from) {
                if let Some(&e) = prev.elastic[k].get(m) {
                    *d += e;
                    sum += e;
                }
            }
            if sum != 0.0 {
                ended.push((prev.i[m], prev.j[m], sum));
            }
        }
    };
    let mut next = 0;
    for &m in src.iter().filter(|&&m| m != NEW) {
        gone(next, m as usize);
        next = m as usize + 1;
    }
    gone(next, prev.len());
}

/// Particle `k` of the view as the user numbers it.
#[inline]
pub(super) fn user(view_uid: Option<&[u32]>, base: usize, k: usize) -> usize {
    view_uid.map_or(k, |u| u[k - base] as usize)
}

impl ContactSet {
    /// Fills `self` with the pair contacts of the particles of `range` at the current state,
    /// carrying history over from `prev` (the same chunk's previous set). Overlap rates come
    /// from the predicted velocities `vpred`, the contact points' slip from the step's
    /// velocities `vel`, `omega` (over the step: velocity Verlet's half-step ones, so that
    /// slip × dt is the tangential displacement of the step).
    pub fn gather_pairs<const D: usize>(
        &mut self,
        prev: &ContactSet,
        range: Range<usize>,
        dom: &Domain<D>,
        nb: &Neighbours<D>,
        view: &View<'_, D>,
    ) -> Result<(), DemError> {
        self.first = range.start;
        let mut cand = std::mem::take(&mut self.cand);
        let listed = nb.start[range.end] as usize - nb.start[range.start] as usize;
        // room for every listed pair (grown, never cleared: each slot is written before read)
        if cand.len() < listed {
            cand.resize(listed, (0, 0));
        }
        let images = dom.images();
        let count = touching(range, nb, &images, view, self.reach_bound, &mut cand);
        self.cand = cand;
        self.pairs_from_candidates(prev, count, &images, view)
    }

    /// Passes 2 and 3 of a pair gathering: the contacts of the first `count` candidates of
    /// `self.cand` (in key order), their history carried over from `prev`.
    pub(super) fn pairs_from_candidates<const D: usize>(
        &mut self,
        prev: &ContactSet,
        count: usize,
        images: &Images<D>,
        view: &View<'_, D>,
    ) -> Result<(), DemError> {
        let cand = std::mem::take(&mut self.cand);
        // pass 2, over the candidates: their geometry, one contact each (a candidate apart
        // by less than the reach of an adhesive law, not touching, is dropped by the merge
        // unless its contact still acts; without such a law every candidate touches)
        let sorted = view.uid.is_some();
        self.start_pairs(count, sorted);
        let out = self.pairs_out(0..count);
        let done = pair_geometry(sorted, &cand[..count], images, view, out);
        self.cand = cand;
        done?;
        self.finish_pairs(prev, view);
        Ok(())
    }

    /// Sizes the set for `count` pair contacts, with their sides when `sorted` (the engine's
    /// own order, see [`ContactSet::sign`]).
    pub(super) fn start_pairs(&mut self, count: usize, sorted: bool) {
        self.sign.clear();
        if sorted {
            self.sign.resize(count, 1.0);
        }
        self.size(count);
    }

    /// The arrays pass 2 writes, for the set's contacts `r` (sized by
    /// [`ContactSet::start_pairs`]).
    pub(super) fn pairs_out(&mut self, r: Range<usize>) -> PairsOut<'_> {
        let sign = if self.sign.is_empty() {
            &mut self.sign[..]
        } else {
            &mut self.sign[r.clone()]
        };
        PairsOut {
            i: &mut self.i[r.clone()],
            j: &mut self.j[r.clone()],
            delta: &mut self.delta[r.clone()],
            rate: &mut self.rate[r.clone()],
            mass: &mut self.mass[r.clone()],
            radius: &mut self.radius[r.clone()],
            normal: &mut self.normal[r.clone()],
            vrel: &mut self.vrel[r],
            sign,
        }
    }

    /// The end of a pair gathering once pass 2 has written the set's contacts: with a rolling
    /// or twisting law, each contact's relative spin ω_i − ω_j from `view` (seen from j where
    /// the contact is: negated, as the normal); then the merge with `prev` ([`ContactSet::carry`]).
    pub(super) fn finish_pairs<const D: usize>(&mut self, prev: &ContactSet, view: &View<'_, D>) {
        if self.rotational() {
            let (base, omega) = (view.base, view.omega);
            let pairs = self.i.iter().zip(&self.j);
            for (k, (w, (&i, &j))) in self.vroll.iter_mut().zip(pairs).enumerate() {
                let (i, j) = (i as usize - base, j as usize - base);
                let mut r = spin::<D>(omega, i) - spin::<D>(omega, j);
                if let Some(&s) = self.sign.get(k) {
                    r *= s;
                }
                *w = [r.x, r.y, r.z];
            }
        }
        self.carry(prev, false);
    }

    /// Fills `self` with the particle–wall contacts of the particles of `range` at the current
    /// state, carrying history over from `prev` (see [`ContactSet::gather_pairs`]). `near`, if
    /// given, holds the only particles of `range` that can be within reach of a wall (sorted:
    /// [`Neighbours::wall_candidates`](crate::dem::cells::Neighbours::wall_candidates)); the
    /// others are not looked at.
    pub fn gather_walls<const D: usize>(
        &mut self,
        prev: &ContactSet,
        range: Range<usize>,
        walls: &[WallState<D>],
        near: Option<&[u32]>,
        view: &View<'_, D>,
    ) -> Result<(), DemError> {
        let count = self.wall_candidates(range, walls, near, view);
        // pass 2: each picked particle's contacts, wall by wall (one not touching is kept only
        // under an adhesive law, for the merge to decide)
        let cand = std::mem::take(&mut self.cand);
        self.size(count * walls.len());
        let adhesive = self.reach_bound > 0.0;
        let mut k = 0;
        for &(ig, _) in &cand[..count] {
            for (w, ws) in walls.iter().enumerate() {
                match wall_contact(ws, ig as usize, view, adhesive) {
                    Ok(None) => {}
                    Ok(Some(c)) => {
                        self.put_wall_contact(k, ig, w, &c);
                        k += 1;
                    }
                    Err(e) => {
                        self.cand = cand;
                        return Err(e.naming(w));
                    }
                }
            }
        }
        self.size(k);
        self.cand = cand;
        self.carry(prev, true);
        Ok(())
    }

    /// Pass 1 of a wall gathering: the particles of `range` within reach of a wall (NaN kept)
    /// written into `self.cand`, in order; their count returned. `near`, if given, holds the
    /// only particles of `range` that can be (see [`ContactSet::gather_walls`]).
    pub(super) fn wall_candidates<const D: usize>(
        &mut self,
        range: Range<usize>,
        walls: &[WallState<D>],
        near: Option<&[u32]>,
        view: &View<'_, D>,
    ) -> usize {
        self.first = range.start;
        let (base, pos, radius) = (view.base, view.pos, view.radius);
        // the chunk's particles, indexed from 0
        let local = range.start - base..range.end - base;
        // the largest overlap of each particle with any wall (NaN kept), wall by wall over
        // the particles, a loop without branches
        let mut cand = std::mem::take(&mut self.cand);
        if cand.len() < range.len() {
            cand.resize(range.len(), (0, 0));
        }
        let mut count = 0;
        if let Some(near) = near {
            // only the particles that can be near a wall, in order: the same picks
            for &ig in near {
                let i = ig as usize - base;
                let mut m = f64::NEG_INFINITY;
                for ws in walls {
                    let d = ws.overlap(&pos[i], radius[i]);
                    m = if d > m || d.is_nan() { d } else { m };
                }
                cand[count] = (ig, 0);
                count += usize::from((m > -self.reach_bound) | m.is_nan());
            }
        } else {
            let mut worst = std::mem::take(&mut self.scratch);
            let (xs, rs) = (&pos[local.clone()], &radius[local.clone()]);
            worst.clear();
            worst.resize(range.len(), f64::NEG_INFINITY);
            for ws in walls {
                ws.overlaps_into(xs, rs, &mut worst);
            }
            for (k, m) in worst.iter().enumerate() {
                cand[count] = ((range.start + k) as u32, 0);
                count += usize::from((*m > -self.reach_bound) | m.is_nan());
            }
            self.scratch = worst;
        }
        self.cand = cand;
        count
    }

    /// Writes the contact `c` of particle `ig` with wall `w` as contact `k`.
    #[inline(always)]
    pub(super) fn put_wall_contact(&mut self, k: usize, ig: u32, w: usize, c: &WallContact) {
        self.pairs_out(k..k + 1).put::<false>(0, ig, w as u32, &c.values);
        if self.rotational() {
            self.vroll[k] = c.spin;
        }
    }

    /// The merge of a gathering: each contact's history carried over from `prev` (the same
    /// chunk's previous set, in key order like this one) or zero if it is new, its first-touch
    /// and last-step flags, the count of first touches. Under an adhesive law, a contact apart
    /// (δ < 0; δ ≤ 0 against a `wall`) is kept only while its previous contact's reach covers
    /// it, and the kept contacts are moved up over the dropped ones. With a rolling or
    /// twisting law, `vroll` holds the relative spin on entry and gets the rolling velocity.
    pub(super) fn carry(&mut self, prev: &ContactSet, wall: bool) {
        let mut owned = std::mem::take(&mut self.src);
        self.merge(prev, &mut owned);
        if self.reach_bound > 0.0 {
            self.drop_apart(prev, &mut owned, wall);
        }
        let n = self.len();
        let src = &owned[..n];
        self.dropped = [0.0; 4];
        self.ended.clear();
        if self.energy {
            dropped_springs(prev, src, &mut self.dropped, &mut self.ended);
        }
        carry_slots(&mut self.hist_n, &prev.hist_n, src, self.slots_n);
        carry_slots(&mut self.hist_t, &prev.hist_t, src, self.slots_t);
        let mut formed = 0;
        for ((f, l), &m) in self.fresh[..n].iter_mut().zip(&mut self.last[..n]).zip(src) {
            let old = prev.last.get(m as usize);
            *f = old.is_none();
            *l = old.is_some_and(|&b| b);
            formed += usize::from(old.is_none());
        }
        self.formed = formed;
        if self.rotational() {
            for (k, &m) in src.iter().enumerate() {
                self.carry_rotation(k, prev, (m != NEW).then_some(m as usize));
            }
        }
        self.src = owned;
    }

    /// The merge proper: `src[k]` ← the index in `prev` of contact `k` ([`NEW`] if none).
    fn merge(&self, prev: &ContactSet, src: &mut Vec<u32>) {
        let n = self.len();
        src.clear();
        src.resize(n, NEW);
        let pkeys = prev.i.iter().zip(&prev.j).map(|(&i, &j)| key(i, j));
        let mut pkeys = pkeys.enumerate().peekable();
        for ((s, &i), &j) in src.iter_mut().zip(&self.i).zip(&self.j) {
            let k = key(i, j);
            while pkeys.next_if(|&(_, p)| p < k).is_some() {}
            if let Some(&(m, p)) = pkeys.peek() {
                if p == k {
                    *s = m as u32;
                }
            }
        }
    }

    /// Under an adhesive law: the contacts apart (δ < 0; δ ≤ 0 against a `wall`) whose previous
    /// contact's reach does not cover them are dropped, the others moved up (with `src`).
    #[cold]
    fn drop_apart(&mut self, prev: &ContactSet, src: &mut [u32], wall: bool) {
        let n = self.len();
        let mut w = 0;
        for k in 0..n {
            let d = self.delta[k];
            let apart = if wall { d <= 0.0 } else { d < 0.0 };
            let m = src[k];
            let acts = m != NEW && prev.reach.get(m as usize).is_some_and(|&r| d >= -r);
            if apart && !acts {
                continue;
            }
            if w != k {
                self.move_contact(k, w);
                src[w] = m;
            }
            w += 1;
        }
        if w != n {
            self.size(w);
        }
    }

    /// Moves contact `k`'s gathered values to slot `w` < `k` (the merge's compaction).
    #[cold]
    fn move_contact(&mut self, k: usize, w: usize) {
        self.i[w] = self.i[k];
        self.j[w] = self.j[k];
        self.delta[w] = self.delta[k];
        self.rate[w] = self.rate[k];
        self.mass[w] = self.mass[k];
        self.radius[w] = self.radius[k];
        self.normal[w] = self.normal[k];
        self.vrel[w] = self.vrel[k];
        if !self.sign.is_empty() {
            self.sign[w] = self.sign[k];
        }
        if self.rotational() {
            self.vroll[w] = self.vroll[k];
        }
    }

    /// The rotational part of the merge for contact `k`: the rolling velocity R_eff (ω_i −
    /// ω_j) × n̂ and the twisting rate (ω_i − ω_j)·n̂ from the relative spin (rad/s) that
    /// `vroll[k]` holds, the rolling and twisting history from `prev`'s contact `found` (or
    /// zero).
    #[cold]
    fn carry_rotation(&mut self, k: usize, prev: &ContactSet, found: Option<usize>) {
        let (w, n) = (Vec3::from(self.vroll[k]), Vec3::from(self.normal[k]));
        let vr = w.cross(&n) * self.radius[k];
        self.vroll[k] = [vr.x, vr.y, vr.z];
        self.twist[k] = w.dot(&n);
        let (sr, sw) = (self.slots_r.unwrap_or(0), self.slots_w.unwrap_or(0));
        let (hr, hw) = (
            &mut self.hist_r[k * sr..(k + 1) * sr],
            &mut self.hist_w[k * sw..(k + 1) * sw],
        );
        match found {
            Some(m) => {
                copy_slots(hr, &prev.hist_r[m * sr..(m + 1) * sr]);
                copy_slots(hw, &prev.hist_w[m * sw..(m + 1) * sw]);
            }
            None => {
                hr.fill(0.0);
                hw.fill(0.0);
            }
        }
    }
}

/// A particle–wall contact's gathered values (see [`ContactSet`]).
pub(super) struct WallContact {
    values: ContactValues,
    /// The particle's spin relative to the wall's (rad/s), for the rolling and twisting part of
    /// the merge.
    spin: [f64; 3],
}

/// Why a wall contact is refused: the particle (the user's number), the overlap (m), the radius
/// (m); [`WallRefusal::naming`] adds the wall.
pub(super) struct WallRefusal(usize, f64, f64);

impl WallRefusal {
    pub(super) fn naming(self, w: usize) -> DemError {
        DemError::Overlap {
            i: self.0,
            partner: format!("wall {w}"),
            delta: self.1,
            radius: self.2,
        }
    }
}

/// The contact of particle `ig` (of `view`) with the wall `ws`: `None` if apart (unless
/// `adhesive`: an adhesive law's contact is kept for the merge to decide); an overlap beyond
/// [`MAX_OVERLAP`] (or NaN) refused.
#[inline(always)]
pub(super) fn wall_contact<const D: usize>(
    ws: &WallState<D>,
    ig: usize,
    view: &View<'_, D>,
    adhesive: bool,
) -> Result<Option<WallContact>, WallRefusal> {
    let i = ig - view.base;
    let (x, r) = (&view.pos[i], view.radius[i]);
    let delta = ws.overlap(x, r);
    if delta <= 0.0 && !adhesive {
        return Ok(None);
    }
    if delta.is_nan() || delta > MAX_OVERLAP * r {
        return Err(WallRefusal(user(view.uid, view.base, ig), delta, r));
    }
    let (n, vw) = ws.contact(x, r, delta);
    let nv = to3(&n);
    let rate = -to3(&(view.vpred[i] - vw)).dot(&nv);
    let dv = to3(&(view.vel[i] - vw));
    let wi = spin::<D>(view.omega, i);
    let v = dv - (wi * r).cross(&nv);
    // (the spin relative to a rotating wall's, for the rolling and twisting laws)
    let wr = if ws.omega == Vec3::zeros() {
        wi
    } else {
        wi - ws.omega
    };
    Ok(Some(WallContact {
        values: ContactValues {
            delta,
            rate,
            mass: view.mass[i],
            radius: r,
            normal: [nv.x, nv.y, nv.z],
            vrel: [v.x, v.y, v.z],
            sign: 1.0,
        },
        spin: [wr.x, wr.y, wr.z],
    }))
}
