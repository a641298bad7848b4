//! Helpers shared by the CLI tests: the seed plugins in a private directory, and the `dashpot`
//! binary run against them.
#![allow(dead_code)] // each test file uses its own subset

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::OnceLock;

pub const SEED: [&str; 9] = [
    "dashpot_lsd",
    "dashpot_hsd",
    "dashpot_kuwabara_kono",
    "dashpot_mcnamara_falcon",
    "dashpot_constant",
    "dashpot_mindlin",
    "dashpot_linear_history",
    "dashpot_thornton",
    "dashpot_walton_braun",
];

pub fn lib(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    deps.join(format!(
        "{}{name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ))
}

/// A fresh directory of this test process under cargo's scratch directory for tests
/// (`target/tmp`, which `cargo clean` empties), not the system's temporary directory.
fn scratch_dir(what: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{what}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `dst` as a hard link to `src` (no copy of a plugin's megabytes), or a copy where links fail.
fn link_or_copy(src: &std::path::Path, dst: &std::path::Path) {
    if std::fs::hard_link(src, dst).is_err() {
        std::fs::copy(src, dst).unwrap();
    }
}

/// A plugin directory holding exactly the plugins of the workspace.
pub fn plugin_dir() -> PathBuf {
    static D: OnceLock<PathBuf> = OnceLock::new();
    D.get_or_init(|| {
        let d = scratch_dir("cli-plugins");
        for n in SEED {
            let src = lib(n);
            link_or_copy(&src, &d.join(src.file_name().unwrap()));
        }
        d
    })
    .clone()
}

/// A plugin directory holding every plugin this test build made (all the workspace's laws and
/// the fault fixture: the libraries `libdashpot_*` of the deps directory but the C library).
pub fn all_plugins_dir() -> PathBuf {
    static D: OnceLock<PathBuf> = OnceLock::new();
    D.get_or_init(|| {
        let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
        let d = scratch_dir("all-plugins");
        let (pre, suf) = (std::env::consts::DLL_PREFIX, std::env::consts::DLL_SUFFIX);
        for e in std::fs::read_dir(&deps).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if name.starts_with(&format!("{pre}dashpot_")) && name.ends_with(suf) && !name.contains("capi") {
                link_or_copy(&p, &d.join(&name));
            }
        }
        d
    })
    .clone()
}

/// `dashpot` with exactly the five seed plugins (`--no-default-plugins`: whatever else sits
/// beside the binary in target/ stays out).
pub fn dashpot(args: &[&str]) -> Output {
    dashpot_with(plugin_dir(), args)
}

/// `dashpot` with exactly the plugins of directory `dir` (e.g. [`all_plugins_dir`]).
pub fn dashpot_with(dir: PathBuf, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .arg("--no-default-plugins")
        .arg("--plugin-dir")
        .arg(dir)
        .args(args)
        .env_remove("DASHPOT_PLUGIN_PATH")
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap()
}

/// Runs a command that must succeed (its stderr is the message if it does not).
pub fn succeeds(args: &[&str]) -> Output {
    let o = dashpot(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

pub fn ok_json(args: &[&str]) -> Value {
    serde_json::from_slice(&succeeds(args).stdout).unwrap()
}

/// Runs a command that must fail: non-zero exit, an `error:` line containing every `needle`,
/// and no panic or backtrace.
pub fn fails(args: &[&str], needles: &[&str]) {
    let o = dashpot(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} should fail");
    assert!(err.contains("error"), "{args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: expected '{n}' in: {err}");
    }
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{args:?}: {err}"
    );
}

/// A command line as the shell splits it (no quoting: the words have no spaces), e.g.
/// `dashpot(&sh("bed --restitution constant --layers 1 --freq 20"))`.
pub fn sh(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// Each case `(words, needles)` run as [`fails`]: `base` followed by `words`, both split as
/// [`sh`] splits them.
pub fn each_fails(base: &str, cases: &[(&str, &[&str])]) {
    for (words, needles) in cases {
        fails(&sh(&format!("{base} {words}")), needles);
    }
}

/// The observables of a bed run (JSON keys), each reported with its standard error over seeds
/// (`KEY_stderr`).
pub const BED_OBSERVABLES: [&str; 5] = [
    "pressure",
    "lid_collision_rate",
    "mean_impulse",
    "temperature",
    "piston_pressure",
];

/// Every one of [`BED_OBSERVABLES`] in the bed's JSON `v` is measured: positive, with a
/// standard error between 0 and the value.
pub fn assert_measured_with_stderr(v: &Value) {
    for k in BED_OBSERVABLES {
        let key = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("key {k} missing in {v}"));
        let (x, e) = (key(k), key(&format!("{k}_stderr")));
        assert!(x > 0.0 && e > 0.0 && e < x, "{k} = {x} ± {e}");
    }
}

/// The file `name` (in the temporary directory, tagged with this process) that the successful
/// command `cmd`, given that file's path as its last word, wrote: its path and its text.
pub fn written_by(cmd: &str, name: &str) -> (PathBuf, String) {
    let f =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{name}", std::process::id()));
    succeeds(&sh(&format!("{cmd} {}", f.to_str().unwrap())));
    let text = std::fs::read_to_string(&f).unwrap();
    (f, text)
}

/// A scene file `name` holding `text`, in a directory of this test process.
pub fn scene(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("scenes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The laws of the seed plugins and those of sdk 0.2, sorted.
pub const SEED_AND_02_LAWS: [&str; 9] = [
    "constant",
    "hsd",
    "kuwabara-kono",
    "linear-history",
    "lsd",
    "mcnamara-falcon",
    "mindlin",
    "thornton",
    "walton-braun",
];
