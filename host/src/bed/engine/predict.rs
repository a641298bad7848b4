//! Prediction: the next event of each disk.

use super::FREE;
use super::{Bed, Kind};
use crate::bed::cells::NONE;
use crate::bed::events::{accel_pair_contact, first_contact, pair_contact_before};
use crate::bed::Restitution;

impl<R: Restitution> Bed<R> {
    /// Predicts the next event of disk `i` from the current time, scanning everything.
    pub(super) fn predict(&mut self, i: usize) {
        self.predict_scope(i, Scope::All);
    }

    /// Predicts the next event of disk `i` from the current time and enters it in the queue.
    ///
    /// Besides its pending event, each disk caches the earliest of its *other* events (disks,
    /// lid, piston) found by the last scan. After a cell crossing, while that cached event is
    /// still valid, only the three cells that just became neighbours (and a wall just come
    /// within reach) need scanning: the other candidates are unchanged, since the disk's
    /// trajectory is, and a neighbour whose trajectory changed has predicted its own events
    /// against this disk. That cuts the work of a crossing, most of the events, by two thirds.
    pub(super) fn predict_scope(&mut self, i: usize, scope: Scope) {
        let now = self.now;
        let (xi, yi, vxi, vyi) = self.state_at(i, now);
        let g = self.g;
        let ayi = self.d[i].ay;
        let rides = self.ride[i] != FREE;
        // a disk riding on the piston stops at the end of its piece (it is re-anchored or leaves)
        let ride_end = if rides {
            self.piston.piece_start(self.ride[i] + 1) - now
        } else {
            f64::INFINITY
        };
        let (nx, ny) = (self.cells.nx, self.cells.ny);
        let (cx, cy) = self.cells.col_row[i];
        let (cx, cy) = (cx as usize, cy as usize);
        // the best event that is not a cell crossing: from the cache or from scratch
        let (mut best, mut kind, mut partner, mut pcount) = match scope {
            Scope::All => (f64::INFINITY, Kind::Never, NONE, 0),
            _ => (
                self.cache_t[i] - now,
                self.cache_kind[i],
                self.cache_partner[i],
                self.cache_pcount[i],
            ),
        };
        let yb = self.cells.y0 + cy as f64 * self.cells.wy;
        // the lid, from the top row only (rows are at least one diameter high)
        if rides {
            if ride_end < best {
                best = ride_end.max(0.0);
                kind = Kind::Horizon;
                partner = NONE;
            }
        } else if cy + 1 == ny && matches!(scope, Scope::All | Scope::Row(1)) {
            if let Some(t) = first_contact(self.lid - self.radius - yi, -vyi, g) {
                if t < best {
                    best = t;
                    kind = Kind::Lid;
                    partner = NONE;
                }
            }
        }
        // disks of this and the eight neighbouring cells (or of the three new ones): the list of
        // cells is worked out once, 9 or 3 of them, a row beyond the grid standing for the empty
        // cell (so that the loop over them has one of two trip counts, which the branch
        // predictor learns; nested loops over rows and columns of varying counts it did not)
        let left = if cx == 0 { nx - 1 } else { cx - 1 };
        let right = if cx + 1 == nx { 0 } else { cx + 1 };
        let out = self.cells.outside();
        let cell = |r: usize, c: usize| if r < ny { r * nx + c } else { out };
        let (below, above) = (cy.wrapping_sub(1), cy + 1);
        let mut list = [out; 9];
        let visit: &[usize] = match scope {
            Scope::All => {
                for (k, r) in [below, cy, above].into_iter().enumerate() {
                    list[3 * k] = cell(r, left);
                    list[3 * k + 1] = cell(r, cx);
                    list[3 * k + 2] = cell(r, right);
                }
                &list
            }
            Scope::Row(dr) => {
                let r = if dr > 0 { above } else { below };
                list[..3].copy_from_slice(&[cell(r, left), cell(r, cx), cell(r, right)]);
                &list[..3]
            }
            Scope::Col(dc) => {
                let c = if dc > 0 { right } else { left };
                list[..3].copy_from_slice(&[cell(below, c), cell(cy, c), cell(above, c)]);
                &list[..3]
            }
        };
        let d = &self.d[..];
        for &c in visit {
            let mut j = self.cells.head(c);
            while j != NONE {
                let ju = j as usize;
                let dj = &d[ju];
                if ju != i {
                    let dtj = now - dj.tl;
                    let xj = dj.x + dj.vx * dtj;
                    let ayj = dj.ay;
                    let yj = dj.y + (dj.vy + 0.5 * ayj * dtj) * dtj;
                    let vyj = dj.vy + ayj * dtj;
                    let rxij = self.wrap(xi - xj);
                    let (ry, vx, vy) = (yi - yj, vxi - dj.vx, vyi - vyj);
                    let hit = if ayj == ayi {
                        pair_contact_before(rxij, ry, vx, vy, self.sigma2, best)
                    } else {
                        // one of the two rides on the piston: search up to its ride's end
                        let end = if rides {
                            ride_end
                        } else if self.ride[ju] != FREE {
                            self.piston.piece_start(self.ride[ju] + 1) - now
                        } else {
                            f64::INFINITY
                        };
                        accel_pair_contact(rxij, ry, vx, vy, ayi - ayj, self.sigma2, best.min(end))
                    };
                    if let Some(t) = hit {
                        if t < best {
                            best = t;
                            kind = Kind::Disk;
                            partner = j;
                            pcount = self.count[ju];
                        }
                    }
                }
                j = self.cells.next(ju);
            }
        }
        // the piston, piece by piece, only from rows it can reach, only from when the disk can
        // be down at the piston's highest, and only if that is before the best event so far
        if !rides && yb < self.piston_reach && matches!(scope, Scope::All | Scope::Row(-1)) {
            let above = yi - self.piston_reach;
            let reach = if above <= 0.0 {
                Some(0.0)
            } else {
                first_contact(above, vyi, -g)
            };
            if let Some(tmin) = reach.filter(|&t| t < best) {
                let k0 = self.piston.piece(now + tmin).max(self.piston.piece(now));
                let mut settled = false;
                for k in k0..k0 + 4 {
                    let start = self.piston.piece_start(k).max(now);
                    if start - now >= best {
                        settled = true;
                        break;
                    }
                    let end = self.piston.piece_start(k + 1);
                    let dt = start - now;
                    let y0 = yi + (vyi - 0.5 * g * dt) * dt;
                    let v0 = vyi - g * dt;
                    let p = self.piston.state_on(k, start);
                    if let Some(t) = first_contact(y0 - self.radius - p.z, v0 - p.v, -g - p.a) {
                        if start + t <= end {
                            let tt = start + t - now;
                            if tt < best {
                                best = tt;
                                kind = Kind::Piston;
                                partner = NONE;
                            }
                            settled = true;
                            break;
                        }
                    }
                }
                if !settled {
                    let h = self.piston.piece_start(k0 + 4) - now;
                    if h < best {
                        best = h;
                        kind = Kind::Horizon;
                        partner = NONE;
                    }
                }
            }
        }
        self.cache_t[i] = now + best;
        self.cache_kind[i] = kind;
        self.cache_partner[i] = partner;
        self.cache_pcount[i] = pcount;
        // cell crossings
        let mut bx = f64::INFINITY;
        let mut kx = Kind::Never;
        if vxi > 0.0 {
            let xr = (cx + 1) as f64 * self.cells.wx;
            bx = ((xr - xi) / vxi).max(0.0);
            kx = Kind::CellRight;
        } else if vxi < 0.0 {
            let xl = cx as f64 * self.cells.wx;
            bx = ((xl - xi) / vxi).max(0.0);
            kx = Kind::CellLeft;
        }
        // a row boundary is only looked for where the disk can reach it: not above while it
        // moves down (or is at rest) and is not pushed up, not below in the mirror case, and not
        // below once it is found to cross above while rising and slowing (it turns back only
        // after that crossing): one square root instead of two for most crossings
        let up = if cy + 1 < ny && (vyi > 0.0 || ayi > 0.0) {
            first_contact(yb + self.cells.wy - yi, -vyi, -ayi)
        } else {
            None
        };
        if let Some(t) = up {
            if t < bx {
                bx = t;
                kx = Kind::CellUp;
            }
        }
        let turns_after_up = up.is_some() && vyi > 0.0 && ayi < 0.0;
        if cy > 0 && (vyi < 0.0 || ayi < 0.0) && !turns_after_up {
            if let Some(t) = first_contact(yi - yb, vyi, ayi) {
                if t < bx {
                    bx = t;
                    kx = Kind::CellDown;
                }
            }
        }
        if bx < best {
            best = bx;
            kind = kx;
            partner = NONE;
        }
        self.kind[i] = kind;
        self.partner[i] = partner;
        self.pcount[i] = pcount;
        self.queue.update(i, now + best);
    }

    /// Whether the cached non-crossing event of `i` still holds (its partner has not collided
    /// since).
    #[inline]
    pub(super) fn cache_valid(&self, i: usize) -> bool {
        self.cache_kind[i] != Kind::Disk || self.count[self.cache_partner[i] as usize] == self.cache_pcount[i]
    }
}

/// Which neighbours a prediction scans.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scope {
    /// All nine cells and both walls.
    All,
    /// Only the row of cells just entered (+1 above, −1 below).
    Row(i64),
    /// Only the column of cells just entered (+1 right, −1 left).
    Col(i64),
}
