//! What the benchmarks share (each bench uses part of it).
#![allow(dead_code)]

use dashpot::dem::{Body, Domain, Engine, EngineConfig, Laws, Material, Vec3, VecD, Wall};

/// The CPU time (s) of clock `clock` (a `libc::CLOCK_*_CPUTIME_ID`).
fn cpu_seconds(clock: libc::clockid_t) -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    assert_eq!(rc, 0, "no CPU clock {clock}");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Uniform numbers in [0, 1) from a xorshift64 generator (Marsaglia 2003) started at `seed`:
/// the same sequence on every run, so each run times the same inputs.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut x = seed;
    move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// This thread's CPU time (s), for benchmarks on a shared machine: time spent descheduled is
/// not the code's.
pub fn thread_cpu_seconds() -> f64 {
    cpu_seconds(libc::CLOCK_THREAD_CPUTIME_ID)
}

/// The CPU time (s) this process has received, all threads together.
pub fn process_cpu_seconds() -> f64 {
    cpu_seconds(libc::CLOCK_PROCESS_CPUTIME_ID)
}

/// The DEM benchmarks' pile: `n` disks (diameters uniform in [0.95, 1] × 2 mm) on a square
/// lattice of spacing 2 mm, 50 (or √n) columns wide, random directions at 0.05 m/s. Returns the
/// disks, the width and the height of the lattice (m).
pub fn pile_bodies(n: usize) -> (Vec<Body<2>>, f64, f64) {
    let d = 0.002;
    let cols = (n as f64).sqrt().max(50.0).floor() as usize;
    let rows = n.div_ceil(cols);
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let bodies = (0..n)
        .map(|k| {
            let (q, r) = ((k % cols) as f64, (k / cols) as f64);
            let a = 2.0 * std::f64::consts::PI * rnd();
            Body {
                position: VecD::<2>::new((q + 0.5) * d, (r + 0.5) * d),
                velocity: VecD::<2>::new(0.05 * a.cos(), 0.05 * a.sin()),
                angular_velocity: Vec3::zeros(),
                diameter: d * (0.95 + 0.05 * rnd()),
            }
        })
        .collect();
    (bodies, cols as f64 * d, rows as f64 * d)
}

/// The pile settling under gravity on a floor at y = 0, periodic sideways, with `laws`; the
/// step from the laws at an impact speed of 1 m/s.
pub fn pile(n: usize, laws: Laws, mat: Material, edge_means: bool) -> Engine<2> {
    let (bodies, width, height) = pile_bodies(n);
    let mut cfg = EngineConfig::<2>::new(mat);
    cfg.gravity = VecD::<2>::new(0.0, -9.81);
    cfg.impact_speed = Some(1.0);
    cfg.edge_means = edge_means;
    cfg.domain = Domain {
        lo: VecD::<2>::new(0.0, -0.01),
        hi: VecD::<2>::new(width, height + 1.0),
        periodic: [true, false],
        bounded: false,
    };
    let floor = Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
    Engine::new(cfg, &bodies, vec![floor], laws).expect("the pile")
}
