//! Sampling: the measuring window, the observables and the report.

use super::{Bed, BedConfig};
use crate::bed::observables::{measured_report, stderr_of, BedObservables};
use crate::bed::{BedError, Restitution};
use serde::Serialize;

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
    /// Times a disk came to rest on the piston and rode with it (chattering ended).
    pub rides: u64,
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
    /// Sum of the impulses given to the piston (N·s), collisions and disks riding on it.
    pub piston_impulse: f64,
    /// One batch per piston period, for the standard errors (batch means).
    pub batches: Vec<Batch>,
    /// The batch being filled.
    pub current: Batch,
}

/// The sums of one period of the measuring window.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Batch {
    /// Start (s).
    pub t0: f64,
    /// End (s).
    pub t1: f64,
    /// Lid collisions.
    pub lid_collisions: u64,
    /// Impulse given to the lid (N·s).
    pub lid_impulse: f64,
    /// Impulse given to the piston (N·s).
    pub piston_impulse: f64,
    /// Sum of the sampled mean kinetic energies per disk (J).
    pub ke_sum: f64,
    /// Kinetic energy samples.
    pub ke_samples: u64,
}

/// Standard errors by batch means: the measured periods are grouped into at most 20 batches of
/// at least 5 periods each (consecutive periods are correlated; batches of 5 or more are nearly
/// independent here), and the standard error of an observable is the standard deviation of its
/// batch values over √(batches). None with fewer than 2 batches.
pub fn batch_stderr(batches: &[Batch], f: &dyn Fn(&Batch) -> Option<f64>) -> Option<f64> {
    let k = batches.len();
    let groups = (k / 5).clamp(2, 20);
    if k < groups {
        return None;
    }
    let vals: Vec<f64> = (0..groups)
        .filter_map(|g| {
            let (a, b) = (g * k / groups, (g + 1) * k / groups);
            let mut s = Batch {
                t0: batches[a].t0,
                t1: batches[b - 1].t1,
                ..Batch::default()
            };
            for x in &batches[a..b] {
                s.lid_collisions += x.lid_collisions;
                s.lid_impulse += x.lid_impulse;
                s.piston_impulse += x.piston_impulse;
                s.ke_sum += x.ke_sum;
                s.ke_samples += x.ke_samples;
            }
            f(&s).filter(|v| v.is_finite())
        })
        .collect();
    stderr_of(&vals)
}

/// The results of an event-driven run, averaged after the transient: what the bed measured
/// ([`BedObservables`], read through `report.pressure`, ...), and the engine's counters.
#[derive(Debug, Clone, Serialize)]
pub struct BedReport {
    /// The observables (their JSON keys at the report's top level).
    #[serde(flatten)]
    pub measured: BedObservables,
    /// Events executed over the whole run (collisions and cell crossings).
    pub events: u64,
    /// Collisions over the whole run (disk–disk, lid, piston).
    pub collisions: u64,
    /// Events per second of wall time.
    pub events_per_second: f64,
    /// Collisions per second of wall time.
    pub collisions_per_second: f64,
    /// Collisions made elastic by the TC model.
    pub tc_firings: u64,
    /// Share of all collisions made elastic by the TC model.
    pub tc_share: f64,
    /// Largest overlap ever seen at a collision (m).
    pub max_overlap: f64,
    /// All counters.
    pub counters: Counters,
}

measured_report!(BedReport);

/// Running sums over the disks for the kinetic-energy samples, at the time `t0` (s): s0 = Σ
/// (vx² + vy(t0)²), s1 = Σ vy(t0) ay, s2 = Σ ay² (m²/s², m²/s³, m²/s⁴). Between events each
/// vy is linear in time, so Σ (vx² + vy²) at t0 + s is s0 + 2 s s1 + s² s2: a sample costs O(1)
/// instead of a pass over the disks; the events that change a disk's velocity or acceleration
/// take its old term out and put its new one in.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct KeSums {
    pub(super) t0: f64,
    pub(super) s0: f64,
    pub(super) s1: f64,
    pub(super) s2: f64,
}

/// How many kinetic energy samples per piston period.
pub const SAMPLES_PER_PERIOD: usize = 64;
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

impl<R: Restitution> Bed<R> {
    /// The translational kinetic-energy term of disk `i` in the running sums: its vertical
    /// velocity at the sums' time t0 is c = vy + ay (t0 − tl), and its contribution at t0 + s is
    /// vx² + (c + ay s)², so (vx² + c², c ay, ay²).
    #[inline]
    fn ke_term(&self, i: usize) -> (f64, f64, f64) {
        let d = &self.d[i];
        let c = d.vy + d.ay * (self.ke.t0 - d.tl);
        (d.vx * d.vx + c * c, c * d.ay, d.ay * d.ay)
    }

    /// Takes disk `i` out of the running sums (before its velocity or acceleration changes).
    #[inline]
    pub(super) fn ke_remove(&mut self, i: usize) {
        let (a, b, c) = self.ke_term(i);
        self.ke.s0 -= a;
        self.ke.s1 -= b;
        self.ke.s2 -= c;
    }

    /// Puts disk `i` back into the running sums (after its velocity or acceleration changed).
    #[inline]
    pub(super) fn ke_add(&mut self, i: usize) {
        let (a, b, c) = self.ke_term(i);
        self.ke.s0 += a;
        self.ke.s1 += b;
        self.ke.s2 += c;
    }

    /// The running sums from scratch at time `t` (s): at the start, after `set_state`, and
    /// once a period, so that the roundoff of the updates never accumulates over more than
    /// one period.
    pub(super) fn ke_recompute(&mut self, t: f64) {
        self.ke = KeSums {
            t0: t,
            ..KeSums::default()
        };
        for i in 0..self.n {
            self.ke_add(i);
        }
    }

    pub(super) fn sample(&mut self, t: f64) -> Result<(), BedError> {
        // Σ (vx² + vy(t)²) from the running sums, O(1), then moved to t exactly as the disks'
        // velocities are (vy(t0 + s) = c + ay s): s0 ← Σ(vx² + (c + ay s)²), s1 ← Σ(c + ay s) ay
        let s = t - self.ke.t0;
        let ke = self.ke.s0 + s * (2.0 * self.ke.s1 + s * self.ke.s2);
        self.ke.s1 += s * self.ke.s2;
        self.ke.s0 = ke;
        self.ke.t0 = t;
        let ke = 0.5 * self.cfg.mass * ke / self.n as f64;
        if self.measuring {
            let period = 1.0 / self.cfg.freq;
            if t - self.window.current.t0 >= period * (1.0 - 1e-9) {
                let mut done = self.window.current;
                done.t1 = t;
                self.window.batches.push(done);
                self.window.current = Batch {
                    t0: t,
                    ..Batch::default()
                };
            }
            self.window.ke_sum += ke;
            self.window.ke_samples += 1;
            self.window.current.ke_sum += ke;
            self.window.current.ke_samples += 1;
        }
        if self.trace.is_some() {
            let ym = (0..self.n).map(|i| self.state_at(i, t).1).sum::<f64>() / self.n as f64;
            let row = TraceRow {
                t,
                piston_z: self.piston.state(t).z,
                kinetic_energy: ke,
                mean_height: ym,
                lid_collisions: self.window.lid_collisions,
                lid_impulse: self.window.lid_impulse,
            };
            if let Some(tr) = self.trace.as_mut() {
                tr.push(row);
            }
        }
        // once a period, every pair of neighbours and every disk against the walls, and the
        // kinetic-energy sums afresh
        self.samples_taken += 1;
        if self.samples_taken % SAMPLES_PER_PERIOD as u64 == 0 {
            self.guard_scan(t)?;
            self.ke_recompute(t);
        }
        Ok(())
    }

    /// Starts the measuring window now.
    pub fn start_window(&mut self) {
        self.measuring = true;
        self.window = Window {
            start: self.now,
            current: Batch {
                t0: self.now,
                ..Batch::default()
            },
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
        BedConfig::check_protocol(transient, cycles)?;
        let clock = std::time::Instant::now();
        let period = 1.0 / self.cfg.freq;
        self.run_until(self.now + transient * period, progress)?;
        self.start_window();
        self.run_until(self.now + cycles * period, progress)?;
        self.guard_scan(self.now)?;
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
        let di = (self.window.lid_collisions > 0)
            .then(|| self.window.lid_impulse / self.window.lid_collisions as f64);
        let c = &self.counters;
        let (b, l) = (&self.window.batches[..], self.width);
        BedReport {
            measured: BedObservables {
                config: self.cfg,
                disks: self.n,
                lid: self.lid,
                piston_speed: self.piston.peak_speed(),
                measured_time: tm,
                // (0 without lid collisions)
                pressure: nc * di.unwrap_or(0.0) / self.width,
                lid_collision_rate: nc,
                mean_impulse: di,
                temperature: if self.window.ke_samples > 0 {
                    self.window.ke_sum / self.window.ke_samples as f64
                } else {
                    0.0
                },
                pressure_stderr: batch_stderr(b, &|x| Some(x.lid_impulse / (l * (x.t1 - x.t0)))),
                lid_collision_rate_stderr: batch_stderr(b, &|x| {
                    Some(x.lid_collisions as f64 / (x.t1 - x.t0))
                }),
                mean_impulse_stderr: batch_stderr(b, &|x| {
                    (x.lid_collisions > 0).then(|| x.lid_impulse / x.lid_collisions as f64)
                }),
                temperature_stderr: batch_stderr(b, &|x| {
                    (x.ke_samples > 0).then(|| x.ke_sum / x.ke_samples as f64)
                }),
                piston_pressure: if tm > 0.0 {
                    self.window.piston_impulse / (l * tm)
                } else {
                    0.0
                },
                piston_pressure_stderr: batch_stderr(b, &|x| Some(x.piston_impulse / (l * (x.t1 - x.t0)))),
                seeds: 1,
                wall_seconds: wall,
                wall_per_simulated_second: wall / self.now.max(1e-300),
            },
            events: c.events,
            collisions: c.collisions,
            events_per_second: c.events as f64 / wall.max(1e-12),
            collisions_per_second: c.collisions as f64 / wall.max(1e-12),
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

impl BedReport {
    /// The mean of runs of independent seeds (same configuration but the seed): the observables'
    /// ([`BedObservables::combine`]); counters summed, the largest overlap the largest. None for
    /// no runs.
    pub fn combine(runs: &[BedReport]) -> Option<BedReport> {
        let mut r = runs.first()?.clone();
        r.measured = BedObservables::combine(runs.iter().map(|r| &r.measured))?;
        r.events = runs.iter().map(|r| r.events).sum();
        r.collisions = runs.iter().map(|r| r.collisions).sum();
        r.tc_firings = runs.iter().map(|r| r.tc_firings).sum();
        r.tc_share = if r.collisions > 0 {
            r.tc_firings as f64 / r.collisions as f64
        } else {
            0.0
        };
        r.max_overlap = runs.iter().map(|r| r.max_overlap).fold(0.0, f64::max);
        Some(r)
    }
}
