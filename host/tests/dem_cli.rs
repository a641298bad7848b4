//! `dashpot dem --scene` as a user runs it: the JSON state, the trajectory, and bad scenes.

mod common;

use common::{fails, ok_json, scene};
use std::path::Path;

/// The arguments of `dashpot dem --scene SCENE --out OUT` followed by `extra`.
fn scene_to<'a>(scene: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "dem",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    args
}

const FREE_FALL: &str = r#"
dimension = 2
gravity = [0.0, -9.81]
duration = 0.01
dt = 1e-5
[law]
name = "hsd"
params = { eps = 0.5 }
[material]
young = 1.0e8
poisson = 0.3
density = 7800.0
[[wall]]
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[particle]]
position = [0.0, 0.05]
velocity = [0.3, 0.0]
angular_velocity = 2.0
diameter = 0.002
"#;

#[test]
fn a_free_flight_follows_the_parabola_and_the_json_has_the_state() {
    let p = scene("free.toml", FREE_FALL);
    let v = ok_json(&["dem", "--scene", p.to_str().unwrap(), "--json"]);
    let t = v["time"].as_f64().unwrap();
    assert_eq!(v["steps"].as_u64().unwrap(), 1000);
    assert!((t - 0.01).abs() < 1e-12);
    let part = &v["particles"][0];
    let x = part["position"][0].as_f64().unwrap();
    let y = part["position"][1].as_f64().unwrap();
    // velocity Verlet is exact under constant acceleration
    assert!((x - 0.3 * t).abs() < 1e-14);
    assert!((y - (0.05 - 0.5 * 9.81 * t * t)).abs() < 1e-13);
    assert!((part["velocity"][1].as_f64().unwrap() + 9.81 * t).abs() < 1e-12);
    assert_eq!(part["angular_velocity"].as_f64().unwrap(), 2.0);
    assert_eq!(part["diameter"].as_f64().unwrap(), 0.002);
    assert_eq!(v["contacts"].as_u64().unwrap(), 0);
    assert_eq!(v["dt"].as_f64().unwrap(), 1e-5);
    // energy: kinetic + potential is conserved in free flight
    let m = std::f64::consts::PI / 6.0 * 7800.0 * 0.002f64.powi(3);
    let i = 0.4 * m * 1e-6;
    let e0 = 0.5 * m * 0.09 + 0.5 * i * 4.0 + m * 9.81 * 0.05;
    assert!((v["energy"].as_f64().unwrap() - e0).abs() < 1e-12 * e0);
}

#[test]
fn the_trajectory_has_one_frame_per_snapshot_plus_the_start() {
    // 1,000 steps exactly, and a duration of 1,000.42 steps: the run takes 1,000 (it stops once
    // t + dt/2 passes the duration), and the last frame must still be written, at the end
    for (k, duration) in ["0.01", "0.0100042"].into_iter().enumerate() {
        frames_of(k, duration);
    }
}

/// Runs the scene `text` (written as `name`) with `--out` and `--json`: its JSON, its output
/// directory and the trajectory's text.
fn run_with_trajectory(name: &str, text: &str) -> (serde_json::Value, std::path::PathBuf, String) {
    let p = scene(name, text);
    let out = p.with_extension("out");
    let v = ok_json(&scene_to(&p, &out, &["--json"]));
    let xyz = std::fs::read_to_string(out.join("trajectory.xyz")).unwrap();
    (v, out, xyz)
}

fn frames_of(k: usize, duration: &str) {
    let (v, out, xyz) = run_with_trajectory(
        &format!("traj{k}.toml"),
        &FREE_FALL
            .replace("dt = 1e-5", "dt = 1e-5\nsnapshots = 4")
            .replace("duration = 0.01", &format!("duration = {duration}")),
    );
    let frames = xyz.lines().filter(|l| l.starts_with("Lattice=")).count();
    assert_eq!(frames, 5, "duration {duration}");
    assert_eq!(v["steps"], 1000, "duration {duration}");
    assert!(xyz.contains("Properties=species:S:1:pos:R:3:velo:R:3:omega:R:3:radius:R:1:power:R:1 "));
    let last: Vec<f64> = xyz
        .lines()
        .last()
        .unwrap()
        .split_whitespace()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    assert!((last[1] - v["particles"][0]["position"][1].as_f64().unwrap()).abs() < 1e-12);
    let fin: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("final.json")).unwrap()).unwrap();
    assert_eq!(fin["steps"], v["steps"]);
}

#[test]
fn energy_false_skips_the_accounting_and_reports_null_not_zeros() {
    let (v, _, xyz) = run_with_trajectory(
        "no_energy.toml",
        &FREE_FALL.replace("dt = 1e-5", "dt = 1e-5\nsnapshots = 1\nenergy = false"),
    );
    for key in ["energy_initial", "elastic", "dissipated"] {
        assert!(v[key].is_null(), "{key} = {}", v[key]);
    }
    // the mechanical energy is the engine's own, still reported
    assert!(v["energy"].as_f64().unwrap() > 0.0);
    assert!(xyz.contains(":radius:R:1 Time=") && !xyz.contains("power"));
    // and the same scene with the accounting on reports them
    let q = scene("energy.toml", FREE_FALL);
    let w = ok_json(&scene_to(&q, &q.with_extension("out"), &["--json"]));
    assert!(w["dissipated"]["total"].as_f64().is_some() && w["energy_initial"].as_f64().is_some());
}

#[test]
fn png_frames_are_drawn_beside_the_trajectory() {
    let p = scene(
        "png.toml",
        &FREE_FALL.replace("dt = 1e-5", "dt = 1e-5\nsnapshots = 2"),
    );
    let out = p.with_extension("pngout");
    ok_json(&scene_to(&p, &out, &["--json", "--png"]));
    // one picture per trajectory frame (the start and 2 snapshots), each a PNG
    for k in 0..3 {
        let f = out.join(format!("frame_{k:04}.png"));
        let bytes = std::fs::read(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        assert!(out.join(format!("frame_{k:04}.svg")).exists());
    }
    assert!(!out.join("frame_0003.png").exists());
    // --png without --out is refused
    common::fails(&["dem", "--scene", p.to_str().unwrap(), "--png"], &["--out"]);
}

#[test]
fn bad_scenes_name_the_key_and_the_value() {
    let cases: [(&str, &str, &[&str]); 7] = [
        ("dimension = 2", "dimension = 4", &["dimension = 4", "2", "3"]),
        (
            "diameter = 0.002",
            "diameter = -0.002",
            &["particle[0].diameter = -0.002", "> 0"],
        ),
        (
            "position = [0.0, 0.05]",
            "position = [0.0, 0.05, 0.0]",
            &["particle[0].position", "3 components"],
        ),
        (
            "young = 1.0e8",
            "young = 1.0e8\nyoung_modulus = 3.0",
            &["young_modulus"],
        ),
        ("name = \"hsd\"", "name = \"no-such-law\"", &["no-such-law"]),
        ("duration = 0.01", "duration = -1.0", &["duration = -1", "> 0"]),
        ("poisson = 0.3", "poisson = 0.7", &["poisson = 0.7", "(-1, 0.5)"]),
    ];
    for (k, (from, to, needles)) in cases.iter().enumerate() {
        let p = scene(&format!("bad{k}.toml"), &FREE_FALL.replace(from, to));
        fails(&["dem", "--scene", p.to_str().unwrap()], needles);
    }
    // a step far too large for the impact: refused before the run (0.04 steps per collision
    // at the expected 6 m/s, where the explicit step is unstable below 2), with the bound
    let impact = FREE_FALL
        .replace("velocity = [0.3, 0.0]", "velocity = [0.0, -3.0]")
        .replace("position = [0.0, 0.05]", "position = [0.0, 0.0011]");
    let p = scene("coarse.toml", &impact.replace("dt = 1e-5", "dt = 2e-3"));
    fails(
        &["dem", "--scene", p.to_str().unwrap()],
        &["dt = 2e-3 s is out of range", "steps", "dt must be <= 4.2"],
    );
    let p = scene(
        "coarse-chosen.toml",
        &impact.replace("dt = 1e-5", "steps_per_collision = 1.5"),
    );
    fails(
        &["dem", "--scene", p.to_str().unwrap()],
        &["steps_per_collision = 1.5", ">= 2"],
    );
    // the same step let through by an impact speed given far too low (2.4 steps per collision
    // at 1 mm/s, a warning): the real impact at 3 m/s is refused as an unphysical overlap, not
    // reported
    let p = scene(
        "overlap.toml",
        &impact.replace("dt = 1e-5", "dt = 2e-4\nimpact_speed = 1e-3"),
    );
    fails(
        &["dem", "--scene", p.to_str().unwrap()],
        &[
            "steps per collision",
            "barely resolved",
            "overlaps wall 0",
            "time step",
        ],
    );
    // and a run that fails after its first frames leaves no trajectory behind, not half of one
    let out = p.with_extension("out");
    let _ = std::fs::remove_dir_all(&out);
    fails(&scene_to(&p, &out, &[]), &["overlaps wall 0"]);
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|f| f.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "a failed run left {left:?}");
}

/// Two species with laws of their own per pair: `--check` names the species (with their
/// particles and materials), every class of contacts with its laws and the walls; the run's
/// JSON names each particle's species and lists the classes.
#[test]
fn check_and_json_report_species_pairs_and_walls() {
    let text = r#"
dimension = 2
gravity = [0.0, -9.81]
duration = 0.002
[law]
name = "hsd"
params = { eps = 0.9 }
[[species]]
name = "steel"
young = 2.0e8
poisson = 0.3
density = 7800.0
[[species]]
name = "rubber"
young = 1.0e7
poisson = 0.45
density = 1100.0
[[pair]]
species = "rubber"
[pair.law]
name = "kuwabara-kono"
params = { A = 2e-6 }
[[pair]]
species = "steel"
wall = "floor"
[pair.law]
name = "hsd"
params = { eps = 0.5 }
[pair.tangential]
name = "mindlin"
params = { mu = 0.3 }
[[wall]]
name = "floor"
point = [0.0, 0.0]
normal = [0.0, 1.0]
material = "steel"
[[particle]]
species = "steel"
position = [0.0, 0.0011]
diameter = 0.002
[[particle]]
species = "rubber"
position = [0.01, 0.0011]
diameter = 0.002
[[particle]]
species = "rubber"
position = [0.01, 0.0032]
diameter = 0.002
"#;
    let p = scene("species.toml", text);
    let out = common::succeeds(&["dem", "--scene", p.to_str().unwrap(), "--check"]);
    let said = String::from_utf8_lossy(&out.stdout).to_string();
    for needle in [
        "species 'steel': 1 particles",
        "species 'rubber': 2 particles",
        "particle pairs rubber–rubber: kuwabara-kono",
        "wall pairs steel–wall 0 ('floor'): hsd (eps = 0.5) + mindlin (mu = 0.3)",
        "wall pairs rubber–wall 0 ('floor'): hsd",
        "wall 0: plane through",
    ] {
        assert!(said.contains(needle), "'{needle}' not in:\n{said}");
    }
    let v = ok_json(&["dem", "--scene", p.to_str().unwrap(), "--json"]);
    let species: Vec<&str> = v["particles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["species"].as_str().unwrap())
        .collect();
    assert_eq!(species, ["steel", "rubber", "rubber"]);
    assert_eq!(v["law"], "hsd");
    assert_eq!(v["pairs"]["species"][1]["name"], "rubber");
    let walls = v["pairs"]["wall_pairs"].as_array().unwrap();
    assert_eq!(walls.len(), 2, "{walls:?}");
    // without the default law, the pair that has none is refused before the first step
    let bare = text.replacen("[law]\nname = \"hsd\"\nparams = { eps = 0.9 }\n", "", 1);
    let p = scene("species-bare.toml", &bare);
    fails(
        &["dem", "--scene", p.to_str().unwrap()],
        &["no law for the pair (steel, rubber)", "[[pair]]"],
    );
}
