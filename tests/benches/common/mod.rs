//! What the benchmarks share.

/// This thread's CPU time (s), for benchmarks on a shared machine: time spent descheduled is
/// not the code's.
pub fn thread_cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "no thread CPU clock");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}
