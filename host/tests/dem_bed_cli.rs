//! `dashpot bed --engine dem` and `dashpot scaling --engine dem` as a user runs them: the
//! event-driven bed's keys, the physics they must obey, and each engine's options refused by the
//! other with the value named.

mod common;

use common::{assert_measured_with_stderr, dashpot, each_fails, fails, ok_json, sh};
use serde_json::Value;

/// A short DEM bed run (JSON): n = 0.5, f = 25 Hz, 1 + 4 periods unless `extra` says otherwise.
fn dem(extra: &[&str]) -> (Value, String) {
    let mut args = vec!["bed", "--engine", "dem", "--json"];
    for (k, v) in [
        ("--layers", "0.5"),
        ("--freq", "25"),
        ("--transient", "1"),
        ("--cycles", "4"),
    ] {
        if !extra.contains(&k) {
            args.extend_from_slice(&[k, v]);
        }
    }
    args.extend_from_slice(extra);
    let o = dashpot(&args);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{args:?}: {err}");
    (serde_json::from_slice(&o.stdout).unwrap(), err)
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("key {k} missing in {v}"))
}

#[test]
fn the_dem_bed_reports_the_event_beds_keys_and_obeys_the_momentum_balance() {
    let (v, err) = dem(&["--law", "hsd", "--set", "eps=0.9", "--young", "1e8"]);
    assert_eq!(v["engine"], "dem");
    assert_eq!(v["law"]["name"], "hsd");
    assert_eq!(v["law"]["params"]["eps"], 0.9);
    assert_measured_with_stderr(&v);
    // P = Nc ΔI / L: the pressure is the rate of episodes times the impulse per episode
    let (p, nc, di) = (
        f(&v, "pressure"),
        f(&v, "lid_collision_rate"),
        f(&v, "mean_impulse"),
    );
    assert!((nc * di / 0.2 - p).abs() < 1e-9 * p, "{p} vs {}", nc * di / 0.2);
    // time-averaged momentum balance of the disks: the piston carries the lid's push and the
    // disks' weight (the disks' momentum at the ends of the measured time is bounded)
    let (n, m, g, l) = (50.0, 3.27e-5, 9.8, 0.2);
    let (pp, ppe, pe) = (
        f(&v, "piston_pressure"),
        f(&v, "piston_pressure_stderr"),
        f(&v, "pressure_stderr"),
    );
    let expect = p + n * m * g / l;
    assert!(
        (pp - expect).abs() < 4.0 * (ppe * ppe + pe * pe).sqrt(),
        "piston {pp} ± {ppe}, lid + weight {expect}"
    );
    // the step: the contact time / 50, printed with the contact time
    let (dt, tau) = (f(&v, "dt"), f(&v, "collision_time"));
    assert!((tau / dt - 50.0).abs() < 1e-9);
    assert!(err.contains("dt = ") && err.contains("contact time"), "{err}");
    assert_eq!(v["disks"], 50);
    assert_eq!(f(&v, "young"), 1e8);
    // the disks carry the bed's mass: the density follows from it
    let rho = f(&v, "density");
    assert!((rho * std::f64::consts::PI / 6.0 * 8e-9 - 3.27e-5).abs() < 1e-15);
}

#[test]
fn young_sets_the_step_by_hertz_scaling() {
    // Hertz: τ ∝ (m² / (r E² v))^{1/5}, so τ(E) / τ(10 E) = 10^{2/5}, HSD's damping scaling alike
    let run = |e: &str| {
        dem(&[
            "--law",
            "hsd",
            "--set",
            "eps=0.9",
            "--young",
            e,
            "--transient",
            "0",
            "--cycles",
            "0.02",
        ])
        .0
    };
    let (soft, hard) = (run("1e8"), run("1e9"));
    let ratio = f(&soft, "collision_time") / f(&hard, "collision_time");
    assert!((ratio - 10f64.powf(0.4)).abs() < 1e-5, "ratio {ratio}");
    // steel by default
    let steel = run("2e11");
    let (d, _) = dem(&sh("--law hsd --set eps=0.9 --transient 0 --cycles 0.02"));
    assert_eq!(f(&d, "young"), 2e11);
    assert_eq!(f(&d, "dt"), f(&steel, "dt"));
}

#[test]
fn young_and_poisson_reach_a_contact_laws_restitution_table() {
    // the event-driven bed's from:LAW table for E = 1e8 Pa, ν = 0.25 is the collision driver's
    // restitution for those disks (identical spheres, and a sphere on a wall)
    let kk = "bed --restitution from:kuwabara-kono --set A=2e-6 --layers 0.5 --freq 25 --transient 1 --cycles 2 --tc 1e-5 --json";
    let v = ok_json(&sh(&format!("{kk} --young 1e8 --poisson 0.25")));
    assert_eq!(v["engine"], "event");
    assert_eq!(f(&v, "young"), 1e8);
    assert_eq!(f(&v, "poisson"), 0.25);
    let row = v["restitution_used"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["speed"] == 1.0)
        .unwrap()
        .clone();
    let density = format!("{}", 3.27e-5 / (std::f64::consts::PI / 6.0 * 8e-9));
    for (wall, key) in [(false, "disk_disk"), (true, "disk_wall")] {
        let line = format!("collide --law kuwabara-kono --set A=2e-6 --diameter 0.002 --density {density} --young 1e8 --poisson 0.25 --v0 1 --end force --json");
        let mut args = sh(&line);
        if wall {
            args.push("--wall");
        }
        let c = ok_json(&args);
        let (a, b) = (f(&c, "restitution"), row[key].as_f64().unwrap());
        assert!((a - b).abs() < 2e-6, "{key}: driver {a}, table {b}");
    }
    // and steel's table differs: a stiffer disk dissipates more under Kuwabara–Kono (1 − ε grows
    // as (E_eff √R / m)^{2/5} v^{1/5}), so steel's ε(1 m/s) is the lower one
    let s = ok_json(&sh(kk));
    let steel = s["restitution_used"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["speed"] == 1.0)
        .unwrap()["disk_disk"]
        .as_f64()
        .unwrap();
    let soft = row["disk_disk"].as_f64().unwrap();
    assert!(steel < soft - 1e-3, "steel {steel}, E = 1e8 Pa {soft}");
}

#[test]
fn scaling_on_the_dem_engine_runs_the_beds_runs() {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("dem-scaling-{}", std::process::id()));
    let out_s = out.to_string_lossy().to_string();
    let rows = ok_json(&sh(&format!(
        "scaling --engine dem --law hsd --set eps=0.9 --young 1e8 --layers 0.5 --freqs 20:30:2 --transient 1 --cycles 2 --out {out_s} --json"
    )));
    assert_eq!(rows["exponents"].as_array().unwrap().len(), 1);
    assert!(rows["exponents"][0]["pressure"]["theta"]
        .as_f64()
        .unwrap()
        .is_finite());
    let grid = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    let lines: Vec<&str> = grid.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 3);
    assert!(lines[0].contains("dt_s") && lines[0].contains("pressure_stderr"));
    // the grid's run at f = 30 Hz is the bed's run at f = 30 Hz (same seed, same engine)
    let (v, _) = dem(&sh(
        "--law hsd --set eps=0.9 --young 1e8 --freq 30 --transient 1 --cycles 2",
    ));
    let p: f64 = lines[2].split(',').nth(3).unwrap().parse().unwrap();
    assert_eq!(p, f(&v, "pressure"));
}

/// What both `bed --engine dem` and `dem --bed` (after `--law hsd`) refuse, with what the error
/// must name.
const DEM_BED_REFUSES: &[(&str, &[&str])] = &[
    ("--young -5", &["--young = -5", "> 0"]),
    ("--poisson 0.7", &["--poisson = 0.7", "(-1, 0.5)"]),
    ("--set eps=1.5", &["eps", "1.5", "(0, 1]"]),
    ("--set eps=abc", &["abc"]),
    ("--tset mu=0.3", &["--tset", "--tangential"]),
    ("--tangential 0.5", &["--tangential 0.5", "mindlin"]),
    ("--transient -1", &["--transient = -1", ">= 0"]),
    ("--dt 0", &["--dt = 0"]),
    (
        "--dt 1e-3",
        &["dt = 1e-3 s is out of range", "steps", "dt must be <="],
    ),
    ("--tc 1e-5", &["--tc"]),
];

#[test]
fn each_engines_options_are_refused_by_the_other() {
    each_fails(
        "bed --layers 0.5 --freq 20 --cycles 1",
        &[
            ("--engine dem", &["--law"]),
            ("--engine dem --law nosuch", &["nosuch"]),
            (
                "--engine dem --law hsd --restitution constant",
                &["--restitution constant"],
            ),
            ("--law hsd --restitution constant", &["--law hsd", "--engine dem"]),
            ("--restitution constant --dt 1e-6", &["--dt"]),
            ("--restitution constant --young 1e8", &["from:LAW", "constant"]),
            (
                "--restitution constant --tangential mindlin",
                &["'mindlin'", "r_t"],
            ),
            // steps that cannot resolve a collision: the explicit step is unstable below 2 per
            // collision
            (
                "--engine dem --law hsd --steps-per-collision 1.5",
                &["--steps-per-collision = 1.5", ">= 2"],
            ),
        ],
    );
    each_fails(
        "bed --layers 0.5 --freq 20 --cycles 1 --engine dem --law hsd",
        DEM_BED_REFUSES,
    );
    // a measuring window shorter than a step would report 0/0 rates
    fails(
        &sh("bed --engine dem --law hsd --layers 0.5 --freq 20 --cycles 1e-7"),
        &["cycles = 0.0000001", "at least one step"],
    );
}

/// `dem --bed` is `bed --engine dem` under another name: the same checks refuse the same
/// values (it once parsed its options itself and let a negative modulus or an unphysical
/// Poisson's ratio through to the engine).
#[test]
fn dem_bed_takes_the_checks_of_bed_engine_dem() {
    each_fails(
        "dem --bed --layers 0.5 --freq 20 --cycles 1 --law hsd",
        DEM_BED_REFUSES,
    );
}
