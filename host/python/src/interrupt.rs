//! Ctrl-C during long runs. Python handles SIGINT by setting a flag that only
//! `PyErr_CheckSignals` on the main thread, with the GIL, turns into `KeyboardInterrupt`. A run
//! of the host that works on rayon's threads (a bed, a sweep) is therefore given its own thread
//! while the caller's thread waits without the GIL, wakes every [`POLL`] to check the signals,
//! and on Ctrl-C raises a flag that the run's progress hook reads: the hook unwinds with
//! [`Interrupted`], the run is dropped, and the caller raises `KeyboardInterrupt` once the run's
//! thread has ended (no thread is left running).

use pyo3::prelude::*;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread checks for signals.
const POLL: Duration = Duration::from_millis(20);

/// The payload a run unwinds with when it was asked to stop.
pub(crate) struct Interrupted;

/// A stop request shared between the waiting thread and the run.
#[derive(Default)]
pub(crate) struct Stop(AtomicBool);

impl Stop {
    /// Unwinds with [`Interrupted`] if a stop was asked for (call it from a run's progress hook;
    /// `resume_unwind` does not run the panic hook, so nothing is printed).
    pub(crate) fn check(&self) {
        if self.0.load(Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new(Interrupted));
        }
    }
}

/// Runs `f` on a thread of its own while this one waits without the GIL and checks for signals;
/// on Ctrl-C (or any signal handler raising), asks `f` to stop, waits for its thread to end and
/// returns the signal's exception (`KeyboardInterrupt`). A panic of `f` other than
/// [`Interrupted`] is resumed here (pyo3 turns it into `PanicException`).
pub(crate) fn watched<T: Send>(py: Python<'_>, f: impl FnOnce(&Stop) -> T + Send) -> PyResult<T> {
    let stop = Stop::default();
    let done = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let (stop, done) = (&stop, &done);
        let worker = s.spawn(move || {
            let r = std::panic::catch_unwind(AssertUnwindSafe(|| f(stop)));
            *done.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            done.1.notify_all();
            r
        });
        let mut signal: Option<PyErr> = None;
        loop {
            let finished = py.allow_threads(|| {
                let g = done.0.lock().unwrap_or_else(|e| e.into_inner());
                let (g, _) = done
                    .1
                    .wait_timeout_while(g, POLL, |d| !*d)
                    .unwrap_or_else(|e| e.into_inner());
                *g
            });
            if finished {
                break;
            }
            if signal.is_none() {
                if let Err(e) = py.check_signals() {
                    stop.0.store(true, Ordering::Relaxed);
                    signal = Some(e);
                }
            }
        }
        let r = py.allow_threads(|| worker.join());
        let r = match r {
            Ok(r) => r,
            Err(p) => std::panic::resume_unwind(p),
        };
        match (r, signal) {
            (Ok(v), None) => Ok(v),
            // the run ended before it saw the request: its result is dropped, the signal raised
            (Ok(_), Some(e)) => Err(e),
            (Err(p), Some(e)) if p.is::<Interrupted>() => Err(e),
            (Err(p), _) => std::panic::resume_unwind(p),
        }
    })
}
