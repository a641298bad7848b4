//! Checkpoint and restart of the DEM engine: a run stopped, written to a checkpoint file, read
//! back into an engine made afresh from the same scene and resumed ends bit for bit as the run
//! that never stopped, stopped anywhere, including in the middle of contacts whose laws carry
//! history in every family (JKR's touch flag, Thornton's plastic overlap, Mindlin's tangential
//! spring, the rolling and twisting springs) and across the periodic seam of a box. Truncated,
//! corrupted, foreign and wrong-version files are refused whole, before anything is used.

use dashpot::cli::dem::scene_engine;
use dashpot::dem::checkpoint::{self, Checkpoint, Header, HEADER_LEN};
use dashpot::dem::scene::SceneFile;
use dashpot::dem::Engine;
use dashpot_tests::registry_03;
use std::path::Path;

/// Two species falling into a box and settling: JKR (cohesive, history) with friction, rolling
/// and twisting springs inside the sticky species, Thornton (plastic, history) inside the
/// plastic one, HSD between them and on the walls; every pair with Mindlin, rolling-sds and
/// twisting-sds (the top-level tables).
const MIXED: &str = r#"
dimension = 3
gravity = [0.0, 0.0, -9.81]
duration = 0.02
impact_speed = 0.8
[law]
name = "hsd"
params = { eps = 0.5 }
[tangential]
name = "mindlin"
params = { mu = 0.5 }
[rolling]
name = "rolling-sds"
params = { k = 100.0, gamma = 0.0, mu = 0.1 }
[twisting]
name = "twisting-sds"
params = { k = 1e-4, gamma = 0.0, mu = 1e-5 }
[[species]]
name = "sticky"
young = 1.0e7
poisson = 0.3
density = 2500.0
[[species]]
name = "plastic"
young = 1.0e7
poisson = 0.3
density = 2500.0
[[pair]]
species = "sticky"
[pair.law]
name = "jkr"
params = { w = 0.05, eps = 0.5 }
[[pair]]
species = "plastic"
[pair.law]
name = "thornton"
params = { py = 2.0e5 }
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[wall]]
point = [0.012, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
[[wall]]
point = [0.0, 0.012, 0.0]
normal = [0.0, -1.0, 0.0]
[[generate]]
species = "sticky"
count = 30
diameter = [0.0018, 0.0024]
lo = [0.0, 0.0, 0.0]
hi = [0.012, 0.012, 0.008]
speed = 0.2
seed = 3
[[generate]]
species = "plastic"
count = 30
diameter = [0.0018, 0.0024]
lo = [0.0, 0.0, 0.009]
hi = [0.012, 0.012, 0.018]
speed = 0.2
seed = 4
"#;

/// Disks settling in a box periodic along x, moving across the seam, under Walton–Braun
/// (plastic, history) with linear-history friction.
const PERIODIC: &str = r#"
dimension = 2
gravity = [0.0, -9.81]
duration = 0.04
impact_speed = 0.5
[law]
name = "walton-braun"
params = { k1 = 2.0e4, k2 = 2.0e5 }
[tangential]
name = "linear-history"
params = { mu = 0.4 }
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
[box]
lo = [0.0, 0.0]
hi = [0.02, 0.05]
periodic = [true, false]
[[wall]]
point = [0.0, 0.0]
normal = [0.0, 1.0]
[generate]
count = 27
diameter = [0.0015, 0.002]
lo = [0.0, 0.0]
hi = [0.02, 0.0065]
speed = 0.05
seed = 7
"#;

/// The engine of `text` (3D or 2D as `D` says).
fn engine<const D: usize>(text: &str) -> Engine<D> {
    let reg = registry_03();
    let file = SceneFile::parse(text).expect("scene");
    let scene = file.scene::<D>().expect("scene");
    scene_engine(&reg, &file, &scene).expect("engine").0
}

/// The whole state of `e` as text (JSON of the checkpoint's state: every float to the bit).
fn state<const D: usize>(e: &Engine<D>) -> String {
    serde_json::to_string(&e.save_state()).expect("json")
}

/// Writes `e`'s checkpoint to `path` for the scene `text`.
fn write<const D: usize>(e: &Engine<D>, text: &str, path: &Path) {
    let ck = Checkpoint {
        scene: text.to_string(),
        laws: "test".into(),
        energy_initial: 0.0,
        frames: 1,
        engine: e.save_state(),
    };
    let header = Header {
        dimension: D as u32,
        scene_hash: checkpoint::scene_hash(D as u32, text, "test"),
    };
    checkpoint::write(path, header, &ck).expect("write");
}

/// An engine of `text` resumed from the checkpoint `path`.
fn resume<const D: usize>(text: &str, path: &Path) -> Engine<D> {
    let (h, payload) = checkpoint::read_raw(path).expect("read");
    assert_eq!(h.scene_hash, checkpoint::scene_hash(D as u32, text, "test"));
    let ck = checkpoint::decode::<D>(path, &payload).expect("decode");
    let mut e = engine::<D>(&ck.scene);
    e.restore_state(ck.engine).expect("restore");
    e
}

/// How many contacts of `e` (pairs and walls) carry a nonzero history in each family (normal,
/// tangential, rolling, twisting).
fn histories<const D: usize>(e: &Engine<D>) -> [usize; 4] {
    let mut out = [0; 4];
    for set in e.pairs.chunks.iter().chain(&e.wall_contacts.chunks) {
        let count = |h: &[f64], s: usize| h.chunks(s.max(1)).filter(|c| c.iter().any(|&x| x != 0.0)).count();
        out[0] += count(&set.hist_n, set.slots_n);
        out[1] += count(&set.hist_t, set.slots_t);
        out[2] += count(&set.hist_r, set.slots_r.unwrap_or(1));
        out[3] += count(&set.hist_w, set.slots_w.unwrap_or(1));
    }
    out
}

/// Runs `text` for `total` steps straight, and again stopped at each of `stops` (written to a
/// checkpoint, read into a fresh engine, resumed): the same state bit for bit at the end, and
/// at every stop the state of the straight run at that step. Returns the histories in use at
/// each stop.
fn stop_and_resume<const D: usize>(text: &str, total: u64, stops: &[u64]) -> Vec<[usize; 4]> {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("run.dpck");
    let mut straight = engine::<D>(text);
    let mut at_stops = Vec::new();
    let mut done = 0;
    for &s in stops {
        straight.advance(s - done).expect("steps");
        done = s;
        at_stops.push(state(&straight));
    }
    straight.advance(total - done).expect("steps");
    let mut e = engine::<D>(text);
    let mut done = 0;
    let mut used = Vec::new();
    for (k, &s) in stops.iter().enumerate() {
        e.advance(s - done).expect("steps");
        done = s;
        write(&e, text, &path);
        e = resume::<D>(text, &path);
        assert_eq!(e.steps(), s);
        assert!(
            state(&e) == at_stops[k],
            "stop {k} at step {s}: the resumed state differs"
        );
        used.push(histories(&e));
    }
    e.advance(total - done).expect("steps");
    assert_eq!(e.steps(), straight.steps());
    assert_eq!(e.time().to_bits(), straight.time().to_bits());
    assert!(
        state(&e) == state(&straight),
        "the resumed run ends elsewhere than the straight one"
    );
    for i in 0..e.p.len() {
        assert_eq!(e.p.pos[i], straight.p.pos[i], "particle {i}");
    }
    used
}

#[test]
fn stopped_mid_contact_in_every_family_resumes_bit_for_bit() {
    let e = engine::<3>(MIXED);
    let steps = e.steps_to(MIXED_END, u64::MAX);
    let stops = [steps / 3, steps / 2 + 7, 3 * steps / 4 + 1];
    let used = stop_and_resume::<3>(MIXED, steps, &stops);
    // the stops fall in contacts: every family's history is in use at the later ones
    let last = used[used.len() - 1];
    for (k, family) in ["normal", "tangential", "rolling", "twisting"].iter().enumerate() {
        assert!(
            last[k] > 0,
            "no {family} history in use at the last stop: {used:?}"
        );
    }
}

/// The end of [`MIXED`]'s run in the test (s): long enough for the pile to settle into
/// lasting contacts.
const MIXED_END: f64 = 0.02;

#[test]
fn a_periodic_run_resumes_bit_for_bit_across_the_seam() {
    let e = engine::<2>(PERIODIC);
    let steps = e.steps_to(0.04, u64::MAX);
    let used = stop_and_resume::<2>(PERIODIC, steps, &[steps / 4, 3 * steps / 4, 3 * steps / 4 + 1]);
    assert!(used[1..].iter().all(|u| u[0] > 0 && u[1] > 0), "{used:?}");
}

/// The bytes of a valid checkpoint of [`PERIODIC`] after a few steps.
fn valid() -> (tempfile::TempDir, std::path::PathBuf, Vec<u8>) {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("ok.dpck");
    let mut e = engine::<2>(PERIODIC);
    e.advance(50).expect("steps");
    write(&e, PERIODIC, &path);
    let bytes = std::fs::read(&path).expect("read");
    (dir, path, bytes)
}

/// The refusal of `bytes` written to a file: its message.
fn refusal(dir: &Path, bytes: &[u8]) -> String {
    let p = dir.join("bad.dpck");
    std::fs::write(&p, bytes).expect("write");
    match checkpoint::read_raw(&p).and_then(|(_, payload)| checkpoint::decode::<2>(&p, &payload)) {
        Ok(_) => panic!("a bad checkpoint was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn truncated_corrupted_foreign_and_wrong_version_files_are_refused() {
    let (dir, _, bytes) = valid();
    let dir = dir.path();
    for cut in [0, 5, HEADER_LEN - 1, HEADER_LEN, HEADER_LEN + 10, bytes.len() - 1] {
        let m = refusal(dir, &bytes[..cut]);
        assert!(
            m.contains("truncated") || m.contains("not a dashpot checkpoint"),
            "cut at {cut}: {m}"
        );
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(refusal(dir, &longer).contains("follow"));
    // a flipped bit anywhere in the state
    for at in [HEADER_LEN, HEADER_LEN + 100, bytes.len() / 2, bytes.len() - 1] {
        let mut bad = bytes.clone();
        bad[at] ^= 0x10;
        assert!(refusal(dir, &bad).contains("corrupted"), "bit flipped at {at}");
    }
    let mut foreign = bytes.clone();
    foreign[..8].copy_from_slice(b"PK\x03\x04\x14\x00\x00\x00");
    assert!(refusal(dir, &foreign).contains("not a dashpot checkpoint"));
    assert!(refusal(dir, b"dimension = 2\nduration = 1.0\n").contains("not a dashpot checkpoint"));
    let mut version = bytes.clone();
    version[8..12].copy_from_slice(&3u32.to_le_bytes());
    let m = refusal(dir, &version);
    assert!(
        m.contains("format version 3") && m.contains("versions 1 to 2"),
        "{m}"
    );
}

#[test]
fn a_state_of_another_scene_is_refused_and_leaves_the_engine_as_it_was() {
    let (_dir, path, _) = valid();
    let (_, payload) = checkpoint::read_raw(&path).expect("read");
    let ck = checkpoint::decode::<2>(&path, &payload).expect("decode");
    // the same scene with ten disks fewer
    let other = PERIODIC.replace("count = 27", "count = 20");
    let mut e = engine::<2>(&other);
    let before = state(&e);
    let m = e.restore_state(ck.engine).expect_err("refused").to_string();
    assert!(m.contains("does not fit this scene"), "{m}");
    assert!(state(&e) == before);
    // the header's hash tells the scenes apart
    assert_ne!(
        checkpoint::scene_hash(2, &checkpoint::canonical_scene(PERIODIC).unwrap(), "laws"),
        checkpoint::scene_hash(2, &checkpoint::canonical_scene(&other).unwrap(), "laws")
    );
    // and not a comment
    let commented = format!("# a comment\n{PERIODIC}");
    assert_eq!(
        checkpoint::canonical_scene(PERIODIC).unwrap(),
        checkpoint::canonical_scene(&commented).unwrap()
    );
}

#[test]
fn a_checkpoint_write_replaces_the_file_whole() {
    let (dir, path, bytes) = valid();
    // a second write over the first: the file is the new checkpoint, and no temporary is left
    let mut e = engine::<2>(PERIODIC);
    e.advance(80).expect("steps");
    write(&e, PERIODIC, &path);
    let (_, payload) = checkpoint::read_raw(&path).expect("read");
    let ck = checkpoint::decode::<2>(&path, &payload).expect("decode");
    assert_eq!(ck.engine.steps(), 80);
    assert_ne!(std::fs::read(&path).expect("read"), bytes);
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|d| d.expect("entry").file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}
