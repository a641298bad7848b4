//! `pair_style dashpot` with LAMMPS's own sub-models against `pair_style granular` and the
//! classic `gran/*` styles: the same `pair_coeff` words (the same `pair_style gran/...`
//! arguments), translated to the gran-* laws, give the same contact force and torques at every
//! step of a two-sphere run (`in.exact`), on 1 and 2 ranks (the contact then between an owned
//! and a ghost atom), newton on and off.
//!
//! Two runs integrate their own trajectories, so a difference of rounding (a law's `cbrt`
//! against libm's) may grow: each step's force and torque are compared to 1e-10 relative to
//! their own size, or to 1e-4 of the run's largest where they cross zero.

use super::{lib_dir, lmp, succeeded, venv};
use std::collections::BTreeMap;
use std::path::Path;

const TOL: f64 = 1e-10;

/// One step: the contact force and torque on sphere 1, and both centres.
type Step = ([f64; 6], [f64; 3], [f64; 3]);

/// Each step's contact force and torque on sphere 1, and both centres.
struct Dump {
    rows: BTreeMap<u64, Step>,
}

fn read_dump(path: &Path) -> Dump {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut rows = BTreeMap::new();
    let mut lines = text.lines();
    let mut step = 0u64;
    while let Some(l) = lines.next() {
        if l.starts_with("ITEM: TIMESTEP") {
            step = lines.next().and_then(|s| s.trim().parse().ok()).expect("step");
            continue;
        }
        if l.starts_with("ITEM") {
            continue;
        }
        let w: Vec<f64> = l.split_whitespace().filter_map(|t| t.parse().ok()).collect();
        if w.len() != 10 {
            continue;
        }
        let x = [w[1], w[2], w[3]];
        if w[0] == 1.0 {
            rows.insert(step, ([w[4], w[5], w[6], w[7], w[8], w[9]], x, [0.0; 3]));
        } else if let Some(r) = rows.get_mut(&step) {
            r.2 = x;
        }
    }
    assert!(rows.len() > 10, "{}: no steps", path.display());
    Dump { rows }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// What a comparison found: the steps in contact, the largest relative difference of force or
/// torque, (granular's) steps with the tangential force at its cap and below it, and steps with
/// a force while the spheres are apart (an adhesive contact held beyond touching).
#[derive(Debug)]
struct Outcome {
    contact_steps: usize,
    worst: f64,
    sliding: usize,
    sticking: usize,
    apart: usize,
}

fn compare(granular: &Dump, dashpot: &Dump, mu: f64, what: &str) -> Outcome {
    assert_eq!(granular.rows.len(), dashpot.rows.len(), "{what}: steps");
    let largest = |r: std::ops::Range<usize>| {
        granular
            .rows
            .values()
            .map(|(g, ..)| norm(&g[r.clone()]))
            .fold(0.0, f64::max)
    };
    let scale = [largest(0..3), largest(3..6)];
    let mut o = Outcome {
        contact_steps: 0,
        worst: 0.0,
        sliding: 0,
        sticking: 0,
        apart: 0,
    };
    for (step, (g, x1, x2)) in &granular.rows {
        let (d, ..) = dashpot
            .rows
            .get(step)
            .unwrap_or_else(|| panic!("{what}: no step {step}"));
        for (q, (range, name)) in [(0..3, "force"), (3..6, "torque")].into_iter().enumerate() {
            let (a, b) = (&g[range.clone()], &d[range]);
            let diff = norm(&[a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
            let size = norm(a).max(1e-4 * scale[q]);
            let rel = if size > 0.0 { diff / size } else { diff };
            assert!(
                rel <= TOL,
                "{what}: step {step}, {name}: granular {a:?}, dashpot {b:?} (relative {rel:e})"
            );
            o.worst = o.worst.max(rel);
        }
        if norm(&g[0..3]) > 0.0 {
            o.contact_steps += 1;
            let r = [x1[0] - x2[0], x1[1] - x2[1], x1[2] - x2[2]];
            // in.exact's diameters: 1 and 1.2 mm
            if norm(&r) > 0.5e-3 + 0.6e-3 {
                o.apart += 1;
            }
            let n: Vec<f64> = r.iter().map(|c| c / norm(&r)).collect();
            let fnorm = g[0] * n[0] + g[1] * n[1] + g[2] * n[2];
            let ft = norm(&[g[0] - fnorm * n[0], g[1] - fnorm * n[1], g[2] - fnorm * n[2]]);
            if mu > 0.0 && ft >= 0.999 * mu * fnorm.abs() {
                o.sliding += 1;
            } else if ft < 0.9 * mu * fnorm.abs() {
                o.sticking += 1;
            }
        }
    }
    o
}

/// One case of `in.exact`: pair_coeff's words (or a classic style and its arguments), the
/// second type's words (a mixed pair), the run, and mu (to tell sticking from sliding).
#[derive(Clone)]
struct Case {
    coeff: String,
    coeff2: Option<String>,
    classic: bool,
    pressed: bool,
    mu: f64,
    /// steps (in.exact's default: 800 for an impact, 2000 pressed)
    n: Option<u32>,
}

impl Case {
    fn impact(coeff: &str, mu: f64) -> Case {
        Case {
            coeff: coeff.into(),
            coeff2: None,
            classic: false,
            pressed: false,
            mu,
            n: None,
        }
    }
    fn pressed(coeff: &str, mu: f64) -> Case {
        Case {
            pressed: true,
            ..Case::impact(coeff, mu)
        }
    }
    fn classic(args: &str, mu: f64) -> Case {
        Case {
            classic: true,
            pressed: true,
            ..Case::impact(args, mu)
        }
    }
    fn mixed(coeff: &str, coeff2: &str, mu: f64) -> Case {
        Case {
            coeff2: Some(coeff2.into()),
            pressed: true,
            ..Case::impact(coeff, mu)
        }
    }

    fn vars(&self, style: &str, dump: &Path, newton: &str) -> Vec<(&'static str, String)> {
        let mut v = vec![
            ("style", style.to_string()),
            ("dump", dump.display().to_string()),
            ("newton", newton.to_string()),
        ];
        if self.classic {
            v.push(("is_classic", "1".into()));
            v.push(("classic", self.coeff.clone()));
        } else {
            v.push(("coeff", self.coeff.clone()));
        }
        if let Some(c2) = &self.coeff2 {
            v.push(("types", "2".into()));
            v.push(("coeff2", c2.clone()));
        }
        if self.pressed {
            v.push(("case", "pressed".into()));
        }
        if let Some(n) = self.n.or(if self.pressed { Some(2000) } else { None }) {
            v.push(("n", n.to_string()));
        }
        v
    }

    /// Runs granular and dashpot on `ranks` ranks with `newton` and compares the dumps.
    fn check(&self, venv: &Path, ranks: u32, newton: &str) -> Outcome {
        let dir = lib_dir().join("lammps-exact");
        std::fs::create_dir_all(&dir).expect("dump dir");
        let key = format!(
            "{}|{:?}|{}|{:?}|{ranks}|{newton}",
            self.coeff, self.coeff2, self.pressed, self.n
        );
        let tag = key.bytes().fold(0xcbf29ce484222325u64, |h, b| {
            (h ^ b as u64).wrapping_mul(0x100000001b3)
        });
        let dumps: Vec<Dump> = ["granular", "dashpot"]
            .iter()
            .map(|style| {
                let dump = dir.join(format!("{tag:x}.{style}"));
                let vars = self.vars(style, &dump, newton);
                succeeded(
                    &lmp(venv, "in.exact", ranks, &vars),
                    &format!("in.exact {vars:?}"),
                );
                read_dump(&dump)
            })
            .collect();
        let what = format!(
            "'{}' ({:?}) on {ranks} rank(s), newton {newton}",
            self.coeff, self.coeff2
        );
        let o = compare(&dumps[0], &dumps[1], self.mu, &what);
        eprintln!("{what}: {o:?}");
        assert!(o.contact_steps > 50, "{what}: the spheres barely touched: {o:?}");
        o
    }
}

const FRICTION: &str = "tangential linear_nohistory 1.0 0.3";

/// Every normal model with every damping model LAMMPS accepts with it (and `limit_damping`), in
/// an oblique, spinning impact with velocity-dependent friction.
#[test]
fn every_normal_and_damping_model_matches_pair_granular_step_by_step() {
    let Some(v) = venv() else { return };
    let mut worst = 0.0f64;
    for normal in [
        "hooke 2e3 DAMP",
        "hertz 5e6 DAMP",
        "hertz/material 1e7 DAMP 0.3",
        "dmt 1e7 DAMP 0.3 0.02",
        "jkr 1e7 DAMP 0.3 0.02",
    ] {
        let cohesive = normal.starts_with("dmt") || normal.starts_with("jkr");
        for (damping, damp) in [
            ("velocity", "2e-3"),
            ("mass_velocity", "50"),
            ("viscoelastic", "0.5"),
            ("tsuji", "0.6"),
            ("coeff_restitution", "0.6"),
        ] {
            if cohesive && (damping == "tsuji" || damping == "coeff_restitution") {
                continue;
            }
            let coeff = format!("{} damping {damping} {FRICTION}", normal.replace("DAMP", damp));
            worst = worst.max(Case::impact(&coeff, 0.3).check(&v, 1, "off").worst);
            if !cohesive && damping == "mass_velocity" {
                let limited = format!("{coeff} limit_damping");
                worst = worst.max(Case::impact(&limited, 0.3).check(&v, 1, "off").worst);
            }
        }
    }
    eprintln!("normal x damping: worst relative difference {worst:e}");
}

/// Every tangential model, pressed and spinning: each spring both sticks and slides.
#[test]
fn every_tangential_model_matches_in_stick_and_in_slip() {
    let Some(v) = venv() else { return };
    for tangential in [
        "linear_nohistory 1.0 0.3",
        "linear_history 2e3 1.0 0.3",
        "mindlin NULL 1.0 0.3",
        "mindlin 3e6 0.5 0.3",
        "mindlin_rescale NULL 1.0 0.3",
        "mindlin/force NULL 1.0 0.3",
        "mindlin_rescale/force NULL 1.0 0.3",
    ] {
        let coeff = format!("hertz/material 1e7 0.5 0.3 damping viscoelastic tangential {tangential}");
        let o = Case::pressed(&coeff, 0.3).check(&v, 1, "off");
        if !tangential.starts_with("linear_nohistory") {
            assert!(o.sliding > 10 && o.sticking > 10, "{tangential}: {o:?}");
        }
    }
}

/// Rolling and twisting resistance (sds; marshall after mindlin and after linear_history), with
/// a cohesive normal model too, pressed and spinning.
#[test]
fn rolling_and_twisting_models_match_pair_granular() {
    let Some(v) = venv() else { return };
    for coeff in [
        "hertz/material 1e7 0.5 0.3 tangential mindlin NULL 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting sds 1e-4 1e-8 1e-4",
        "hertz/material 1e7 0.5 0.3 tangential mindlin NULL 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting marshall",
        "hertz 5e6 0.5 tangential linear_history 2e3 1.0 0.3 twisting marshall",
        "jkr 1e7 0.5 0.3 0.02 tangential mindlin 5e6 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting marshall",
    ] {
        Case::pressed(coeff, 0.3).check(&v, 1, "off");
    }
    // JKR's neck: the contact formed holds beyond touching until LAMMPS's pull-off distance,
    // with every family acting, then ends at the same step
    for coeff in [
        "jkr 1e7 0.5 0.3 0.2 tangential linear_history 2e3 1.0 0.3",
        "jkr 1e7 0.5 0.3 0.2 tangential mindlin NULL 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting marshall",
    ] {
        let o = Case {
            n: Some(3000),
            ..Case::impact(coeff, 0.3)
        }
        .check(&v, 1, "off");
        assert!(o.apart > 5, "{coeff}: never held apart: {o:?}");
    }
}

/// The classic styles, their arguments unchanged: `pair_style dashpot gran/hooke ...`.
#[test]
fn the_classic_styles_match_their_lammps_twins() {
    let Some(v) = venv() else { return };
    for args in [
        "gran/hooke 2000 NULL 50 NULL 0.3 1",
        "gran/hooke/history 2000 NULL 50 NULL 0.3 1",
        "gran/hooke/history 2000 1000 50 20 0.3 1 limit_damping",
        "gran/hertz/history 2e7 NULL 50 NULL 0.3 1",
    ] {
        Case::classic(args, 0.3).check(&v, 1, "off");
    }
}

/// Unset pairs of two types mix as LAMMPS mixes them (the pair modulus of the two materials,
/// the geometric mean of every other coefficient, mindlin's NULL stiffness from the mixed
/// modulus and Poisson's ratio), and a contact of the mixed pair crosses the rank boundary:
/// 1 and 2 ranks, newton on and off, equal LAMMPS's.
#[test]
fn mixed_pairs_and_two_ranks_match_pair_granular_newton_on_and_off() {
    let Some(v) = venv() else { return };
    let mixed = [
        Case::mixed(
            "hertz/material 1e7 0.5 0.3 tangential mindlin NULL 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting marshall",
            "hertz/material 3e7 0.2 0.2 tangential mindlin NULL 0.5 0.5 rolling sds 5e2 0.02 0.3 twisting marshall",
            0.3f64.min(0.5),
        ),
        Case::mixed(
            "jkr 1e7 0.5 0.3 0.02 tangential linear_history 2e3 1.0 0.3",
            "jkr 3e7 0.2 0.2 0.05 tangential linear_history 4e3 0.5 0.5",
            0.3,
        ),
    ];
    // the mixed JKR pair holds beyond touching (to the pull-off distance of the mixed modulus
    // and cohesion), then ruptures
    let held = |case: &Case, o: Outcome| {
        assert!(
            !case.coeff.starts_with("jkr") || o.apart > 0,
            "JKR never held apart: {o:?}"
        )
    };
    for case in &mixed {
        held(case, case.check(&v, 1, "off"));
    }
    for case in [
        mixed[0].clone(),
        mixed[1].clone(),
        Case::classic("gran/hooke/history 2000 NULL 50 NULL 0.3 1", 0.3),
    ] {
        for newton in ["off", "on"] {
            held(&case, case.check(&v, 2, newton));
        }
    }
}

/// The thermo rows `in.exact -var local 1` prints: every 50 steps, the sums over the pairs of
/// `compute pair/local p1 ... p12 force`.
fn local_rows(stdout: &str) -> Vec<Vec<f64>> {
    stdout
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("Step"))
        .skip(1)
        .take_while(|l| !l.starts_with("Loop time"))
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .filter_map(|t| t.parse().ok())
                .collect()
        })
        .collect()
}

/// `compute pair/local` through single(): with LAMMPS's words, pair_style dashpot fills
/// `granular`'s 12 columns (and the force) with granular's values, each column to 1e-10 of its
/// largest over the run.
#[test]
fn single_fills_pair_granulars_pair_local_columns() {
    let Some(v) = venv() else { return };
    for coeff in [
        "hertz/material 1e7 0.5 0.3 damping tsuji tangential mindlin NULL 1.0 0.3 rolling sds 1e3 0.05 0.1 twisting marshall",
        "jkr 1e7 0.5 0.3 0.02 tangential linear_history 2e3 1.0 0.3 twisting sds 1e-4 1e-8 1e-4",
    ] {
        let rows: Vec<Vec<Vec<f64>>> = ["granular", "dashpot"]
            .iter()
            .map(|style| {
                let vars = [
                    ("style", style.to_string()),
                    ("coeff", coeff.to_string()),
                    ("case", "pressed".to_string()),
                    ("n", "1000".to_string()),
                    ("local", "1".to_string()),
                    ("dump", lib_dir().join(format!("local.{style}")).display().to_string()),
                ];
                local_rows(&succeeded(&lmp(&v, "in.exact", 1, &vars), coeff))
            })
            .collect();
        let (g, d) = (&rows[0], &rows[1]);
        assert_eq!(g.len(), d.len(), "{coeff}: rows");
        assert!(g.len() > 10 && g.iter().all(|r| r.len() == 13), "{coeff}: {g:?}");
        let mut set = 0;
        for c in 0..13 {
            let largest = g.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
            set += usize::from(largest > 0.0);
            for (a, b) in g.iter().zip(d) {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-10 * largest,
                    "{coeff}: column {}: granular {a:?}, dashpot {b:?}",
                    c + 1
                );
            }
        }
        // the normal, damping and tangential columns at least (rolling ones with rolling)
        assert!(set >= 8, "{coeff}: only {set} columns ever set");
    }
}
