//! Soft-sphere DEM in 2D against LAMMPS on the same pile with the same physics, one core each:
//! 2,000 polydisperse disks (1.9–2 mm, E = 10⁸ Pa, ν = 0.3, steel density, spheres confined
//! to the plane) settling under gravity on a floor, periodic sideways, HSD (ε = 0.5) + Mindlin
//! (μ = 0.3, history, no tangential damping) between disks and against the floor.
//!
//! LAMMPS runs `examples/dem/lammps/in.pile2d` (`pair_style granular hertz/material ... damping
//! coeff_restitution tangential mindlin NULL 0 μ`, `fix wall/gran` with the same model, `fix
//! enforce2d`) on the very disks dashpot starts from (positions, diameters, velocities written
//! to a data file; the total mass LAMMPS computes is checked against dashpot's), at dashpot's
//! time step and with dashpot's neighbour skin (the engine's default, 0.3 of the smallest diameter). Both settle 5,000 steps, then 3,500 steps are timed: CPU
//! seconds of the measuring thread for dashpot, LAMMPS's loop time × its CPU share. Three
//! rounds, the two programs alternating; best of 3.
//!
//! LAMMPS comes from `$DASHPOT_LAMMPS_VENV` (default: `~/.cache/dashpot/lammps-venv-2025.7.22.4.0`,
//! what `.ci/run` installs); without it the comparison is skipped with the reason printed.
//!
//! Run: `cargo bench -p dashpot-tests --bench dem_lammps`

mod common;

use common::thread_cpu_seconds;
use dashpot::dem::{Body, Engine, Laws, Material};
use dashpot_sdk::ParamValue;
use dashpot_tests::full_registry;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

const N: usize = 2000;
const SETTLE: usize = 5000;
const STEPS: usize = 3500;
const ROUNDS: usize = 3;

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: dashpot::dem::DiskMass::Sphere,
};

fn bodies() -> (Vec<Body<2>>, f64, f64) {
    common::pile_bodies(N)
}

fn engine(reg: &dashpot::Registry) -> Engine<2> {
    let laws = Laws::from_registry(
        reg,
        ("hsd", &[ParamValue::new("eps", 0.5)]),
        Some(("mindlin", &[ParamValue::new("mu", 0.3)])),
        &MAT,
    )
    .expect("laws");
    common::pile(N, laws, MAT, true)
}

/// The pile as a LAMMPS data file (atom_style sphere: id type diameter density x y z).
fn write_data(path: &Path) -> f64 {
    let (b, width, height) = bodies();
    let mut s = String::new();
    let _ = writeln!(s, "dashpot DEM benchmark pile, 2D\n\n{N} atoms\n1 atom types\n");
    let _ = writeln!(s, "0 {width:.17e} xlo xhi");
    let _ = writeln!(s, "-0.01 {:.17e} ylo yhi", height + 1.0);
    let _ = writeln!(s, "-0.001 0.001 zlo zhi\n\nAtoms # sphere\n");
    let mut mass = 0.0;
    for (i, p) in b.iter().enumerate() {
        let _ = writeln!(
            s,
            "{} 1 {:.17e} {:.17e} {:.17e} {:.17e} 0",
            i + 1,
            p.diameter,
            MAT.density,
            p.position.x,
            p.position.y
        );
        // dashpot's own mass of a disk (the convention LAMMPS's total is checked against)
        mass += MAT.mass_inertia(2, p.diameter).0;
    }
    let _ = writeln!(s, "\nVelocities\n");
    for (i, p) in b.iter().enumerate() {
        let _ = writeln!(s, "{} {:.17e} {:.17e} 0 0 0 0", i + 1, p.velocity.x, p.velocity.y);
    }
    std::fs::write(path, s).expect("write the data file");
    mass
}

fn venv() -> Result<PathBuf, String> {
    let v = match std::env::var_os("DASHPOT_LAMMPS_VENV") {
        Some(v) => PathBuf::from(v),
        None => PathBuf::from(std::env::var_os("HOME").ok_or("no HOME")?)
            .join(".cache/dashpot/lammps-venv-2025.7.22.4.0"),
    };
    if v.join("bin/lmp").is_file() {
        Ok(v)
    } else {
        Err(format!(
            "no LAMMPS at {} (run .ci/run once, or set DASHPOT_LAMMPS_VENV)",
            v.display()
        ))
    }
}

/// Runs the deck; returns (CPU seconds of the timed loop, total mass, final position of atom 1).
fn lammps(venv: &Path, data: &Path, dt: f64, skin: f64) -> (f64, f64, [f64; 2]) {
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/dem/lammps/in.pile2d");
    let out = Command::new(venv.join("bin/lmp"))
        .arg("-in")
        .arg(&deck)
        .args(["-log", "none", "-var", "data"])
        .arg(data)
        .args(["-var", "dt", &format!("{dt:.17e}")])
        .args(["-var", "skin", &format!("{skin:.17e}")])
        .args(["-var", "settle", &SETTLE.to_string()])
        .args(["-var", "nsteps", &STEPS.to_string()])
        .env("OMP_NUM_THREADS", "1")
        .output()
        .expect("run lmp");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "LAMMPS failed:\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let loops: Vec<&str> = text.lines().filter(|l| l.starts_with("Loop time of")).collect();
    let last = loops.last().expect("a loop time");
    // "Loop time of T on 1 procs for S steps with N atoms"
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
    let grab = |key: &str| -> Vec<f64> {
        text.lines()
            .find(|l| l.starts_with(key))
            .map(|l| {
                l.split_whitespace()
                    .skip(1)
                    .filter_map(|x| x.parse().ok())
                    .collect()
            })
            .unwrap_or_default()
    };
    let m = grab("TOTAL_MASS");
    let x = grab("FINAL_X1");
    (t * cpu_share, m[0], [x[0], x[1]])
}

fn main() {
    let reg = full_registry();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let venv = venv();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/dem_lammps");
    std::fs::create_dir_all(&dir).expect("target/dem_lammps");
    let data = dir.join("pile2d.data");
    let mass = write_data(&data);
    // dashpot's step and neighbour skin, as the engine chose them, for LAMMPS too
    let (dt, skin) = one.install(|| {
        let e = engine(&reg);
        (e.dt(), e.skin())
    });

    let (mut td, mut tl) = (Vec::new(), Vec::new());
    let mut contacts = 0;
    for round in 0..ROUNDS {
        let (t, c, x) = one.install(|| {
            let mut e = engine(&reg);
            e.advance(SETTLE as u64).expect("steps");
            let s = thread_cpu_seconds();
            e.advance(STEPS as u64).expect("steps");
            (thread_cpu_seconds() - s, e.contacts(), e.p.pos[0])
        });
        td.push(t);
        contacts = c;
        let Ok(venv) = &venv else { continue };
        let (tl_, m, xl) = lammps(venv, &data, dt, skin);
        tl.push(tl_);
        assert!(
            (m - mass).abs() <= 1e-12 * mass,
            "LAMMPS's total mass {m:e} kg is not dashpot's {mass:e} kg: the disks differ"
        );
        if round == 0 {
            println!(
                "disk 1 after {} steps: dashpot ({:.6e}, {:.6e}) m, LAMMPS ({:.6e}, {:.6e}) m (a chaotic pile: a consistency check, not a test)",
                SETTLE + STEPS,
                x.x,
                x.y,
                xl[0],
                xl[1]
            );
        }
    }
    td.sort_by(f64::total_cmp);
    tl.sort_by(f64::total_cmp);
    let ps = |t: f64| (N * STEPS) as f64 / t;
    println!(
        "2D pile, {N} disks, HSD + Mindlin (eps = 0.5, mu = 0.3), dt = {dt:.3e} s, {STEPS} steps after {SETTLE}, one core, best of {ROUNDS} (CPU time)"
    );
    println!(
        "  dashpot (plugins)  {:.3e} particle-steps/s   ({contacts} contacts at the end)",
        ps(td[0])
    );
    if let Err(why) = &venv {
        println!("  LAMMPS: skipped: {why}");
        return;
    }
    println!("  LAMMPS granular    {:.3e} particle-steps/s", ps(tl[0]));
    println!(
        "  speed ratio dashpot / LAMMPS: {:.2}x (best) | {:.2}x (median)   target >= 2x",
        tl[0] / td[0],
        tl[ROUNDS / 2] / td[ROUNDS / 2]
    );
}
