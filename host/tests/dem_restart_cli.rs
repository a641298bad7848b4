//! `dashpot dem --checkpoint-every` and `--restart` as a user runs them: a run written to
//! checkpoints ends as the plain run does, a run resumed from its checkpoint (written on a
//! schedule, or on Ctrl-C) ends bit for bit as the run that never stopped, trajectory included,
//! and bad checkpoints are refused with a message.

mod common;

use common::{dashpot, fails, ok_json, plugin_dir, scene};
use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Disks poured onto a floor in a box periodic along x, with friction: contacts that last,
/// with tangential springs, across the seam.
const PILE: &str = r#"
dimension = 2
gravity = [0.0, -9.81]
duration = DURATION
impact_speed = 0.5
snapshots = 8
[law]
name = "hsd"
params = { eps = 0.5 }
[tangential]
name = "mindlin"
params = { mu = 0.4 }
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
[box]
lo = [0.0, 0.0]
hi = [0.04, 0.1]
periodic = [true, false]
[[wall]]
point = [0.0, 0.0]
normal = [0.0, 1.0]
[generate]
count = COUNT
diameter = [0.0015, 0.002]
lo = [0.0, 0.0]
hi = [0.04, 0.08]
speed = 0.3
seed = 11
"#;

/// The pile of `count` disks run for `duration` (s).
fn pile(name: &str, count: usize, duration: f64) -> PathBuf {
    scene(
        name,
        &PILE
            .replace("DURATION", &duration.to_string())
            .replace("COUNT", &count.to_string()),
    )
}

/// A fresh directory `name` of this test process.
fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("restart-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// What must match between two runs' `--json`: all but the wall-clock figures.
fn physics(mut v: Value) -> Value {
    let o = v.as_object_mut().unwrap();
    o.remove("wall_seconds");
    o.remove("particle_steps_per_second");
    v
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn checkpoints_on_a_schedule_change_nothing_and_a_resumed_run_ends_bit_for_bit() {
    let sc = pile("sched.toml", 120, 0.05);
    let d = dir("sched");
    let ck = d.join("run.dpck");
    let straight = physics(ok_json(&["dem", "--scene", s(&sc), "--json"]));
    let steps = straight["steps"].as_u64().unwrap();
    let every = steps / 3 + 1;
    let with = physics(ok_json(&[
        "dem",
        "--scene",
        s(&sc),
        "--json",
        "--checkpoint-every",
        &every.to_string(),
        "--checkpoint",
        s(&ck),
    ]));
    assert!(with == straight, "writing checkpoints changed the run");
    // the last checkpoint was written at step 2 * every: resume from it
    let o = dashpot(&["dem", "--restart", s(&ck), "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&format!("step {}", 2 * every)), "{err}");
    let resumed = physics(serde_json::from_slice(&o.stdout).unwrap());
    assert!(resumed == straight, "the resumed run ends elsewhere");
    assert!(
        resumed["contacts"].as_u64().unwrap() > 50,
        "{}",
        resumed["contacts"]
    );
    // with its scene named too, the same
    let again = physics(ok_json(&[
        "dem",
        "--scene",
        s(&sc),
        "--restart",
        s(&ck),
        "--json",
    ]));
    assert!(again == straight);
}

#[test]
fn ctrl_c_writes_a_checkpoint_stops_and_the_resumed_run_ends_bit_for_bit() {
    let sc = pile("sigint.toml", 400, 0.06);
    let (d1, d2) = (dir("straight"), dir("stopped"));
    let straight = physics(ok_json(&["dem", "--scene", s(&sc), "--json", "--out", s(&d1)]));
    let ck = d2.join("checkpoint.dpck");
    let mut child = Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .args(["--no-default-plugins", "--plugin-dir", s(&plugin_dir())])
        .args(["dem", "--scene", s(&sc), "--json", "--out", s(&d2)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // the handler is in place once the run says where its checkpoints go
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut text = String::new();
    while !text.contains("Ctrl-C writes one") {
        let mut line = String::new();
        assert!(
            err.read_line(&mut line).unwrap() > 0,
            "no checkpoint line: {text}"
        );
        text.push_str(&line);
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{text}{rest}");
    assert!(
        rest.contains("interrupted at t =") && rest.contains("--restart"),
        "{rest}"
    );
    assert!(ck.exists(), "{rest}");
    // a partial trajectory up to the checkpoint, no result
    assert!(d2.join("trajectory.xyz").exists() && !d2.join("final.json").exists());
    let o = dashpot(&["dem", "--restart", s(&ck), "--json", "--out", s(&d2)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let resumed = physics(serde_json::from_slice(&o.stdout).unwrap());
    assert!(resumed["steps"] == straight["steps"]);
    assert!(resumed == straight, "the resumed run ends elsewhere");
    let traj = |d: &Path| std::fs::read_to_string(d.join("trajectory.xyz")).unwrap();
    assert!(traj(&d1) == traj(&d2), "the trajectories differ");
}

#[test]
fn bad_checkpoints_and_intervals_are_refused_with_a_message() {
    let sc = pile("bad.toml", 40, 0.01);
    let d = dir("bad");
    let ck = d.join("ok.dpck");
    let o = dashpot(&[
        "dem",
        "--scene",
        s(&sc),
        "--checkpoint-every",
        "50",
        "--checkpoint",
        s(&ck),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&ck).unwrap();
    let cut = d.join("cut.dpck");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    fails(
        &["dem", "--restart", s(&cut)],
        &["truncated", "cannot be resumed"],
    );
    let mut flipped = bytes.clone();
    let at = bytes.len() - 20;
    flipped[at] ^= 1;
    let bad = d.join("flipped.dpck");
    std::fs::write(&bad, &flipped).unwrap();
    fails(&["dem", "--restart", s(&bad)], &["corrupted"]);
    fails(&["dem", "--restart", s(&sc)], &["not a dashpot checkpoint"]);
    fails(&["dem", "--restart", s(&d.join("none.dpck"))], &["none.dpck"]);
    // another scene given beside it
    let other = pile("other.toml", 41, 0.01);
    fails(
        &["dem", "--scene", s(&other), "--restart", s(&ck)],
        &["another scene"],
    );
    for bad in ["0", "-5", "10x", "s", "0s"] {
        fails(
            &["dem", "--scene", s(&sc), "--checkpoint-every", bad],
            &["not a checkpoint interval"],
        );
    }
}
