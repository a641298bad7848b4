//! Third-party laws without surprises (issue 10): out-of-tree plugins, written as an outside
//! author would, built by the test suite, then used and misused through the `dashpot` binary.
//!
//! The plugins (`tests/fixtures/third-party/`, their own workspace): `hooke-limited`, a linear
//! spring-dashpot valid only below 1 mm of overlap (it panics beyond); `twin`, one name
//! exported twice; and a law that calls itself `hsd`, shadowing the built-in one.

mod common;

#[allow(dead_code)]
#[path = "../../tests/lib.rs"]
mod ext;

use common::{dashpot, lib, plugin_dir, sh, SEED, SEED_AND_02_LAWS};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn fixture(package: &str, lib_name: &str) -> PathBuf {
    ext::build_external(
        &ext::workspace_root().join("tests/fixtures/third-party/Cargo.toml"),
        package,
        lib_name,
        &[],
    )
}

fn limited() -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| fixture("dashpot-fixture-limited", "dashpot_fixture_limited"))
        .clone()
}

fn twice() -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| fixture("dashpot-fixture-twice", "dashpot_fixture_twice"))
        .clone()
}

fn shadow_hsd() -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| fixture("dashpot-fixture-shadow-hsd", "dashpot_fixture_shadow_hsd"))
        .clone()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn json(o: &Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// A failure with exit status `code`, no panic of the host, no backtrace, every needle present.
fn refused(o: &Output, code: i32, needles: &[&str]) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert!(
        !err.contains("RUST_BACKTRACE") && !err.contains("thread 'main'"),
        "{err}"
    );
    for n in needles {
        assert!(err.contains(n), "expected '{n}' in: {err}");
    }
    err
}

/// A private installation: the dashpot binary with the five seed plugins beside it (its
/// built-in laws), so that the default plugin directory is known exactly.
fn installed() -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| {
        let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("installed-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::copy(env!("CARGO_BIN_EXE_dashpot"), d.join("dashpot")).unwrap();
        for n in SEED {
            let src = lib(n);
            std::fs::copy(&src, d.join(src.file_name().unwrap())).unwrap();
        }
        d.join("dashpot")
    })
    .clone()
}

fn run_installed(args: &[&str], env: Option<&Path>) -> Output {
    let mut c = Command::new(installed());
    c.args(args)
        .env_remove("DASHPOT_PLUGIN_PATH")
        .env_remove("RUST_BACKTRACE");
    if let Some(p) = env {
        c.env("DASHPOT_PLUGIN_PATH", p);
    }
    c.output().unwrap()
}

fn law_names(v: &Value) -> Vec<String> {
    let mut n: Vec<String> = v["laws"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["name"].as_str().unwrap().to_string())
        .collect();
    n.sort();
    n
}

/// Item 1: the collision driver, `calibrate` and `bed --restitution from:` never ask a law
/// about an overlap far beyond the collision's own (the law panics above 1 mm; at v0 = 1 m/s
/// the collision peaks at 2e-5 m).
#[test]
fn a_law_valid_below_1_mm_is_only_probed_below_it() {
    let lp = limited();
    let v = json(&dashpot(&sh(&format!(
        "--plugin {} collide --law hooke-limited --v0 1 --json",
        s(&lp)
    ))));
    let m = v["pair"]["mass"].as_f64().unwrap();
    let dmax = (m / 1e6).sqrt(); // undamped linear spring: δ_max = v0 √(m/k)
    assert!(
        (v["max_overlap"].as_f64().unwrap() / dmax - 1.0).abs() < 1e-9,
        "{v}"
    );
    assert!((v["restitution"].as_f64().unwrap() - 1.0).abs() < 1e-9, "{v}");

    // calibrate: the default --fit of a law without eps is its only parameter other than k
    let v = json(&dashpot(&sh(&format!(
        "--plugin {} calibrate --law hooke-limited --restitution 0.7 --json",
        s(&lp)
    ))));
    assert!(v["restitution_residual"].as_f64().unwrap().abs() < 1e-9, "{v}");
    assert!(v["params"]["c"].as_f64().unwrap() > 0.0, "c was fitted: {v}");
    assert_eq!(v["provenance"]["param_sources"]["c"], "given");

    // the bed's r(v) from the law, tabulated over 1e-4 … 20 m/s, and printed (item 6)
    let o = dashpot(&sh(&format!("--plugin {} bed --restitution from:hooke-limited --set c=0.001 --layers 1 --freq 20 --cycles 1 --transient 0", s(&lp))));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("restitution used (from:hooke-limited, tabulated from the collision driver)"),
        "{out}"
    );
    assert!(
        out.contains("r disk-disk") && out.contains("r disk-wall"),
        "{out}"
    );
    let row = out.lines().find(|l| l.trim_start().starts_with("1 ")).unwrap();
    let r: Vec<f64> = row.split_whitespace().map(|x| x.parse().unwrap()).collect();
    assert!(r[1] > 0.0 && r[1] < 1.0 && r[2] > 0.0 && r[2] < 1.0, "{row}");

    // a collision that really goes past 1 mm: the error names the overlap, not a probe's 1 m
    let err = refused(
        &dashpot(&sh(&format!(
            "--plugin {} collide --law hooke-limited --set k=1 --v0 1",
            s(&lp)
        ))),
        1,
        &["beyond what this law supports (1 mm)"],
    );
    assert!(!err.contains("overlap 1 m "), "{err}");
}

/// Item 2: --plugin, --plugin-dir and DASHPOT_PLUGIN_PATH add to the built-in laws;
/// --no-default-plugins removes them; `reproduce` without them fails.
#[test]
fn plugins_given_by_the_user_add_to_the_built_in_laws() {
    let lp = limited();
    let seed = SEED_AND_02_LAWS;
    let mut all: Vec<String> = seed.iter().map(|s| s.to_string()).collect();
    all.push("hooke-limited".into());
    all.sort();
    // a directory holding only this plugin (target/external holds other test plugins too)
    let dir = &std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("limited-{}", std::process::id()));
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(&lp, dir.join(lp.file_name().unwrap())).unwrap();
    for args in [
        vec!["--plugin", s(&lp), "laws", "--json"],
        vec!["--plugin-dir", s(dir), "laws", "--json"],
    ] {
        assert_eq!(law_names(&json(&run_installed(&args, None))), all, "{args:?}");
    }
    assert_eq!(
        law_names(&json(&run_installed(&["laws", "--json"], Some(dir)))),
        all,
        "DASHPOT_PLUGIN_PATH"
    );
    assert_eq!(
        law_names(&json(&run_installed(
            &["--no-default-plugins", "--plugin", s(&lp), "laws", "--json"],
            None
        ))),
        ["hooke-limited"]
    );
    // --help says so
    let h = String::from_utf8_lossy(&run_installed(&["--help"], None).stdout).to_string();
    assert!(
        h.contains("--no-default-plugins") && h.contains("stay loaded"),
        "{h}"
    );

    // reproduce cannot do its job without the built-in laws: it fails and says why
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("repro-none-{}", std::process::id()));
    refused(
        &run_installed(
            &sh(&format!(
                "--no-default-plugins --plugin {} reproduce --quick --out {}",
                s(&lp),
                s(&out)
            )),
            None,
        ),
        1,
        &[
            "reproduce needs the built-in laws lsd, hsd, kuwabara-kono, mcnamara-falcon, constant",
            "'lsd', 'hsd', 'kuwabara-kono', 'mcnamara-falcon', 'constant' were not found",
            "--no-default-plugins",
        ],
    );
    assert!(!out.join("report.md").exists());
}

/// Item 3: a shadowed law is announced when used, and every result carries its provenance.
#[test]
fn every_result_names_its_plugin_file_versions_and_all_parameters() {
    let shadow = shadow_hsd();
    let o = dashpot(&sh(&format!(
        "--plugin {} collide --law hsd --v0 1 --json",
        s(&shadow)
    )));
    let v = json(&o);
    let err = stderr(&o);
    let builtin = plugin_dir().join("libdashpot_hsd.so");
    assert!(
        err.contains(&format!(
            "warning: law 'hsd' is taken from {}; it shadows the law of the same name in {}",
            shadow.display(),
            builtin.display()
        )),
        "{err}"
    );
    let p = &v["provenance"];
    assert_eq!(p["plugin"]["file"], s(&shadow));
    assert_eq!(p["plugin"]["name"], "dashpot-fixture-shadow-hsd");
    assert_eq!(p["plugin"]["version"], "0.3.1");
    assert_eq!(p["plugin"]["sdk_version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(p["shadows"][0], s(&builtin));
    assert_eq!(p["dashpot_version"], env!("CARGO_PKG_VERSION"));
    assert!(
        (v["restitution"].as_f64().unwrap() - 1.0).abs() < 1e-9,
        "the elastic impostor"
    );

    // every parameter, including those left at their defaults or derived
    let v = json(&dashpot(&sh("collide --law lsd --set eps=0.5 --v0 1 --json")));
    assert_eq!(v["params"]["eps"], 0.5);
    assert!(
        v["params"]["k"].is_null() && v["params"].as_object().unwrap().len() == 2,
        "{v}"
    );
    let p = &v["provenance"];
    assert_eq!(p["param_sources"]["eps"], "given");
    assert_eq!(p["param_sources"]["k"], "derived from the pair");
    assert_eq!(p["plugin"]["file"], s(&plugin_dir().join("libdashpot_lsd.so")));
    assert_eq!(p["plugin"]["name"], "dashpot-lsd");
    assert_eq!(p["host_sdk_version"], env!("CARGO_PKG_VERSION"));
    assert!(p["shadows"].as_array().unwrap().is_empty());
    let v = json(&dashpot(&sh("collide --law hsd --v0 1 --json")));
    assert_eq!(v["params"]["eps"], 0.54);
    assert_eq!(v["provenance"]["param_sources"]["eps"], "default");

    // text output
    let o = dashpot(&sh("collide --law lsd --set eps=0.5 --v0 1"));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("law: lsd (contact): eps = 0.5 (given), k = derived from the pair"),
        "{out}"
    );
    assert!(
        out.contains(&format!(
            "plugin: {} (dashpot-lsd ",
            plugin_dir().join("libdashpot_lsd.so").display()
        )) && out.contains(&format!(
            "built against dashpot-sdk {v}); dashpot {v}",
            v = env!("CARGO_PKG_VERSION")
        )),
        "{out}"
    );
    // eval, calibrate and the bed too
    for args in [
        vec![
            "eval",
            "--law",
            "kuwabara-kono",
            "--delta",
            "1e-6",
            "--rate",
            "0",
            "--json",
        ],
        vec!["calibrate", "--law", "hsd", "--restitution", "0.5", "--json"],
        vec![
            "bed",
            "--restitution",
            "constant",
            "--tc",
            "1e-5",
            "--layers",
            "1",
            "--freq",
            "20",
            "--cycles",
            "1",
            "--transient",
            "0",
            "--json",
        ],
    ] {
        let v = json(&dashpot(&args));
        let p = &v["provenance"];
        assert!(
            p["plugin"]["file"].as_str().unwrap().ends_with(".so")
                && p["params"].as_object().is_some_and(|m| !m.is_empty())
                && p["dashpot_version"] == env!("CARGO_PKG_VERSION"),
            "{args:?}: {v}"
        );
    }
}

/// Item 4: a plugin exporting one name twice is refused with a message (named on the command
/// line: an error; found in a directory: a warning, the other plugins load).
#[test]
fn a_plugin_exporting_a_name_twice_is_refused() {
    let tw = twice();
    refused(
        &dashpot(&["--plugin", s(&tw), "laws"]),
        1,
        &[
            &format!("cannot load plugin {}", tw.display()),
            "exports the law name 'twin' twice",
            "Rename one of them",
        ],
    );
    let d =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("twice-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(&tw, d.join(tw.file_name().unwrap())).unwrap();
    let o = dashpot(&["--plugin-dir", s(&d), "laws"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("exports the law name 'twin' twice"));
    assert!(String::from_utf8_lossy(&o.stdout).contains("hsd  [contact]"));
    let o = dashpot(&["--plugin-dir", s(&d), "collide", "--law", "twin"]);
    refused(&o, 1, &["unknown law 'twin'", "refused", "'twin' twice"]);
}

/// Item 5 (and a text file given as a plugin, item 6): a path a user types means a file.
#[test]
fn a_bare_file_name_is_the_file_in_the_current_directory() {
    let lp = limited();
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cwd-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let name = lp.file_name().unwrap().to_str().unwrap();
    std::fs::copy(&lp, d.join(name)).unwrap();
    std::fs::write(d.join("notes.txt"), "not a library\n").unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_dashpot"))
            .args(["--no-default-plugins"])
            .args(args)
            .current_dir(&d)
            .env_remove("DASHPOT_PLUGIN_PATH")
            .output()
            .unwrap()
    };
    let v = json(&run(&["--plugin", name, "law", "hooke-limited", "--json"]));
    assert_eq!(v["plugin"]["file"], s(&d.join(name)));
    let err = refused(
        &run(&["--plugin", "notes.txt", "laws"]),
        1,
        &[
            "cannot load plugin notes.txt: it is not a shared library (14 bytes, not an ELF",
            "crate-type = [\"cdylib\"]",
        ],
    );
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    refused(
        &run(&["--plugin", "libnothere.so", "laws"]),
        1,
        &[&format!(
            "cannot load plugin libnothere.so: no such file ({} does not exist",
            d.join("libnothere.so").display()
        )],
    );
}

/// Item 6: the smaller misuses, each answered precisely.
#[test]
fn misuses_are_answered_with_the_value_and_the_remedy() {
    // the same --set twice, a value with a unit: malformed command lines, exit status 2
    refused(
        &dashpot(&sh("collide --law hsd --set eps=0.3 --set eps=0.5")),
        2,
        &["--set eps is given twice (0.3 and 0.5); give each parameter once"],
    );
    refused(
        &dashpot(&sh("collide --law lsd --set k=1e6N")),
        2,
        &["'1e6N' is not a number (write plain SI values without units, e.g. k=1e6)"],
    );
    refused(
        &dashpot(&sh(
            "bed --restitution constant --set r=0.5 --set r=0.6 --layers 1 --freq 20",
        )),
        2,
        &["--set r is given twice"],
    );
    // a contact law where the bed wants a restitution law: the remedy is from:LAW
    refused(
        &dashpot(&sh("bed --restitution hsd --layers 1 --freq 20")),
        1,
        &[
            "law 'hsd' is a contact law, but a restitution law is needed here",
            "`dashpot bed --restitution from:hsd`",
            "restitution laws loaded: constant, mcnamara-falcon",
        ],
    );
    // the bed's header without parameters
    let o = dashpot(&sh(
        "bed --restitution mcnamara-falcon --layers 1 --freq 20 --cycles 1 --transient 0",
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.starts_with("bed: law mcnamara-falcon, n = 1 (N = 100)"),
        "{out}"
    );
    // an overdamped law under --end overlap: the error says so and suggests --end force
    let lp = limited();
    refused(
        &dashpot(&sh(&format!(
            "--plugin {} collide --law hooke-limited --set c=100 --v0 1",
            s(&lp)
        ))),
        1,
        &["the law may be overdamped", "With --end force"],
    );
    let v = json(&dashpot(&sh(&format!(
        "--plugin {} collide --law hooke-limited --set c=100 --v0 1 --end force --json",
        s(&lp)
    ))));
    assert!(v["restitution"].as_f64().unwrap() < 0.1, "{v}");
    // the default of --fit is documented where the user looks
    let h = String::from_utf8_lossy(&dashpot(&["calibrate", "--help"]).stdout).to_string();
    assert!(
        h.contains(
            "Default: `eps` if the law has one, else `damp` (LAMMPS's `gran-*` laws), else its only \
             parameter other than `k`"
        ),
        "{h}"
    );
}

/// Item 7: the sdk pulls in nothing a law does not use (abi_stable without its default
/// channels and serde_json support), so a third-party law compiles as little as possible.
#[test]
fn the_sdk_pulls_in_only_what_a_law_needs() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let o = Command::new(cargo)
        .args([
            "tree",
            "--offline",
            "-e",
            "normal",
            "--prefix",
            "none",
            "-p",
            "dashpot-sdk",
        ])
        .arg("--manifest-path")
        .arg(ext::workspace_root().join("Cargo.toml"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let tree = String::from_utf8_lossy(&o.stdout);
    for unwanted in ["crossbeam-channel", "serde_json"] {
        assert!(
            !tree.contains(unwanted),
            "dashpot-sdk depends on {unwanted}:\n{tree}"
        );
    }
}
