//! The event-driven engine.
//!
//! Split by concern: [`config`] (the parameters), [`predict`] (each disk's next event),
//! [`execute`] (the event loop and the collision rules), [`guards`] (what stops a run that went
//! wrong: collapse, missed contacts, overlap), [`sampling`] (observables and their standard
//! errors), [`riding`] (disks at rest on the piston).
//!
//! Each disk keeps its own clock: its position and velocity are stored at the time `tl` of its
//! last event and evaluated on demand (free flight under gravity). Each disk has exactly one
//! pending event (the earliest of: a collision with a disk of its own or a neighbouring cell,
//! the lid, the piston, leaving its cell); the disks' event times live in a tournament tree.
//! A disk–disk event remembers the partner's collision counter when it was predicted; when it
//! reaches the top of the queue with a changed counter the partner has moved on, and the disk is
//! predicted again instead (the re-check of the top event). A pair that has just collided is
//! never made to collide again at the same instant (the ping-pong guard), and a run whose event
//! rate explodes in simulated time stops with an error naming the time and the disks.

mod config;
mod execute;
mod guards;
mod predict;
mod sampling;

pub use config::BedConfig;
pub use sampling::{batch_stderr, Batch, BedReport, Counters, TraceRow, Window, SAMPLES_PER_PERIOD};

use super::cells::{Cells, NONE};
use super::events::Tournament;
use super::{BedError, Laws, Restitution};
use crate::piston::Piston;
use serde::Serialize;

/// The kind of a pending or executed event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[repr(u8)]
pub enum Kind {
    /// Collision with another disk.
    Disk,
    /// Collision with the lid.
    Lid,
    /// Collision with the piston.
    Piston,
    /// Crossing into the cell on the right (+x).
    CellRight,
    /// Crossing into the cell on the left (−x).
    CellLeft,
    /// Crossing into the cell above.
    CellUp,
    /// Crossing into the cell below.
    CellDown,
    /// End of the window over which the piston was searched: predict again.
    Horizon,
    /// Nothing ahead.
    Never,
}

/// One executed event, when the log is on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EventRecord {
    /// Time (s).
    pub t: f64,
    /// What happened.
    pub kind: Kind,
    /// The disk.
    pub i: u32,
    /// The partner disk (u32::MAX if none).
    pub j: u32,
    /// The normal impact speed (m/s) of a collision, 0 otherwise.
    pub speed: f64,
    /// The restitution applied (1 when the TC model fired), 0 for non-collisions.
    pub r: f64,
}
/// The simulation.
pub struct Bed<R> {
    cfg: BedConfig,
    laws: Laws<R>,
    n: usize,
    radius: f64,
    sigma2: f64,
    g: f64,
    lid: f64,
    piston: Piston,
    /// Height above which the piston can never touch a disk: A/2 + R.
    piston_reach: f64,
    width: f64,
    half_width: f64,
    rough: Option<f64>,
    tc: f64,
    // disk state at its own clock `tl`, packed so that a neighbour is one cache line
    d: Vec<DiskState>,
    w: Vec<f64>,
    /// The piston piece a disk rides on (at rest on the piston), or FREE.
    ride: Vec<i64>,
    /// When each ride began (s) and the piston's velocity then (m/s): the impulse it took.
    ride_from: Vec<(f64, f64)>,
    samples_taken: u64,
    /// Running sums for the kinetic energy samples (see [`sampling`]).
    ke: sampling::KeSums,
    count: Vec<u32>,
    last_coll: Vec<f64>,
    last_partner: Vec<u32>,
    same_instant: Vec<u32>,
    // cached best non-crossing event of each disk (absolute time)
    cache_t: Vec<f64>,
    cache_kind: Vec<Kind>,
    cache_partner: Vec<u32>,
    cache_pcount: Vec<u32>,
    // pending event of each disk
    kind: Vec<Kind>,
    partner: Vec<u32>,
    pcount: Vec<u32>,
    queue: Tournament,
    cells: Cells,
    now: f64,
    /// Counters over the whole run.
    pub counters: Counters,
    /// The measuring window.
    pub window: Window,
    measuring: bool,
    next_sample: f64,
    sample_dt: f64,
    log: Option<Vec<EventRecord>>,
    trace: Option<Vec<TraceRow>>,
    // explosion guard
    block_start_t: f64,
    block_events: u64,
    block_len: u64,
    block_hits: Vec<u32>,
}
/// A tiny seeded generator (SplitMix64), enough for initial states.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
impl<R: Restitution> Bed<R> {
    /// A bed with disks on a loose lattice above the piston (at rest at its lowest position),
    /// random velocities with components uniform in ±`initial_speed`, from `cfg.seed`.
    pub fn new(cfg: BedConfig, laws: Laws<R>) -> Result<Bed<R>, BedError> {
        cfg.validate()?;
        let n = cfg.disks();
        let d = cfg.diameter;
        let radius = 0.5 * d;
        let piston = Piston::new(cfg.amplitude, cfg.freq);
        let lid = cfg.lid();
        let bottom = -0.5 * cfg.amplitude;
        // lattice: spacing 1.05 d across, rows 1.05 d apart
        let per_row = (cfg.width / (1.05 * d)).floor() as usize;
        let rows = n.div_ceil(per_row.max(1));
        let top_needed = bottom + 1.05 * d * rows as f64 + 0.05 * d;
        if per_row == 0 || top_needed > lid {
            return Err(BedError::Invalid(format!(
                "the box is too small for the disks: N = {n} disks of d = {d} m need {rows} rows \
                 of {per_row} ({:.4} m) between the piston's lowest position and the lid, but \
                 there are {:.4} m; raise --headroom or --width, or lower --layers",
                top_needed - bottom,
                lid - bottom
            )));
        }
        // (before the disks are made: a bed past the machine's memory is refused)
        let need = crate::budget::bed_need(n as f64, 1.0, 0.0);
        crate::budget::check_memory(
            &format!("the bed of layers n = {} (N = {n} disks)", cfg.layers),
            &need,
            "lower --layers (or --width)",
        )
        .map_err(|e| BedError::Invalid(e.0))?;
        let mut rng = SplitMix64(cfg.seed ^ 0x6a09_e667_f3bc_c909);
        let spacing = cfg.width / per_row as f64;
        let (mut x, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut vx, mut vy) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for k in 0..n {
            let (row, col) = (k / per_row, k % per_row);
            let jitter = (spacing - 1.01 * d).max(0.0);
            x.push(col as f64 * spacing + 0.505 * d + jitter * rng.uniform());
            y.push(bottom + radius + 0.05 * d + 1.05 * d * row as f64);
            vx.push(cfg.initial_speed * (2.0 * rng.uniform() - 1.0));
            vy.push(cfg.initial_speed * (2.0 * rng.uniform() - 1.0));
        }
        let cells = Cells::new(cfg.width, bottom, lid, d * 1.0000001, n);
        let sample_dt = 1.0 / (cfg.freq * SAMPLES_PER_PERIOD as f64);
        let block_len = 200_000 + 2_000 * n as u64;
        let disks: Vec<DiskState> = (0..n)
            .map(|k| DiskState {
                x: x[k],
                y: y[k],
                vx: vx[k],
                vy: vy[k],
                tl: 0.0,
                ay: -cfg.gravity,
            })
            .collect();
        let mut bed = Bed {
            cfg,
            laws,
            n,
            radius,
            sigma2: d * d,
            g: cfg.gravity,
            lid,
            piston,
            piston_reach: piston.top() + radius,
            width: cfg.width,
            half_width: 0.5 * cfg.width,
            rough: cfg.tangential,
            tc: cfg.tc.unwrap_or(-1.0),
            d: disks,
            w: vec![0.0; n],
            ride: vec![FREE; n],
            ride_from: vec![(0.0, 0.0); n],
            samples_taken: 0,
            ke: sampling::KeSums::default(),
            count: vec![0; n],
            last_coll: vec![f64::NEG_INFINITY; n],
            last_partner: vec![NONE; n],
            same_instant: vec![0; n],
            cache_t: vec![f64::INFINITY; n],
            cache_kind: vec![Kind::Never; n],
            cache_partner: vec![NONE; n],
            cache_pcount: vec![0; n],
            kind: vec![Kind::Never; n],
            partner: vec![NONE; n],
            pcount: vec![0; n],
            queue: Tournament::new(n),
            cells,
            now: 0.0,
            counters: Counters::default(),
            window: Window::default(),
            measuring: false,
            next_sample: 0.0,
            sample_dt,
            log: None,
            trace: None,
            block_start_t: 0.0,
            block_events: 0,
            block_len,
            block_hits: vec![0; n],
        };
        bed.check_cells()?;
        for i in 0..n {
            let c = bed.cells.locate(bed.d[i].x, bed.d[i].y);
            bed.cells.insert(i, c);
        }
        for i in 0..n {
            bed.predict(i);
        }
        bed.ke_recompute(0.0);
        Ok(bed)
    }

    pub(super) fn check_cells(&self) -> Result<(), BedError> {
        if self.cells.nx < 3 {
            return Err(BedError::Invalid(format!(
                "the box is too small: width L = {} m holds {} cells of one diameter; at least 3 needed",
                self.width, self.cells.nx
            )));
        }
        Ok(())
    }

    /// Places disks explicitly (positions (m), velocities (m/s)), replacing the initial state;
    /// for tests and special set-ups. Fails if a disk is outside the box or two overlap.
    pub fn set_state(&mut self, pos: &[(f64, f64)], vel: &[(f64, f64)]) -> Result<(), BedError> {
        if pos.len() != self.n || vel.len() != self.n {
            return Err(BedError::Invalid(format!(
                "set_state: {} positions and {} velocities for {} disks",
                pos.len(),
                vel.len(),
                self.n
            )));
        }
        let z = self.piston.state(self.now).z;
        for (k, &(px, py)) in pos.iter().enumerate() {
            if !(0.0..self.width).contains(&px) || py < z + self.radius || py > self.lid - self.radius {
                return Err(BedError::Invalid(format!(
                    "set_state: disk {k} at ({px}, {py}) m is outside the box"
                )));
            }
            for (l, &(qx, qy)) in pos.iter().enumerate().take(k) {
                let dx = self.wrap(px - qx);
                if dx * dx + (py - qy).powi(2) < self.sigma2 {
                    return Err(BedError::Invalid(format!("set_state: disks {l} and {k} overlap")));
                }
            }
        }
        for i in 0..self.n {
            self.cells.remove(i);
            (self.d[i].x, self.d[i].y) = pos[i];
            (self.d[i].vx, self.d[i].vy) = vel[i];
            self.w[i] = 0.0;
            self.d[i].tl = self.now;
            self.d[i].ay = -self.g;
            self.ride[i] = FREE;
            let c = self.cells.locate(self.d[i].x, self.d[i].y);
            self.cells.insert(i, c);
        }
        for i in 0..self.n {
            self.predict(i);
        }
        self.ke_recompute(self.now);
        Ok(())
    }

    /// Keeps a log of every executed event (for tests of determinism and of closed forms).
    pub fn enable_log(&mut self) {
        self.log = Some(Vec::new());
    }

    /// The event log (empty unless [`Bed::enable_log`] was called).
    pub fn log(&self) -> &[EventRecord] {
        self.log.as_deref().unwrap_or(&[])
    }

    /// Keeps the sampled time series (`--trace`).
    pub fn enable_trace(&mut self) {
        self.trace = Some(Vec::new());
    }

    /// The sampled time series.
    pub fn trace(&self) -> &[TraceRow] {
        self.trace.as_deref().unwrap_or(&[])
    }

    /// Number of disks.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True if there are no disks (never, for a validated configuration).
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The current time (s).
    pub fn now(&self) -> f64 {
        self.now
    }

    /// The configuration.
    pub fn config(&self) -> &BedConfig {
        &self.cfg
    }

    /// The lid height (m).
    pub fn lid(&self) -> f64 {
        self.lid
    }

    /// The piston.
    pub fn piston(&self) -> &Piston {
        &self.piston
    }

    #[inline]
    pub(super) fn wrap(&self, dx: f64) -> f64 {
        if dx > self.half_width {
            dx - self.width
        } else if dx < -self.half_width {
            dx + self.width
        } else {
            dx
        }
    }

    /// Position (m), velocity (m/s) of disk `i` at time `t` (s), from its own clock.
    #[inline]
    pub fn state_at(&self, i: usize, t: f64) -> (f64, f64, f64, f64) {
        let dt = t - self.d[i].tl;
        (
            self.d[i].x + self.d[i].vx * dt,
            self.d[i].y + (self.d[i].vy + 0.5 * self.d[i].ay * dt) * dt,
            self.d[i].vx,
            self.d[i].vy + self.d[i].ay * dt,
        )
    }

    /// Whether disk `i` is at rest on the piston, riding with it (see [`Bed`]'s guards).
    pub fn riding(&self, i: usize) -> bool {
        self.ride[i] != FREE
    }

    /// Angular velocity of disk `i` (rad/s, counter-clockwise).
    pub fn spin(&self, i: usize) -> f64 {
        self.w[i]
    }

    /// Total kinetic energy (J) at the current time, translational and rotational.
    pub fn kinetic_energy(&self) -> f64 {
        let m = self.cfg.mass;
        let inertia = 0.5 * m * self.radius * self.radius;
        (0..self.n)
            .map(|i| {
                let (_, _, vx, vy) = self.state_at(i, self.now);
                0.5 * m * (vx * vx + vy * vy) + 0.5 * inertia * self.w[i] * self.w[i]
            })
            .sum()
    }

    /// Positions (m) of all disks at the current time, x wrapped into [0, L).
    pub fn positions(&self) -> Vec<(f64, f64)> {
        (0..self.n)
            .map(|i| {
                let (x, y, _, _) = self.state_at(i, self.now);
                (x.rem_euclid(self.width), y)
            })
            .collect()
    }

    /// The largest overlap (m) between any two disks, or a disk and a wall, now (O(N²); tests).
    pub fn overlap_now(&self) -> f64 {
        let p = self.positions();
        let z = self.piston.state(self.now).z;
        let mut worst: f64 = 0.0;
        for i in 0..self.n {
            worst = worst.max(z + self.radius - p[i].1);
            worst = worst.max(p[i].1 + self.radius - self.lid);
            for j in 0..i {
                let dx = self.wrap(p[i].0 - p[j].0);
                let dy = p[i].1 - p[j].1;
                worst = worst.max(self.cfg.diameter - (dx * dx + dy * dy).sqrt());
            }
        }
        worst
    }
}

/// A disk's position (m), velocity (m/s) and acceleration at its own clock `tl` (s).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
struct DiskState {
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    tl: f64,
    /// Vertical acceleration (m/s²): −g in free flight, the piston's while riding on it.
    ay: f64,
}

/// `ride[i]` of a disk in free flight.
const FREE: i64 = i64::MIN;
#[cfg(test)]
mod tests {
    use super::*;
    use crate::bed::Compiled;

    /// r = const, compiled in.
    struct Fixed(f64);
    impl dashpot_sdk::BoundRestitution for Fixed {
        fn restitution(&self, _speed: f64) -> f64 {
            self.0
        }
    }

    fn dropped(r: f64) -> Bed<Compiled<Fixed>> {
        let cfg = BedConfig {
            amplitude: 0.0,
            headroom: 0.2,
            ..BedConfig::paper(0.01, 20.0)
        };
        let laws = Laws {
            disk: Compiled(Fixed(r)),
            wall: Compiled(Fixed(r)),
        };
        let mut bed = Bed::new(cfg, laws).unwrap();
        bed.set_state(&[(0.1, 0.051)], &[(0.0, 0.0)]).unwrap();
        bed
    }

    #[test]
    fn a_disk_on_a_disk_at_rest_on_the_floor_collapses_and_a_guard_stops_it() {
        // disk 1 dropped onto disk 0, which rests on a fixed floor, r = 0.9: the bounces of 1
        // on 0 accumulate (a two-disk inelastic collapse, which riding does not resolve); the
        // run stops with an error naming a disk and the remedy, before any overlap
        let cfg = BedConfig {
            amplitude: 0.0,
            headroom: 0.2,
            ..BedConfig::paper(0.02, 20.0)
        };
        let laws = Laws {
            disk: Compiled(Fixed(0.9)),
            wall: Compiled(Fixed(0.9)),
        };
        let mut bed = Bed::new(cfg, laws).unwrap();
        bed.block_len = 1_000;
        bed.set_state(&[(0.1, 0.001), (0.1, 0.01)], &[(0.0, 0.0), (0.0, 0.0)])
            .unwrap();
        let err = bed.run_until(5.0, &mut |_| {}).unwrap_err().to_string();
        assert!(err.contains("disk ") && err.contains("--tc"), "{err}");
        assert!(
            bed.counters.max_overlap <= 1e-9 * 0.002,
            "{:e}",
            bed.counters.max_overlap
        );
        assert!(bed.counters.rides > 0);
    }

    /// Runs `bed` to 600 instants between events and checks the O(1) kinetic-energy sums
    /// against the sum over the disks there, to roundoff of the largest sum seen (the sums
    /// carry the roundoff of the terms they took out, however small what remains).
    fn check_ke_sums(mut bed: Bed<Compiled<Fixed>>, freq: f64) -> Bed<Compiled<Fixed>> {
        let (mut t, mut peak) = (0.0, 0.0f64);
        for k in 0..600 {
            t += (0.37 + (k % 7) as f64 * 0.11) / (SAMPLES_PER_PERIOD as f64 * freq);
            bed.run_until(t, &mut |_| {}).unwrap();
            let direct: f64 = (0..bed.n)
                .map(|i| {
                    let (_, _, vx, vy) = bed.state_at(i, t);
                    vx * vx + vy * vy
                })
                .sum();
            peak = peak.max(direct);
            let s = t - bed.ke.t0;
            let sums = bed.ke.s0 + s * (2.0 * bed.ke.s1 + s * bed.ke.s2);
            assert!(
                (sums - direct).abs() <= 1e-12 * peak,
                "t = {t}: {sums} against {direct}"
            );
        }
        bed
    }

    #[test]
    fn the_running_kinetic_energy_sums_equal_the_sum_over_the_disks() {
        // the vibrated bed (disk, lid and piston collisions), and a disk dropped with r = 0.5
        // that chatters and rides on the floor (rides, re-anchored at each piece)
        let laws = Laws {
            disk: Compiled(Fixed(0.9)),
            wall: Compiled(Fixed(0.9)),
        };
        let bed = Bed::new(BedConfig::paper(3.0, 30.0), laws).unwrap();
        let bed = check_ke_sums(bed, 30.0);
        assert!(bed.counters.disk_collisions > 1000 && bed.counters.piston_collisions > 10);
        let bed = check_ke_sums(dropped(0.5), 20.0);
        assert!(bed.counters.rides > 0, "no ride: the riding path is untested");
    }

    #[test]
    fn no_pair_can_touch_before_the_next_event_of_either_disk() {
        // the cells, the list of cells a prediction visits and the cache of each disk's best
        // other event must never let a contact through: at any instant, every pair of disks
        // that will touch (in free flight, by the closed form over all N² pairs) does so no
        // earlier than the next pending event of one of the two, which predicts it or comes
        // first and predicts again
        let laws = Laws {
            disk: Compiled(Fixed(0.95)),
            wall: Compiled(Fixed(0.95)),
        };
        let mut bed = Bed::new(BedConfig::paper(3.0, 30.0), laws).unwrap();
        let mut checked = 0;
        for _ in 0..100 {
            bed.run_events(499).unwrap();
            let now = bed.now;
            for i in 0..bed.n {
                let (xi, yi, vxi, vyi) = bed.state_at(i, now);
                for j in 0..i {
                    if bed.d[i].ay != bed.d[j].ay {
                        continue; // one rides on the piston: not a free-flight pair
                    }
                    let (xj, yj, vxj, vyj) = bed.state_at(j, now);
                    let rx = bed.wrap(xi - xj);
                    let hit = crate::bed::events::pair_contact(rx, yi - yj, vxi - vxj, vyi - vyj, bed.sigma2);
                    if let Some(t) = hit {
                        let next = bed.queue.key(i).min(bed.queue.key(j));
                        assert!(
                            now + t >= next - 1e-12,
                            "disks {i} and {j} touch at {} before {next}",
                            now + t
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(
            checked > 10_000 && bed.counters.cell_crossings > 20_000,
            "{checked}"
        );
    }

    #[test]
    fn a_law_outside_zero_one_is_refused() {
        let mut bed = dropped(1.2);
        let err = bed.run_until(1.0, &mut |_| {}).unwrap_err().to_string();
        assert!(err.contains("r = 1.2") && err.contains("[0, 1]"), "{err}");
    }
}
