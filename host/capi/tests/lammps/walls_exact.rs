//! `fix wall/dashpot` and `fix wall/dashpot/region` step by step against LAMMPS's own `fix
//! wall/gran` and `wall/gran/region` on every kind of wall, on 1 and 2 MPI ranks: LAMMPS's
//! sub-models in LAMMPS's words on both sides (the gran-* laws: damped tangential springs,
//! rolling, twisting marshall, JKR, the classic hooke/history and hertz/history), and dashpot's
//! own laws where they are LAMMPS's sub-models with the same numbers: `hsd eps` is `hertz/material E eps ν damping coeff_restitution` (and `lsd k eps`
//! `hooke k eps damping coeff_restitution`), `linear-history kt mu` is `linear_history kt 0 mu`
//! while the normal force stays ≥ 0 (an elastic normal law: LAMMPS caps friction by |F_n|, sdk
//! 0.3's laws by max(F_n, 0)), `rolling sds`, `twisting sds` are LAMMPS's; `wall=particle` gives
//! the wall fix wall/gran's material convention.

use super::walls::{norm, overridden, read_dump, vars, Row, DECK, PRESSED};
use super::{lib_dir, lmp, succeeded, venv};
use std::path::{Path, PathBuf};

/// LAMMPS's words and dashpot's for the same contact: Hertz (elastic) + Cundall–Strack friction
/// (dashpot's own `hsd` and `linear-history`, undamped: LAMMPS's physics) + rolling and twisting
/// sds (LAMMPS's, `gran-*`: dashpot's own `rolling-sds` and `twisting-sds` differ by design once
/// they slide, their dashpot never acting on the slip).
const GRAN_FRICTION: &str = "granular hertz/material 1e7 1.0 0.3 damping coeff_restitution tangential \
     linear_history 2e3 0.0 0.4 rolling sds 500 0.01 0.2 twisting sds 1e-3 1e-7 0.01";
const DASHPOT_FRICTION: &str = "1e7 0.3 hsd eps=1 tangential linear-history kt=2e3 mu=0.4 rolling \
     gran-rolling-sds k=500 gamma=0.01 mu=0.2 twisting gran-twisting-sds k=1e-3 gamma=1e-7 mu=0.01 \
     wall=particle";

/// The largest difference of the forces (and of the torques) of two runs, each relative to the
/// larger magnitude of that row's force (torque), or to 1e-4 of the run's largest where that
/// is smaller (a contact closing or ending, where two integrations' rounding is no longer small
/// beside the force); panics unless the rows are the same steps and atoms.
fn worst_difference(a: &[Row], b: &[Row], what: &str) -> f64 {
    assert_eq!(a.len(), b.len(), "{what}: {} rows against {}", a.len(), b.len());
    let largest = |lo: usize, hi: usize| a.iter().map(|r| norm(&r.ft[lo..hi])).fold(0.0, f64::max);
    let floor = [1e-4 * largest(0, 3), 1e-4 * largest(3, 6)];
    let mut worst = 0.0f64;
    for (ra, rb) in a.iter().zip(b) {
        assert_eq!((ra.step, ra.id), (rb.step, rb.id), "{what}");
        for (q, (lo, hi)) in [(0, 3), (3, 6)].into_iter().enumerate() {
            let scale = norm(&ra.ft[lo..hi]).max(norm(&rb.ft[lo..hi]));
            if scale == 0.0 {
                continue;
            }
            let scale = scale.max(floor[q]);
            for k in lo..hi {
                worst = worst.max((ra.ft[k] - rb.ft[k]).abs() / scale);
            }
        }
    }
    worst
}

/// A wall kind run through wall/gran and wall/dashpot.
struct Case {
    name: &'static str,
    /// in.wall's variables for both runs
    vars: Vec<(&'static str, String)>,
    /// and for the wall/gran run only (another wall giving the same physics), if any
    gran_vars: Vec<(&'static str, String)>,
    /// the coordinate (0 x, 1 y) the 2-rank grid splits at 0
    split: usize,
}

/// Runs in.wall with `style` (gran, dashpot), returning the dump's rows and the output.
fn run_wall(
    venv: &Path,
    style: &str,
    ranks: u32,
    case: &Case,
    gran: &str,
    dashpot: &str,
) -> (Vec<Row>, String) {
    // a file per case, style, ranks and models: the tests run in parallel
    let models = format!("{gran}|{dashpot}");
    let tag = models.bytes().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    });
    let dump: PathBuf = lib_dir().join(format!(
        "walls-{}-{style}-{ranks}-{tag:x}.dump",
        case.name.replace(' ', "-")
    ));
    let _ = std::fs::remove_file(&dump);
    let mut v: Vec<(&str, String)> = vec![
        ("style", style.to_string()),
        ("gmodel", gran.to_string()),
        ("dmodel", dashpot.to_string()),
        ("dump", dump.display().to_string()),
    ];
    if ranks == 2 {
        v.push((
            "procs",
            if case.split == 0 { "2 1 1" } else { "1 2 1" }.to_string(),
        ));
    }
    v.extend(if style == "gran" {
        overridden(&case.vars, &case.gran_vars)
    } else {
        case.vars.clone()
    });
    let out = succeeded(
        &lmp(venv, DECK, ranks, &v),
        &format!("{} {style} on {ranks} rank(s)", case.name),
    );
    (read_dump(&dump), out)
}

fn cases() -> Vec<Case> {
    // a sphere of 1 cm (1.3 g) pressed on the wall by a modulated force, sliding and spinning
    // across the rank split: it sticks and slips, rolls and twists
    let drum = "cylinder z 0 0 0.03 -0.05 0.05 side in rotate v_theta 0 0 0 0 0 1";
    // the drum turns clockwise at 0.2 m/s at its radius 0.03 m: period -2 pi 0.03 / 0.2
    let drum_period = "-0.94247779607693793";
    let in_drum = [
        ("x1", "0.0003"),
        ("y1", "-0.0250082"),
        ("z1", "0.0"),
        ("vx1", "-0.1"),
        ("vy1", "-0.005"),
        ("vz1", "0.02"),
        ("w1", "0 0 40"),
        ("g", "9.81"),
        ("gdir", "0 -1 0"),
        ("n", "6000"),
    ];
    let pressed = PRESSED;
    let with = |base: &[(&'static str, &'static str)], more: &[(&'static str, &'static str)]| {
        overridden(&vars(base), &vars(more))
    };
    vec![
        Case {
            name: "zplane",
            vars: with(&pressed, &[("wall", "zplane 0.0 NULL")]),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "zplane wiggling",
            vars: with(
                &pressed,
                &[("wall", "zplane 0.0 NULL"), ("extra", "wiggle z 0.0001 0.02")],
            ),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "yplane hi sheared",
            vars: vars(&[
                ("wall", "yplane NULL 0.0"),
                ("extra", "shear x 0.3"),
                ("x1", "-0.0003"),
                ("y1", "-0.00499"),
                ("z1", "0.0"),
                ("vx1", "0.1"),
                ("vy1", "0.0"),
                ("vz1", "0.05"),
                ("fpy", "0.2"),
                ("w1", "10 0 5"),
                ("period", "0.02"),
            ]),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "xplane lo hi wiggling in plane",
            vars: vars(&[
                ("wall", "xplane -0.02 0.02"),
                ("extra", "wiggle y 0.001 0.01"),
                ("x1", "0.01501"),
                ("y1", "-0.0003"),
                ("z1", "0.0"),
                ("vx1", "0.0"),
                ("vy1", "0.2"),
                ("vz1", "0.1"),
                ("fpx", "0.2"),
                ("w1", "0 20 -10"),
                ("period", "0.02"),
            ]),
            gran_vars: vec![],
            split: 1,
        },
        Case {
            name: "zcylinder",
            vars: with(&in_drum, &[("wall", "zcylinder 0.03")]),
            gran_vars: vec![],
            split: 0,
        },
        // LAMMPS 22 Jul 2025's wall/gran zcylinder with shear adds vshear along dim to the
        // spinning surface's velocity (and sums it over the atoms): compared with the documented
        // spinning cylinder, which is wall/gran/region's rotating cylinder
        Case {
            name: "zcylinder spinning",
            vars: with(&in_drum, &[("wall", "zcylinder 0.03"), ("extra", "shear x 0.2")]),
            gran_vars: vars(&[
                ("kind", "region"),
                ("wall", "region R"),
                ("extra", ""),
                ("region", drum),
                ("period", drum_period),
            ]),
            split: 0,
        },
        Case {
            name: "region plane",
            vars: with(
                &pressed,
                &[
                    ("kind", "region"),
                    ("wall", "region R"),
                    ("region", "plane 0 0 0 0 0 1 side in"),
                ],
            ),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "region moving plane",
            vars: with(
                &pressed,
                &[
                    ("kind", "region"),
                    ("wall", "region R"),
                    ("region", "plane 0 0 0 0 0 1 side in move v_xw NULL v_zw"),
                    ("ax", "0.002"),
                    ("az", "0.0001"),
                ],
            ),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "region rotating drum",
            vars: with(
                &in_drum,
                &[
                    ("kind", "region"),
                    ("wall", "region R"),
                    ("region", drum),
                    ("period", drum_period),
                ],
            ),
            gran_vars: vec![],
            split: 0,
        },
        // a corner: two of the block's faces at once, each contact with its own history
        Case {
            name: "region block corner",
            vars: vars(&[
                ("kind", "region"),
                ("wall", "region R"),
                ("region", "block -0.02 0.02 -0.02 0.02 -0.02 0.02 side in"),
                ("x1", "0.0149"),
                ("y1", "-0.0003"),
                ("z1", "-0.0149"),
                ("vx1", "0.1"),
                ("vy1", "0.2"),
                ("vz1", "-0.1"),
                ("fpx", "0.03"),
                ("fpz", "-0.03"),
                ("w1", "5 -20 8"),
            ]),
            gran_vars: vec![],
            split: 1,
        },
    ]
}

/// Every kind of wall (planes, sheared and wiggling; the z cylinder, still and spinning; a
/// static, a moving and a rotating region; a block's corner, two contacts at once), one sphere
/// sticking, slipping, rolling and twisting on it: the wall's force and torque through
/// wall/dashpot equal wall/gran's at every step to 1e-10 of their magnitude, on 1 rank and on 2
/// (the sphere crosses the split while in contact, its history travelling with it).
#[test]
fn wall_dashpot_equals_wall_gran_on_every_kind_of_wall() {
    let Some(v) = venv() else { return };
    for case in cases() {
        for ranks in [1, 2] {
            let (g, _) = run_wall(&v, "gran", ranks, &case, GRAN_FRICTION, DASHPOT_FRICTION);
            let (d, out) = run_wall(&v, "dashpot", ranks, &case, GRAN_FRICTION, DASHPOT_FRICTION);
            let worst = worst_difference(&g, &d, case.name);
            let touching: Vec<&Row> = d.iter().filter(|r| norm(&r.ft[..3]) > 0.0).collect();
            eprintln!(
                "{} on {ranks} rank(s): {} steps in contact, worst relative difference {worst:.3e}",
                case.name,
                touching.len()
            );
            assert!(
                touching.len() > 1000,
                "{}: the sphere hardly touched the wall",
                case.name
            );
            assert!(worst <= 1e-10, "{} on {ranks} rank(s): {worst:e}", case.name);
            if ranks == 2 {
                assert!(
                    out.contains("2 by 1 by 1") || out.contains("1 by 2 by 1"),
                    "{out}"
                );
                let s = case.split;
                assert!(
                    touching.iter().any(|r| r.x[s] < 0.0) && touching.iter().any(|r| r.x[s] > 0.0),
                    "{}: the sphere did not cross the ranks' split while touching",
                    case.name
                );
            }
        }
    }
}

/// A damped normal law without friction (the normal force then pulls at the end of a
/// contact, where friction would be capped differently by sdk 0.3's laws): `hsd` is
/// `hertz/material ... damping coeff_restitution`, `lsd` is `hooke ... damping
/// coeff_restitution`, step by step, on a plane, the cylinder and a rotating region.
#[test]
fn damped_impacts_equal_wall_gran_step_by_step() {
    let Some(v) = venv() else { return };
    let models = [
        (
            "granular hertz/material 1e7 0.7 0.3 damping coeff_restitution tangential linear_nohistory 0.0 0.0",
            "1e7 0.3 hsd eps=0.7 wall=particle",
        ),
        (
            "granular hooke 2e3 0.7 damping coeff_restitution tangential linear_nohistory 0.0 0.0",
            "1e7 0.3 lsd k=2e3 eps=0.7",
        ),
    ];
    let impact = |wall: &str, extra: &[(&'static str, &str)]| {
        overridden(
            &vars(&[("wall", wall), ("vx1", "0.2"), ("vz1", "-0.3"), ("w1", "3 30 40")]),
            &vars(extra),
        )
    };
    let cases = [
        Case {
            name: "impact zplane",
            vars: impact("zplane 0.0 NULL", &[]),
            gran_vars: vec![],
            split: 0,
        },
        Case {
            name: "impact region",
            vars: impact(
                "region R",
                &[
                    ("kind", "region"),
                    (
                        "region",
                        "sphere 0 0 -0.1 0.1 side out rotate v_theta 0 0 -0.1 1 0 0",
                    ),
                    ("period", "1.0"),
                ],
            ),
            gran_vars: vec![],
            split: 0,
        },
    ];
    for (gran, dashpot) in models {
        for case in &cases {
            let (g, _) = run_wall(&v, "gran", 1, case, gran, dashpot);
            let (d, _) = run_wall(&v, "dashpot", 1, case, gran, dashpot);
            let worst = worst_difference(&g, &d, case.name);
            eprintln!(
                "{} with {dashpot}: worst relative difference {worst:.3e}",
                case.name
            );
            assert!(
                d.iter().filter(|r| r.ft[2] != 0.0).count() > 300,
                "{}: no impact",
                case.name
            );
            assert!(worst <= 1e-10, "{} {dashpot}: {worst:e}", case.name);
        }
    }
}

/// LAMMPS's own sub-models in LAMMPS's words on both sides (`fix wall/dashpot` takes `fix
/// wall/gran`'s model words as they are): a damped Mindlin spring (its damping the normal
/// model's prefactor, passed in the normal context), rolling and twisting marshall, JKR's
/// adhesive wall, and the classic `hertz/history` and `hooke/history` walls; every kind of wall
/// for the first, a plane, the cylinder and the rotating drum for the others; 2 ranks too on the
/// plane and the drum.
#[test]
fn lammps_sub_models_on_walls_equal_wall_gran_step_by_step() {
    let Some(v) = venv() else { return };
    let full = "hertz/material 1e7 0.5 0.3 damping tsuji tangential mindlin NULL 1.0 0.4 \
         rolling sds 500 0.01 0.2 twisting marshall";
    let others = [
        "granular jkr 1e7 0.5 0.3 0.05 tangential linear_history 2e3 1.0 0.4",
        "hertz/history 2e7 NULL 50 NULL 0.4 1",
        "hooke/history 2e3 NULL 50 NULL 0.4 1",
    ];
    let some = ["zplane", "zcylinder", "region rotating drum"];
    let mut worst_all = 0.0f64;
    for case in cases() {
        let gran = format!("granular {full}");
        let mut models: Vec<(String, String)> = vec![(gran.clone(), full.to_string())];
        if some.contains(&case.name) {
            models.extend(others.iter().map(|m| (m.to_string(), m.to_string())));
        }
        for (k, (gran, dashpot)) in models.iter().enumerate() {
            // 2 ranks (the history crossing them, law by law the same bookkeeping: the test
            // above crosses every kind of wall) for the first model on a plane and the drum
            let two = k == 0 && (case.name == "zplane" || case.name == "region rotating drum");
            for ranks in if two { vec![1, 2] } else { vec![1] } {
                let (g, _) = run_wall(&v, "gran", ranks, &case, gran, dashpot);
                let (d, _) = run_wall(&v, "dashpot", ranks, &case, gran, dashpot);
                let worst = worst_difference(&g, &d, case.name);
                let touching = d.iter().filter(|r| norm(&r.ft[..3]) > 0.0).count();
                eprintln!(
                    "{} with '{dashpot}' on {ranks} rank(s): {touching} steps in contact, worst {worst:.3e}",
                    case.name
                );
                assert!(
                    touching > 500,
                    "{} '{dashpot}': the sphere hardly touched the wall",
                    case.name
                );
                assert!(
                    worst <= 1e-10,
                    "{} '{dashpot}' on {ranks} rank(s): {worst:e}",
                    case.name
                );
                worst_all = worst_all.max(worst);
            }
        }
    }
    eprintln!("LAMMPS's sub-models on walls: worst relative difference {worst_all:e}");
}
