//! Guards: what stops a run that went wrong, with an error naming the time, the disks and
//! the remedy.

use super::Bed;
use crate::bed::cells::NONE;
use crate::bed::{BedError, Restitution};

/// The largest overlap (in diameters) a run may show: beyond it the run stops with an error.
pub const OVERLAP_LIMIT: f64 = 1e-9;

impl<R: Restitution> Bed<R> {
    /// The overlap guard: disk `i` meets `with` (a disk, [`LID`] or [`PISTON`]) overlapping by
    /// `overlap` (m). Beyond [`OVERLAP_LIMIT`] diameters a contact was missed (disks pinned
    /// against a wall or each other in an inelastic collapse): the run stops with an error
    /// naming the disks, the time, the overlap and the remedy, rather than report wrong physics.
    #[inline(always)]
    pub(super) fn guard_overlap(&self, i: usize, with: u32, overlap: f64) -> Result<(), BedError> {
        if overlap <= OVERLAP_LIMIT * self.cfg.diameter {
            return Ok(());
        }
        Err(self.missed_contact(i, with, overlap))
    }

    /// The error of [`Bed::guard_overlap`] (out of the event loop's way).
    #[cold]
    #[inline(never)]
    fn missed_contact(&self, i: usize, with: u32, overlap: f64) -> BedError {
        let (x, y, _, _) = self.state_at(i, self.now);
        let what = match with {
            LID => "the lid".to_string(),
            PISTON => "the piston".to_string(),
            j => format!("disk {j}"),
        };
        BedError::Overlap(format!(
            "overlap at t = {:.9} s: disk {i} (at x = {:.4} m, y = {:.4} m) and {what} overlap by \
             {overlap:.3e} m ({:.3e} d), more than {OVERLAP_LIMIT:e} d: a contact was missed, \
             which happens when disks are pinned against each other or a wall in an inelastic \
             collapse. Remedy: the TC model (--tc SECONDS, e.g. --tc 1e-5), or a restitution \
             law that tends to 1 at low impact speed (e.g. mcnamara-falcon)",
            self.now,
            x.rem_euclid(self.width),
            y,
            overlap / self.cfg.diameter
        ))
    }

    /// The largest overlap (m) at time `t` (s) between neighbours and between a disk and a wall,
    /// with the disk and its partner, through the cells (O(N)).
    pub fn scan_overlap(&self, t: f64) -> (f64, usize, u32) {
        let (nx, ny) = (self.cells.nx, self.cells.ny);
        let z = self.piston.state(t).z;
        let mut worst = (0.0, 0, NONE);
        for i in 0..self.n {
            let (xi, yi, _, _) = self.state_at(i, t);
            if self.ride[i] == super::FREE {
                let o = z + self.radius - yi;
                if o > worst.0 {
                    worst = (o, i, PISTON);
                }
            }
            let o = yi + self.radius - self.lid;
            if o > worst.0 {
                worst = (o, i, LID);
            }
            let c = self.cells.cell[i] as usize;
            let (cx, cy) = (c % nx, c / nx);
            for dy in -1i64..=1 {
                let ry = cy as i64 + dy;
                if ry < 0 || ry >= ny as i64 {
                    continue;
                }
                for dx in -1i64..=1 {
                    let rx = (cx as i64 + dx).rem_euclid(nx as i64) as usize;
                    let mut j = self.cells.head(ry as usize * nx + rx);
                    while j != NONE {
                        let ju = j as usize;
                        if ju > i {
                            let (xj, yj, _, _) = self.state_at(ju, t);
                            let ddx = self.wrap(xi - xj);
                            let o = self.cfg.diameter - (ddx * ddx + (yi - yj).powi(2)).sqrt();
                            if o > worst.0 {
                                worst = (o, i, j);
                            }
                        }
                        j = self.cells.next(ju);
                    }
                }
            }
        }
        worst
    }

    /// Scans every pair of neighbours and every disk against the walls at time `t` (s); the run
    /// stops if any overlap is beyond [`OVERLAP_LIMIT`].
    pub(super) fn guard_scan(&mut self, t: f64) -> Result<(), BedError> {
        let (o, i, with) = self.scan_overlap(t);
        if o > self.counters.max_overlap {
            self.counters.max_overlap = o;
        }
        let now = self.now;
        self.now = t;
        let r = self.guard_overlap(i, with, o);
        self.now = now;
        r
    }

    /// The ping-pong guard: a disk colliding again at the very instant of its last collision
    /// (roundoff can make a pair that just separated look approaching) is allowed a few times,
    /// then the run stops with an error naming the time and the disk, instead of looping.
    #[inline(always)]
    pub(super) fn guard_same_instant(&mut self, i: usize) -> Result<(), BedError> {
        if self.last_coll[i] == self.now {
            self.same_instant[i] += 1;
            if self.same_instant[i] > SAME_INSTANT_LIMIT {
                return Err(self.ping_pong(i));
            }
        } else {
            self.same_instant[i] = 0;
        }
        Ok(())
    }

    /// The error of [`Bed::guard_same_instant`] for disk `i` (out of the event loop's way).
    #[cold]
    #[inline(never)]
    fn ping_pong(&self, i: usize) -> BedError {
        let (x, y, _, _) = self.state_at(i, self.now);
        let with = match self.last_partner[i] {
            LID => "the lid".to_string(),
            PISTON => "the piston".to_string(),
            j => format!("disk {j}"),
        };
        BedError::Collapse(format!(
            "ping-pong at t = {:.9} s: disk {i} (at x = {:.4} m, y = {:.4} m) collided \
             {} times at the same instant, last with {with} (inelastic collapse: disks \
             coming to rest on each other, e.g. one on a disk that rides on the piston; \
             largest overlap so far {:.3e} d); use the TC model (--tc SECONDS, e.g. \
             --tc 1e-5) or a restitution that tends to 1 at low speed",
            self.now,
            x.rem_euclid(self.width),
            y,
            self.same_instant[i],
            self.counters.max_overlap / self.cfg.diameter
        ))
    }

    /// The explosion guard: `block_len` events within a simulated time so short that each disk
    /// would have more than 10⁹ events per simulated second.
    pub(super) fn check_rate(&mut self) -> Result<(), BedError> {
        let dt = self.now - self.block_start_t;
        let limit = self.block_len as f64 / (self.n as f64 * 1e9);
        if dt < limit {
            let mut idx: Vec<usize> = (0..self.n).collect();
            idx.sort_by_key(|&k| std::cmp::Reverse(self.block_hits[k]));
            let worst: Vec<String> = idx
                .iter()
                .take(5)
                .filter(|&&k| self.block_hits[k] > 0)
                .map(|&k| {
                    let (x, y, _, _) = self.state_at(k, self.now);
                    format!(
                        "disk {k} ({} collisions, at x = {:.4} m, y = {:.4} m)",
                        self.block_hits[k],
                        x.rem_euclid(self.width),
                        y
                    )
                })
                .collect();
            return Err(BedError::Collapse(format!(
                "the event rate exploded at t = {:.9} s: {} events in {:.3e} s of simulated time \
                 (inelastic collapse, or disks pinned against a wall; largest overlap so far \
                 {:.3e} d); most involved: {}. Use the TC model (--tc SECONDS, e.g. --tc 1e-5) \
                 or a restitution that tends to 1 at low speed",
                self.now,
                self.block_events,
                dt,
                self.counters.max_overlap / self.cfg.diameter,
                worst.join(", ")
            )));
        }
        self.block_start_t = self.now;
        self.block_events = 0;
        self.block_hits.iter_mut().for_each(|h| *h = 0);
        Ok(())
    }
}

/// Collisions of one disk allowed at one instant before the run is stopped.
pub(super) const SAME_INSTANT_LIMIT: u32 = 64;
/// Partner code of the lid in `last_partner`.
pub(super) const LID: u32 = u32::MAX - 1;
/// Partner code of the piston in `last_partner`.
pub(super) const PISTON: u32 = u32::MAX - 2;
