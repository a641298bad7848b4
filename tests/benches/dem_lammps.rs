//! Soft-sphere DEM against LAMMPS on the same piles with the same physics, on one core and on
//! two:
//!
//! - **2D**: 2,000 polydisperse disks (1.9–2 mm, E = 10⁸ Pa, ν = 0.3, steel density, spheres
//!   confined to the plane) settling under gravity on a floor, periodic sideways: both settle
//!   5,000 steps, then 3,500 steps are timed;
//! - **3D**: 4,000 polydisperse spheres (1.6–2.4 mm, the same material) falling from a loose
//!   lattice onto a floor, periodic in x and y, and settling: 60,000 steps (0.13 s, the fall
//!   and the settling) timed whole.
//!
//! Both with HSD (ε = 0.5) + Mindlin (μ = 0.3, history, no tangential damping) between
//! particles and against the floor. LAMMPS runs `examples/dem/lammps/in.pile2d` and
//! `in.pile3d` (`pair_style granular hertz/material ... damping coeff_restitution tangential
//! mindlin NULL 0 μ`, `fix wall/gran` with the same model) on the very particles dashpot starts
//! from (positions, diameters, velocities written to a data file; the total mass LAMMPS computes
//! is checked against dashpot's), at dashpot's time step and with dashpot's neighbour skin (the
//! engine's default, 0.3 of the smallest diameter). Both piles' centres of mass are compared at
//! the end (target: within 1 %).
//!
//! One core: CPU seconds of dashpot's measuring thread against LAMMPS's loop time × its CPU
//! share. Two cores: wall seconds of dashpot on a pool of two threads against LAMMPS's loop time
//! on two MPI ranks (`mpirun -np 2` of the venv). Each contest is run as pairs, the two programs
//! alternating, and reports the median of the pairs' ratios (the machine is shared and drifts:
//! within a pair the drift mostly cancels).
//!
//! LAMMPS comes from `$DASHPOT_LAMMPS_VENV` (default: `~/.cache/dashpot/lammps-venv-2025.7.22.4.0`,
//! what `.ci/run` installs); without it the comparison is skipped with the reason printed.
//!
//! Run: `cargo bench -p dashpot-tests --bench dem_lammps [-- 2d | 3d] [one | two]` (sections by
//! name, all by default); `DASHPOT_BENCH_PAIRS` pairs per contest (default 3),
//! `DASHPOT_BENCH_3D_STEPS` the 3D run's length.

mod common;

use common::{median, process_cpu_seconds, thread_cpu_seconds};
use dashpot::dem::{Body, Engine, Laws, Material};
use dashpot_sdk::ParamValue;
use dashpot_tests::full_registry;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: dashpot::dem::DiskMass::Sphere,
};

/// One pile: its dimension, size, untimed and timed steps, and LAMMPS deck.
#[derive(Clone, Copy)]
struct Case {
    n: usize,
    settle: usize,
    steps: usize,
    deck: &'static str,
}

fn laws(reg: &dashpot::Registry) -> Laws {
    Laws::from_registry(
        reg,
        ("hsd", &[ParamValue::new("eps", 0.5)]),
        Some(("mindlin", &[ParamValue::new("mu", 0.3)])),
        &MAT,
    )
    .expect("laws")
}

/// The pile as a LAMMPS data file (atom_style sphere: id type diameter density x y z); returns
/// dashpot's total mass (kg).
fn write_data<const D: usize>(path: &Path, b: &[Body<D>], hi: [f64; 3], title: &str) -> f64 {
    let mut s = String::new();
    let _ = writeln!(s, "{title}\n\n{} atoms\n1 atom types\n", b.len());
    let lo = if D == 2 {
        [0.0, -0.01, -0.001]
    } else {
        [0.0, 0.0, -0.01]
    };
    for (k, ax) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(s, "{:.17e} {:.17e} {ax}lo {ax}hi", lo[k], hi[k]);
    }
    let _ = writeln!(s, "\nAtoms # sphere\n");
    let mut mass = 0.0;
    let xyz = |v: &dashpot::dem::VecD<D>| [v[0], v[1], if D == 3 { v[D - 1] } else { 0.0 }];
    for (i, p) in b.iter().enumerate() {
        let x = xyz(&p.position);
        let _ = writeln!(
            s,
            "{} 1 {:.17e} {:.17e} {:.17e} {:.17e} {:.17e}",
            i + 1,
            p.diameter,
            MAT.density,
            x[0],
            x[1],
            x[2]
        );
        // dashpot's own mass of a particle (the convention LAMMPS's total is checked against)
        mass += MAT.mass_inertia(D, p.diameter).0;
    }
    let _ = writeln!(s, "\nVelocities\n");
    for (i, p) in b.iter().enumerate() {
        let v = xyz(&p.velocity);
        let _ = writeln!(s, "{} {:.17e} {:.17e} {:.17e} 0 0 0", i + 1, v[0], v[1], v[2]);
    }
    std::fs::write(path, s).expect("write the data file");
    mass
}

fn venv() -> Result<PathBuf, String> {
    dashpot_tests::dir_holding(
        "DASHPOT_LAMMPS_VENV",
        || {
            Ok(PathBuf::from(std::env::var_os("HOME").ok_or("no HOME")?)
                .join(".cache/dashpot/lammps-venv-2025.7.22.4.0"))
        },
        "bin/lmp",
        "LAMMPS at",
        "run .ci/run once, or set DASHPOT_LAMMPS_VENV",
    )
}

/// What one LAMMPS run gave.
struct LammpsRun {
    /// Seconds of the timed loop: CPU seconds on one rank, wall seconds on more.
    seconds: f64,
    /// Total mass (kg).
    mass: f64,
    /// Centre-of-mass height at the end (m).
    height: f64,
}

/// Runs `case`'s deck on `ranks` MPI ranks.
fn lammps(venv: &Path, case: &Case, data: &Path, dt: f64, skin: f64, ranks: usize) -> LammpsRun {
    let deck = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/dem/lammps")
        .join(case.deck);
    let mut cmd = dashpot_tests::lammps::lmp_command(venv, ranks as u32);
    let out = cmd
        .arg("-in")
        .arg(&deck)
        .args(["-log", "none", "-var", "data"])
        .arg(data)
        .args(["-var", "dt", &format!("{dt:.17e}")])
        .args(["-var", "skin", &format!("{skin:.17e}")])
        .args(["-var", "settle", &case.settle.to_string()])
        .args(["-var", "nsteps", &case.steps.to_string()])
        .env("OMP_NUM_THREADS", "1")
        .output()
        .expect("run lmp");
    let text = dashpot_tests::lammps::succeeded(&out, "LAMMPS");
    let last = text
        .lines()
        .rfind(|l| l.starts_with("Loop time of"))
        .expect("a loop time");
    // "Loop time of T on P procs for S steps with N atoms"
    let t: f64 = last
        .split_whitespace()
        .nth(3)
        .and_then(|x| x.parse().ok())
        .expect("loop time");
    let cpu_share = text
        .lines()
        .rfind(|l| l.contains("% CPU use"))
        .and_then(|l| l.split('%').next())
        .and_then(|x| x.trim().parse::<f64>().ok())
        .unwrap_or(100.0)
        / 100.0;
    let grab = |key: &str| -> f64 {
        text.lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|x| x.parse().ok())
            .unwrap_or_else(|| panic!("LAMMPS printed no {key}"))
    };
    LammpsRun {
        seconds: if ranks == 1 { t * cpu_share } else { t },
        mass: grab("TOTAL_MASS"),
        height: grab("ZCM"),
    }
}

/// Runs `case` in dashpot on `pool`: the settling steps, then the timed ones. Returns the
/// seconds of the timed steps (the calling thread's CPU time on a one-thread pool, wall time on
/// more), the centre-of-mass height at the end (m) and the contacts then.
fn dashpot_run<const D: usize>(
    pool: &rayon::ThreadPool,
    make: &(dyn Fn() -> Engine<D> + Sync),
    case: &Case,
) -> (f64, f64, usize) {
    let one = pool.current_num_threads() == 1;
    pool.install(|| {
        let mut e = make();
        e.advance(case.settle as u64).expect("steps");
        let (c, w, all) = (thread_cpu_seconds(), Instant::now(), process_cpu_seconds());
        e.advance(case.steps as u64).expect("steps");
        let t = if one {
            thread_cpu_seconds() - c
        } else {
            // how busy the threads were (waits spin): a wall time far above the CPU time
            // over the threads means they were not given their cores
            let cpu = process_cpu_seconds() - all;
            let wall = w.elapsed().as_secs_f64();
            print!("  (dashpot {wall:.3} s wall, {cpu:.3} s CPU over its threads)");
            wall
        };
        (t, common::com_height(&e), e.contacts())
    })
}

/// One contest: `pairs` alternating pairs of dashpot on `threads` threads and LAMMPS on as many
/// ranks, the ratios printed.
#[allow(clippy::too_many_arguments)]
fn contest<const D: usize>(
    label: &str,
    case: &Case,
    make: &(dyn Fn() -> Engine<D> + Sync),
    venv: &Result<PathBuf, String>,
    data: &Path,
    mass: f64,
    threads: usize,
    pairs: usize,
) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    // dashpot's step and neighbour skin, as the engine chose them, for LAMMPS too
    let (dt, skin) = pool.install(|| {
        let e = make();
        (e.dt(), e.skin())
    });
    let clock = if threads == 1 { "CPU s" } else { "wall s" };
    println!(
        "{label}: {} particles, dt = {dt:.4e} s, {} steps timed after {}, {threads} thread(s) / rank(s), {pairs} pairs ({clock})",
        case.n, case.steps, case.settle
    );
    let (mut ratios, mut td, mut tl) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..pairs {
        // alternate which program goes first
        let mut d = None;
        let mut l = None;
        for turn in 0..2 {
            if (turn + k) % 2 == 0 {
                d = Some(dashpot_run(&pool, make, case));
            } else if let Ok(v) = venv {
                l = Some(lammps(v, case, data, dt, skin, threads));
            }
        }
        let (t, h, contacts) = d.expect("dashpot ran");
        td.push(t);
        let Some(l) = l else {
            println!("  pair {k}: dashpot {t:.3} s, height {h:.6e} m, {contacts} contacts");
            continue;
        };
        assert!(
            (l.mass - mass).abs() <= 1e-12 * mass,
            "LAMMPS's total mass {:e} kg is not dashpot's {mass:e} kg: the particles differ",
            l.mass
        );
        tl.push(l.seconds);
        ratios.push(l.seconds / t);
        println!(
            "  pair {k}: dashpot {t:.3} s, LAMMPS {:.3} s, ratio {:.2}; centre-of-mass height dashpot {h:.6e} m, LAMMPS {:.6e} m ({:+.2} %); {contacts} contacts",
            l.seconds,
            l.seconds / t,
            l.height,
            100.0 * (h / l.height - 1.0)
        );
    }
    let ps = |t: f64| (case.n * case.steps) as f64 / t;
    let tdm = median(&td);
    print!("  dashpot {:.3e} particle-steps/s (median)", ps(tdm));
    if let Err(why) = venv {
        println!("; LAMMPS skipped: {why}");
        return;
    }
    let tlm = median(&tl);
    let lo = ratios.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = ratios.iter().cloned().fold(0.0, f64::max);
    println!(
        ", LAMMPS {:.3e}\n  speed ratio dashpot / LAMMPS: {:.2}x (median of the pairs' ratios; {lo:.2}-{hi:.2})   target >= 2x",
        ps(tlm),
        median(&ratios)
    );
}

/// What every contest of a run shares.
struct Run<'a> {
    reg: &'a dashpot::Registry,
    venv: &'a Result<PathBuf, String>,
    dir: &'a Path,
    threads: &'a [usize],
    pairs: usize,
}

impl Run<'_> {
    /// The contests of one pile (`dim`: "2D" or "3D"), made by `make` from the laws, on each
    /// thread count: its particles `b` written for LAMMPS in a box of corner `hi` (m).
    fn contests<const D: usize>(
        &self,
        dim: &str,
        case: &Case,
        b: &[Body<D>],
        hi: [f64; 3],
        make: &(dyn Fn(Laws) -> Engine<D> + Sync),
    ) {
        let data = self.dir.join(format!("pile{}.data", dim.to_lowercase()));
        let mass = write_data(&data, b, hi, &format!("dashpot DEM benchmark pile, {dim}"));
        let make = || make(laws(self.reg));
        for &t in self.threads {
            contest(
                &format!("{dim} pile, HSD + Mindlin, {t} core(s)"),
                case,
                &make,
                self.venv,
                &data,
                mass,
                t,
                self.pairs,
            );
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let on = |names: &[&str]| {
        let given: Vec<&String> = args.iter().filter(|a| names.contains(&a.as_str())).collect();
        move |name: &str| given.is_empty() || given.iter().any(|a| *a == name)
    };
    let (dim_on, cores_on) = (on(&["2d", "3d"]), on(&["one", "two"]));
    let env = |k: &str, d: usize| std::env::var(k).ok().and_then(|s| s.parse().ok()).unwrap_or(d);
    let pairs = env("DASHPOT_BENCH_PAIRS", 3);
    let reg = full_registry();
    let venv = venv();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/dem_lammps");
    std::fs::create_dir_all(&dir).expect("target/dem_lammps");
    let threads: Vec<usize> = [1, 2]
        .into_iter()
        .filter(|&t| cores_on(if t == 1 { "one" } else { "two" }))
        .collect();

    let run = Run {
        reg: &reg,
        venv: &venv,
        dir: &dir,
        threads: &threads,
        pairs,
    };
    if dim_on("2d") {
        let case = Case {
            n: 2000,
            settle: 5000,
            steps: 3500,
            deck: "in.pile2d",
        };
        let (b, width, height) = common::pile_bodies(case.n);
        let make = |l| common::pile(case.n, l, MAT, true);
        run.contests("2D", &case, &b, [width, height + 1.0, 0.001], &make);
    }
    if dim_on("3d") {
        let case = Case {
            n: 4000,
            settle: 0,
            steps: env("DASHPOT_BENCH_3D_STEPS", 60_000),
            deck: "in.pile3d",
        };
        let (b, side, top) = common::pile3d_bodies(case.n);
        let make = |l| common::pile3d(case.n, l, MAT);
        run.contests("3D", &case, &b, [side, side, top + 0.01], &make);
    }
}
