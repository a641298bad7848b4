//! A new user's first hour (issue 23), through the CLI: scenes refused for what is wrong with
//! them (not for the time step), `dem --scene FILE --check`, TOML errors that name the key,
//! "did you mean" for laws, parameters, keys and commands, and the provenance of every result
//! of `scaling` and `figures`.

mod common;

use common::{dashpot, fails, ok_json, plugin_dir, scene, sh, succeeds};
use std::path::{Path, PathBuf};

/// The `[material]` table of this file's scenes: steel's density (kg/m³) and Poisson's ratio with
/// a soft Young's modulus (Pa), so that a DEM step is microseconds.
const SOFT_STEEL: &str = "[material]
young = 1.0e8
poisson = 0.3
density = 7800.0";

/// A 3D scene of 1 ms on [`SOFT_STEEL`]: `top`, more top-level keys; `law`, the `[law]` table's
/// lines; `body`, the walls and particles.
fn scene_3d(top: &str, law: &str, body: &str) -> String {
    format!("\ndimension = 3\nduration = 0.001\n{top}\n[law]\n{law}\n{SOFT_STEEL}\n{body}")
}

/// A 3D scene of 2 mm steel-like spheres (HSD, ε = 0.5) over a floor at z = 0, with `particles`
/// appended.
fn spheres(top: &str, particles: &str) -> String {
    let floor = "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]";
    scene_3d(
        top,
        "name = \"hsd\"\nparams = { eps = 0.5 }",
        &format!("{floor}\n{particles}"),
    )
}

fn particle(pos: [f64; 3], d: f64) -> String {
    format!(
        "[[particle]]\nposition = [{:?}, {:?}, {:?}]\ndiameter = {d:?}\n",
        pos[0], pos[1], pos[2]
    )
}

/// stderr of a command that must fail (non-zero, an `error:` line, no panic), and its first
/// line: what the user reads first.
fn error_of(args: &[&str]) -> (String, String) {
    let o = dashpot(args);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!o.status.success(), "{args:?} should fail");
    assert!(err.starts_with("error: "), "{args:?}: {err}");
    assert!(!err.contains("panicked") && !err.contains("backtrace"), "{err}");
    let first = err.lines().next().unwrap_or("").to_string();
    (err, first)
}

/// The error of `dem --scene` on the scene `text` (written as `name`): its stderr and its first
/// line, which names every one of `needles`.
fn refused_scene(name: &str, text: &str, needles: &[&str]) -> (String, String) {
    let p = scene(name, text);
    let (err, first) = error_of(&["dem", "--scene", p.to_str().unwrap()]);
    for needle in needles {
        assert!(first.contains(needle), "'{needle}' not on the first line: {err}");
    }
    (err, first)
}

/// [`refused_scene`] for a placement: the message says nothing of the time step.
fn refused_placement(name: &str, text: &str, needles: &[&str]) -> (String, String) {
    let (err, first) = refused_scene(name, text, needles);
    says_nothing_of_the_step(&err);
    (err, first)
}

/// No word of the time step in a message about the placement.
fn says_nothing_of_the_step(err: &str) {
    for w in ["time step", "dt", "step"] {
        assert!(!err.contains(w), "'{w}' in: {err}");
    }
}

#[test]
fn two_spheres_placed_overlapping_are_refused_for_the_placement_not_the_step() {
    // two 2 mm spheres 0.1 mm apart: they overlap by 2 mm − 0.1 mm = 1.9 mm
    let text = spheres(
        "",
        &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.0001, 0.0, 0.01], 0.002)),
    );
    let (err, first) = refused_placement(
        "overlap.toml",
        &text,
        &[
            "1 pair(s) of particles overlap at the start",
            "1.9000e-3 m",
            "particle 0 at [0.0, 0.0, 0.01] m",
            "particle 1 at [0.0001, 0.0, 0.01] m",
            "allow_initial_overlap = true",
        ],
    );
    // shrinking dt, as the old message sent users to do, changes nothing: the same message
    let p = scene(
        "overlap-again.toml",
        &text.replace("duration = 0.001", "duration = 0.001\ndt = 1e-9"),
    );
    let (err2, first2) = error_of(&["dem", "--scene", p.to_str().unwrap()]);
    let message = |l: &str| l.split_once("scene: ").map(|x| x.1.to_string());
    assert!(message(&first).is_some(), "{err}");
    assert_eq!(message(&first2), message(&first), "{err2}");
    // three spheres on one spot: three pairs, the largest overlap the full diameter
    let p = scene(
        "overlap3.toml",
        &spheres(
            "",
            &(particle([0.0, 0.0, 0.01], 0.002)
                + &particle([0.0, 0.0, 0.01], 0.002)
                + &particle([0.0005, 0.0, 0.01], 0.002)),
        ),
    );
    let (err, first) = error_of(&["dem", "--scene", p.to_str().unwrap()]);
    assert!(first.contains("3 pair(s) of particles overlap"), "{err}");
    assert!(first.contains("largest overlap is 2.0000e-3 m"), "{err}");
    assert!(
        first.contains("particle 0") && first.contains("particle 1"),
        "{err}"
    );
}

#[test]
fn a_sphere_placed_inside_a_wall_is_refused_naming_the_wall() {
    // a 2 mm sphere with its centre 0.5 mm below the floor: overlap r + 0.5 mm = 1.5 mm
    refused_placement(
        "in-wall.toml",
        &spheres(
            "",
            &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.05, 0.0, -0.0005], 0.002)),
        ),
        &[
            "1 particle(s) overlap a wall at the start",
            "1.5000e-3 m",
            "particle 1 at [0.05, 0.0, -0.0005] m",
            "wall 0 (plane through [0.0, 0.0, 0.0] m, normal [0.0, 0.0, 1.0])",
            "behind the wall",
            "allow_initial_overlap = true",
        ],
    );
    // resting on the floor (touching, centre exactly r above it) is no overlap
    let p = scene("on-wall.toml", &spheres("", &particle([0.0, 0.0, 0.001], 0.002)));
    succeeds(&["dem", "--scene", p.to_str().unwrap(), "--check"]);
}

/// A pre-compressed pair, allowed by the explicit key: released, it springs apart with the
/// Hertz energy of the initial overlap, (2/5) K δ0^{5/2}, K = (4/3) E* √R*, and no momentum.
#[test]
fn allow_initial_overlap_admits_a_precompressed_pair_and_it_springs_apart_with_the_hertz_energy() {
    let pair = particle([0.0, 0.0, 0.0], 0.002) + &particle([0.0019, 0.0, 0.0], 0.002);
    let text = scene_3d(
        "allow_initial_overlap = true",
        "name = \"kuwabara-kono\"\nparams = { A = 0.0 }",
        &pair,
    );
    let p = scene("precompressed.toml", &text);
    let v = ok_json(&["dem", "--scene", p.to_str().unwrap(), "--json"]);
    let (e, nu, r, d0) = (1.0e8_f64, 0.3_f64, 1e-3_f64, 1e-4_f64);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    let k = 4.0 / 3.0 * e_star * (r / 2.0).sqrt();
    let u0 = 0.4 * k * d0.powf(2.5);
    let ke = v["energies"]["translational"].as_f64().unwrap();
    assert_eq!(v["contacts"].as_u64(), Some(0), "still in contact: {v}");
    assert!(
        (ke / u0 - 1.0).abs() < 5e-3,
        "kinetic {ke} J against Hertz {u0} J"
    );
    let vx = |i: usize| v["particles"][i]["velocity"][0].as_f64().unwrap();
    assert!(vx(0) < 0.0 && vx(1) > 0.0, "{v}");
    assert!(
        (vx(0) + vx(1)).abs() <= 1e-12 * vx(1).abs(),
        "momentum: {} {}",
        vx(0),
        vx(1)
    );
    // beyond half the radius the key does not help: the laws do not hold that deep
    refused_placement(
        "too-deep.toml",
        &text.replace("0.0019", "0.0012"),
        &[
            "overlap at the start",
            "even with allow_initial_overlap = true",
            "8.0000e-4 m",
        ],
    );
}

#[test]
fn a_particle_outside_a_bounded_box_is_refused_before_the_run() {
    let text = spheres(
        "[box]\nlo = [-0.01, -0.01, 0.0]\nhi = [0.01, 0.01, 0.05]\nbounded = true",
        &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.0, 0.02, 0.01], 0.002)),
    );
    refused_placement(
        "outside.toml",
        &text,
        &[
            "1 particle(s) start outside the bounded box",
            "particle 1 at [0.0, 0.02, 0.01] m",
            "along axis 1",
            "[-0.01, 0.01] m",
        ],
    );
}

#[test]
fn a_packing_that_cannot_fit_its_count_says_how_many_fit() {
    // 1 cm × 1 cm, diameters up to 2 mm: sites of 2.1 mm, 4 × 4 = 16
    let text = format!(
        r#"
dimension = 2
duration = 0.001
[law]
name = "hsd"
{SOFT_STEEL}
[generate]
count = 100
diameter = [0.0018, 0.002]
lo = [0.0, 0.0]
hi = [0.01, 0.01]
"#
    );
    refused_scene(
        "crowded.toml",
        &text,
        &[
            "count = 100",
            "cannot fit",
            "holds at most 16",
            "4 x 4",
            "generate.count",
        ],
    );
    // 16 fit
    let p = scene("sixteen.toml", &text.replace("count = 100", "count = 16"));
    let v = ok_json(&["dem", "--scene", p.to_str().unwrap(), "--check", "--json"]);
    assert_eq!(v["particles"].as_u64(), Some(16), "{v}");
}

#[test]
fn check_prints_the_step_contact_time_count_and_sizes_and_does_not_run() {
    let text = spheres(
        "",
        &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.01, 0.0, 0.01], 0.003)),
    );
    let p = scene("check.toml", &text);
    let out = p.with_extension("out");
    let _ = std::fs::remove_dir_all(&out);
    let o = dashpot(&sh(&format!(
        "dem --scene {} --check --out {}",
        p.to_str().unwrap(),
        out.to_str().unwrap()
    )));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for needle in [
        "every check passed (not run)",
        "dt = ",
        "contact time",
        "50.0 steps per collision",
        "2 3D particles, diameters 2.0000e-3 .. 3.0000e-3 m",
        "steps: ",
        "peak memory: about ",
        "wall time: about ",
    ] {
        assert!(stdout.contains(needle), "'{needle}' in: {stdout}");
    }
    assert!(!out.exists(), "--check wrote {}", out.display());
    // the step is the contact time over steps_per_collision, exactly
    let v = ok_json(&["dem", "--scene", p.to_str().unwrap(), "--check", "--json"]);
    let (dt, tau) = (v["dt"].as_f64().unwrap(), v["collision_time"].as_f64().unwrap());
    assert!((dt - tau / 50.0).abs() <= 1e-15 * tau, "{v}");
    assert_eq!(v["particles"].as_u64(), Some(2));
    assert_eq!(v["diameter_min"].as_f64(), Some(0.002));
    assert_eq!(v["diameter_max"].as_f64(), Some(0.003));
    // the estimate: the steps to the duration, a peak above what the process holds, a time
    let est = &v["estimate"];
    let steps = est["steps"].as_u64().unwrap();
    assert_eq!(steps, (0.001 / dt).ceil() as u64, "{est}");
    assert!(
        est["memory_bytes"].as_f64().unwrap() > est["resident_bytes_after_sample"].as_f64().unwrap() * 0.5,
        "{est}"
    );
    assert!(est["wall_seconds"].as_f64().unwrap() > 0.0, "{est}");
    // the same with steps_per_collision = 100: half the step
    let p100 = scene(
        "check100.toml",
        &text.replace("duration = 0.001", "duration = 0.001\nsteps_per_collision = 100"),
    );
    let v100 = ok_json(&["dem", "--scene", p100.to_str().unwrap(), "--check", "--json"]);
    assert!(
        (v100["dt"].as_f64().unwrap() - dt / 2.0).abs() <= 1e-15 * dt,
        "{v100}"
    );
    // a failing check: non-zero, the checks' message, nothing printed as passed
    let bad = scene(
        "check-bad.toml",
        &spheres(
            "",
            &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.0, 0.0, 0.0105], 0.002)),
        ),
    );
    let o = dashpot(&["dem", "--scene", bad.to_str().unwrap(), "--check"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("overlap at the start"));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("passed"));
    // --check is a scene's option
    fails(&["dem", "--bed", "--check"], &["--scene"]);
}

#[test]
fn scene_errors_name_the_key_path_the_type_and_the_closest_key_on_the_first_line() {
    let good = spheres(
        "",
        &(particle([0.0, 0.0, 0.01], 0.002) + &particle([0.01, 0.0, 0.01], 0.002)),
    );
    let cases: [(&str, &str, &[&str]); 6] = [
        (
            "position = [0.01, 0.0, 0.01]",
            "position = [0.01, 0.0, 0.01]\nvelocty = [1.0, 0.0, 0.0]",
            &[
                "unknown key `particle[1].velocty`",
                "did you mean `velocity`?",
                "line 20",
            ],
        ),
        (
            "position = [0.01, 0.0, 0.01]",
            "position = [0.01, 0.0, 0.01]\nvelocity = \"fast\"",
            &[
                "`particle[1].velocity`",
                "expected an array",
                "found string \"fast\"",
            ],
        ),
        (
            "diameter = 0.002\n",
            "diameter = \"2 mm\"\n",
            &[
                "`particle[0].diameter`",
                "expected a number",
                "found string \"2 mm\"",
            ],
        ),
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 1.0]\nmotion = { kind = \"pistn\", amplitude = 0.001, frequency = 20.0 }",
            &[
                "`wall[0].motion.kind` = \"pistn\"",
                "did you mean `piston`?",
                "`fixed`, `piston`, `sine`",
            ],
        ),
        (
            "density = 7800.0",
            "densty = 7800.0",
            &["unknown key `material.densty`", "did you mean `density`?"],
        ),
        (
            "name = \"hsd\"",
            "name = \"hdd\"",
            &["unknown law 'hdd'", "did you mean `hsd`?"],
        ),
    ];
    for (k, (from, to, needles)) in cases.iter().enumerate() {
        assert!(good.contains(from), "{from}");
        let p = scene(&format!("key{k}.toml"), &good.replacen(from, to, 1));
        let (err, first) = error_of(&["dem", "--scene", p.to_str().unwrap()]);
        assert!(!first.contains("TOML parse error"), "{err}");
        for n in *needles {
            assert!(first.contains(n), "'{n}' not on the first line: {err}");
        }
    }
    // a scene's law parameter with a typo
    let p = scene("param.toml", &good.replace("eps = 0.5", "epsx = 0.5"));
    let (err, _) = error_of(&["dem", "--scene", p.to_str().unwrap()]);
    assert!(err.contains("no parameter 'epsx' (did you mean `eps`?)"), "{err}");
}

#[test]
fn config_errors_name_the_key_and_the_closest_one() {
    let f = scene("cfg.toml", "[law]\nname = \"hsd\"\n[particle]\ndiamter = 0.002\n");
    let (err, first) = error_of(&sh(&format!(
        "eval --config {} --delta 1e-5 --rate 0.1",
        f.to_str().unwrap()
    )));
    for n in [
        "not a valid dashpot configuration",
        "unknown key `particle.diamter`",
        "did you mean `diameter`?",
        "line 4, column 1",
    ] {
        assert!(first.contains(n), "'{n}' not on the first line: {err}");
    }
    let f = scene("cfg2.toml", "[law]\nname = \"hsd\"\n[partner]\ntype = \"wal\"\n");
    let (err, first) = error_of(&sh(&format!(
        "eval --config {} --delta 1e-5 --rate 0.1",
        f.to_str().unwrap()
    )));
    assert!(first.contains("`partner.type` = \"wal\""), "{err}");
    assert!(first.contains("did you mean `wall`?"), "{err}");
    let f = scene(
        "cfg3.toml",
        "[law]\nname = \"hsd\"\n[particle]\ndensity = \"heavy\"\n",
    );
    let (err, first) = error_of(&sh(&format!(
        "eval --config {} --delta 1e-5 --rate 0.1",
        f.to_str().unwrap()
    )));
    assert!(
        first.contains("`particle.density`: expected a number, found string \"heavy\""),
        "{err}"
    );
}

#[test]
fn law_parameter_and_command_typos_get_the_name_meant() {
    let eval = ["eval", "--delta", "1e-5", "--rate", "0.1"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { eval.iter().chain(extra).copied().collect() };
    fails(
        &with(&["--law", "hdd"]),
        &["unknown law 'hdd' (did you mean `hsd`?)", "available laws"],
    );
    fails(
        &with(&["--law", "hsd", "--set", "epsx=0.5"]),
        &[
            "law 'hsd' has no parameter 'epsx' (did you mean `eps`?)",
            "its parameters are: eps",
        ],
    );
    // nothing close: no guess, the list as before
    let (err, _) = error_of(&with(&["--law", "hertz"]));
    assert!(!err.contains("did you mean"), "{err}");
    // a restitution law and a tangential law, through the other commands
    fails(
        &sh("bed --restitution constnt --layers 1 --freq 20"),
        &["did you mean `constant`?"],
    );
    fails(
        &sh("bed --engine dem --law hsd --tangential mindln --layers 1 --freq 20"),
        &["did you mean `mindlin`?"],
    );
    // commands and flags: clap's own suggestions
    fails(&["evl"], &["unrecognized subcommand 'evl'", "eval"]);
    fails(
        &["eval", "--lawx", "hsd"],
        &["--lawx", "a similar argument exists: '--law'"],
    );
}

/// Every non-empty CSV in `dir` (recursively) begins with the provenance block: its law lines
/// and plugin lines, as `#` comments before the header.
fn csvs_have_provenance(dir: &Path) -> usize {
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            n += csvs_have_provenance(&p);
        } else if p.extension().is_some_and(|x| x == "csv") {
            let s = std::fs::read_to_string(&p).unwrap();
            assert!(s.starts_with("# law: "), "{}:\n{s}", p.display());
            assert!(s.contains("\n# plugin: "), "{}", p.display());
            assert!(s.contains("dashpot 0."), "{}", p.display());
            n += 1;
        }
    }
    n
}

fn out_dir(tag: &str) -> PathBuf {
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("new-user-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn scaling_results_carry_the_provenance_on_both_engines() {
    // a small grid into `out`, with the options `opts`
    let scaling = |tag: &str, opts: &str, grid: &str| {
        let out = out_dir(tag);
        let line = format!(
            "scaling {opts} --layers 0.5 {grid} --out {} --json",
            out.display()
        );
        (ok_json(&sh(&line)), out)
    };
    let event_grid = "--freqs 10:12:2 --transient 2 --cycles 3";
    let (v, out) = scaling("scaling", "--restitution constant --set r=0.9", event_grid);
    let prov = &v["provenance"];
    assert_eq!(prov["law"], "constant", "{v}");
    assert_eq!(prov["params"]["r"].as_f64(), Some(0.9));
    assert_eq!(prov["param_sources"]["r"], "given");
    assert!(prov["plugin"]["file"]
        .as_str()
        .unwrap()
        .contains("dashpot_constant"));
    assert!(prov["plugin"]["version"].is_string() && prov["dashpot_version"].is_string());
    assert_eq!(v["exponents"].as_array().unwrap().len(), 1);
    assert_eq!(csvs_have_provenance(&out), 2);
    let grid = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    assert!(
        grid.starts_with("# law: constant (restitution): r = 0.9 (given)\n"),
        "{grid}"
    );
    // a contact law as a restitution law: the contact law's provenance, every parameter
    let (v, out) = scaling(
        "scaling-from",
        "--restitution from:hsd --set eps=0.8 --tc 1e-5",
        event_grid,
    );
    assert_eq!(v["provenance"]["law"], "hsd", "{v}");
    assert_eq!(v["provenance"]["params"]["eps"].as_f64(), Some(0.8));
    assert_eq!(csvs_have_provenance(&out), 2);
    // the DEM engine with friction: both laws
    let (v, out) = scaling(
        "scaling-dem",
        "--engine dem --law hsd --set eps=0.9 --tangential mindlin --tset mu=0.3 --young 1e8",
        "--freqs 20:30:2 --transient 1 --cycles 2",
    );
    assert_eq!(v["provenance"]["law"], "hsd", "{v}");
    assert_eq!(v["tangential_provenance"]["law"], "mindlin", "{v}");
    assert_eq!(v["tangential_provenance"]["params"]["mu"].as_f64(), Some(0.3));
    // mindlin's damping, not given, is listed at its default
    assert_eq!(v["tangential_provenance"]["param_sources"]["damping"], "default");
    assert_eq!(csvs_have_provenance(&out), 2);
    let grid = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    assert!(
        grid.contains("# law: mindlin (tangential): mu = 0.3 (given)"),
        "{grid}"
    );
    // the text output prints it too
    let line = format!(
        "scaling --restitution constant --set r=0.9 --layers 0.5 {event_grid} --out {}",
        out.display()
    );
    let o = dashpot(&sh(&line));
    assert!(String::from_utf8_lossy(&o.stdout).contains("plugin: "));
}

#[test]
fn figures_collide_csvs_carry_the_provenance() {
    let out = out_dir("figc");
    succeeds(&["figures", "collide", "--out", out.to_str().unwrap()]);
    assert!(csvs_have_provenance(&out) >= 7);
    let fig1 = std::fs::read_to_string(out.join("fig1_phase_trajectories.csv")).unwrap();
    assert!(
        fig1.contains("# law: lsd (contact): eps = 0.54 (given)"),
        "{fig1}"
    );
    assert!(
        fig1.contains("# law: hsd (contact): eps = 0.54 (given)"),
        "{fig1}"
    );
    let fig3 = std::fs::read_to_string(out.join("fig3_time_ratio.csv")).unwrap();
    assert!(fig3.contains("# eps varies along the rows"), "{fig3}");
}

/// `figures bed` on both engines, at the tiny size (the CLI's smallest, --quick, takes minutes
/// in a debug build): every CSV carries its laws' provenance.
#[test]
fn figures_bed_csvs_carry_the_provenance_on_both_engines() {
    use dashpot::report::bed::{run_dem, run_only, Size};
    let reg = dashpot::Registry::discover(&dashpot::SearchPath {
        dirs: vec![plugin_dir()],
        files: vec![],
        use_env: false,
        use_default: false,
    })
    .unwrap();
    let out = out_dir("figb");
    run_only(&reg, &out, &Size::tiny(), &[2, 4]).unwrap();
    assert_eq!(csvs_have_provenance(&out), 3 + 8);
    let f = std::fs::read_to_string(out.join("fig2c_r095.csv")).unwrap();
    assert!(
        f.starts_with("# law: constant (restitution): r = 0.95 (given)\n"),
        "{f}"
    );
    let f = std::fs::read_to_string(out.join("fig4b_theta.csv")).unwrap();
    assert!(
        f.starts_with("# law: mcnamara-falcon (restitution): r0 = 0.95 (default), vy = 0.3 (default)\n"),
        "{f}"
    );
    let out = out_dir("figb-dem");
    run_dem(&reg, &out, &Size::tiny(), 1e8, &[2, 4]).unwrap();
    assert_eq!(csvs_have_provenance(&out), 3 + 4);
    let f = std::fs::read_to_string(out.join("dem_fig2_kk.csv")).unwrap();
    assert!(
        f.starts_with("# law: kuwabara-kono (contact): A = 0.000002 (given)\n"),
        "{f}"
    );
}
