//! Know before a run: what it needs (memory, steps, time) against what the machine has, and the
//! refusals of runs that cannot fit or would not end.
//!
//! Every command that allocates in proportion to its input (`dem`, `bed`, `scaling`, `sweep`,
//! `reproduce`, and the Python package's scenes and beds) estimates its peak memory from its
//! own configuration before it allocates ([`Need`], built by each engine's model: for the DEM
//! engine [`crate::dem::footprint`], for the event-driven bed [`bed_need`]) and checks it against
//! the memory this process may still take ([`Memory::now`]: `MemAvailable` of `/proc/meminfo`,
//! lowered by a cgroup's limit if there is one) with [`check_memory`]. A run whose step count is
//! absurd is refused by [`check_steps`] before its first step, and a run whose measured pace puts
//! it past a limit the user can raise (`--max-hours`) by [`check_hours`].
//!
//! The environment variable `DASHPOT_MEMORY_AVAILABLE` (bytes, or with a suffix: `512M`, `2G`)
//! overrides the memory the machine reports (to rehearse a smaller machine, or to leave room for
//! other work).

use std::fmt::Write as _;

mod machine;

pub use machine::{rss, Memory, Rss};

/// The most steps a run may take ([`check_steps`]): 10¹² steps of the cheapest particle take
/// hours on any machine; past it, a step is almost surely smaller than the user meant (a
/// modulus, a stiffness or a step count a few orders of magnitude off).
pub const MAX_STEPS: f64 = 1e12;

/// The fastest a run of the DEM engine can step, in particle-steps per second, on any machine
/// (some hundred times this machine's rate): a run refused with it as its pace
/// ([`check_hours`]) could not end in time even there.
pub const FASTEST_PARTICLE_STEPS_PER_SECOND: f64 = 1e9;

/// The default of `--max-hours`: a run whose estimate is longer is refused (the limit can be
/// raised).
pub const DEFAULT_MAX_HOURS: f64 = 24.0;

/// Why a run was refused before it started: the message names what it would need, what there
/// is, and what to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct Refused(pub String);

/// What a run needs in memory: what this process holds already, and the parts (name, bytes) it
/// will allocate; its peak is their sum.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Need {
    /// What this process holds before the run (bytes: its code, plugins, data): part of the
    /// peak, but not of what is still to be found.
    pub resident: f64,
    /// The parts still to allocate: a name (e.g. "particles") and its bytes.
    pub parts: Vec<(String, f64)>,
}

impl Need {
    /// No parts yet.
    pub fn new() -> Need {
        Need::default()
    }

    /// Adds a part of `bytes` (skipped when zero).
    pub fn add(&mut self, name: &str, bytes: f64) -> &mut Need {
        if bytes != 0.0 {
            self.parts.push((name.to_string(), bytes));
        }
        self
    }

    /// What this process holds already (bytes).
    pub fn holding(&mut self, resident: f64) -> &mut Need {
        self.resident = resident;
        self
    }

    /// The peak: what is held and the parts (bytes).
    pub fn total(&self) -> f64 {
        self.resident + self.more()
    }

    /// The parts still to allocate (bytes).
    pub fn more(&self) -> f64 {
        self.parts.iter().map(|(_, b)| b).sum()
    }

    /// The parts, largest first, as `particles 1.2 GiB, contacts 800 MiB`.
    pub fn breakdown(&self) -> String {
        let mut p = self.parts.clone();
        p.sort_by(|a, b| b.1.total_cmp(&a.1));
        p.iter()
            .map(|(n, b)| format!("{n} {}", bytes(*b)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Refuses `what` (e.g. "generate.count = 1000000000000 particles") if it needs more memory than
/// this process may take: the message names the need and its parts, the memory available and
/// where that figure comes from, and `advice` (what to change).
pub fn check_memory(what: &str, need: &Need, advice: &str) -> Result<(), Refused> {
    check_memory_against(what, need, &Memory::now(), advice)
}

/// [`check_memory`] against `mem`.
pub fn check_memory_against(what: &str, need: &Need, mem: &Memory, advice: &str) -> Result<(), Refused> {
    let more = need.more();
    if more.is_finite() && more <= mem.available as f64 {
        return Ok(());
    }
    let mut msg = format!(
        "{what} would need about {} of memory ({}), but {} is available ({})",
        bytes(more),
        need.breakdown(),
        bytes(mem.available as f64),
        mem.source
    );
    if !advice.is_empty() {
        let _ = write!(msg, ": {advice}");
    }
    Err(Refused(msg))
}

/// The largest count `n` of items whose need `need_of(n)` (bytes, growing with `n`) fits in
/// `available` bytes (0 if not even one does): for a refusal's advice.
pub fn largest_fitting(available: f64, need_of: impl Fn(f64) -> f64) -> u64 {
    if need_of(1.0) > available {
        return 0;
    }
    let (mut lo, mut hi) = (1.0f64, 2.0f64);
    while need_of(hi) <= available && hi < 1e18 {
        lo = hi;
        hi *= 2.0;
    }
    while hi - lo > 1.0 {
        let mid = (0.5 * (lo + hi)).floor();
        if need_of(mid) <= available {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo as u64
}

/// The number of steps of `dt` (s) a run of `span` seconds of simulated time takes (`what`
/// names the run), refused beyond [`MAX_STEPS`] (or not finite) with a message naming dt, the
/// span, the step count and the least wall time it would take at `particles` particles, and
/// `advice`.
pub fn check_steps(what: &str, dt: f64, span: f64, particles: usize, advice: &str) -> Result<u64, Refused> {
    let steps = if span <= 0.0 { 0.0 } else { (span / dt).ceil() };
    if steps.is_finite() && steps <= MAX_STEPS && dt > 0.0 {
        return Ok(steps as u64);
    }
    let least = steps * particles.max(1) as f64 / FASTEST_PARTICLE_STEPS_PER_SECOND;
    let mut msg = format!(
        "{what}: dt = {dt:.4e} s over {span:.4e} s of simulated time is {steps:.3e} steps, beyond the {MAX_STEPS:.0e} a run may take (at {:.0e} particle-steps/s, faster than any machine steps, it would still take {})",
        FASTEST_PARTICLE_STEPS_PER_SECOND,
        seconds(least)
    );
    if !advice.is_empty() {
        let _ = write!(msg, "; {advice}");
    }
    Err(Refused(msg))
}

/// Refuses `what` if its estimated wall time `estimate` (s) exceeds `max_hours` (the limit the
/// user can raise, `--max-hours`), naming the estimate, how it was made (`basis`) and the limit.
pub fn check_hours(what: &str, estimate: f64, basis: &str, max_hours: f64) -> Result<(), Refused> {
    if estimate <= max_hours * 3600.0 {
        return Ok(());
    }
    Err(Refused(format!(
        "{what} would take about {} ({basis}), past --max-hours = {max_hours}: raise --max-hours if you mean it, or shorten the run",
        seconds(estimate)
    )))
}

/// Checks a `--max-hours` value: finite and > 0.
pub fn check_max_hours(h: f64) -> Result<f64, Refused> {
    if h.is_finite() && h > 0.0 {
        Ok(h)
    } else {
        Err(Refused(format!(
            "--max-hours = {h} is out of range: it must be finite and > 0"
        )))
    }
}

/// The memory of the event-driven bed of `disks` disks (bytes), `seeds` of them at once, with a
/// sampled trace of `trace_rows` rows if one is written: per disk its state, cell links and
/// event-queue entries (measured: about 0.5 kB a disk with the queue's slack), per trace row
/// its 6 numbers.
pub fn bed_need(disks: f64, seeds: f64, trace_rows: f64) -> Need {
    let mut n = Need::new();
    n.holding(rss().now as f64);
    n.add("disks and their events", seeds * disks * BED_BYTES_PER_DISK);
    n.add("trace", trace_rows * 64.0);
    n
}

/// Bytes per disk of the event-driven bed (its state, cells and event queue, with slack).
pub const BED_BYTES_PER_DISK: f64 = 512.0;

/// `b` bytes as `12.3 MiB`.
pub fn bytes(b: f64) -> String {
    const UNITS: [&str; 7] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if !b.is_finite() {
        return format!("{b} B");
    }
    let mut v = b;
    let mut u = 0;
    while v.abs() >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{v:.0} B")
    } else if v.abs() >= 1024.0 {
        format!("{:.3e} {}", v, UNITS[u])
    } else {
        format!("{v:.1} {}", UNITS[u])
    }
}

/// `s` seconds as `0.42 s`, `3 min 20 s`, `5.2 h`, `3.1 days` or `2.0e12 years`.
pub fn seconds(s: f64) -> String {
    if !s.is_finite() {
        return format!("{s} s");
    }
    if s < 60.0 {
        format!("{s:.2} s")
    } else if s < 3600.0 {
        format!("{} min {:.0} s", (s / 60.0).floor(), s % 60.0)
    } else if s < 2.0 * 86400.0 {
        format!("{:.1} h", s / 3600.0)
    } else if s < 365.25 * 86400.0 {
        format!("{:.1} days", s / 86400.0)
    } else {
        format!("{:.2e} years", s / (365.25 * 86400.0))
    }
}

/// Parses a byte count: a number, optionally with a suffix K, M, G, T (powers of 1024, an
/// optional trailing `B` or `iB`).
pub fn parse_bytes(s: &str) -> Option<u64> {
    let t = s.trim();
    let t = t
        .strip_suffix("iB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(t)
        .trim_end();
    let (num, mult) = match t.chars().last()? {
        'k' | 'K' => (&t[..t.len() - 1], 1024.0),
        'm' | 'M' => (&t[..t.len() - 1], 1024.0 * 1024.0),
        'g' | 'G' => (&t[..t.len() - 1], 1024.0f64.powi(3)),
        't' | 'T' => (&t[..t.len() - 1], 1024.0f64.powi(4)),
        _ => (t, 1.0),
    };
    let v: f64 = num.trim().parse().ok()?;
    let b = v * mult;
    (b.is_finite() && b >= 0.0 && b < u64::MAX as f64).then_some(b as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_read_and_print() {
        assert_eq!(parse_bytes("512"), Some(512));
        assert_eq!(parse_bytes("2K"), Some(2048));
        assert_eq!(parse_bytes("1.5 GiB"), Some(3 * 512 * 1024 * 1024));
        assert_eq!(parse_bytes("3MB"), Some(3 * 1024 * 1024));
        assert_eq!(parse_bytes("x"), None);
        assert_eq!(parse_bytes("-1"), None);
        assert_eq!(bytes(512.0), "512 B");
        assert_eq!(bytes(1536.0), "1.5 KiB");
        assert_eq!(bytes(8e13), "72.8 TiB");
        assert_eq!(seconds(30.0), "30.00 s");
        assert_eq!(seconds(90.0), "1 min 30 s");
        assert_eq!(seconds(7200.0), "2.0 h");
    }

    #[test]
    fn a_need_past_the_memory_is_refused_naming_both() {
        let mut need = Need::new();
        need.add("particles", 3e12).add("contacts", 1e12);
        let mem = Memory {
            available: 8 << 30,
            source: "a test".into(),
        };
        let e = check_memory_against("count = 1e10", &need, &mem, "lower count").unwrap_err();
        assert!(e.0.contains("3.6 TiB"), "{e}");
        assert!(e.0.contains("particles 2.7 TiB, contacts 931.3 GiB"), "{e}");
        assert!(e.0.contains("8.0 GiB is available (a test)"), "{e}");
        assert!(e.0.ends_with(": lower count"), "{e}");
        let mut small = Need::new();
        small.add("particles", 1e6);
        assert!(check_memory_against("x", &small, &mem, "").is_ok());
        // what the process holds already is part of the peak, not of what is still needed
        small.holding(1e12);
        assert!(check_memory_against("x", &small, &mem, "").is_ok());
        assert_eq!(small.total(), 1e12 + 1e6);
        // the largest count that fits: 8 GiB at 1 kB each
        let n = largest_fitting(8.0 * (1u64 << 30) as f64, |n| 1000.0 * n);
        assert_eq!(n, (8.0 * (1u64 << 30) as f64 / 1000.0).floor() as u64);
        assert_eq!(largest_fitting(10.0, |n| 100.0 * n), 0);
    }

    #[test]
    fn absurd_step_counts_are_refused_naming_dt_and_the_count() {
        assert_eq!(check_steps("run", 1e-3, 1.0, 10, ""), Ok(1000));
        assert_eq!(check_steps("run", 1e-3, 0.0, 10, ""), Ok(0));
        let e = check_steps("dem", 2.7e-126, 0.5, 10, "give dt").unwrap_err();
        assert!(e.0.contains("dt = 2.7000e-126 s"), "{e}");
        assert!(e.0.contains("1.852e125 steps"), "{e}");
        assert!(e.0.contains("years"), "{e}");
        assert!(e.0.ends_with("; give dt"), "{e}");
        assert!(check_steps("dem", 1e-300, 1.0, 1, "").is_err());
        assert!(check_steps("dem", 0.0, 1.0, 1, "").is_err());
        assert!(check_steps("dem", 1e-12, 1.0, 1, "").is_ok());
        assert!(check_steps("dem", 1e-13, 1.0, 1, "").is_err());
        assert!(check_hours("dem", 3600.0, "measured", 2.0).is_ok());
        let e = check_hours("dem", 3.0 * 86400.0, "measured", 24.0).unwrap_err();
        assert!(
            e.0.contains("3.0 days") && e.0.contains("--max-hours = 24"),
            "{e}"
        );
        assert!(check_max_hours(f64::NAN).is_err() && check_max_hours(0.0).is_err());
    }
}
