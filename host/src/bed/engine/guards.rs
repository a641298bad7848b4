//! Guards: what stops a run that went wrong, with an error naming the time, the disks and
//! the remedy.

use super::Bed;
use crate::bed::{BedError, Restitution};

impl<R: Restitution> Bed<R> {
    /// The ping-pong guard: a disk colliding again at the very instant of its last collision
    /// (roundoff can make a pair that just separated look approaching) is allowed a few times,
    /// then the run stops with an error naming the time and the disk, instead of looping.
    pub(super) fn guard_same_instant(&mut self, i: usize) -> Result<(), BedError> {
        if self.last_coll[i] == self.now {
            self.same_instant[i] += 1;
            if self.same_instant[i] > SAME_INSTANT_LIMIT {
                let (x, y, _, _) = self.state_at(i, self.now);
                let with = match self.last_partner[i] {
                    LID => "the lid".to_string(),
                    PISTON => "the piston".to_string(),
                    j => format!("disk {j}"),
                };
                return Err(BedError::Collapse(format!(
                    "ping-pong at t = {:.9} s: disk {i} (at x = {:.4} m, y = {:.4} m) collided \
                     {} times at the same instant, last with {with} (inelastic collapse); use \
                     the TC model (--tc SECONDS, e.g. 1e-5) or a restitution that tends to 1 at low speed",
                    self.now,
                    x.rem_euclid(self.width),
                    y,
                    self.same_instant[i]
                )));
            }
        } else {
            self.same_instant[i] = 0;
        }
        Ok(())
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
                 (inelastic collapse, or disks pinned against a wall); most involved: {}. \
                 Use the TC model (--tc SECONDS, e.g. 1e-5) or a restitution that tends to 1 at low speed",
                self.now,
                self.block_events,
                dt,
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
