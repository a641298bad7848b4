//! `dashpot bed`, `dashpot scaling` and `dashpot figures bed` as a user runs them.

mod common;

use common::{assert_measured_with_stderr, dashpot, each_fails, fails, ok_json, sh, succeeds};
use serde_json::Value;

#[test]
fn bed_json_reports_the_observables_and_writes_snapshot_and_trace() {
    let dir = std::env::temp_dir().join(format!("dashpot-bed-cli-{}", std::process::id()));
    let snap = dir.join("snap.png");
    let trace = dir.join("trace.csv");
    let o = succeeds(&sh(&format!("bed --restitution mcnamara-falcon --layers 1 --freq 25 --transient 5 --cycles 10 --json --snapshot {} --trace {}", snap.to_str().unwrap(), trace.to_str().unwrap())));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
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
    let out = std::env::temp_dir().join(format!("dashpot-bed-nolid-{}", std::process::id()));
    let o = succeeds(&sh(&format!("scaling --layers 0.5 --freqs 10:12:2 --headroom 0.5 --transient 2 --cycles 3 --restitution constant --set r=0.9 --out {}", out.to_str().unwrap())));
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
