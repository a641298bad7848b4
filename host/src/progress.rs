//! Long runs: a progress bar with an estimated time to go, blocks of steps paced by the wall
//! clock, and a clean stop on Ctrl-C.
//!
//! - [`Progress`]: the bar of a run (indicatif, on stderr), drawn only on a terminal and never
//!   under `--json`.
//! - [`Pace`]: how many steps the next block of a run may take so that it ends about every
//!   [`TICK`] of wall time: the bar moves, and a stop request is seen, within that.
//! - [`stop`]: Ctrl-C as a request. A run that honours it calls [`stop::install`] first, then
//!   [`stop::requested`] between its blocks, and on `true` ends as it would on an error
//!   (returning [`Interrupted`]): its result files are not written (nothing half-written is
//!   left), and the CLI exits with 130. Whoever wants to save the state first (a checkpoint)
//!   does it where `requested()` is seen, before returning [`Interrupted`]. A second Ctrl-C
//!   kills the process at once.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// How long a block of steps runs between two looks at the bar and the stop request: long
/// enough that a block of a large pile amortizes what a call of the engine costs beyond its
/// steps (its memory order's permutation, waking its threads), short enough for Ctrl-C.
pub const TICK: Duration = Duration::from_millis(1000);

/// A run ended early because the user asked it to (Ctrl-C): `at` says where it was.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("stopped by Ctrl-C {at}; no result was written")]
pub struct Interrupted {
    /// Where the run was, e.g. "at step 1200, t = 1.2e-3 s".
    pub at: String,
}

/// The progress bar of a run.
pub struct Progress {
    bar: indicatif::ProgressBar,
}

impl Progress {
    /// A bar of `len` units (`unit`, e.g. "steps") for `what`, hidden when `quiet` (`--json`)
    /// or when stderr is not a terminal.
    pub fn new(len: u64, what: &str, unit: &str, quiet: bool) -> Progress {
        use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
        let target = if quiet || !std::io::stderr().is_terminal() {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let bar = ProgressBar::with_draw_target(Some(len), target);
        if let Ok(style) = ProgressStyle::with_template(&format!(
            "{what} [{{elapsed_precise}}] {{wide_bar}} {{human_pos}}/{{human_len}} {unit} (eta {{eta}})"
        )) {
            bar.set_style(style);
        }
        Progress { bar }
    }

    /// Whether the bar is drawn.
    pub fn drawn(&self) -> bool {
        !self.bar.is_hidden()
    }

    /// Moves the bar to `pos`.
    pub fn set(&self, pos: u64) {
        self.bar.set_position(pos);
    }

    /// Adds `k` to the bar.
    pub fn inc(&self, k: u64) {
        self.bar.inc(k);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// Blocks of steps paced by the wall clock: after a block of `k` steps that took `t`, the next
/// may take about `k TICK / t` steps (at most four times more than the last, at least one).
#[derive(Debug, Clone)]
pub struct Pace {
    block: u64,
    started: Instant,
    since: Instant,
    first_steps: u64,
}

impl Default for Pace {
    fn default() -> Self {
        Pace::new()
    }
}

impl Pace {
    /// Starting with one step.
    pub fn new() -> Pace {
        let now = Instant::now();
        Pace {
            block: 1,
            started: now,
            since: now,
            first_steps: 0,
        }
    }

    /// The most steps the next block may take.
    pub fn block(&self) -> u64 {
        self.block
    }

    /// A block of `k` steps has ended now: the next block's length follows.
    pub fn done(&mut self, k: u64) {
        let now = Instant::now();
        let took = now.duration_since(self.since).as_secs_f64().max(1e-9);
        self.since = now;
        self.first_steps += k;
        let scale = (TICK.as_secs_f64() / took).min(4.0);
        self.block = ((k.max(1) as f64 * scale) as u64).clamp(1, 1 << 32);
    }

    /// Wall time since the start (s).
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}

/// Ctrl-C as a request to stop (see the module doc).
pub mod stop {
    use std::sync::atomic::{AtomicBool, Ordering};

    static REQUESTED: AtomicBool = AtomicBool::new(false);

    /// Whether Ctrl-C was pressed since [`install`] (or the last [`clear`]).
    #[inline]
    pub fn requested() -> bool {
        REQUESTED.load(Ordering::Relaxed)
    }

    /// Forgets a request.
    pub fn clear() {
        REQUESTED.store(false, Ordering::Relaxed);
    }

    /// Asks for a stop as Ctrl-C does (tests, embedding code).
    pub fn request() {
        REQUESTED.store(true, Ordering::Relaxed);
    }

    #[cfg(unix)]
    extern "C" fn on_sigint(_: libc::c_int) {
        if REQUESTED.swap(true, Ordering::Relaxed) {
            // the second Ctrl-C: the default action, at once
            // SAFETY: signal and raise are async-signal-safe.
            unsafe {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                libc::raise(libc::SIGINT);
            }
        }
    }

    /// Makes Ctrl-C (SIGINT) a request ([`requested`]) instead of the end of the process; a
    /// second Ctrl-C ends it at once. Only for the CLI's runs that look at [`requested`]
    /// (a library embedded in another program, such as Python, keeps its host's handler).
    pub fn install() {
        #[cfg(unix)]
        // SAFETY: the handler only touches an atomic and calls async-signal-safe functions.
        unsafe {
            libc::signal(
                libc::SIGINT,
                on_sigint as extern "C" fn(libc::c_int) as libc::sighandler_t,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_grow_to_the_tick_and_no_faster_than_fourfold() {
        let mut p = Pace::new();
        assert_eq!(p.block(), 1);
        p.done(1);
        assert!(p.block() <= 4 && p.block() >= 1);
        std::thread::sleep(Duration::from_millis(20));
        p.done(100);
        // 100 steps in >= 20 ms: at most 400 (fourfold), fewer than 5000 fill the tick
        assert!(p.block() <= 400 && p.block() >= 1, "{}", p.block());
    }
}
