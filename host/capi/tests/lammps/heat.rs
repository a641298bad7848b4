//! Heat conduction through `pair_style dashpot` and `fix wall/dashpot`: LAMMPS's `heat radius k`
//! and `heat area h` (and any dashpot heat law) read each atom's `temperature` and add to its
//! `heatflow` (fix property/atom), which fix heat/flow integrates. Two spheres held in static
//! contact (`in.heat`) relax as explicit Euler's closed form and as `pair_style granular` to
//! 1e-9, on 1 and 2 ranks (the pair across the ranks' split) with newton on and off, with and
//! without a wall at an oscillating temperature; LAMMPS's `in.pour.heat` gives the same
//! temperatures, statistically, as with `pair_style granular`.

use super::decks::{deck_agrees, switch_sh, Deck};
use super::{assert_same, failing_deck, num, run_deck, venv};
use std::collections::HashMap;
use std::path::Path;

const DECK: &str = "in.heat";

fn run(v: &Path, ranks: u32, vars: &[(&str, &str)]) -> HashMap<String, String> {
    let vars: Vec<(&str, String)> = vars.iter().map(|&(k, x)| (k, x.to_string())).collect();
    run_deck(v, DECK, ranks, &vars)
}

/// Explicit Euler on two bodies of heat capacities C1, C2 joined by a constant conductance H:
/// T1 - T2 = ΔT0 (1 - dt H (1/C1 + 1/C2))^n, and C1 T1 + C2 T2 is conserved.
fn assert_relaxes(r: &HashMap<String, String>, h: f64, steps: i32, dt: f64, what: &str) {
    let (t1, t2) = (num(r, "t1"), num(r, "t2"));
    // cp = 1: C = m
    let (c1, c2) = (num(r, "m1"), num(r, "m2"));
    let expect = (1.0 - dt * h * (1.0 / c1 + 1.0 / c2)).powi(steps);
    assert!(
        ((t1 - t2) - expect).abs() <= 1e-12,
        "{what}: T1 - T2 = {} against the closed form {expect}",
        t1 - t2
    );
    assert!(
        (c1 * t1 + c2 * t2 - c1).abs() <= 1e-14 * c1,
        "{what}: C1 T1 + C2 T2 = {} against {c1} at the start",
        c1 * t1 + c2 * t2
    );
    // the closed form moved: the test can fail
    assert!(expect < 0.9, "{what}: too little heat flowed ({expect})");
}

/// The contact radius of the two spheres (radius 0.5 each) at the deck's gap: a = √(R δ).
fn contact_radius(r: &HashMap<String, String>) -> f64 {
    (0.25 * (1.0 - num(r, "gap"))).sqrt()
}

/// The two spheres through granular's `heat radius` (types 2 and 8: mixed as √(k1 k2) = 4) and
/// `heat area` (10 and 40: 20), then through dashpot by the one word: the closed form of explicit Euler to 1e-12
/// with H = 2 k a and h π a², and granular's temperatures to 1e-9, on 1 and 2 ranks, newton on
/// and off.
#[test]
fn two_spheres_relax_as_with_granular() {
    let Some(v) = venv() else { return };
    for (heat1, heat2, conductance) in [
        ("heat radius 2.0", "heat radius 8.0", 2.0 * 4.0),
        ("heat area 10.0", "heat area 40.0", 0.0),
    ] {
        for ranks in [1, 2] {
            for newton in ["on", "off"] {
                let vars = |style| {
                    vec![
                        ("style", style),
                        ("heat1", heat1),
                        ("heat2", heat2),
                        ("newton", newton),
                    ]
                };
                let g = run(&v, ranks, &vars("granular"));
                let d = run(&v, ranks, &vars("dashpot"));
                let what = format!("{heat1}/{heat2} on {ranks} rank(s), newton {newton}");
                eprintln!("{what}: granular {g:?}\n  dashpot {d:?}");
                let a = contact_radius(&d);
                let h = if conductance > 0.0 {
                    conductance * a
                } else {
                    20.0 * std::f64::consts::PI * a * a
                };
                assert_relaxes(&d, h, 300, 0.001, &format!("dashpot, {what}"));
                assert_relaxes(&g, h, 300, 0.001, &format!("granular, {what}"));
                for k in ["t1", "t2"] {
                    assert_same(k, &g, &d, 1e-9, &what);
                }
            }
        }
    }
}

/// Both spheres also rest on a wall whose temperature oscillates (`temperature v_twall`,
/// `heat area 5.0` in the wall's model): heat enters from the wall, and the temperatures are
/// granular's (fix wall/gran) to 1e-9 on 1 and 2 ranks.
#[test]
fn two_spheres_on_a_heating_wall_as_with_granular() {
    let Some(v) = venv() else { return };
    for ranks in [1, 2] {
        let g = run(&v, ranks, &[("style", "granular"), ("wall", "1")]);
        let d = run(&v, ranks, &[("style", "dashpot"), ("wall", "1")]);
        eprintln!("wall, {ranks} rank(s): granular {g:?}\n  dashpot {d:?}");
        for k in ["t1", "t2"] {
            assert_same(k, &g, &d, 1e-9, &format!("on the wall, {ranks} rank(s)"));
        }
        assert_wall_conducted(&d);
    }
}

/// dashpot's own syntax: `heat LAW key=value` after the other laws (here the short name
/// `radius` for heat-radius, under hsd, whose contact radius is the Hertzian √(R δ)), and a wall
/// of `heat heat-area h=5`: the closed form without the wall, and the same run on 1 and 2 ranks
/// with it.
#[test]
fn dashpot_syntax_heat_laws_conduct() {
    let Some(v) = venv() else { return };
    let base = [
        ("style", "dashpot"),
        ("own", "1"),
        ("coeff", "1e5 0.3 hsd eps=0.8 heat radius k=2"),
        ("wallcoeff", "1e5 0.3 hsd eps=0.8 heat heat-area h=5"),
    ];
    for ranks in [1, 2] {
        let d = run(&v, ranks, &base);
        let a = contact_radius(&d);
        assert_relaxes(
            &d,
            2.0 * 2.0 * a,
            300,
            0.001,
            &format!("hsd + heat-radius, {ranks} rank(s)"),
        );
    }
    let mut wall = base.to_vec();
    wall.push(("wall", "1"));
    let (one, two) = (run(&v, 1, &wall), run(&v, 2, &wall));
    for k in ["t1", "t2"] {
        assert_same(
            k,
            &one,
            &two,
            1e-12,
            "hsd + heat-radius on a heat-area wall, 1 against 2 ranks",
        );
    }
    assert_wall_conducted(&one);
}

/// The wall gave or took heat: the pair's own C1 T1 + C2 T2 (C1 at the start) is not conserved.
fn assert_wall_conducted(r: &HashMap<String, String>) {
    let (c1, c2) = (num(r, "m1"), num(r, "m2"));
    let sum = c1 * num(r, "t1") + c2 * num(r, "t2");
    assert!((sum - c1).abs() > 1e-4 * c1, "no heat from the wall: {r:?}");
}

/// Bad input stops LAMMPS with an error naming what is missing.
#[test]
fn heat_refuses_bad_input_by_name() {
    let Some(v) = venv() else { return };
    for (vars, needle) in [
        (
            vec![("props", "0")],
            "a heat law needs per-atom temperature and heatflow: add 'fix ID all property/atom",
        ),
        (
            vec![("wall", "1"), ("walltemp", "0")],
            "heat law 'heat-area' needs the wall's temperature",
        ),
        (
            vec![
                ("wall", "1"),
                (
                    "wallmodel",
                    "hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5",
                ),
            ],
            "'temperature' needs a heat law in the wall's model",
        ),
        (
            vec![("heat1", "heat volume 2.0")],
            "unknown heat model 'volume' (valid: none, radius, area)",
        ),
        (
            vec![("heat2", "heat area 2.0")],
            "cannot mix the heat models of types 1 1 and 2 2 ('radius' and 'area')",
        ),
        (
            vec![("own", "1"), ("coeff", "1e5 0.3 hsd heat hsd")],
            "creating the heat law",
        ),
    ] {
        let mut w: Vec<(&str, &str)> = vec![("style", "dashpot")];
        w.extend(vars);
        let text = failing_deck(&v, DECK, &w);
        assert!(
            text.contains("ERROR") && text.contains(needle),
            "{w:?}: expected '{needle}' in\n{text}"
        );
    }
}

/// The style lines of LAMMPS's in.pour.heat through `switch.sh`: one word each (and the
/// plugin's options), the heat models, `temperature v_oscillate`, fix property/atom and fix
/// heat/flow kept as they are.
#[test]
fn switch_sh_switches_in_pour_heat_by_one_word() {
    let model = "hertz/material 1e5 0.1 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji";
    let deck = format!(
        "pair_style granular\n\
         pair_coeff * * hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji heat area 5.0\n\
         fix 0 all property/atom temperature heatflow\n\
         fix 3 all heat/flow constant 1.0\n\
         fix 5 all wall/gran/region granular {model} heat area 5.0 region bottom_wall temperature v_oscillate\n"
    );
    let (text, _) = switch_sh(&deck, "lammps-switch-heat");
    let lines: Vec<&str> = text.lines().collect();
    let fix5 = format!(
        "fix 5 all wall/dashpot/region {model} heat area 5.0 region bottom_wall temperature v_oscillate plugin_dir=/laws"
    );
    let expect = [
        "plugin load     /p/dashpotplugin.so",
        "pair_style dashpot plugin_dir=/laws",
        "pair_coeff * * hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji heat area 5.0",
        "fix 0 all property/atom temperature heatflow",
        "fix 3 all heat/flow constant 1.0",
        fix5.as_str(),
    ];
    assert_eq!(lines, expect, "switched deck:\n{text}");
}

/// LAMMPS's in.pour.heat by the one word, shortened (300 particles poured onto the plate, 8000
/// steps): the particles' mean temperature and its spread over the particles, averaged over two
/// pours on 1 and 2 ranks, within the scatter of granular's own runs (or 2 % of its mean).
#[test]
fn in_pour_heat_warms_as_with_granular() {
    let Some(v) = venv() else { return };
    let deck = Deck {
        file: "in.pour.heat",
        vars: &[("n", "150"), ("nsteps", "8000")],
        com: &[("tmean", 0.02), ("tspread", 0.02), ("zcom", 0.02)],
        seeds: &["1234", "4321"],
    };
    deck_agrees(&v, &deck);
}
