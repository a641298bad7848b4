//! Contacts gathered each step into arrays (structure of arrays, what the laws' batch calls
//! take), and their history carried from step to step.
//!
//! A contact is keyed by `(i, j)`: two particles with `i < j`, or particle `i` and wall `j`.
//! Contacts are gathered in key order (particle by particle, partners sorted), and so was the
//! previous step's set; a contact's history is found in the previous set by scanning the short
//! row of its particle `i` (compressed rows, `start[i]..start[i+1]`). A contact that is new
//! starts from zero history; one that is gone is not carried over (dropped at separation).
//! Particle indices never change, so neither a neighbour-list rebuild nor a periodic wrap
//! touches the history.

use super::cells::{Domain, Neighbours};
use super::state::{to3, Vec3, VecD};
use super::walls::WallState;
use super::DemError;
use crate::laws::{NormalLaw, TangentialForce};
use dashpot_sdk::{NormalBatch, TangentialBatch};
use rayon::prelude::*;

/// One kind of contacts (particle pairs, or particles against walls), structure of arrays.
#[derive(Debug, Clone, Default)]
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
    /// Rows by particle i: `start[i]..start[i+1]` (n + 1 entries).
    pub start: Vec<u32>,
    /// Contacts of this set that were not in the previous one (first touches this step).
    pub formed: usize,
}

/// The overlap beyond which a run is refused, as a fraction of the smaller radius.
pub const MAX_OVERLAP: f64 = 0.5;

/// Contacts per law call (and per parallel task).
pub const LAW_CHUNK: usize = 1024;

/// Particles per gathering task.
const GATHER_CHUNK: usize = 4096;

impl ContactSet {
    /// An empty set for laws keeping `slots_n` and `slots_t` history values.
    pub fn new(slots_n: usize, slots_t: usize) -> ContactSet {
        ContactSet {
            slots_n,
            slots_t,
            ..Default::default()
        }
    }

    /// An empty set with room for `cap` contacts (so that gathering a step's contacts, about
    /// as many as the last step's, does not grow eleven arrays by doubling every step).
    fn with_capacity(slots_n: usize, slots_t: usize, cap: usize) -> ContactSet {
        ContactSet {
            i: Vec::with_capacity(cap),
            j: Vec::with_capacity(cap),
            delta: Vec::with_capacity(cap),
            rate: Vec::with_capacity(cap),
            mass: Vec::with_capacity(cap),
            radius: Vec::with_capacity(cap),
            normal: Vec::with_capacity(cap),
            vrel: Vec::with_capacity(cap),
            hist_n: Vec::with_capacity(cap * slots_n),
            hist_t: Vec::with_capacity(cap * slots_t),
            fresh: Vec::with_capacity(cap),
            slots_n,
            slots_t,
            ..Default::default()
        }
    }

    /// The parts gathered chunk by chunk, in order, as one set (the first part's arrays are
    /// kept, not copied: with one chunk nothing moves).
    fn concat(
        slots_n: usize,
        slots_t: usize,
        parts: Vec<Result<ContactSet, DemError>>,
    ) -> Result<ContactSet, DemError> {
        let mut parts = parts.into_iter();
        let mut next = match parts.next() {
            Some(p) => p?,
            None => ContactSet::new(slots_n, slots_t),
        };
        for p in parts {
            next.append(&mut p?);
        }
        Ok(next)
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.i.len()
    }

    /// No contacts.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// The history of contact (i, j) in this set, if it exists.
    #[inline]
    fn find(&self, i: usize, j: u32) -> Option<usize> {
        if i + 1 >= self.start.len() {
            return None;
        }
        let (a, b) = (self.start[i] as usize, self.start[i + 1] as usize);
        (a..b).find(|&k| self.j[k] == j)
    }

    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn push(
        &mut self,
        prev: &ContactSet,
        i: usize,
        j: u32,
        delta: f64,
        rate: f64,
        mass: f64,
        radius: f64,
        n: Vec3,
        v: Vec3,
    ) {
        self.i.push(i as u32);
        self.j.push(j);
        self.delta.push(delta);
        self.rate.push(rate);
        self.mass.push(mass);
        self.radius.push(radius);
        self.normal.push([n.x, n.y, n.z]);
        self.vrel.push([v.x, v.y, v.z]);
        match prev.find(i, j) {
            Some(k) => {
                let (sn, st) = (self.slots_n, self.slots_t);
                self.hist_n.extend_from_slice(&prev.hist_n[k * sn..(k + 1) * sn]);
                self.hist_t.extend_from_slice(&prev.hist_t[k * st..(k + 1) * st]);
                self.fresh.push(false);
                self.last.push(prev.last[k]);
            }
            None => {
                self.hist_n.extend(std::iter::repeat_n(0.0, self.slots_n));
                self.hist_t.extend(std::iter::repeat_n(0.0, self.slots_t));
                self.fresh.push(true);
                self.last.push(false);
                self.formed += 1;
            }
        }
    }

    fn append(&mut self, o: &mut ContactSet) {
        self.i.append(&mut o.i);
        self.j.append(&mut o.j);
        self.delta.append(&mut o.delta);
        self.rate.append(&mut o.rate);
        self.mass.append(&mut o.mass);
        self.radius.append(&mut o.radius);
        self.normal.append(&mut o.normal);
        self.vrel.append(&mut o.vrel);
        self.hist_n.append(&mut o.hist_n);
        self.hist_t.append(&mut o.hist_t);
        self.fresh.append(&mut o.fresh);
        self.last.append(&mut o.last);
        self.formed += o.formed;
    }

    fn index_rows(&mut self, n: usize) {
        self.start.clear();
        self.start.resize(n + 1, 0);
        for &i in &self.i {
            self.start[i as usize + 1] += 1;
        }
        for k in 0..n {
            self.start[k + 1] += self.start[k];
        }
    }

    /// Replaces `self` by the contacts of the current state, carrying history over from `self`.
    /// Overlap rates come from the predicted velocities `vpred`, the contact points' slip from
    /// the step's velocities `vel`, `omega` (over the step: velocity Verlet's half-step ones, so
    /// that slip × dt is the tangential displacement of the step).
    #[allow(clippy::too_many_arguments)]
    pub fn gather_pairs<const D: usize>(
        &mut self,
        dom: &Domain<D>,
        nb: &Neighbours<D>,
        pos: &[VecD<D>],
        vpred: &[VecD<D>],
        vel: &[VecD<D>],
        omega: &[Vec3],
        radius: &[f64],
        mass: &[f64],
    ) -> Result<(), DemError> {
        let n = pos.len();
        let prev = &*self;
        let chunks = n.div_ceil(GATHER_CHUNK);
        let cap = chunk_capacity(prev.len(), chunks);
        let parts: Vec<Result<ContactSet, DemError>> = par_or_seq(chunks, |ch| {
            let mut out = ContactSet::with_capacity(prev.slots_n, prev.slots_t, cap);
            for i in ch * GATHER_CHUNK..((ch + 1) * GATHER_CHUNK).min(n) {
                for &j in nb.of(i) {
                    let ju = j as usize;
                    let d = dom.delta(&pos[i], &pos[ju]);
                    let sum = radius[i] + radius[ju];
                    let r2 = d.norm_squared();
                    if r2 >= sum * sum {
                        continue;
                    }
                    let dist = r2.sqrt();
                    let delta = sum - dist;
                    let rmin = radius[i].min(radius[ju]);
                    if delta.is_nan() || delta > MAX_OVERLAP * rmin {
                        return Err(DemError::Overlap {
                            i,
                            partner: format!("particle {ju}"),
                            delta,
                            radius: rmin,
                        });
                    }
                    let nv = to3(&(d / dist));
                    let rate = -to3(&(vpred[i] - vpred[ju])).dot(&nv);
                    let dv = to3(&(vel[i] - vel[ju]));
                    let v = dv - (omega[i] * radius[i] + omega[ju] * radius[ju]).cross(&nv);
                    let (mi, mj) = (mass[i], mass[ju]);
                    out.push(
                        prev,
                        i,
                        j,
                        delta,
                        rate,
                        mi * mj / (mi + mj),
                        radius[i] * radius[ju] / sum,
                        nv,
                        v,
                    );
                }
            }
            Ok(out)
        });
        let mut next = ContactSet::concat(self.slots_n, self.slots_t, parts)?;
        next.index_rows(n);
        next.fnorm.resize(next.len(), 0.0);
        next.ftan.resize(next.len(), [0.0; 3]);
        *self = next;
        Ok(())
    }

    /// Replaces `self` by the particle–wall contacts of the current state.
    #[allow(clippy::too_many_arguments)]
    pub fn gather_walls<const D: usize>(
        &mut self,
        walls: &[WallState<D>],
        pos: &[VecD<D>],
        vpred: &[VecD<D>],
        vel: &[VecD<D>],
        omega: &[Vec3],
        radius: &[f64],
        mass: &[f64],
    ) -> Result<(), DemError> {
        let n = pos.len();
        let mut next = ContactSet::new(self.slots_n, self.slots_t);
        if !walls.is_empty() {
            let prev = &*self;
            let chunks = n.div_ceil(GATHER_CHUNK);
            let cap = chunk_capacity(prev.len(), chunks);
            let parts: Vec<Result<ContactSet, DemError>> = par_or_seq(chunks, |ch| {
                let mut out = ContactSet::with_capacity(prev.slots_n, prev.slots_t, cap);
                for i in ch * GATHER_CHUNK..((ch + 1) * GATHER_CHUNK).min(n) {
                    for (w, ws) in walls.iter().enumerate() {
                        let gap = (pos[i] - ws.point).dot(&ws.normal);
                        let delta = radius[i] - gap;
                        if delta <= 0.0 {
                            continue;
                        }
                        if delta.is_nan() || delta > MAX_OVERLAP * radius[i] {
                            return Err(DemError::Overlap {
                                i,
                                partner: format!("wall {w}"),
                                delta,
                                radius: radius[i],
                            });
                        }
                        let nv = to3(&ws.normal);
                        let rate = -to3(&(vpred[i] - ws.velocity)).dot(&nv);
                        let dv = to3(&(vel[i] - ws.velocity));
                        let v = dv - (omega[i] * radius[i]).cross(&nv);
                        out.push(prev, i, w as u32, delta, rate, mass[i], radius[i], nv, v);
                    }
                }
                Ok(out)
            });
            next = ContactSet::concat(self.slots_n, self.slots_t, parts)?;
        }
        next.index_rows(n);
        next.fnorm.resize(next.len(), 0.0);
        next.ftan.resize(next.len(), [0.0; 3]);
        *self = next;
        Ok(())
    }

    /// Calls the laws on every contact (in batches of [`LAW_CHUNK`], in parallel): normal forces,
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
    /// batch call per chunk that has such contacts. A law with history (Thornton, Walton–Braun)
    /// keeps the step-end rule, as does every law when `edge_means` is false.
    pub fn evaluate(
        &mut self,
        normal: &dyn NormalLaw,
        tangential: Option<&dyn TangentialForce>,
        dt: f64,
        edge_means: bool,
    ) -> Result<(), DemError> {
        let n = self.len();
        if n == 0 {
            return Ok(());
        }
        let (sn, st) = (self.slots_n, self.slots_t);
        let ContactSet {
            delta,
            rate,
            mass,
            radius,
            normal: nrm,
            vrel,
            hist_n,
            hist_t,
            fnorm,
            ftan,
            fresh,
            last,
            ..
        } = self;
        let tasks: Vec<_> = fnorm
            .chunks_mut(LAW_CHUNK)
            .zip(ftan.chunks_mut(LAW_CHUNK))
            .zip(split_rows(hist_n, sn, n))
            .zip(split_rows(hist_t, st, n))
            .zip(last.chunks_mut(LAW_CHUNK))
            .enumerate()
            .collect();
        // a law with history would see its history advanced by the extra calls: plain rule
        let edges = edge_means && sn == 0;
        let run = |(c, ((((f, ft), hn), ht), ls)): Task<'_>| -> Result<(), DemError> {
            let a = c * LAW_CHUNK;
            let b = a + f.len();
            normal.force_batch(NormalBatch {
                delta: &delta[a..b],
                rate: &rate[a..b],
                mass: &mass[a..b],
                radius: &radius[a..b],
                slots: sn,
                history: hn,
                force: &mut *f,
            })?;
            if edges {
                step_edge_means(
                    normal,
                    Edges {
                        delta: &delta[a..b],
                        rate: &rate[a..b],
                        mass: &mass[a..b],
                        radius: &radius[a..b],
                        fresh: &fresh[a..b],
                    },
                    ls,
                    f,
                    dt,
                )?;
            }
            if let Some(t) = tangential {
                t.force_batch(TangentialBatch {
                    dt,
                    normal: &nrm[a..b],
                    velocity: &vrel[a..b],
                    normal_force: &*f,
                    delta: &delta[a..b],
                    mass: &mass[a..b],
                    radius: &radius[a..b],
                    slots: st,
                    history: ht,
                    force: ft,
                })?;
            }
            Ok(())
        };
        if tasks.len() == 1 {
            tasks.into_iter().try_for_each(run)
        } else {
            tasks.into_par_iter().try_for_each(run)
        }
    }
}

/// One parallel task of [`ContactSet::evaluate`]: chunk index, normal forces, tangential forces,
/// normal and tangential history rows, the contacts' `last` flags.
type Task<'a> = (
    usize,
    (
        (
            ((&'a mut [f64], &'a mut [[f64; 3]]), &'a mut [f64]),
            &'a mut [f64],
        ),
        &'a mut [bool],
    ),
);

/// 5-point Gauss–Legendre nodes and weights on [0, 1].
const GAUSS5: [(f64, f64); 5] = [
    (0.046_910_077_030_668_02, 0.118_463_442_528_094_54),
    (0.230_765_344_947_158_45, 0.239_314_335_249_683_23),
    (0.5, 0.284_444_444_444_444_44),
    (0.769_234_655_052_841_6, 0.239_314_335_249_683_23),
    (0.953_089_922_969_332, 0.118_463_442_528_094_54),
];

/// The contacts of one chunk, as [`step_edge_means`] reads them.
struct Edges<'a> {
    delta: &'a [f64],
    rate: &'a [f64],
    mass: &'a [f64],
    radius: &'a [f64],
    fresh: &'a [bool],
}

/// The first- and last-step means of [`ContactSet::evaluate`], for one chunk: `f` holds the
/// law's forces at the step end and is corrected in place; `last` is read (the previous step's
/// flag) and written.
fn step_edge_means(
    law: &dyn NormalLaw,
    c: Edges<'_>,
    last: &mut [bool],
    f: &mut [f64],
    dt: f64,
) -> Result<(), DemError> {
    let h = 0.5 * dt;
    // (contact, upper overlap D of the mean, the time-to-overlap factor |δ̇| dt)
    let mut jobs: Vec<(usize, f64, f64)> = Vec::new();
    for m in 0..f.len() {
        let (d, r) = (c.delta[m], c.rate[m]);
        let was_last = last[m];
        last[m] = false;
        if c.fresh[m] && r > 0.0 && d <= 1.5 * r * dt {
            jobs.push((m, d + r * h, r * dt));
        } else if was_last && r < 0.0 && d < -r * h {
            f[m] = 0.0;
        } else if r < 0.0 && d + r * dt - f[m] / c.mass[m] * h * dt <= 0.0 {
            jobs.push((m, d - r * h, -r * dt));
            last[m] = true;
        }
    }
    if jobs.is_empty() {
        return Ok(());
    }
    let k = jobs.len() * GAUSS5.len();
    let (mut qd, mut qr, mut qm, mut qa) = (
        Vec::with_capacity(k),
        Vec::with_capacity(k),
        Vec::with_capacity(k),
        Vec::with_capacity(k),
    );
    for &(m, dd, _) in &jobs {
        for (u, _) in GAUSS5 {
            qd.push(dd * u.powi(4));
            qr.push(c.rate[m]);
            qm.push(c.mass[m]);
            qa.push(c.radius[m]);
        }
    }
    let mut qf = vec![0.0; k];
    law.force_batch(NormalBatch {
        delta: &qd,
        rate: &qr,
        mass: &qm,
        radius: &qa,
        slots: 0,
        history: &mut [],
        force: &mut qf,
    })?;
    for (q, &(m, dd, div)) in jobs.iter().enumerate() {
        // ∫_0^D F dδ = ∫_0^1 F(D u⁴) 4 D u³ du
        let integral: f64 = GAUSS5
            .iter()
            .enumerate()
            .map(|(g, (u, w))| w * qf[q * GAUSS5.len() + g] * 4.0 * dd * u.powi(3))
            .sum();
        f[m] = integral / div;
    }
    Ok(())
}

/// Below this many particles the engine runs serially: rayon's dispatch per parallel loop costs
/// more than a few thousand particles' work (a 50-disk bed ran at 175 µs per step).
pub const SERIAL_BELOW: usize = 4096;

/// Room for one gathering chunk's contacts: its share of the last step's count, an eighth more.
fn chunk_capacity(last: usize, chunks: usize) -> usize {
    let share = last / chunks.max(1);
    share + share / 8 + 16
}

/// `f(0..chunks)` collected, in parallel when there is more than one chunk.
fn par_or_seq<T: Send>(chunks: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    if chunks <= 1 {
        (0..chunks).map(f).collect()
    } else {
        (0..chunks).into_par_iter().map(f).collect()
    }
}

/// `hist` cut into the history rows of successive [`LAW_CHUNK`]s of `n` contacts.
fn split_rows(mut hist: &mut [f64], slots: usize, n: usize) -> Vec<&mut [f64]> {
    let mut out = Vec::with_capacity(n.div_ceil(LAW_CHUNK));
    let mut left = n;
    while left > 0 {
        let k = left.min(LAW_CHUNK);
        let (a, b) = std::mem::take(&mut hist).split_at_mut(k * slots);
        out.push(a);
        hist = b;
        left -= k;
    }
    out
}
