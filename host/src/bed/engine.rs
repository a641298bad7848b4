//! The event-driven engine.
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

use super::cells::{Cells, NONE};
use super::events::{first_contact, pair_contact, Tournament};
use super::piston::Piston;
use super::{BedError, Laws, Restitution};
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

/// The parameters of a bed. Defaults ([`BedConfig::paper`]) are McNamara & Falcon's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BedConfig {
    /// Number of layers n = N d / L (dimensionless); N = round(n L/d) disks.
    pub layers: f64,
    /// Piston frequency f (Hz).
    pub freq: f64,
    /// Gravity g (m/s², pointing down; 0 for none).
    pub gravity: f64,
    /// Piston amplitude A, peak to peak (m); 0 is a fixed floor.
    pub amplitude: f64,
    /// Box width L (m), periodic.
    pub width: f64,
    /// Disk diameter d (m).
    pub diameter: f64,
    /// Disk mass m (kg).
    pub mass: f64,
    /// Headroom h − h0 (m): the lid is at A/2 + n d + headroom.
    pub headroom: f64,
    /// Tangential restitution r_t ∈ [−1, 1] (rough disks that rotate), or None: smooth disks.
    pub tangential: Option<f64>,
    /// The TC model's time t_c (s): a collision of a disk that collided less than t_c ago is
    /// elastic. None: off.
    pub tc: Option<f64>,
    /// Seed of the initial state.
    pub seed: u64,
    /// Largest initial velocity component (m/s).
    pub initial_speed: f64,
}

impl BedConfig {
    /// The paper's bed with `layers` layers at frequency `freq` (Hz): d = 2 mm,
    /// m = 3.27e-5 kg, L = 0.2 m, A = 25 mm, h − h0 = 15 mm, g = 9.8 m/s², smooth disks, no TC.
    pub fn paper(layers: f64, freq: f64) -> BedConfig {
        BedConfig {
            layers,
            freq,
            gravity: 9.8,
            amplitude: 0.025,
            width: 0.2,
            diameter: 0.002,
            mass: 3.27e-5,
            headroom: 0.015,
            tangential: None,
            tc: None,
            seed: 1,
            initial_speed: 0.5,
        }
    }

    /// Number of disks N = round(n L / d).
    pub fn disks(&self) -> usize {
        (self.layers * self.width / self.diameter).round().max(0.0) as usize
    }

    /// Height of the lid (m): A/2 + n d + (h − h0).
    pub fn lid(&self) -> f64 {
        0.5 * self.amplitude + self.layers * self.diameter + self.headroom
    }

    /// Checks every value; the message names the value and its valid range.
    pub fn validate(&self) -> Result<(), BedError> {
        let bad = |s: String| Err(BedError::Invalid(s));
        let fin = |name: &str, v: f64| -> Result<(), BedError> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(BedError::Invalid(format!("{name} = {v} is not a finite number")))
            }
        };
        for (n, v) in [
            ("layers", self.layers),
            ("freq", self.freq),
            ("gravity", self.gravity),
            ("amplitude", self.amplitude),
            ("width", self.width),
            ("diameter", self.diameter),
            ("mass", self.mass),
            ("headroom", self.headroom),
            ("initial speed", self.initial_speed),
        ] {
            fin(n, v)?;
        }
        if self.layers <= 0.0 {
            return bad(format!(
                "layers n = {} is out of range: n must be > 0",
                self.layers
            ));
        }
        if self.freq <= 0.0 {
            return bad(format!(
                "frequency f = {} Hz is out of range: f must be > 0",
                self.freq
            ));
        }
        if self.gravity < 0.0 {
            return bad(format!(
                "gravity g = {} m/s² is out of range: g must be >= 0",
                self.gravity
            ));
        }
        if self.amplitude < 0.0 {
            return bad(format!(
                "amplitude A = {} m is out of range: A must be >= 0",
                self.amplitude
            ));
        }
        if self.diameter <= 0.0 {
            return bad(format!(
                "diameter d = {} m is out of range: d must be > 0",
                self.diameter
            ));
        }
        if self.mass <= 0.0 {
            return bad(format!(
                "mass m = {} kg is out of range: m must be > 0",
                self.mass
            ));
        }
        if self.width < 3.0 * self.diameter {
            return bad(format!(
                "the box is too small: width L = {} m must be at least 3 diameters ({} m)",
                self.width,
                3.0 * self.diameter
            ));
        }
        if self.disks() == 0 {
            return bad(format!(
                "layers n = {} gives no disk (N = n L/d = {:.3}); raise n",
                self.layers,
                self.layers * self.width / self.diameter
            ));
        }
        if self.layers * self.diameter + self.headroom < self.diameter {
            return bad(format!(
                "the box is too small: the gap between the piston at its highest and the lid, \
                 n d + (h - h0) = {} m, must be at least one diameter ({} m); raise --headroom",
                self.layers * self.diameter + self.headroom,
                self.diameter
            ));
        }
        if let Some(rt) = self.tangential {
            if !(-1.0..=1.0).contains(&rt) {
                return bad(format!(
                    "tangential restitution r_t = {rt} is out of range: r_t must be in [-1, 1]"
                ));
            }
        }
        if let Some(tc) = self.tc {
            if !(tc.is_finite() && tc >= 0.0) {
                return bad(format!("TC time t_c = {tc} s is out of range: t_c must be >= 0"));
            }
        }
        if self.initial_speed < 0.0 {
            return bad(format!(
                "initial speed = {} m/s is out of range: must be >= 0",
                self.initial_speed
            ));
        }
        Ok(())
    }
}

/// Counters and running sums of a run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Counters {
    /// Executed events (collisions, cell crossings, horizon re-predictions).
    pub events: u64,
    /// Collisions: disk–disk + disk–lid + disk–piston.
    pub collisions: u64,
    /// Disk–disk collisions.
    pub disk_collisions: u64,
    /// Disk–lid collisions.
    pub lid_collisions: u64,
    /// Disk–piston collisions.
    pub piston_collisions: u64,
    /// Cell crossings.
    pub cell_crossings: u64,
    /// Events found stale at the top of the queue (partner moved on) and predicted again.
    pub invalidated: u64,
    /// Collisions made elastic by the TC model.
    pub tc_firings: u64,
    /// Largest overlap seen at any collision (m).
    pub max_overlap: f64,
}

/// Averages over the measuring window, accumulated after the transient.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Window {
    /// Start of the window (s).
    pub start: f64,
    /// Lid collisions in the window.
    pub lid_collisions: u64,
    /// Sum of the impulses given to the lid (N·s).
    pub lid_impulse: f64,
    /// Sum of the sampled mean kinetic energies per disk (J).
    pub ke_sum: f64,
    /// Number of kinetic energy samples.
    pub ke_samples: u64,
}

/// The results of a run, averaged after the transient.
#[derive(Debug, Clone, Serialize)]
pub struct BedReport {
    /// The configuration.
    pub config: BedConfig,
    /// Number of disks N.
    pub disks: usize,
    /// Lid height (m).
    pub lid: f64,
    /// Piston peak speed V = 4Af (m/s).
    pub piston_speed: f64,
    /// Measured time (s) after the transient.
    pub measured_time: f64,
    /// Lid pressure P = Nc ΔI / L (N/m).
    pub pressure: f64,
    /// Lid collision frequency Nc (1/s).
    pub lid_collision_rate: f64,
    /// Mean impulse per lid collision ΔI (N·s).
    pub mean_impulse: f64,
    /// Granular temperature T: time-averaged translational kinetic energy per disk (J).
    pub temperature: f64,
    /// Events executed over the whole run (collisions and cell crossings).
    pub events: u64,
    /// Collisions over the whole run (disk–disk, lid, piston).
    pub collisions: u64,
    /// Events per second of wall time.
    pub events_per_second: f64,
    /// Collisions per second of wall time.
    pub collisions_per_second: f64,
    /// Wall time (s).
    pub wall_seconds: f64,
    /// Wall seconds per simulated second.
    pub wall_per_simulated_second: f64,
    /// Collisions made elastic by the TC model.
    pub tc_firings: u64,
    /// Share of all collisions made elastic by the TC model.
    pub tc_share: f64,
    /// Largest overlap ever seen at a collision (m).
    pub max_overlap: f64,
    /// All counters.
    pub counters: Counters,
}

/// How many kinetic energy samples per piston period.
pub const SAMPLES_PER_PERIOD: usize = 64;

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

/// One sample of the time series (`--trace`).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TraceRow {
    /// Time (s).
    pub t: f64,
    /// Piston height (m).
    pub piston_z: f64,
    /// Mean translational kinetic energy per disk (J).
    pub kinetic_energy: f64,
    /// Mean disk height (m).
    pub mean_height: f64,
    /// Lid collisions since the start of the window.
    pub lid_collisions: u64,
    /// Impulse given to the lid since the start of the window (N·s).
    pub lid_impulse: f64,
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
        Ok(bed)
    }

    fn check_cells(&self) -> Result<(), BedError> {
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
            let c = self.cells.locate(self.d[i].x, self.d[i].y);
            self.cells.insert(i, c);
        }
        for i in 0..self.n {
            self.predict(i);
        }
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
    fn wrap(&self, dx: f64) -> f64 {
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
            self.d[i].y + (self.d[i].vy - 0.5 * self.g * dt) * dt,
            self.d[i].vx,
            self.d[i].vy - self.g * dt,
        )
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

    // ---------------------------------------------------------------- prediction

    /// Predicts the next event of disk `i` from the current time, scanning everything.
    fn predict(&mut self, i: usize) {
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
    fn predict_scope(&mut self, i: usize, scope: Scope) {
        let now = self.now;
        let (xi, yi, vxi, vyi) = self.state_at(i, now);
        let g = self.g;
        let c = self.cells.cell[i] as usize;
        let (nx, ny) = (self.cells.nx, self.cells.ny);
        let (cx, cy) = (c % nx, c / nx);
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
        if cy + 1 == ny && matches!(scope, Scope::All | Scope::Row(1)) {
            if let Some(t) = first_contact(self.lid - self.radius - yi, -vyi, g) {
                if t < best {
                    best = t;
                    kind = Kind::Lid;
                    partner = NONE;
                }
            }
        }
        // the piston, piece by piece, only from rows it can reach
        if yb < self.piston_reach && matches!(scope, Scope::All | Scope::Row(-1)) {
            let k0 = self.piston.piece(now);
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
        // disks of this and the eight neighbouring cells (or of the three new ones)
        let (rows, cols) = match scope {
            Scope::All => (-1i64..=1, -1i64..=1),
            Scope::Row(d) => (d..=d, -1..=1),
            Scope::Col(d) => (-1..=1, d..=d),
        };
        for dy in rows {
            let ry = cy as i64 + dy;
            if ry < 0 || ry >= ny as i64 {
                continue;
            }
            for dx in cols.clone() {
                let rx = (cx as i64 + dx).rem_euclid(nx as i64) as usize;
                let mut j = self.cells.head(ry as usize * nx + rx);
                while j != NONE {
                    let ju = j as usize;
                    if ju != i {
                        let dtj = now - self.d[ju].tl;
                        let xj = self.d[ju].x + self.d[ju].vx * dtj;
                        let yj = self.d[ju].y + (self.d[ju].vy - 0.5 * g * dtj) * dtj;
                        let vyj = self.d[ju].vy - g * dtj;
                        let rxij = self.wrap(xi - xj);
                        if let Some(t) =
                            pair_contact(rxij, yi - yj, vxi - self.d[ju].vx, vyi - vyj, self.sigma2)
                        {
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
        if cy + 1 < ny {
            if let Some(t) = first_contact(yb + self.cells.wy - yi, -vyi, g) {
                if t < bx {
                    bx = t;
                    kx = Kind::CellUp;
                }
            }
        }
        if cy > 0 {
            if let Some(t) = first_contact(yi - yb, vyi, -g) {
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
    fn cache_valid(&self, i: usize) -> bool {
        self.cache_kind[i] != Kind::Disk || self.count[self.cache_partner[i] as usize] == self.cache_pcount[i]
    }

    /// The ping-pong guard: a disk colliding again at the very instant of its last collision
    /// (roundoff can make a pair that just separated look approaching) is allowed a few times,
    /// then the run stops with an error naming the time and the disk, instead of looping.
    fn guard_same_instant(&mut self, i: usize) -> Result<(), BedError> {
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

    /// Moves disk `i`'s clock to now.
    #[inline]
    fn advance(&mut self, i: usize) {
        let (x, y, vx, vy) = self.state_at(i, self.now);
        self.d[i].x = x;
        self.d[i].y = y;
        self.d[i].vx = vx;
        self.d[i].vy = vy;
        self.d[i].tl = self.now;
    }

    // ---------------------------------------------------------------- execution

    /// The restitution for a collision of `i` (and `j`, for a pair) at impact speed `u` (m/s),
    /// after the TC model.
    fn restitution(&mut self, i: usize, j: Option<usize>, u: f64, wall: bool) -> Result<f64, BedError> {
        let recent = |k: usize| self.now - self.last_coll[k] < self.tc;
        if self.tc >= 0.0 && (recent(i) || j.is_some_and(recent)) {
            self.counters.tc_firings += 1;
            return Ok(1.0);
        }
        let law = if wall { &self.laws.wall } else { &self.laws.disk };
        let r = law.r(u)?;
        if !(0.0..=1.0).contains(&r) {
            return Err(BedError::Law(dashpot_sdk::LawError::new(
                dashpot_sdk::ErrorKind::NonFinite,
                format!("the law returned r = {r} at impact speed {u:e} m/s; a bed needs r in [0, 1]"),
            )));
        }
        Ok(r)
    }

    fn record(&mut self, kind: Kind, i: usize, j: u32, speed: f64, r: f64) {
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

    fn collide_pair(&mut self, i: usize, j: usize) -> Result<(), BedError> {
        self.guard_same_instant(i)?;
        self.guard_same_instant(j)?;
        self.advance(i);
        self.advance(j);
        let dx = self.wrap(self.d[i].x - self.d[j].x);
        let dy = self.d[i].y - self.d[j].y;
        let dist = (dx * dx + dy * dy).sqrt();
        let overlap = self.cfg.diameter - dist;
        if overlap > self.counters.max_overlap {
            self.counters.max_overlap = overlap;
        }
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
        self.record(Kind::Disk, i, j as u32, u, r);
        self.predict(i);
        self.predict(j);
        Ok(())
    }

    /// Disk `i` against a wall of normal `ny` (+1: the piston below, −1: the lid above) moving
    /// at vertical velocity `vw` (m/s). Returns (impact speed, r).
    fn collide_wall(&mut self, i: usize, ny: f64, vw: f64, gap: f64) -> Result<(f64, f64), BedError> {
        self.guard_same_instant(i)?;
        if -gap > self.counters.max_overlap {
            self.counters.max_overlap = -gap;
        }
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
    fn step(&mut self, t_end: f64) -> Result<bool, BedError> {
        let (i, t) = self.queue.top();
        if t > t_end {
            return Ok(false);
        }
        while self.next_sample <= t && self.next_sample <= t_end {
            self.sample(self.next_sample);
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
                self.advance(i);
                let gap = self.lid - self.radius - self.d[i].y;
                let (u, r) = self.collide_wall(i, -1.0, 0.0, gap)?;
                self.counters.lid_collisions += 1;
                if self.measuring {
                    self.window.lid_collisions += 1;
                    self.window.lid_impulse += self.cfg.mass * (1.0 + r) * u;
                }
                self.last_partner[i] = LID;
                self.record(Kind::Lid, i, NONE, u, r);
                self.predict(i);
            }
            Kind::Piston => {
                self.advance(i);
                let p = self.piston.state(t);
                let gap = self.d[i].y - self.radius - p.z;
                let (u, r) = self.collide_wall(i, 1.0, p.v, gap)?;
                self.counters.piston_collisions += 1;
                self.last_partner[i] = PISTON;
                self.record(Kind::Piston, i, NONE, u, r);
                self.predict(i);
            }
            k @ (Kind::CellRight | Kind::CellLeft | Kind::CellUp | Kind::CellDown) => {
                self.advance(i);
                let nx = self.cells.nx;
                let c = self.cells.cell[i] as usize;
                let (mut cx, mut cy) = (c % nx, c / nx);
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
                self.cells.moveto(i, (cy * nx + cx) as u32);
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

    /// The explosion guard: `block_len` events within a simulated time so short that each disk
    /// would have more than 10⁹ events per simulated second.
    fn check_rate(&mut self) -> Result<(), BedError> {
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

    fn sample(&mut self, t: f64) {
        let mut ke = 0.0;
        let mut ym = 0.0;
        for i in 0..self.n {
            let (_, y, vx, vy) = self.state_at(i, t);
            ke += vx * vx + vy * vy;
            ym += y;
        }
        let ke = 0.5 * self.cfg.mass * ke / self.n as f64;
        if self.measuring {
            self.window.ke_sum += ke;
            self.window.ke_samples += 1;
        }
        if let Some(tr) = self.trace.as_mut() {
            tr.push(TraceRow {
                t,
                piston_z: self.piston.state(t).z,
                kinetic_energy: ke,
                mean_height: ym / self.n as f64,
                lid_collisions: self.window.lid_collisions,
                lid_impulse: self.window.lid_impulse,
            });
        }
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
            self.sample(self.next_sample);
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

    /// Starts the measuring window now.
    pub fn start_window(&mut self) {
        self.measuring = true;
        self.window = Window {
            start: self.now,
            ..Window::default()
        };
    }

    /// The paper's protocol: `transient` periods, then `cycles` periods of measurement; the
    /// run ends with the piston at its lowest position. `wall` is the wall-clock time to report
    /// (s) — measured by the caller around this call, or 0 to measure here.
    pub fn run_protocol(
        &mut self,
        transient: f64,
        cycles: f64,
        progress: &mut dyn FnMut(f64),
    ) -> Result<BedReport, BedError> {
        if !(transient >= 0.0 && transient.is_finite()) {
            return Err(BedError::Invalid(format!(
                "transient = {transient} periods is out of range: must be >= 0"
            )));
        }
        if !(cycles > 0.0 && cycles.is_finite()) {
            return Err(BedError::Invalid(format!(
                "cycles = {cycles} periods is out of range: must be > 0"
            )));
        }
        let clock = std::time::Instant::now();
        let period = 1.0 / self.cfg.freq;
        self.run_until(self.now + transient * period, progress)?;
        self.start_window();
        self.run_until(self.now + cycles * period, progress)?;
        Ok(self.report(clock.elapsed().as_secs_f64()))
    }

    /// The report of the measuring window, with `wall` seconds of wall time for the rates.
    pub fn report(&self, wall: f64) -> BedReport {
        let tm = self.now - self.window.start;
        let nc = if tm > 0.0 {
            self.window.lid_collisions as f64 / tm
        } else {
            0.0
        };
        let di = if self.window.lid_collisions > 0 {
            self.window.lid_impulse / self.window.lid_collisions as f64
        } else {
            0.0
        };
        let c = &self.counters;
        BedReport {
            config: self.cfg,
            disks: self.n,
            lid: self.lid,
            piston_speed: self.piston.peak_speed(),
            measured_time: tm,
            pressure: nc * di / self.width,
            lid_collision_rate: nc,
            mean_impulse: di,
            temperature: if self.window.ke_samples > 0 {
                self.window.ke_sum / self.window.ke_samples as f64
            } else {
                0.0
            },
            events: c.events,
            collisions: c.collisions,
            events_per_second: c.events as f64 / wall.max(1e-12),
            collisions_per_second: c.collisions as f64 / wall.max(1e-12),
            wall_seconds: wall,
            wall_per_simulated_second: wall / self.now.max(1e-300),
            tc_firings: c.tc_firings,
            tc_share: if c.collisions > 0 {
                c.tc_firings as f64 / c.collisions as f64
            } else {
                0.0
            },
            max_overlap: c.max_overlap,
            counters: c.clone(),
        }
    }
}

/// A disk's position (m) and velocity (m/s) at its own clock `tl` (s).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
struct DiskState {
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    tl: f64,
}

/// Which neighbours a prediction scans.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scope {
    /// All nine cells and both walls.
    All,
    /// Only the row of cells just entered (+1 above, −1 below).
    Row(i64),
    /// Only the column of cells just entered (+1 right, −1 left).
    Col(i64),
}

/// Collisions of one disk allowed at one instant before the run is stopped.
const SAME_INSTANT_LIMIT: u32 = 64;
/// Partner code of the lid in `last_partner`.
const LID: u32 = u32::MAX - 1;
/// Partner code of the piston in `last_partner`.
const PISTON: u32 = u32::MAX - 2;

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
    fn the_rate_guard_stops_a_collapse_while_time_still_advances() {
        // r = 0.99: the bounce intervals shrink by 1 % a bounce; long before they reach the
        // resolution of the clock, a block of events spans less than the guard's limit
        let mut bed = dropped(0.99);
        bed.block_len = 1_000;
        let t_star = (0.1f64 / 9.8).sqrt() * (1.0 + 2.0 * 0.99 / 0.01);
        let err = bed.run_until(2.0 * t_star, &mut |_| {}).unwrap_err().to_string();
        assert!(err.contains("event rate exploded at t = "), "{err}");
        assert!(err.contains("disk 0 ("), "{err}");
        // at the analytic collapse time t* = t1 (1 + 2r/(1 − r)), to roundoff
        assert!(
            (bed.now() - t_star).abs() < 1e-9 * t_star,
            "{} vs {t_star}",
            bed.now()
        );
    }

    #[test]
    fn a_law_outside_zero_one_is_refused() {
        let mut bed = dropped(1.2);
        let err = bed.run_until(1.0, &mut |_| {}).unwrap_err().to_string();
        assert!(err.contains("r = 1.2") && err.contains("[0, 1]"), "{err}");
    }
}
