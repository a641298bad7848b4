//! `pair_style dashpot` per pair of types, with newton on, under `pair_style hybrid` and in
//! reduced units; and the spec layer's own unit test (C++, no LAMMPS needed).

use super::{assert_same, failing_deck, lammps_dir, lib_dir, num, run_deck, venv};
use std::process::Command;

/// The spec layer (`examples/lammps/dashpot_spec.cpp`, `dashpot_translate.cpp`: dashpot's
/// syntax, LAMMPS's granular and classic syntaxes translated to the gran-* laws, the refusals,
/// the mixing of two types) compiled alone with its unit test and run: no LAMMPS header is
/// needed.
#[test]
fn the_spec_layer_passes_its_unit_test() {
    let dir = lib_dir().join("lammps-spec-test");
    std::fs::create_dir_all(&dir).expect("spec test dir");
    let exe = dir.join("test_spec");
    let src = lammps_dir();
    let cxx = std::env::var("CXX").unwrap_or_else(|_| "g++".to_string());
    let built = Command::new(&cxx)
        .args(["-std=c++17", "-O1", "-Wall", "-Wextra", "-Werror"])
        .arg(src.join("test_spec.cpp"))
        .arg(src.join("dashpot_spec.cpp"))
        .arg(src.join("dashpot_translate.cpp"))
        .arg("-o")
        .arg(&exe)
        .output()
        .expect("run the C++ compiler");
    assert!(
        built.status.success(),
        "{cxx} failed:\n{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let run = Command::new(&exe).output().expect("run test_spec");
    let out = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{out}");
    assert!(out.contains("all checks passed"), "{out}");
}

fn collision_types(v: &std::path::Path, c11: &str, c22: &str, c12: Option<&str>) -> f64 {
    let mut vars = vec![
        ("types", "1".to_string()),
        ("c11", c11.to_string()),
        ("c22", c22.to_string()),
    ];
    if let Some(c) = c12 {
        vars.push(("set12", "1".into()));
        vars.push(("c12", c.into()));
    }
    let r = run_deck(v, "in.collision", 1, &vars);
    assert!(num(&r, "gap") > 0.0, "{r:?}");
    num(&r, "realized")
}

/// Two spheres of types 1 and 2 collide head on, `pair_style dashpot` naming no law: the pair
/// takes the laws of its own `pair_coeff 1 2` (HSD realizes its ε, not the types' own), and
/// without one mixes `1 1` and `2 2` as `pair_style granular` does: the geometric mean of the
/// two ε. HSD realizes its ε exactly (to the integrator's 1e-4), so each value shows which
/// parameters the contact was bound with.
#[test]
fn pairs_of_types_take_their_own_laws_and_mix_unset_ones() {
    let Some(v) = venv() else { return };
    let (e, nu) = ("6e9", "0.3");
    let c = |law: &str| format!("{e} {nu} {law}");
    let own = collision_types(&v, &c("hsd eps=0.9"), &c("hsd eps=0.9"), Some(&c("hsd eps=0.3")));
    eprintln!("pair 1 2 with its own eps = 0.3: realized {own}");
    assert!((own - 0.3).abs() < 1e-3, "{own}");
    let mixed = collision_types(&v, &c("hsd eps=0.81"), &c("hsd eps=0.25"), None);
    eprintln!("pair 1 2 mixing eps = 0.81 and 0.25: realized {mixed} (sqrt: 0.45)");
    assert!((mixed - 0.45).abs() < 1e-3, "{mixed}");
    // the laws given once to pair_style, the materials per type: the same contact
    let plain = run_deck(&v, "in.collision", 1, &[("eps", "0.45".into())]);
    assert!(
        (num(&plain, "realized") - mixed).abs() < 1e-9,
        "{plain:?} vs {mixed}"
    );
}

/// Bad input per pair of types stops LAMMPS with a message naming the word and the choices.
#[test]
fn bad_pair_coeff_input_is_refused_with_the_word_and_the_choices() {
    let Some(v) = venv() else { return };
    let types = |c11: &str, c22: &str| {
        failing_deck(&v, "in.collision", &[("types", "1"), ("c11", c11), ("c22", c22)])
    };
    for (c11, c22, needle) in [
        (
            "6e9 0.3 hsd eps=0.5",
            "6e9 0.3 lsd eps=0.5",
            "cannot mix the normal laws of types 1 1 and 2 2 ('hsd' and 'lsd'): give pair_coeff 1 2 explicitly",
        ),
        (
            "6e9 0.3",
            "6e9 0.3 hsd",
            "pair_coeff 1 1: no law for these types, and pair_style dashpot names none",
        ),
        ("6e9", "6e9 0.3 hsd", "after Young's modulus '6e9' comes Poisson's ratio"),
        (
            "6e9 0.3 hsd eps=0.5 bogus",
            "6e9 0.3 hsd",
            "unexpected word 'bogus' after law 'hsd': expected key=value, 'tangential LAW'",
        ),
        ("6e9 0.3 hsd eps=0.5", "6e9 0.3 hsd epsilon=0.5", "law 'hsd' has no parameter 'epsilon'; its parameters are: eps"),
        ("hsd eps=0.5", "hsd eps=0.5", "type 1 has no material: give pair_coeff 1 1 E nu"),
        (
            "6e9 0.3 hsd tangential mindlin mu=0.5",
            "6e9 0.3 hsd",
            "cannot mix the tangential laws of types 1 1 and 2 2 ('mindlin' and none)",
        ),
    ] {
        let text = types(c11, c22);
        assert!(
            text.contains("ERROR") && text.contains(needle),
            "{c11} / {c22}: expected '{needle}' in\n{text}"
        );
    }
    // issue 37: a family keyword followed by an option names the missing law
    let text = failing_deck(&v, "in.sliding", &[("tangential", "plugin_dir=/nowhere")]);
    assert!(
        text.contains("'tangential' must be followed by one tangential law name, got 'plugin_dir=/nowhere'"),
        "{text}"
    );
    // the history fix deleted by the deck mid-contact: refused rather than silently reset
    let text = failing_deck(&v, "in.twospheres", &[("unfix", "1")]);
    assert!(
        text.contains("its history fix DASHPOT_HISTORY was deleted (unfix)"),
        "{text}"
    );
}

/// With newton on each contact is computed by one rank only, and its history must reach the
/// rank that computes it after the next list build (a reverse communication of the ghosts'
/// records): the long frictional contact crossing the rank boundary ends exactly as with newton
/// off, on 1 and 2 ranks, also through a restart file mid-contact.
#[test]
fn newton_on_gives_the_newton_off_trajectory_on_one_and_two_ranks() {
    let Some(v) = venv() else { return };
    let off = run_deck(&v, "in.twospheres", 1, &[]);
    let dir = lib_dir().join("lammps-restart-newton");
    std::fs::create_dir_all(&dir).expect("restart dir");
    for (ranks, restart) in [(1, false), (2, false), (2, true)] {
        let mut vars = vec![("newton", "on".to_string())];
        if restart {
            vars.push(("restart", "1".into()));
            vars.push(("restart_dir", dir.display().to_string()));
            vars.push(("repeat_pair", "0".into()));
        }
        let on = run_deck(&v, "in.twospheres", ranks, &vars);
        eprintln!("newton on, {ranks} rank(s), restart {restart}: {on:?}");
        // a restart changes LAMMPS's own first step (1e-8 here: see the restart test)
        let tol = if restart { 1e-6 } else { 1e-12 };
        for k in ["x1", "y1", "z1", "vx1", "vy1", "vz1", "vx2", "vy2", "w1", "w3"] {
            assert_same(k, &off, &on, tol, &format!("newton off / on, {ranks} rank(s)"));
        }
    }
}

/// Issue 34's case: sphere 2 of type 2, the laws from two `dashpot` sub-styles of `pair_style
/// hybrid` (the same laws in both; the contact is the first's). Each instance keeps its own
/// history fix, so 1 and 2 ranks end as the plain style does (vy1 = -0.0059296...; with a shared
/// fix the second instance erased the first's history: -0.0015049 on 2 ranks). A `zplane` wall
/// inside hybrid acts on its own instance's types, as the plain style's does.
#[test]
fn two_dashpot_sub_styles_of_hybrid_keep_their_own_history() {
    let Some(v) = venv() else { return };
    let plain = run_deck(&v, "in.twospheres", 1, &[]);
    for ranks in [1, 2] {
        let hybrid = run_deck(&v, "in.twospheres", ranks, &[("hybrid", "1".into())]);
        eprintln!("hybrid on {ranks} rank(s): {hybrid:?}");
        for k in ["x1", "y1", "vx1", "vy1", "vz1", "vx2", "vy2", "w1", "w3"] {
            assert_same(
                k,
                &plain,
                &hybrid,
                1e-12,
                &format!("plain and hybrid on {ranks} rank(s)"),
            );
        }
    }
    let plain = run_deck(&v, "in.sliding", 1, &[]);
    let hybrid = run_deck(&v, "in.sliding", 1, &[("hybrid", "1".into())]);
    for k in ["ratio", "roll", "wzz", "pzz"] {
        assert_same(
            k,
            &plain,
            &hybrid,
            1e-12,
            "zplane in the plain style and inside hybrid",
        );
    }
}

/// Reduced (lj) units: the head-on collision with d = 1, ρ = 1, E = 1e5 realizes its ε as in SI
/// units, and as `pair_style granular`'s `coeff_restitution` does in the same units: nothing in
/// the pair style assumes SI magnitudes.
#[test]
fn lj_units_run_and_realize_the_restitution() {
    let Some(v) = venv() else { return };
    for eps in ["0.3", "0.8"] {
        let d = run_deck(
            &v,
            "in.collision",
            1,
            &[("units", "lj".into()), ("eps", eps.into())],
        );
        let g = run_deck(
            &v,
            "in.collision",
            1,
            &[
                ("units", "lj".into()),
                ("eps", eps.into()),
                ("style", "coeffrest".into()),
            ],
        );
        eprintln!("lj units, eps {eps}: dashpot {d:?}\n    granular {g:?}");
        let e: f64 = eps.parse().expect("eps");
        assert!((num(&d, "realized") - e).abs() < 1e-3, "{d:?}");
        assert_same(
            "realized",
            &d,
            &g,
            1e-6,
            "dashpot hsd and granular coeff_restitution, lj units",
        );
    }
}

/// Contacts of different pairs of types share a batch chunk, each model called on its own
/// contacts with its own record width: a second long contact between two spheres of type 2,
/// whose laws keep wider records (Coulomb spring, rolling and twisting), runs beside the first
/// pair's; the first pair ends exactly as without it, on 1 and 2 ranks, newton off and on.
#[test]
fn contacts_of_different_models_share_chunks_without_mixing_their_records() {
    let Some(v) = venv() else { return };
    let alone = run_deck(&v, "in.twospheres", 1, &[]);
    for (ranks, newton) in [(1, "off"), (2, "off"), (2, "on")] {
        let vars = [("spectators", "1".to_string()), ("newton", newton.to_string())];
        let beside = run_deck(&v, "in.twospheres", ranks, &vars);
        eprintln!("with the second contact, {ranks} rank(s), newton {newton}: {beside:?}");
        for k in ["x1", "y1", "z1", "vx1", "vy1", "vz1", "vx2", "vy2", "w1", "w3"] {
            assert_same(
                k,
                &alone,
                &beside,
                1e-12,
                &format!("{ranks} rank(s), newton {newton}"),
            );
        }
    }
}
