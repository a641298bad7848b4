//! The `dashpot` binary as a user runs it.

mod common;

use common::{dashpot, fails, lib, ok_json, plugin_dir, sh, succeeds, written_by, SEED_AND_02_LAWS};
use serde_json::Value;
use std::process::Command;

#[test]
fn laws_json_lists_the_laws_with_their_schemas() {
    let v = ok_json(&["laws", "--json"]);
    let laws = v["laws"].as_array().unwrap();
    let mut names: Vec<&str> = laws.iter().map(|l| l["name"].as_str().unwrap()).collect();
    names.sort();
    assert_eq!(names, SEED_AND_02_LAWS);
    let get = |n: &str| laws.iter().find(|l| l["name"] == n).unwrap();
    let hsd = get("hsd");
    assert_eq!(hsd["kind"], "contact");
    assert_eq!(hsd["end_criterion"], "overlap");
    assert!(hsd["plugin"]["file"]
        .as_str()
        .unwrap()
        .ends_with("libdashpot_hsd.so"));
    assert_eq!(hsd["plugin"]["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(hsd["plugin"]["sdk_version"], env!("CARGO_PKG_VERSION"));
    let eps = &hsd["params"][0];
    assert_eq!(
        (eps["name"].as_str(), eps["unit"].as_str(), eps["range"].as_str()),
        (Some("eps"), Some("1"), Some("(0, 1]"))
    );
    assert_eq!(eps["min_inclusive"], false);
    assert_eq!(eps["max"], 1.0);
    let lsd = get("lsd");
    let k = lsd["params"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "k")
        .unwrap();
    assert!(k["default"].is_null(), "k is derived from the pair when unset");
    assert_eq!(k["unit"], "N/m");
    assert_eq!(get("kuwabara-kono")["params"][0]["unit"], "s");
    assert_eq!(get("kuwabara-kono")["end_criterion"], "force");
    let mf = get("mcnamara-falcon");
    assert_eq!(mf["kind"], "restitution");
    let names: Vec<&str> = mf["params"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["r0", "vy"]);
    assert_eq!(get("constant")["params"][0]["default"], 0.95);
}

#[test]
fn law_shows_documentation() {
    let o = dashpot(&["law", "hsd"]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(
        s.contains("eq. 17") && s.contains("eps [1]") && s.contains("valid (0, 1]"),
        "{s}"
    );
}

#[test]
fn eval_contact_law_gives_the_hsd_force() {
    let v = ok_json(&sh("eval --law hsd --set eps=0.3 --delta 2e-5 --rate 0.4 --json"));
    let (m, r, e) = (
        v["pair"]["mass"].as_f64().unwrap(),
        v["pair"]["radius"].as_f64().unwrap(),
        v["pair"]["young"].as_f64().unwrap(),
    );
    let k = 4.0 / 3.0 * e * r.sqrt();
    let l = f64::ln(0.3);
    let alpha = -(5f64).sqrt() * l / (l * l + std::f64::consts::PI.powi(2)).sqrt();
    let expected = k * 2e-5f64.powf(1.5) + alpha * (m * k).sqrt() * 2e-5f64.powf(0.25) * 0.4;
    let f = v["force"].as_f64().unwrap();
    assert!((f / expected - 1.0).abs() < 1e-13, "{f} vs {expected}");
    assert_eq!(v["law"], "hsd");
    // default pair: two 1 cm MCC spheres
    assert!((r - 0.0025).abs() < 1e-15);
}

#[test]
fn eval_restitution_law_and_wall() {
    let v = ok_json(&sh("eval --law mcnamara-falcon --speed 1 --json"));
    let r = v["restitution"].as_f64().unwrap();
    assert!((r - 0.95 * (1.0f64 / 0.3).powf(-0.25)).abs() < 1e-14);
    let v = ok_json(&sh(
        "eval --law lsd --wall --diameter 0.002 --delta 0 --rate 0 --json",
    ));
    assert!((v["pair"]["radius"].as_f64().unwrap() - 0.001).abs() < 1e-18);
    assert_eq!(v["force"], 0.0);
}

#[test]
fn toml_config_with_set_override() {
    let f = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("cfg-{}.toml", std::process::id()));
    std::fs::write(
        &f,
        "[law]\nname = \"constant\"\nparams = { r = 0.4 }\n[particle]\ndiameter = 0.002\n",
    )
    .unwrap();
    let fs = f.to_str().unwrap();
    let v = ok_json(&["eval", "--config", fs, "--speed", "3", "--json"]);
    assert_eq!(v["restitution"], 0.4);
    let v = ok_json(&["eval", "--config", fs, "--set", "r=0.8", "--speed", "3", "--json"]);
    assert_eq!(v["restitution"], 0.8);
    std::fs::write(&f, "[law]\nname = \"constant\"\n[partical]\nd = 1\n").unwrap();
    fails(
        &["eval", "--config", fs, "--speed", "1"],
        &["not a valid dashpot configuration", "partical"],
    );
    std::fs::remove_file(&f).ok();
}

#[test]
fn bad_input_is_a_clear_error_with_nonzero_exit() {
    fails(
        &sh("eval --law hertz --speed 1"),
        &["unknown law 'hertz'", "hsd", "mcnamara-falcon"],
    );
    fails(
        &sh("eval --law hsd --set eps=1.5 --delta 1e-5 --rate 1"),
        &["'eps'", "1.5", "(0, 1]"],
    );
    fails(
        &sh("eval --law hsd --set eps=0 --delta 1e-5 --rate 1"),
        &["'eps'", "(0, 1]"],
    );
    fails(
        &sh("eval --law hsd --set eps=nan --delta 1e-5 --rate 1"),
        &["NaN", "(0, 1]"],
    );
    fails(
        &sh("eval --law hsd --set gamma=1 --delta 1e-5 --rate 1"),
        &["no parameter 'gamma'", "eps"],
    );
    fails(
        &sh("eval --law hsd --set eps --delta 1e-5 --rate 1"),
        &["NAME=VALUE"],
    );
    fails(
        &sh("eval --law hsd --poisson 0.5 --delta 1e-5 --rate 1"),
        &["poisson = 0.5", "(-1, 0.5)"],
    );
    fails(
        &sh("eval --law hsd --poisson -1 --delta 1e-5 --rate 1"),
        &["poisson = -1"],
    );
    fails(
        &sh("eval --law hsd --young 0 --delta 1e-5 --rate 1"),
        &["young = 0", "> 0"],
    );
    fails(
        &sh("eval --law hsd --density -1500 --delta 1e-5 --rate 1"),
        &["density = -1500"],
    );
    fails(
        &sh("eval --law hsd --diameter nan --delta 1e-5 --rate 1"),
        &["diameter = NaN"],
    );
    fails(&sh("eval --law hsd --delta nan --rate 1"), &["--delta = NaN"]);
    fails(&sh("eval --law hsd --delta 1e-5"), &["--rate"]);
    fails(&sh("eval --law hsd --speed 1"), &["contact law", "--delta"]);
    fails(
        &sh("eval --law constant --delta 1 --rate 1"),
        &["restitution law", "--speed"],
    );
    fails(&sh("eval --law constant --speed -1"), &["--speed = -1", ">= 0"]);
    fails(&["eval", "--speed", "1"], &["no law given"]);
    fails(&sh("eval --law hsd --delta abc --rate 1"), &["abc"]);
}

#[test]
fn a_panicking_plugin_is_an_error_in_the_cli() {
    let o = Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .args(["--plugin"])
        .arg(lib("dashpot_fixture_faulty"))
        .args(["eval", "--law", "panicky", "--delta", "1", "--rate", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("contact law 'panicky' panicked: deliberate panic at delta = 1"),
        "{err}"
    );
    assert!(
        err.contains("fixtures/faulty/src/lib.rs"),
        "panic location is reported: {err}"
    );
}

#[test]
fn plugin_path_environment_variable() {
    let o = Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .args(["eval", "--law", "constant", "--speed", "1", "--json"])
        .env("DASHPOT_PLUGIN_PATH", plugin_dir())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["restitution"], 0.95);
    // an empty plugin directory: a clear error naming where it looked
    let empty =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .arg("--no-default-plugins")
        .arg("--plugin-dir")
        .arg(&empty)
        .arg("laws")
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no plugins found"));
}

#[test]
fn reproduce_writes_the_report() {
    let out =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("repro-{}", std::process::id()));
    succeeds(&["reproduce", "--quick", "--out", out.to_str().unwrap()]);
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("0.7031"), "r(1 m/s) in the report");
    assert!(md.contains("## McNamara & Falcon (2005): the vibrated bed"));
    assert!(md.contains("### Fig. 4 a–d"));
    for f in ["fig2_pressure", "fig3_snapshots", "fig4_theta"] {
        assert!(out.join("bed").join(format!("{f}.png")).exists(), "{f}");
        assert!(out.join("bed").join(format!("{f}.svg")).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("mcnamara_falcon_fig1.csv")).unwrap();
    assert_eq!(csv.lines().count(), 242);
    let laws: Value = serde_json::from_str(&std::fs::read_to_string(out.join("laws.json")).unwrap()).unwrap();
    assert_eq!(laws.as_array().unwrap().len(), common::SEED.len());
    // the laws table names each plugin file and the sdk it was built against
    assert!(
        md.contains("| law | kind | plugin | sdk | file | parameters |"),
        "{md}"
    );
    assert!(md.contains("libdashpot_hsd.so`"), "{md}");
    for f in ["thornton_vs_mcnamara_falcon", "oblique_test4", "oblique_test5"] {
        assert!(out.join(format!("{f}.png")).exists(), "{f}");
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn collide_reports_the_observables_in_json() {
    let v = ok_json(&sh("collide --law hsd --set eps=0.54 --v0 1 --json"));
    for k in ["restitution", "contact_time", "max_overlap", "law", "v0", "end"] {
        assert!(!v[k].is_null(), "key {k} missing");
    }
    assert!((v["restitution"].as_f64().unwrap() - 0.54).abs() < 1e-9);
    assert_eq!(v["end"], "overlap");
    assert_eq!(v["law"], "hsd");
    let f = ok_json(&sh("collide --law hsd --set eps=0.54 --v0 1 --end force --json"));
    assert_eq!(f["end"], "force");
    assert!(f["restitution"].as_f64().unwrap() > 0.54);
    // a wall: the particle's own mass
    let w = ok_json(&sh("collide --law lsd --wall --v0 1 --json"));
    assert!((w["pair"]["mass"].as_f64().unwrap() - std::f64::consts::PI / 6.0 * 1500.0 * 1e-6).abs() < 1e-12);
}

#[test]
fn collide_writes_a_trajectory() {
    let (f, csv) = written_by("collide --law lsd --v0 0.5 --trajectory", "traj.csv");
    let mut lines = csv.lines();
    // provenance first, as comment lines
    assert!(lines.next().unwrap().starts_with("# law: lsd (contact): eps = "));
    assert!(lines.next().unwrap().starts_with("# plugin: "));
    assert_eq!(lines.next(), Some("t_s,delta_m,rate_m_per_s,force_N"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() > 100);
    assert_eq!(rows[0][1], 0.0);
    assert!((rows[0][2] - 0.5).abs() < 1e-15);
    assert!(rows.last().unwrap()[1].abs() < 1e-12, "ends at δ = 0");
    std::fs::remove_file(&f).ok();
}

#[test]
fn collide_bad_input() {
    fails(&sh("collide --law hsd --v0 0"), &["--v0 = 0", "> 0"]);
    fails(&sh("collide --law hsd --v0 -2"), &["--v0 = -2"]);
    fails(&sh("collide --law hsd --v0 nan"), &["--v0 = NaN"]);
    fails(&sh("collide --law nope --v0 1"), &["unknown law 'nope'", "hsd"]);
    fails(
        &sh("collide --law mcnamara-falcon --v0 1"),
        &["restitution law", "contact law is needed", "lsd"],
    );
    fails(
        &sh("collide --law hsd --rtol 1"),
        &["--rtol = 1", "[1e-14, 1e-3]"],
    );
    fails(&sh("collide --law hsd --end sideways"), &["sideways"]);
    // a law that never pushes the particles apart: a clear error, not a hang
    let o = Command::new(env!("CARGO_BIN_EXE_dashpot"))
        .arg("--plugin")
        .arg(lib("dashpot_fixture_faulty"))
        .args(["collide", "--law", "sticky", "--v0", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err.contains("did not return the particles") && err.contains("limit"),
        "{err}"
    );
}

#[test]
fn sweep_and_calibrate() {
    let (f, text) = written_by(
        "sweep --law hsd --v0 0.01:1:3 --vary eps=0.2,0.8 --out",
        "sweep.csv",
    );
    // provenance first, as comment lines: the law with every parameter, the plugin file
    let (comments, rows): (Vec<&str>, Vec<&str>) = text.lines().partition(|l| l.starts_with('#'));
    assert!(
        comments[0].starts_with("# law: hsd (contact): eps = 0.54 (default)"),
        "{text}"
    );
    assert!(
        comments[1].contains("libdashpot_hsd.so")
            && comments[1].contains(&format!("dashpot {}", env!("CARGO_PKG_VERSION")))
    );
    let csv = rows.join("\n");
    assert_eq!(csv.lines().count(), 7);
    assert!(csv.starts_with("law,eps,v0_m_per_s,end,restitution,contact_time_s"));
    for l in csv.lines().skip(1) {
        let c: Vec<&str> = l.split(',').collect();
        let (eps, r): (f64, f64) = (c[1].parse().unwrap(), c[4].parse().unwrap());
        assert!((eps - r).abs() < 1e-9, "{l}");
    }
    std::fs::remove_file(&f).ok();
    fails(&sh("sweep --law hsd --v0 1:2:x"), &["invalid grid"]);

    let v = ok_json(&sh(
        "calibrate --law kuwabara-kono --restitution 0.8 --v0 0.5 --json",
    ));
    assert_eq!(v["method"], "numerical");
    assert_eq!(
        v["end"], "force",
        "KK is calibrated under the criterion it declares"
    );
    assert!(v["restitution_residual"].as_f64().unwrap().abs() < 1e-9);
    let v = ok_json(&sh(
        "calibrate --law lsd --restitution 0.5 --contact-time 1e-4 --json",
    ));
    assert_eq!(v["method"], "closed form");
    assert!(v["contact_time_residual"].as_f64().unwrap().abs() < 1e-14);
    fails(
        &sh("calibrate --law hsd --restitution 0"),
        &["--restitution = 0", "(0, 1]"],
    );
    fails(
        &sh("calibrate --law hsd --restitution 0.5 --contact-time -1"),
        &["--contact-time = -1"],
    );
}

#[test]
fn figures_collide_reproduces_antypov_elliott() {
    let out =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("figc-{}", std::process::id()));
    succeeds(&["figures", "collide", "--out", out.to_str().unwrap()]);
    for f in [
        "fig1_phase_trajectories",
        "fig2_collision_time",
        "fig3_time_ratio",
        "kuwabara_kono_restitution",
    ] {
        for ext in ["png", "svg", "csv"] {
            let p = out.join(format!("{f}.{ext}"));
            assert!(
                std::fs::metadata(&p).map(|m| m.len() > 100).unwrap_or(false),
                "{}",
                p.display()
            );
        }
    }
    let md = std::fs::read_to_string(out.join("collide.md")).unwrap();
    assert_eq!(
        md.matches("| -0.2000000000 |").count(),
        3,
        "HSD slope −1/5 for all three ε:\n{md}"
    );
    assert!(
        md.contains("near ε = 1 (eq. 28 and the paper's numerical check: 0.1): 0.1000"),
        "{md}"
    );
    std::fs::remove_dir_all(&out).ok();
}
