//! `dashpot bed`, `dashpot scaling` and `dashpot figures bed` as a user runs them.

mod common;

use common::{assert_measured_with_stderr, dashpot, each_fails, fails, ok_json, sh, succeeds};
use serde_json::Value;

#[test]
fn bed_json_reports_the_observables_and_writes_snapshot_and_trace() {
    let dir =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("bed-cli-{}", std::process::id()));
    let snap = dir.join("snap.png");
    let trace = dir.join("trace.csv");
    let o = succeeds(&sh(&format!("bed --restitution mcnamara-falcon --layers 1 --freq 25 --transient 5 --cycles 10 --json --snapshot {} --trace {}", snap.to_str().unwrap(), trace.to_str().unwrap())));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    for k in [
        "pressure",
        "lid_collision_rate",
        "mean_impulse",
        "temperature",
        "events",
        "collisions",
        "events_per_second",
        "tc_firings",
        "max_overlap",
    ] {
        assert!(v.get(k).is_some(), "missing {k}: {v}");
    }
    let (p, nc, di) = (
        v["pressure"].as_f64().unwrap(),
        v["lid_collision_rate"].as_f64().unwrap(),
        v["mean_impulse"].as_f64().unwrap(),
    );
    assert!(p > 0.0 && (p - nc * di / 0.2).abs() < 1e-12 * p);
    assert_eq!(v["disks"], 100);
    assert!(v["collisions"].as_u64().unwrap() < v["events"].as_u64().unwrap());
    // measured over exactly 10 periods
    assert!((v["measured_time"].as_f64().unwrap() - 10.0 / 25.0).abs() < 1e-12);
    assert!(std::fs::read(&snap).unwrap().starts_with(b"\x89PNG"));
    assert!(dir.join("snap.svg").exists());
    let csv = std::fs::read_to_string(&trace).unwrap();
    assert!(csv.starts_with("t,piston_z,kinetic_energy,mean_height,lid_collisions,lid_impulse"));
    // 64 samples per period over 15 periods, plus the one at t = 0
    assert_eq!(csv.lines().count() - 1, 64 * 15 + 1);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn scaling_fits_the_classical_exponents_without_gravity_and_constant_r() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("scaling-cli-{}", std::process::id()));
    let o = succeeds(&sh(&format!("scaling --restitution constant --set r=0.95 --tc 1e-5 --gravity 0 --layers 0.5 --freqs 10:30:3 --transient 5 --cycles 10 --json --out {}", dir.to_str().unwrap())));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // with g = 0 and constant r, V is the only time scale: P ∝ V², Nc ∝ V, ΔI ∝ V
    let th = |k: &str| v["exponents"][0][k]["theta"].as_f64().unwrap();
    assert!((th("pressure") - 2.0).abs() < 0.15, "{v}");
    assert!((th("lid_collision_rate") - 1.0).abs() < 0.15, "{v}");
    assert!((th("mean_impulse") - 1.0).abs() < 0.15, "{v}");
    let csv = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    // after the provenance's comment lines
    assert!(csv
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .starts_with("layers,theta_p,theta_p_stderr,resid_p"));
    assert_eq!(
        std::fs::read_to_string(dir.join("grid.csv"))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .count(),
        4
    );
    assert!(dir.join("theta.png").exists() && dir.join("theta.svg").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_bed_input_is_a_clear_error() {
    each_fails(
        "bed --restitution mcnamara-falcon",
        &[
            ("--layers -1 --freq 20", &["layers n = -1", "n must be > 0"]),
            ("--layers 1 --freq 0", &["f = 0 Hz", "f must be > 0"]),
            ("--layers 1 --freq -3", &["f = -3 Hz"]),
            (
                "--layers 1 --freq 20 --width 0.004",
                &["box is too small", "width L = 0.004"],
            ),
            ("--layers 40 --freq 20 --headroom -0.07", &["box is too small"]),
            ("--layers 1 --freq 20 --tangential 2", &["r_t = 2", "[-1, 1]"]),
            ("--layers 1 --freq 20 --cycles 0", &["--cycles = 0"]),
        ],
    );
    each_fails(
        "",
        &[
            (
                "bed --restitution nope --layers 1 --freq 20",
                &["nope", "mcnamara-falcon"],
            ),
            (
                "bed --restitution hsd --layers 1 --freq 20",
                &["restitution law is needed"],
            ),
            (
                "bed --restitution constant --set r=1.5 --layers 1 --freq 20",
                &["1.5"],
            ),
            (
                "scaling --restitution constant --layers 1 --freqs 10:30",
                &["FROM:TO:COUNT"],
            ),
            (
                "scaling --restitution constant --layers 1,-2 --freqs 10:30:3",
                &["layers n = -2"],
            ),
        ],
    );
}

#[test]
fn a_contact_law_runs_the_bed_as_a_restitution_law() {
    let run = |law: &str, set: &str| -> Value {
        let o = dashpot(&[
            "bed",
            "--restitution",
            law,
            "--set",
            set,
            "--layers",
            "0.5",
            "--freq",
            "25",
            "--transient",
            "2",
            "--cycles",
            "4",
            // a dissipative contact law chatters disks to rest on disks that ride on the piston,
            // which the engine stops on: the TC model prevents it
            "--tc",
            "1e-5",
            "--json",
        ]);
        assert!(
            o.status.success(),
            "{law}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = run("from:kuwabara-kono", "A=2e-6");
    assert!(v["pressure"].as_f64().unwrap() > 0.0);
    assert!(v["collisions"].as_u64().unwrap() > 100);
    // HSD realizes its eps at every speed: as a restitution law it is the constant eps
    let h = run("from:hsd", "eps=0.8");
    assert!(h["pressure"].as_f64().unwrap() > 0.0);
    fails(
        &sh("bed --restitution from:constant --layers 1 --freq 20"),
        &["restitution law, but a contact law is needed"],
    );
    fails(
        &sh("bed --restitution from:nope --layers 1 --freq 20"),
        &["unknown law 'nope'"],
    );
}

/// A run that exits 0 reports no overlap beyond 1e-9 d; one that does not names the disk, the
/// time, and the remedy. Never a result with a larger overlap.
fn trusted_or_clear_error(law: &str, set: &[&str]) {
    let mut args = vec!["bed", "--restitution", law];
    for s in set {
        args.extend(["--set", s]);
    }
    args.extend([
        "--layers",
        "1",
        "--freq",
        "20",
        "--transient",
        "1",
        "--cycles",
        "2",
        "--json",
    ]);
    let o = dashpot(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    if o.status.success() {
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        let ov = v["max_overlap_diameters"].as_f64().unwrap();
        assert!(ov <= 1e-9, "{args:?}: exit 0 with an overlap of {ov:e} d");
        assert!(v["pressure"].as_f64().unwrap() > 0.0);
    } else {
        assert!(
            o.stdout.is_empty(),
            "{args:?}: a result was printed beside the error"
        );
        assert!(err.contains("error") && !err.contains("panicked"), "{err}");
        if err.contains("as a restitution law") {
            // the contact law could not be turned into r(v) at all: refused before the run
            return;
        }
        for needle in ["error", "disk ", "t = ", "--tc"] {
            assert!(err.contains(needle), "{args:?}: no '{needle}' in: {err}");
        }
        assert!(
            err.contains("overlap") && (err.contains(" d") || err.contains(" d)")),
            "{args:?}: the error states the overlap: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn the_issue_cases_finish_without_overlap_or_stop_with_a_clear_error() {
    trusted_or_clear_error("from:hsd", &["eps=0.8"]);
    trusted_or_clear_error("from:kuwabara-kono", &["A=1e-6"]);
    trusted_or_clear_error("constant", &["r=0.8"]);
}

#[test]
fn every_seed_contact_law_as_a_restitution_law_is_trusted_or_stops() {
    for law in [
        "from:lsd",
        "from:hsd",
        "from:kuwabara-kono",
        "from:thornton",
        "from:walton-braun",
    ] {
        trusted_or_clear_error(law, &[]);
    }
    trusted_or_clear_error("mcnamara-falcon", &[]);
    trusted_or_clear_error("constant", &[]);
}

#[test]
fn seeds_run_in_parallel_and_report_standard_errors() {
    let v = ok_json(&sh(
        "bed --restitution mcnamara-falcon --layers 0.5 --freq 25 --transient 2 --cycles 10 --seeds 3 --json",
    ));
    assert_eq!(v["seeds"], 3);
    assert_measured_with_stderr(&v);
    fails(
        &sh("bed --restitution mcnamara-falcon --layers 1 --freq 20 --seeds 0"),
        &["--seeds = 0"],
    );
}

/// A lid out of the disks' reach: no lid collision, so the pressure and the collision rate
/// are 0 (measured) and the mean impulse per collision is not measured: `null` in the JSON, not
/// a 0 that reads as a measurement, on both engines and over seeds.
#[test]
fn a_lid_nobody_reaches_has_no_mean_impulse() {
    let quiet = [
        "bed",
        "--layers",
        "0.5",
        "--freq",
        "10",
        "--headroom",
        "0.5",
        "--transient",
        "2",
        "--cycles",
        "3",
        "--json",
    ];
    let engines: [&[&str]; 3] = [
        &["--restitution", "constant", "--set", "r=0.9"],
        &sh("--restitution constant --set r=0.9 --seeds 2"),
        &sh("--engine dem --law hsd --set eps=0.9 --young 1e7"),
    ];
    for e in engines {
        let args: Vec<&str> = quiet.iter().chain(e.iter()).copied().collect();
        let v = ok_json(&args);
        assert_eq!(v["lid_collision_rate"].as_f64(), Some(0.0), "{e:?}: {v}");
        assert_eq!(v["pressure"].as_f64(), Some(0.0), "{e:?}");
        assert!(v["mean_impulse"].is_null(), "{e:?}: {}", v["mean_impulse"]);
        assert!(v["mean_impulse_stderr"].is_null(), "{e:?}");
        // the disks still press on the piston: their weight, N m g / L
        assert!(v["piston_pressure"].as_f64().unwrap() > 0.0, "{e:?}");
    }
    // in a grid's CSV: an empty cell, not a 0
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("bed-nolid-{}", std::process::id()));
    succeeds(&sh(&format!("scaling --layers 0.5 --freqs 10:12:2 --headroom 0.5 --transient 2 --cycles 3 --restitution constant --set r=0.9 --out {}", out.to_str().unwrap())));
    let csv = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "mean_impulse_n_s").unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{csv}");
        assert_eq!(r[k], "", "{csv}");
        assert_eq!(r[k + 1], "", "{csv}");
    }
}

/// `dem --bed` builds the experiment of `bed --engine dem` from its own options and runs it
/// through the same code: the same values give the same observables and the same steps, to the
/// bit (only the wall times differ).
#[test]
fn dem_bed_is_bed_engine_dem_to_the_bit() {
    let common = "--layers 0.5 --freq 25 --transient 1 --cycles 2 --law hsd --set eps=0.8 --tangential mindlin --tset mu=0.3 --young 1e8 --seed 3 --json";
    let run = |head: &str| ok_json(&sh(&format!("{head} {common}")));
    let (a, b) = (run("bed --engine dem"), run("dem --bed"));
    for k in [
        "pressure",
        "pressure_stderr",
        "lid_collision_rate",
        "mean_impulse",
        "temperature",
        "piston_pressure",
        "measured_time",
        "dt",
        "steps",
        "lid_episodes",
    ] {
        assert!(a[k].is_number(), "{k} missing: {a}");
        assert_eq!(a[k], b[k], "{k}");
    }
    assert_eq!(a["law"], b["law"]);
    assert_eq!(a["tangential"], b["tangential"]);
}
