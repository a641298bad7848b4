//! A sweep of absurd inputs through every command: counts, durations, sizes, grids and steps near
//! the limits of f64 and of memory. Each is refused with a message naming the value (or runs),
//! with no abort, no panic and no hang: every run has a deadline (a hang detector, not a timing:
//! the refusals take well under a second), past which it is killed and the test fails. Failed
//! writes (`/dev/full`) are errors naming the path, and leave the device in place.

mod common;

use common::{plugin_dir, scene};
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest any case may take before it counts as a hang (a loaded machine, a debug build).
const DEADLINE: Duration = Duration::from_secs(60);

/// What a case must do.
enum Want<'a> {
    /// Fail (exit 1) with an `error:` naming every needle.
    Refused(&'a [&'a str]),
    /// Succeed.
    Runs,
}

/// `dashpot ARGS` with the seed plugins (and `env`), killed at the deadline: (exit code, stdout,
/// stderr, wall time).
fn run(args: &[&str], env: &[(&str, &str)]) -> (Option<i32>, String, String, Duration) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_dashpot"));
    cmd.arg("--no-default-plugins")
        .arg("--plugin-dir")
        .arg(plugin_dir())
        .args(args)
        .env_remove("DASHPOT_PLUGIN_PATH")
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let t0 = Instant::now();
    let mut child = cmd.spawn().expect("spawn dashpot");
    // read both pipes on threads, so that a chatty run never blocks on a full pipe
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let to = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let te = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if t0.elapsed() > DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} hung: killed after {DEADLINE:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let took = t0.elapsed();
    (status.code(), to.join().unwrap(), te.join().unwrap(), took)
}

/// Runs a case and checks what it did.
fn case(args: &[&str], want: Want<'_>) {
    case_env(args, &[], want)
}

fn case_env(args: &[&str], env: &[(&str, &str)], want: Want<'_>) {
    let (code, _out, err, took) = run(args, env);
    eprintln!("{args:?}: exit {code:?} in {took:.2?}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace") && !err.contains("memory allocation"),
        "{args:?} crashed: {err}"
    );
    match want {
        Want::Refused(needles) => {
            assert_eq!(code, Some(1), "{args:?} should be refused (exit 1): {err}");
            assert!(err.contains("error:"), "{args:?}: {err}");
            for n in needles {
                assert!(err.contains(n), "{args:?}: expected '{n}' in: {err}");
            }
        }
        Want::Runs => assert_eq!(code, Some(0), "{args:?} should run: {err}"),
    }
}

/// A 3D scene of `generate` particles under `law`, its top-level keys `top` (TOML lines).
fn scene_text(top: &str, law: &str, material: &str, generate: &str) -> String {
    format!(
        "dimension = 3\ngravity = [0.0, 0.0, -9.81]\n{top}\n[law]\n{law}\n[material]\n{material}\n[generate]\n{generate}\n"
    )
}

const HSD: &str = "name = \"hsd\"\nparams = { eps = 0.7 }";
const SOFT: &str = "young = 1.0e7\npoisson = 0.3\ndensity = 2500.0";

fn gen(count: &str, diameter: &str, hi: f64) -> String {
    format!("count = {count}\ndiameter = {diameter}\nlo = [0.0, 0.0, 0.0]\nhi = [{hi:?}, {hi:?}, {hi:?}]\nseed = 5")
}

/// A scene file of this test for `text`, as a `--scene` argument.
fn file(name: &str, text: &str) -> String {
    scene(name, text).to_str().unwrap().to_string()
}

#[test]
fn absurd_scenes_are_refused_before_they_allocate_or_step() {
    let ok_gen = gen("10", "[0.002, 0.003]", 0.05);
    let cases: Vec<(&str, String, Want)> = vec![
        // a count past memory: refused before the particles are made, naming count and memory
        (
            "count.toml",
            scene_text(
                "duration = 0.02",
                HSD,
                SOFT,
                &gen("1000000000000", "[0.002, 0.003]", 100.0),
            ),
            Want::Refused(&["generate.count = 1000000000000", "of memory", "is available"]),
        ),
        (
            "count-max.toml",
            scene_text(
                "duration = 0.02",
                HSD,
                SOFT,
                &gen("9223372036854775807", "[1e-300, 1e-300]", 1e300),
            ),
            Want::Refused(&["generate.count = 9223372036854775807"]),
        ),
        // particles too small to have a mass (5e-324 m hung the cell build)
        (
            "tiny.toml",
            scene_text("duration = 0.02", HSD, SOFT, &gen("10", "[5e-324, 5e-324]", 0.05)),
            Want::Refused(&["diameter = 5e-324 m"]),
        ),
        (
            "tiny2.toml",
            scene_text("duration = 0.02", HSD, SOFT, &gen("10", "1e-320", 0.05)),
            Want::Refused(&["diameter = 1e-320 m"]),
        ),
        // steps past any machine: a stiff material, a tiny dt, a stiff law, a step count
        (
            "stiff.toml",
            scene_text(
                "duration = 0.02",
                HSD,
                "young = 1e308\npoisson = 0.3\ndensity = 2500.0",
                &ok_gen,
            ),
            Want::Refused(&["dt = ", "steps, beyond the 1e12", "young"]),
        ),
        (
            "dt.toml",
            scene_text("duration = 0.02\ndt = 1e-300", HSD, SOFT, &ok_gen),
            Want::Refused(&["dt = 1.0000e-300 s", "steps, beyond"]),
        ),
        (
            "lsd.toml",
            scene_text(
                "duration = 0.02",
                "name = \"lsd\"\nparams = { k = 1e300, eps = 0.5 }",
                SOFT,
                &ok_gen,
            ),
            Want::Refused(&["steps, beyond"]),
        ),
        (
            "spc.toml",
            scene_text("duration = 0.02\nsteps_per_collision = 1e12", HSD, SOFT, &ok_gen),
            Want::Refused(&["steps, beyond", "steps_per_collision = 1000000000000"]),
        ),
        (
            "long.toml",
            scene_text("duration = 1e300", HSD, SOFT, &ok_gen),
            Want::Refused(&["steps, beyond"]),
        ),
        (
            "huge.toml",
            scene_text("duration = 0.02", HSD, SOFT, &gen("10", "1e300", 1e302)),
            Want::Refused(&["diameter = 1e300 m"]),
        ),
        // a skin far larger than the particles lists every pair: refused by its memory
        (
            "skin.toml",
            scene_text(
                "duration = 0.02\nskin = 1e300",
                HSD,
                SOFT,
                &gen("400000", "0.002", 1.0),
            ),
            Want::Refused(&["of memory", "is available"]),
        ),
        // the shortest duration runs (one step or none)
        (
            "short.toml",
            scene_text("duration = 5e-324", HSD, SOFT, &ok_gen),
            Want::Runs,
        ),
    ];
    for (name, text, want) in cases {
        let f = file(name, &text);
        case(&["dem", "--scene", &f, "--check"], want);
    }
    // the run itself refuses too (not only --check), and Ctrl-C-free limits are checked
    let stiff = file(
        "stiff.toml",
        &scene_text(
            "duration = 0.02",
            HSD,
            "young = 1e308\npoisson = 0.3\ndensity = 2500.0",
            &ok_gen,
        ),
    );
    case(&["dem", "--scene", &stiff], Want::Refused(&["steps, beyond"]));
    let ok = file("ok.toml", &scene_text("duration = 0.002", HSD, SOFT, &ok_gen));
    case(
        &["dem", "--scene", &ok, "--max-hours", "0"],
        Want::Refused(&["--max-hours = 0"]),
    );
    case(
        &["dem", "--scene", &ok, "--max-hours", "NaN"],
        Want::Refused(&["--max-hours = NaN"]),
    );
    // a machine with little memory: a modest scene is refused with the figure it was given,
    // before its particles are generated, or (listed ones) before the engine is built
    case_env(
        &["dem", "--scene", &ok, "--check"],
        &[("DASHPOT_MEMORY_AVAILABLE", "1K")],
        Want::Refused(&[
            "generate.count = 10",
            "DASHPOT_MEMORY_AVAILABLE = 1K",
            "lower generate.count to 2",
        ]),
    );
    let two = file(
        "two.toml",
        "dimension = 3\nduration = 0.001\n[law]\nname = \"hsd\"\n[material]\nyoung = 1e7\npoisson = 0.3\ndensity = 2500.0\n[[particle]]\nposition = [0.0, 0.0, 0.0]\ndiameter = 0.002\n[[particle]]\nposition = [0.01, 0.0, 0.0]\ndiameter = 0.002\n",
    );
    case_env(
        &["dem", "--scene", &two, "--check"],
        &[("DASHPOT_MEMORY_AVAILABLE", "1K")],
        Want::Refused(&[
            "the run of 2 3D particles",
            "DASHPOT_MEMORY_AVAILABLE = 1K",
            "particles would fit",
        ]),
    );
    case_env(
        &["dem", "--scene", &two, "--check"],
        &[("DASHPOT_MEMORY_AVAILABLE", "1G")],
        Want::Runs,
    );
}

#[test]
fn absurd_beds_and_grids_are_refused() {
    let cases: Vec<(Vec<&str>, Want)> = vec![
        (
            common::sh("bed --restitution mcnamara-falcon --layers 1e12 --freq 20"),
            Want::Refused(&["layers"]),
        ),
        (
            common::sh("bed --restitution mcnamara-falcon --layers 1e300 --freq 20"),
            Want::Refused(&["layers"]),
        ),
        (
            common::sh("bed --engine dem --law hsd --layers 1e12 --freq 20"),
            Want::Refused(&["of memory", "--layers"]),
        ),
        (
            common::sh("bed --engine dem --law hsd --young 1e308 --layers 0.1 --freq 20"),
            Want::Refused(&["dt = ", "steps, beyond"]),
        ),
        (
            common::sh("bed --engine dem --law hsd --dt 1e-300 --layers 0.1 --freq 20"),
            Want::Refused(&["steps, beyond"]),
        ),
        (
            common::sh("bed --engine dem --law hsd --young 1e8 --layers 0.1 --freq 20 --cycles 1e300"),
            Want::Refused(&["steps, beyond"]),
        ),
        (
            common::sh("bed --restitution mcnamara-falcon --layers 0.1 --freq 1e-300"),
            Want::Refused(&[]),
        ),
        (
            common::sh("bed --restitution mcnamara-falcon --layers 0.1 --freq 20 --seeds 18446744073709551615 --check"),
            Want::Refused(&["seeds"]),
        ),
        (
            common::sh("dem --bed --law hsd --layers 1e12 --freq 20"),
            Want::Refused(&["of memory"]),
        ),
        (
            common::sh("scaling --restitution mcnamara-falcon --layers 1 --freqs 10:30:1000000000000"),
            Want::Refused(&["COUNT = 1000000000000"]),
        ),
        (
            common::sh("scaling --restitution mcnamara-falcon --layers 1,2 --freqs 10:30:3 --cycles 1e15"),
            Want::Refused(&["the scaling grid would take", "--max-hours"]),
        ),
        (
            common::sh("sweep --law hsd --v0 1e-3:10:1000000000000"),
            Want::Refused(&["COUNT"]),
        ),
        (
            common::sh("sweep --law hsd --v0 1:2:1000000 --vary eps=0.1:0.9:1000000"),
            Want::Refused(&["1000000000000 collisions", "of memory"]),
        ),
        (
            common::sh("collide --law hsd --v0 1e308"),
            Want::Refused(&[]),
        ),
        (
            common::sh("collide --law hsd --v0 1e-300"),
            Want::Refused(&[]),
        ),
        (common::sh("bed --restitution constant --layers 0.1 --freq 20 --check"), Want::Runs),
    ];
    for (args, want) in cases {
        case(&args, want);
    }
}

/// A failed write is an error naming the path and the reason, never "wrote ...": the device
/// stays a device (a rename over it would have replaced it with a file).
#[cfg(target_os = "linux")]
#[test]
fn failed_writes_are_errors_naming_the_path() {
    use std::os::unix::fs::FileTypeExt;
    if !std::path::Path::new("/dev/full").exists() {
        eprintln!("skipped: no /dev/full");
        return;
    }
    let is_device = || {
        std::fs::metadata("/dev/full")
            .map(|m| m.file_type().is_char_device())
            .unwrap_or(false)
    };
    assert!(is_device());
    for args in [
        common::sh("sweep --law hsd --v0 1:2:3 --out /dev/full"),
        common::sh("collide --law hsd --v0 1 --trajectory /dev/full"),
        common::sh(
            "bed --restitution constant --layers 0.1 --freq 20 --cycles 1 --transient 0 --trace /dev/full",
        ),
    ] {
        case(
            &args,
            Want::Refused(&["cannot write /dev/full", "No space left on device"]),
        );
        let (_, _, err, _) = run(&args, &[]);
        assert_eq!(err.matches("/dev/full").count(), 1, "the path named once: {err}");
        assert!(is_device(), "{args:?} replaced /dev/full");
    }
    // a device that takes the bytes is written in place, and stays a device
    case(
        &common::sh("sweep --law hsd --v0 1:2:3 --out /dev/null"),
        Want::Runs,
    );
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // stdout itself full: an error, not a panic
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "'{}' --no-default-plugins --plugin-dir '{}' laws > /dev/full",
            env!("CARGO_BIN_EXE_dashpot"),
            plugin_dir().display()
        ))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("error: failed printing to stdout") && !err.contains("panicked"),
        "{err}"
    );
}
