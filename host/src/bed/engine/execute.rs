//! Execution: the event loop and the collision rules.

use super::guards::{LID, PISTON};
use super::predict::Scope;
use super::{Bed, EventRecord, Kind, FREE};
use crate::bed::cells::NONE;
use crate::bed::{BedError, Restitution};

/// A disk whose rebound off the pressing piston is slower than this times √((g + a_p) d) is put
/// at rest on it (see [`Bed::maybe_ride`]): a rebound height below 5·10⁻¹³ d.
pub const RIDE_SPEED: f64 = 1e-6;

impl<R: Restitution> Bed<R> {
    /// Moves disk `i`'s clock to now.
    #[inline]
    pub(super) fn advance(&mut self, i: usize) {
        let (x, y, vx, vy) = self.state_at(i, self.now);
        self.d[i].x = x;
        self.d[i].y = y;
        self.d[i].vx = vx;
        self.d[i].vy = vy;
        self.d[i].tl = self.now;
    }

    /// Disk `i` (its clock at now) leaves the piston, if it was riding on it: free flight.
    #[inline]
    pub(super) fn unride(&mut self, i: usize) {
        if self.ride[i] != FREE {
            self.ride_impulse(i, self.d[i].vy);
            self.ride[i] = FREE;
            self.d[i].ay = -self.g;
        }
    }

    /// After a piston collision that leaves disk `i` (its clock at now) with relative rebound
    /// speed `rebound` (m/s): chattering ends in the locked state. While the piston presses
    /// (its acceleration a_p > −g), a disk bouncing on it with r < 1 makes infinitely many ever
    /// shorter bounces that end, after a finite time, with the disk at rest on the piston (Luck
    /// & Mehta, PRE 48, 3988 (1993): "chattering" then "locking"); an event-driven run can only
    /// follow it until roundoff makes the disk sink into the piston. So once the rebound is
    /// below `RIDE_SPEED` √((g + a_p) d) the disk is put at rest on the piston and rides with
    /// it (acceleration a_p) until the piston decelerates faster than g, when it flies off
    /// with the piston's velocity. What this drops: bounces of height below 5·10⁻¹³ d and a
    /// remaining chattering time below ~10⁻⁶ √(d/(g + a_p))/(1 − r).
    pub(super) fn maybe_ride(&mut self, i: usize, rebound: f64) {
        let k = self.piston.piece(self.now);
        let p = self.piston.state_on(k, self.now);
        let press = self.g + p.a;
        if press > 0.0 && rebound < RIDE_SPEED * (press * self.cfg.diameter).sqrt() {
            self.ride[i] = k;
            self.d[i].y = p.z + self.radius;
            self.d[i].vy = p.v;
            self.d[i].ay = p.a;
            self.ride_from[i] = (self.now, p.v);
            self.counters.rides += 1;
        }
    }

    /// Disk `i` rides on the piston and its piece has ended (now): it rides on with the next
    /// piece while the piston presses it (g + a_p > 0), or else flies off with the piston's
    /// velocity. Its trajectory changes either way: its counter moves, so that the predictions
    /// of others against it are re-checked.
    pub(super) fn ride_on(&mut self, i: usize) {
        let k = self.ride[i] + 1;
        let p = self.piston.state_on(k, self.now);
        self.d[i].x += self.d[i].vx * (self.now - self.d[i].tl);
        self.d[i].tl = self.now;
        self.d[i].y = p.z + self.radius;
        self.d[i].vy = p.v;
        self.ride_impulse(i, p.v);
        if self.g + p.a > 0.0 {
            self.ride[i] = k;
            self.d[i].ay = p.a;
            self.ride_from[i] = (self.now, p.v);
        } else {
            self.ride[i] = FREE;
            self.d[i].ay = -self.g;
        }
        self.count[i] = self.count[i].wrapping_add(1);
    }

    /// The impulse (N·s) the piston gave disk `i` while it rode on it, from the start of the ride
    /// to now, when its velocity is `v` (m/s): m (Δv + g Δt), added to the window.
    fn ride_impulse(&mut self, i: usize, v: f64) {
        let (t0, v0) = self.ride_from[i];
        if self.measuring && t0 >= self.window.start {
            let j = self.cfg.mass * (v - v0 + self.g * (self.now - t0));
            self.window.piston_impulse += j;
            self.window.current.piston_impulse += j;
        }
    }

    // ---------------------------------------------------------------- execution

    /// The restitution for a collision of `i` (and `j`, for a pair) at impact speed `u` (m/s),
    /// after the TC model.
    #[inline(always)]
    pub(super) fn restitution(
        &mut self,
        i: usize,
        j: Option<usize>,
        u: f64,
        wall: bool,
    ) -> Result<f64, BedError> {
        let recent = |k: usize| self.now - self.last_coll[k] < self.tc;
        if self.tc >= 0.0 && (recent(i) || j.is_some_and(recent)) {
            self.counters.tc_firings += 1;
            return Ok(1.0);
        }
        let law = if wall { &self.laws.wall } else { &self.laws.disk };
        let r = law.r(u)?;
        if !(0.0..=1.0).contains(&r) {
            return Err(out_of_range(r, u));
        }
        Ok(r)
    }

    pub(super) fn record(&mut self, kind: Kind, i: usize, j: u32, speed: f64, r: f64) {
        if let Some(log) = self.log.as_mut() {
            log.push(EventRecord {
                t: self.now,
                kind,
                i: i as u32,
                j,
                speed,
                r,
            });
        }
    }

    pub(super) fn collide_pair(&mut self, i: usize, j: usize) -> Result<(), BedError> {
        self.guard_same_instant(i)?;
        self.guard_same_instant(j)?;
        self.ke_remove(i);
        self.ke_remove(j);
        self.advance(i);
        self.advance(j);
        // a disk riding on the piston that is hit leaves it (it may come straight back)
        self.unride(i);
        self.unride(j);
        let dx = self.wrap(self.d[i].x - self.d[j].x);
        let dy = self.d[i].y - self.d[j].y;
        let dist = (dx * dx + dy * dy).sqrt();
        let overlap = self.cfg.diameter - dist;
        if overlap > self.counters.max_overlap {
            self.counters.max_overlap = overlap;
        }
        self.guard_overlap(i, j as u32, overlap)?;
        let (nx, ny) = (dx / dist, dy / dist);
        let vn = (self.d[i].vx - self.d[j].vx) * nx + (self.d[i].vy - self.d[j].vy) * ny;
        let u = (-vn).max(0.0);
        let r = self.restitution(i, Some(j), u, false)?;
        let dv = 0.5 * (1.0 + r) * u;
        self.d[i].vx += dv * nx;
        self.d[i].vy += dv * ny;
        self.d[j].vx -= dv * nx;
        self.d[j].vy -= dv * ny;
        if let Some(rt) = self.rough {
            // tangent t = z × n; slip of the contact point of i relative to j's
            let (tx, ty) = (-ny, nx);
            let gt = (self.d[i].vx - self.d[j].vx) * tx + (self.d[i].vy - self.d[j].vy) * ty
                - self.radius * (self.w[i] + self.w[j]);
            let jt = -(1.0 + rt) * gt / 6.0; // tangential impulse / m, disk I = m R²/2
            self.d[i].vx += jt * tx;
            self.d[i].vy += jt * ty;
            self.d[j].vx -= jt * tx;
            self.d[j].vy -= jt * ty;
            self.w[i] -= 2.0 * jt / self.radius;
            self.w[j] -= 2.0 * jt / self.radius;
        }
        self.counters.collisions += 1;
        self.counters.disk_collisions += 1;
        self.count[i] = self.count[i].wrapping_add(1);
        self.count[j] = self.count[j].wrapping_add(1);
        self.last_coll[i] = self.now;
        self.last_coll[j] = self.now;
        self.last_partner[i] = j as u32;
        self.last_partner[j] = i as u32;
        self.block_hits[i] += 1;
        self.block_hits[j] += 1;
        self.ke_add(i);
        self.ke_add(j);
        self.record(Kind::Disk, i, j as u32, u, r);
        self.predict(i);
        self.predict(j);
        Ok(())
    }

    /// Disk `i` against a wall of normal `ny` (+1: the piston below, −1: the lid above) moving
    /// at vertical velocity `vw` (m/s). Returns (impact speed, r).
    pub(super) fn collide_wall(
        &mut self,
        i: usize,
        ny: f64,
        vw: f64,
        gap: f64,
    ) -> Result<(f64, f64), BedError> {
        self.guard_same_instant(i)?;
        if -gap > self.counters.max_overlap {
            self.counters.max_overlap = -gap;
        }
        self.guard_overlap(i, if ny > 0.0 { PISTON } else { LID }, -gap)?;
        // at contact exactly (the gap is roundoff)
        self.d[i].y -= gap * ny;
        let u = (-(self.d[i].vy - vw) * ny).max(0.0);
        let r = self.restitution(i, None, u, true)?;
        self.d[i].vy += (1.0 + r) * u * ny;
        if let Some(rt) = self.rough {
            // t = z × n = (−ny, 0)
            let tx = -ny;
            let gt = self.d[i].vx * tx - self.radius * self.w[i];
            let jt = -(1.0 + rt) * gt / 3.0;
            self.d[i].vx += jt * tx;
            self.w[i] -= 2.0 * jt / self.radius;
        }
        self.counters.collisions += 1;
        self.count[i] = self.count[i].wrapping_add(1);
        self.last_coll[i] = self.now;
        self.block_hits[i] += 1;
        Ok((u, r))
    }

    /// Executes the top event if it comes before `t_end` (s); returns false when the next event
    /// is later (and then nothing happened).
    pub(super) fn step(&mut self, t_end: f64) -> Result<bool, BedError> {
        let (i, t) = self.queue.top();
        if t > t_end || t == f64::INFINITY {
            // nothing left to happen before t_end (or ever: no sampling towards infinity)
            return Ok(false);
        }
        while self.next_sample <= t && self.next_sample <= t_end {
            self.sample(self.next_sample)?;
            self.next_sample += self.sample_dt;
        }
        self.now = t;
        match self.kind[i] {
            Kind::Disk => {
                let j = self.partner[i] as usize;
                if self.count[j] != self.pcount[i] {
                    self.counters.invalidated += 1;
                    self.predict(i);
                    return Ok(true);
                }
                self.collide_pair(i, j)?;
            }
            Kind::Lid => {
                self.ke_remove(i);
                self.advance(i);
                let gap = self.lid - self.radius - self.d[i].y;
                let (u, r) = self.collide_wall(i, -1.0, 0.0, gap)?;
                self.counters.lid_collisions += 1;
                if self.measuring {
                    self.window.lid_collisions += 1;
                    self.window.lid_impulse += self.cfg.mass * (1.0 + r) * u;
                    self.window.current.lid_collisions += 1;
                    self.window.current.lid_impulse += self.cfg.mass * (1.0 + r) * u;
                }
                self.ke_add(i);
                self.last_partner[i] = LID;
                self.record(Kind::Lid, i, NONE, u, r);
                self.predict(i);
            }
            Kind::Piston => {
                self.ke_remove(i);
                self.advance(i);
                let p = self.piston.state(t);
                let gap = self.d[i].y - self.radius - p.z;
                let (u, r) = self.collide_wall(i, 1.0, p.v, gap)?;
                self.counters.piston_collisions += 1;
                if self.measuring {
                    let j = self.cfg.mass * (1.0 + r) * u;
                    self.window.piston_impulse += j;
                    self.window.current.piston_impulse += j;
                }
                self.maybe_ride(i, r * u);
                self.ke_add(i);
                self.last_partner[i] = PISTON;
                self.record(Kind::Piston, i, NONE, u, r);
                self.predict(i);
            }
            k @ (Kind::CellRight | Kind::CellLeft | Kind::CellUp | Kind::CellDown) => {
                self.advance(i);
                let nx = self.cells.nx;
                let (cx, cy) = self.cells.col_row[i];
                let (mut cx, mut cy) = (cx as usize, cy as usize);
                match k {
                    Kind::CellRight => {
                        cx += 1;
                        if cx == nx {
                            cx = 0;
                            self.d[i].x -= self.width;
                        }
                    }
                    Kind::CellLeft => {
                        if cx == 0 {
                            cx = nx - 1;
                            self.d[i].x += self.width;
                        } else {
                            cx -= 1;
                        }
                    }
                    Kind::CellUp => cy += 1,
                    _ => cy -= 1,
                }
                self.cells.moveto_xy(i, cx, cy);
                self.counters.cell_crossings += 1;
                self.record(k, i, NONE, 0.0, 0.0);
                let scope = if !self.cache_valid(i) {
                    Scope::All
                } else {
                    match k {
                        Kind::CellRight => Scope::Col(1),
                        Kind::CellLeft => Scope::Col(-1),
                        Kind::CellUp => Scope::Row(1),
                        _ => Scope::Row(-1),
                    }
                };
                self.predict_scope(i, scope);
            }
            Kind::Horizon => {
                self.record(Kind::Horizon, i, NONE, 0.0, 0.0);
                if self.ride[i] != FREE {
                    self.ke_remove(i);
                    self.ride_on(i);
                    self.ke_add(i);
                }
                self.predict(i);
            }
            Kind::Never => return Ok(false),
        }
        self.counters.events += 1;
        self.block_events += 1;
        if self.block_events >= self.block_len {
            self.check_rate()?;
        }
        Ok(true)
    }

    /// Runs until time `t_end` (s); all disks are then brought to `t_end`. `progress` is called
    /// now and then with the current time.
    pub fn run_until(&mut self, t_end: f64, progress: &mut dyn FnMut(f64)) -> Result<(), BedError> {
        let mut k = 0u32;
        while self.step(t_end)? {
            k = k.wrapping_add(1);
            if k % 65_536 == 0 {
                progress(self.now);
            }
        }
        while self.next_sample <= t_end {
            self.sample(self.next_sample)?;
            self.next_sample += self.sample_dt;
        }
        if t_end > self.now {
            self.now = t_end;
        }
        progress(self.now);
        Ok(())
    }

    /// Runs `events` events (or until nothing is left to happen).
    pub fn run_events(&mut self, events: u64) -> Result<(), BedError> {
        let target = self.counters.events + events;
        while self.counters.events < target {
            if !self.step(f64::INFINITY)? {
                break;
            }
        }
        Ok(())
    }
}

/// The error of a restitution `r` outside [0, 1] at impact speed `u` (m/s) (out of the event
/// loop's way).
#[cold]
#[inline(never)]
fn out_of_range(r: f64, u: f64) -> BedError {
    BedError::Law(dashpot_sdk::LawError::new(
        dashpot_sdk::ErrorKind::NonFinite,
        format!("the law returned r = {r} at impact speed {u:e} m/s; a bed needs r in [0, 1]"),
    ))
}
