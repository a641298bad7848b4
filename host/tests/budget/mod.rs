//! What `--check`'s validation shares between its test (`tests/budget_validation.rs`) and its
//! measurement (`benches/budget.rs`): a run's peak resident memory and wall time, the piles and
//! bed runs measured, and their estimate against the run.
#![allow(dead_code)]

use crate::common::plugin_dir;
use serde_json::Value;
use std::process::{Command, Stdio};
use std::time::Instant;

/// `dashpot ARGS` (stdout discarded unless `capture`): its stdout, peak resident memory (bytes)
/// and wall time (s).
// (the child is reaped by `wait4`, for its rusage: `Child::wait` would not report it)
#[allow(clippy::zombie_processes)]
pub fn measured(args: &[&str], capture: bool) -> (String, f64, f64) {
    let t0 = Instant::now();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_dashpot"));
    cmd.arg("--no-default-plugins")
        .arg("--plugin-dir")
        .arg(plugin_dir())
        .args(args)
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .stdout(if capture { Stdio::piped() } else { Stdio::null() });
    let mut child = cmd.spawn().expect("spawn");
    let mut out = String::new();
    if let Some(mut o) = child.stdout.take() {
        use std::io::Read;
        o.read_to_string(&mut out).expect("stdout");
    }
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: an all-zero rusage is valid; wait4 fills it for our child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(r, pid, "wait4");
    let wall = t0.elapsed().as_secs_f64();
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{args:?} failed"
    );
    (out, usage.ru_maxrss as f64 * 1024.0, wall)
}

/// A pile of `n` spheres of 0.9-1.1 mm on a lattice (as `generate` makes it) over a floor,
/// periodic sideways, settling for `duration` s.
pub fn pile(n: usize, duration: f64) -> String {
    let side = (n as f64).cbrt().ceil();
    let a = 1.05 * 1.1e-3;
    let l = side * a + 1e-9;
    format!(
        "dimension = 3\ngravity = [0.0, 0.0, -9.81]\nduration = {duration:e}\n\
         [law]\nname = \"hsd\"\nparams = {{ eps = 0.7 }}\n\
         [material]\nyoung = 1.0e7\npoisson = 0.3\ndensity = 2500.0\n\
         [box]\nlo = [0.0, 0.0, -0.01]\nhi = [{l:e}, {l:e}, {h:e}]\nperiodic = [true, true, false]\n\
         [[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n\
         [generate]\ncount = {n}\ndiameter = [0.9e-3, 1.1e-3]\nlo = [0.0, 0.0, 0.0]\nhi = [{l:e}, {l:e}, {h:e}]\nspeed = 0.01\nseed = 3\n",
        h = 1.2 * side * a,
    )
}

pub fn check(args: &[&str]) -> Value {
    let (out, _, _) = measured(args, true);
    let v: Value = serde_json::from_str(&out).expect("--check --json");
    v["estimate"].clone()
}

/// The estimate against the run: (memory ratio, time ratio), printed as a row.
pub fn row(what: &str, est: &Value, rss: f64, wall: f64) -> (f64, f64) {
    let (m, t) = (
        est["memory_bytes"].as_f64().unwrap(),
        est["wall_seconds"].as_f64().unwrap(),
    );
    println!(
        "{what:<34} estimate {:>9.1} MiB {:>8.1} s | run {:>9.1} MiB {:>8.1} s | memory {:>5.2}x time {:>5.2}x",
        m / 1048576.0,
        t,
        rss / 1048576.0,
        wall,
        m / rss,
        t / wall
    );
    (m / rss, t / wall)
}

pub fn scratch() -> std::path::PathBuf {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("budget-validation-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A pile of `n` spheres written to `dir`, its duration from `steps_or_settle` (None: 0.1 s,
/// the pile settles; Some(k): k steps of the scene's own dt): `--check`'s estimate against the
/// run.
pub fn pile_pair(dir: &std::path::Path, n: usize, steps: Option<f64>) -> (f64, f64) {
    let p = dir.join(format!("pile-{n}.toml"));
    let duration = match steps {
        None => 0.1,
        Some(k) => {
            // the step first (it does not depend on the duration)
            std::fs::write(&p, pile(n, 1e-3)).unwrap();
            let est = check(&["dem", "--scene", p.to_str().unwrap(), "--check", "--json"]);
            k * est["dt"].as_f64().unwrap()
        }
    };
    std::fs::write(&p, pile(n, duration)).unwrap();
    let est = check(&["dem", "--scene", p.to_str().unwrap(), "--check", "--json"]);
    let (_, rss, wall) = measured(&["dem", "--scene", p.to_str().unwrap()], false);
    row(
        &format!("dem pile {n} spheres, {} steps", est["steps"]),
        &est,
        rss,
        wall,
    )
}

/// `--check` of `args` against their run.
pub fn cli_pair(what: &str, args: &str) -> (f64, f64) {
    let words: Vec<&str> = args.split_whitespace().collect();
    let est = check(&[&words[..], &["--check", "--json"]].concat());
    let (_, rss, wall) = measured(&words, false);
    row(what, &est, rss, wall)
}
