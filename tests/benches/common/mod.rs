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
pub fn xorshift_uniform(seed: u64) -> impl FnMut() -> f64 {
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

/// The median of `v` (the mean of the middle two of an even count).
pub fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// The DEM benchmarks' pile: `n` disks (diameters uniform in [0.95, 1] × 2 mm) on a square
/// lattice of spacing 2 mm, 50 (or √n) columns wide, random directions at 0.05 m/s. Returns the
/// disks, the width and the height of the lattice (m).
pub fn pile_bodies(n: usize) -> (Vec<Body<2>>, f64, f64) {
    let d = 0.002;
    let cols = (n as f64).sqrt().max(50.0).floor() as usize;
    let rows = n.div_ceil(cols);
    let mut rnd = dashpot_tests::lcg_uniform(7);
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

/// [`EngineConfig::sort_from`] for the benchmarks' engines: `default` (the engine's), or from
/// `DASHPOT_BENCH_SORT` (`off`: never reorder; a number: from that many particles on), for
/// same-binary A/B runs of the engine's memory order.
pub fn sort_from(default: usize) -> usize {
    match std::env::var("DASHPOT_BENCH_SORT").ok().as_deref() {
        Some("off") => usize::MAX,
        Some(s) => s.parse().expect("DASHPOT_BENCH_SORT: off or a particle count"),
        None => default,
    }
}

/// The pile settling under gravity on a floor at y = 0, periodic sideways, with `laws`; the
/// step from the laws at an impact speed of 1 m/s.
pub fn pile(n: usize, laws: Laws, mat: Material, edge_means: bool) -> Engine<2> {
    let (bodies, width, height) = pile_bodies(n);
    let mut cfg = EngineConfig::<2>::new(mat);
    cfg.gravity = VecD::<2>::new(0.0, -9.81);
    cfg.impact_speed = Some(1.0);
    cfg.edge_means = edge_means;
    cfg.sort_from = sort_from(cfg.sort_from);
    cfg.domain = Domain {
        lo: VecD::<2>::new(0.0, -0.01),
        hi: VecD::<2>::new(width, height + 1.0),
        periodic: [true, false],
        bounded: false,
    };
    let floor = Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
    Engine::new(cfg, &bodies, vec![floor], laws).expect("the pile")
}

/// The 3D pile's lattice for `n` spheres: its columns along x and along y (√(n/10), at least
/// 8), its layers, and its spacing (m: 1.2 × the largest diameter, so nothing touches).
pub fn pile3d_lattice(n: usize) -> (usize, usize, f64) {
    let cols = ((n as f64 / 10.0).sqrt().ceil() as usize).max(8);
    (cols, n.div_ceil(cols * cols), 1.2 * 1.2 * 0.002)
}

/// The 3D benchmarks' pile: `n` spheres (diameters uniform in [0.8, 1.2] × 2 mm) on the simple
/// cubic lattice of [`pile3d_lattice`] (spacing 2.88 mm), sphere k at column k mod cols, row
/// (k / cols) mod cols, layer k / cols², the lowest layer's centres one spacing above the floor,
/// random directions at 0.05 m/s. Returns the spheres, the box's side (x and y, m) and the
/// lattice's top (m).
pub fn pile3d_bodies(n: usize) -> (Vec<Body<3>>, f64, f64) {
    let d = 0.002;
    let (cols, layers, s) = pile3d_lattice(n);
    let mut rnd = dashpot_tests::lcg_uniform(11);
    let bodies = (0..n)
        .map(|k| {
            let (a, b, c) = (k % cols, (k / cols) % cols, k / (cols * cols));
            // a random direction: z uniform in [-1, 1], azimuth uniform
            let (z, phi) = (2.0 * rnd() - 1.0, 2.0 * std::f64::consts::PI * rnd());
            let rho = (1.0 - z * z).sqrt();
            Body {
                position: VecD::<3>::new((a as f64 + 0.5) * s, (b as f64 + 0.5) * s, (c as f64 + 1.0) * s),
                velocity: VecD::<3>::new(rho * phi.cos(), rho * phi.sin(), z) * 0.05,
                angular_velocity: Vec3::zeros(),
                diameter: d * (0.8 + 0.4 * rnd()),
            }
        })
        .collect();
    (bodies, cols as f64 * s, layers as f64 * s)
}

/// The 3D pile falling and settling under gravity onto a floor at z = 0, periodic in x and y,
/// with `laws`; the step from the laws at an impact speed of 1 m/s.
pub fn pile3d(n: usize, laws: Laws, mat: Material) -> Engine<3> {
    let (bodies, side, top) = pile3d_bodies(n);
    pile3d_engine(&bodies, [side, side], top, laws, mat, false)
}

/// The engine of a 3D pile: `bodies` in a box of sides `side` (x, y; m, both periodic) over a
/// floor at z = 0, gravity along −z, the step from the laws at an impact speed of 1 m/s, energy
/// accounting on or off (`energy`, [`EngineConfig::energy`]); `top` (m): the particles' highest
/// start.
pub fn pile3d_engine(
    bodies: &[Body<3>],
    side: [f64; 2],
    top: f64,
    laws: Laws,
    mat: Material,
    energy: bool,
) -> Engine<3> {
    let (cfg, walls) = pile3d_config(side, top, mat, energy);
    Engine::new(cfg, bodies, walls, laws).expect("the 3D pile")
}

/// The configuration and the floor of [`pile3d_engine`].
pub fn pile3d_config(
    side: [f64; 2],
    top: f64,
    mat: Material,
    energy: bool,
) -> (EngineConfig<3>, Vec<Wall<3>>) {
    let mut cfg = EngineConfig::<3>::new(mat);
    cfg.gravity = VecD::<3>::new(0.0, 0.0, -9.81);
    cfg.impact_speed = Some(1.0);
    cfg.energy = energy;
    cfg.sort_from = sort_from(cfg.sort_from);
    cfg.domain = Domain {
        lo: VecD::<3>::new(0.0, 0.0, -0.01),
        hi: VecD::<3>::new(side[0], side[1], top + 0.01),
        periodic: [true, true, false],
        bounded: false,
    };
    let floor = Wall::fixed(VecD::<3>::zeros(), VecD::<3>::new(0.0, 0.0, 1.0));
    (cfg, vec![floor])
}

/// How [`tile3d`] numbers the spheres of its copies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileOrder {
    /// As [`pile3d_bodies`] numbers the whole lattice of tx·cols × ty·cols columns (each copy's
    /// sphere at the lattice site its base sphere started from): memory laid out as in a pile
    /// generated at the full size, neighbours along z a layer (tx·ty·cols² spheres) apart.
    Lattice,
    /// Copy after copy, each in its base's order: every copy's spheres close in memory.
    Copies,
}

/// A larger 3D pile made of `tiles` = [tx, ty] copies of `base`, a [`pile3d`] of `n` spheres
/// stepped as far as wanted (positions wrapped into its periodic box, velocities and spins
/// kept; the contacts' history starts afresh), side by side in x and y: every copy at the same
/// stage of the same pile, the spheres numbered in `order`. Returns the spheres, the box's
/// sides (m) and the lattice's top (m).
pub fn tile3d(
    base: &Engine<3>,
    n: usize,
    tiles: [usize; 2],
    order: TileOrder,
) -> (Vec<Body<3>>, [f64; 2], f64) {
    let (cols, layers, s) = pile3d_lattice(n);
    let side = cols as f64 * s;
    let [tx, ty] = tiles;
    let mut keyed = Vec::with_capacity(n * tx * ty);
    for (y, x) in (0..ty).flat_map(|y| (0..tx).map(move |x| (y, x))) {
        for i in 0..n {
            let mut b = base.p.body(i);
            for (k, t) in [x, y].into_iter().enumerate() {
                b.position[k] = b.position[k].rem_euclid(side) + t as f64 * side;
            }
            let (a, r, c) = (i % cols, (i / cols) % cols, i / (cols * cols));
            let key = match order {
                TileOrder::Lattice => (a + x * cols) + tx * cols * ((r + y * cols) + ty * cols * c),
                TileOrder::Copies => keyed.len(),
            };
            keyed.push((key, b));
        }
    }
    keyed.sort_unstable_by_key(|(k, _)| *k);
    let bodies = keyed.into_iter().map(|(_, b)| b).collect();
    (bodies, [tx as f64 * side, ty as f64 * side], layers as f64 * s)
}

/// The height of the centre of mass along the last axis (m).
pub fn com_height<const D: usize>(e: &Engine<D>) -> f64 {
    let p = &e.p;
    let m: f64 = p.mass.iter().sum();
    p.pos.iter().zip(&p.mass).map(|(x, m)| x[D - 1] * m).sum::<f64>() / m
}
