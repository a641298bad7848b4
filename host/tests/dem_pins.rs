//! The example scenes' results, pinned bit for bit: each scene of `examples/dem/` (some cut
//! short) and a few variants that take the engine's other paths (a 3D pile of small chunks
//! kept in the engine's own order and stepped in parallel, an adhesive law with a vibrated
//! floor, the DEM vibrated bed) run through `dashpot dem --json` (or `dashpot bed --engine dem
//! --json`), and a digest of everything the run reports but the timings and the plugins' paths
//! must equal the one recorded in `tests/fixtures/dem_pins.txt`. `DASHPOT_PIN_BIN=PATH` runs
//! another build's `dashpot` instead (with `DASHPOT_WRITE_PINS=1`: records that build's pins;
//! `DASHPOT_PIN_PROFILE=release` for a release build's).
//!
//! What it guards: a one-species scene with flat walls must run exactly as it did before
//! species, per-pair laws, curved and moving walls and checkpoints came to the engine (and as
//! it will after whatever comes next). A change that moves these bits on purpose (a new
//! summation order, a physics fix) records the new digests with `DASHPOT_WRITE_PINS=1 cargo
//! test -p dashpot --test dem_pins` and says why in its commit.

mod common;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The recorded digests.
fn pins_file() -> PathBuf {
    root().join("host/tests/fixtures/dem_pins.txt")
}

/// `dashpot ARGS` with every plugin of the workspace; its JSON output.
fn run(args: &[&str]) -> Value {
    // (DASHPOT_PIN_BIN: another build's binary, to record the pins of the code it was built from)
    let bin = std::env::var_os("DASHPOT_PIN_BIN").unwrap_or(env!("CARGO_BIN_EXE_dashpot").into());
    let out = Command::new(bin)
        .arg("--no-default-plugins")
        .arg("--plugin-dir")
        .arg(common::all_plugins_dir())
        .args(args)
        .env_remove("DASHPOT_PLUGIN_PATH")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "dashpot {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// FNV-1a, 64 bits.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The keys of `dashpot dem --json` the digest reads: the results (a key added to the output
/// later does not move the pins; one of these changing does).
const DEM_KEYS: [&str; 18] = [
    "particles",
    "dt",
    "steps",
    "time",
    "energy",
    "energies",
    "contacts",
    "pair_contacts",
    "wall_contacts",
    "pair_episodes",
    "neighbour_rebuilds",
    "collision_time",
    "impact_speed",
    "dt_given",
    "mean_velocity",
    "energy_initial",
    "elastic",
    "dissipated",
];

/// The digest of a run's JSON: for `dem`, the keys [`DEM_KEYS`]; for others every key but the
/// wall-clock ones (`wall_seconds`, `wall_per_simulated_second`, ...) and the provenance; floats as serde_json writes them (the shortest text that reads back to the
/// same bits: equal text, equal bits).
fn digest(v: &Value) -> String {
    let m = v.as_object().expect("a JSON object");
    let kept: serde_json::Map<String, Value> = if m.contains_key("particles") {
        DEM_KEYS
            .iter()
            .map(|&k| {
                (
                    k.to_string(),
                    m.get(k).cloned().unwrap_or_else(|| panic!("no key {k}")),
                )
            })
            .collect()
    } else {
        m.iter()
            .filter(|(k, _)| !(k.contains("second") || k.as_str() == "provenance"))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect()
    };
    format!("{:016x}", fnv(serde_json::to_string(&kept).unwrap().as_bytes()))
}

/// An example scene with `edits` applied to its text (`key = value` lines replaced), written
/// to the scratch directory.
fn example(name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text = std::fs::read_to_string(root().join("examples/dem").join(name)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{name}: no '{from}' to edit");
        text = text.replacen(from, to, 1);
    }
    common::scene(&format!("pin-{name}"), &text)
}

/// A 2D pile of 400 disks under JKR (w = 0.05 J/m²) with Mindlin friction on a floor that
/// vibrates (a sine of 0.5 mm at 40 Hz), periodic sideways.
const ADHESIVE_2D: &str = r#"
dimension = 2
gravity = [0.0, -9.81]
duration = 0.01
[law]
name = "jkr"
params = { w = 0.05 }
[tangential]
name = "mindlin"
params = { mu = 0.3 }
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
[box]
lo = [0.0, -0.01]
hi = [0.05, 0.1]
periodic = [true, false]
[[wall]]
point = [0.0, 0.0]
normal = [0.0, 1.0]
motion = { kind = "sine", amplitude = 5e-4, frequency = 40.0 }
[generate]
count = 400
diameter = [0.0018, 0.0022]
lo = [0.0, 0.0006]
hi = [0.05, 0.1]
speed = 0.05
seed = 11
"#;

/// Every pinned run: its name and the JSON it printed.
fn runs() -> Vec<(String, Value)> {
    let scene = |p: &Path| -> Value { run(&["dem", "--scene", p.to_str().unwrap(), "--json"]) };
    vec![
        ("drop".into(), scene(&example("drop.toml", &[]))),
        (
            "pile2d".into(),
            scene(&example("pile2d.toml", &[("duration = 0.05", "duration = 0.01")])),
        ),
        ("rolling-pile".into(), scene(&example("rolling-pile.toml", &[]))),
        ("spheres3d".into(), scene(&example("spheres3d.toml", &[]))),
        // 1,600 spheres: 16 small chunks, the slab order, the parallel pipeline
        (
            "spheres3d-small-chunks".into(),
            scene(&example(
                "spheres3d.toml",
                &[
                    ("duration = 0.02", "duration = 0.004"),
                    ("count = 500", "count = 1600"),
                    ("hi = [0.03, 0.03, 0.05]", "hi = [0.03, 0.03, 0.1]"),
                ],
            )),
        ),
        (
            "adhesive-2d".into(),
            scene(&common::scene("pin-adhesive.toml", ADHESIVE_2D)),
        ),
        (
            "energy-off".into(),
            scene(&example(
                "rolling-pile.toml",
                &[("duration = 0.02", "duration = 0.005\nenergy = false")],
            )),
        ),
        (
            "dem-bed".into(),
            run(&[
                "bed",
                "--engine",
                "dem",
                "--law",
                "hsd",
                "--set",
                "eps=0.9",
                "--young",
                "1e8",
                "--layers",
                "0.5",
                "--freq",
                "20",
                "--transient",
                "0.5",
                "--cycles",
                "1",
                "--json",
            ]),
        ),
    ]
}

/// The build profile of the binary the pins are for: `dev` (what `cargo test` builds, with
/// debug assertions) or `release`. The two profiles' bits differ (the host's arithmetic is
/// compiled differently at opt-level 1 and 3), so each has its own pins.
fn profile() -> &'static str {
    match std::env::var("DASHPOT_PIN_PROFILE") {
        Ok(p) if p == "release" => "release",
        Ok(p) if p == "dev" => "dev",
        _ if cfg!(debug_assertions) => "dev",
        _ => "release",
    }
}

#[test]
fn the_example_scenes_run_bit_for_bit_as_pinned() {
    let got: Vec<(String, String)> = runs().iter().map(|(n, v)| (n.clone(), digest(v))).collect();
    let text = std::fs::read_to_string(pins_file()).unwrap_or_default();
    let mut lines: Vec<(String, String, String)> = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(f.len(), 3, "a pin is 'profile name digest': {l}");
            (f[0].to_string(), f[1].to_string(), f[2].to_string())
        })
        .collect();
    let me = profile();
    if std::env::var_os("DASHPOT_WRITE_PINS").is_some() {
        lines.retain(|(p, _, _)| p != me);
        lines.extend(got.iter().map(|(n, d)| (me.to_string(), n.clone(), d.clone())));
        lines.sort_by(|a, b| a.0.cmp(&b.0));
        let body: String = lines.iter().map(|(p, n, d)| format!("{p} {n} {d}\n")).collect();
        std::fs::write(
            pins_file(),
            format!("# profile run digest (host/tests/dem_pins.rs)\n{body}"),
        )
        .unwrap();
        return;
    }
    let pinned: Vec<(&str, &str)> = lines
        .iter()
        .filter(|(p, _, _)| p == me)
        .map(|(_, n, d)| (n.as_str(), d.as_str()))
        .collect();
    assert_eq!(pinned.len(), got.len(), "one pin per run for the {me} profile");
    let moved: Vec<String> = got
        .iter()
        .zip(&pinned)
        .filter(|((n, d), (pn, pd))| n != pn || d != pd)
        .map(|((n, d), (_, pd))| format!("{n}: {d}, pinned {pd}"))
        .collect();
    assert!(
        moved.is_empty(),
        "runs no longer bit for bit as pinned ({me} profile):\n{}",
        moved.join("\n")
    );
}
