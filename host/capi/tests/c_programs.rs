//! The C ABI used from C and Fortran: the examples are compiled with the system's compilers and
//! run against the plugins cargo built, and their physics is checked; a C program exercises the
//! error path of every function; valgrind checks the C programs for leaks and invalid accesses.
//!
//! Compilers: `$CC` (default `cc`), `$FC` (default `gfortran`). A missing tool skips its test
//! with a printed reason on a developer machine, and fails it under `CI=true`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `target/<profile>/deps`: the plugin libraries cargo built as dev-dependencies.
fn deps_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("current_exe");
    exe.parent().expect("exe dir").to_path_buf()
}

/// `target/<profile>`: where the compiled test programs go.
fn lib_dir() -> PathBuf {
    deps_dir().parent().expect("profile dir").to_path_buf()
}

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn examples_dir() -> PathBuf {
    crate_dir().join("../../examples")
}

fn build_dir(name: &str) -> PathBuf {
    let d = lib_dir().join("capi-programs").join(name);
    std::fs::create_dir_all(&d).expect("create build dir");
    d
}

/// Whether `tool` runs; if not, `None` on a developer machine (the caller skips) and a panic
/// under CI.
fn tool(env: &str, default: &str) -> Option<String> {
    let t = std::env::var(env).unwrap_or_else(|_| default.to_string());
    let ok = Command::new(&t)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some(t);
    }
    let reason = format!("`{t}` (set ${env} to override) is not installed");
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{reason}; CI must have it (.ci/run installs it)");
    }
    eprintln!("SKIPPED: {reason}");
    None
}

fn run(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed ({}):\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn link_args(cmd: &mut Command) {
    // `cargo test` builds this crate's cdylib for its integration tests into `deps/` (it is
    // uplifted to `target/<profile>` only by `cargo build`): link the fresh one there.
    let lib = deps_dir();
    cmd.arg(format!("-L{}", lib.display()))
        .arg("-ldashpot_capi")
        // DT_RPATH, not RUNPATH: it wins over LD_LIBRARY_PATH, where cargo puts target/<profile>
        // (a `cargo build` leaves an older copy of the library there)
        .arg("-Wl,--disable-new-dtags")
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-lm");
}

fn compile_c(src: &Path, name: &str) -> Option<PathBuf> {
    let cc = tool("CC", "cc")?;
    let exe = build_dir(name).join(name);
    let mut cmd = Command::new(cc);
    cmd.args([
        "-std=c11",
        "-D_DEFAULT_SOURCE",
        "-O1",
        "-g",
        "-Wall",
        "-Wextra",
        "-Werror",
    ])
    .arg(format!("-I{}", crate_dir().join("include").display()))
    .arg(src)
    .arg("-o")
    .arg(&exe);
    link_args(&mut cmd);
    run(&mut cmd);
    Some(exe)
}

fn compile_fortran() -> Option<PathBuf> {
    let fc = tool("FC", "gfortran")?;
    let dir = build_dir("fortran-collision");
    let exe = dir.join("collision");
    let src = examples_dir().join("fortran");
    let mut cmd = Command::new(fc);
    cmd.args(["-O2", "-Wall", "-Werror", "-std=f2008"])
        .arg("-J")
        .arg(&dir)
        .arg(src.join("dashpot.f90"))
        .arg(src.join("collision.f90"))
        .arg("-o")
        .arg(&exe);
    link_args(&mut cmd);
    run(&mut cmd);
    Some(exe)
}

/// The realized restitution of each `v0 ... realized restitution E` line.
fn realized(stdout: &str) -> Vec<(f64, f64)> {
    stdout
        .lines()
        .filter(|l| l.contains("realized restitution"))
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            let v0 = w[1].parse().expect("v0");
            let e = w.last().expect("value").parse().expect("restitution");
            (v0, e)
        })
        .collect()
}

/// HSD with the exact α(ε) realizes ε at every impact speed (Antypov & Elliott): the
/// program's own velocity-Verlet loop with dt = τ/2000 must get within 2e-4 of it.
fn check_hsd_collisions(exe: &Path) {
    for eps in [0.1, 0.54, 0.9] {
        let out = run(Command::new(exe).arg(deps_dir()).arg("hsd").arg(eps.to_string()));
        let stdout = String::from_utf8_lossy(&out.stdout);
        let r = realized(&stdout);
        assert_eq!(
            r.iter().map(|p| p.0).collect::<Vec<_>>(),
            vec![0.1, 1.0, 5.0],
            "{stdout}"
        );
        for (v0, e) in r {
            assert!(
                (e - eps).abs() < 2e-4,
                "hsd eps = {eps}, v0 = {v0} m/s: realized {e}\n{stdout}"
            );
        }
    }
}

#[test]
fn c_example_realizes_the_hsd_restitution() {
    let Some(exe) = compile_c(&examples_dir().join("c/collision.c"), "c-collision") else {
        return;
    };
    check_hsd_collisions(&exe);
    // An unknown law is reported with the library's message and a non-zero exit.
    let out = refused(&exe, &["hsdx"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("DASHPOT_ERR_UNKNOWN_LAW") && err.contains("unknown law 'hsdx'"),
        "{err}"
    );
}

/// The output of the example `exe` run on the plugins with `args`, which it must refuse (a
/// non-zero exit).
fn refused(exe: &Path, args: &[&str]) -> std::process::Output {
    let out = Command::new(exe)
        .arg(deps_dir())
        .args(args)
        .output()
        .expect("run");
    assert!(!out.status.success(), "{args:?} was accepted");
    out
}

#[test]
fn fortran_example_realizes_the_hsd_restitution() {
    let Some(exe) = compile_fortran() else {
        return;
    };
    check_hsd_collisions(&exe);
    let out = refused(&exe, &["hsd", "1.5"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("DASHPOT_ERR_INVALID_PARAMETER") && stdout.contains("= 1.5 is out of range"),
        "{stdout}"
    );
}

#[test]
fn every_function_reports_its_errors_to_c() {
    let Some(exe) = compile_c(&crate_dir().join("tests/c/error_paths.c"), "error-paths") else {
        return;
    };
    let out = run(Command::new(&exe).arg(deps_dir()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().unwrap_or_default();
    let passed: usize = last
        .split_whitespace()
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(last.ends_with(" passed, 0 failed") && passed >= 280, "{stdout}");
}

fn valgrind(exe: &Path, args: &[&std::ffi::OsStr]) {
    let Some(vg) = tool("VALGRIND", "valgrind") else {
        return;
    };
    let supp = crate_dir().join("tests/c/valgrind.supp");
    let mut cmd = Command::new(vg);
    cmd.args([
        "--leak-check=full",
        "--show-leak-kinds=definite,indirect,possible",
        "--errors-for-leak-kinds=definite,indirect,possible",
        "--error-exitcode=99",
    ])
    .arg(format!("--suppressions={}", supp.display()))
    .arg(exe)
    .args(args);
    let out = run(&mut cmd);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("ERROR SUMMARY: 0 errors"), "{stderr}");
    assert!(
        stderr.contains("definitely lost: 0 bytes") || stderr.contains("All heap blocks were freed"),
        "{stderr}"
    );
}

#[test]
fn c_programs_are_clean_under_valgrind() {
    if let Some(exe) = compile_c(&examples_dir().join("c/collision.c"), "c-collision-vg") {
        valgrind(&exe, &[deps_dir().as_os_str(), "hsd".as_ref(), "0.54".as_ref()]);
    }
    if let Some(exe) = compile_c(&crate_dir().join("tests/c/error_paths.c"), "error-paths-vg") {
        valgrind(&exe, &[deps_dir().as_os_str()]);
    }
}
