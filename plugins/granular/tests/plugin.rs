//! The `gran-*` laws as a host sees them: the built plugin library loaded by the registry, its
//! laws listed with their kinds, schemas and history, bad parameters refused with a message
//! naming them, and a collision through the plugin equal to the law linked in.

use dashpot_core::collide::{collide, collide_named, Options, PairLaw};
use dashpot_core::laws::{compiled, compiled_tangential, EnergyOut};
use dashpot_core::Registry;
use dashpot_granular::normal_laws::{GranHertzMaterialCoeffRestitution, GranJkrViscoelastic};
use dashpot_granular::tangential_laws::GranMindlin;
use dashpot_sdk::{
    ContactLaw, EndCriterion, LawKind, MaterialPair, NormalBatch, NormalContext, Pair, ParamValue,
    TangentialBatch, TangentialLaw,
};
use std::path::PathBuf;

/// The plugin library this test build made (`target/<profile>/libdashpot_granular.so`).
fn library() -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let name = format!(
        "{}dashpot_granular{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    [deps.join(&name), deps.parent().unwrap().join(&name)]
        .into_iter()
        .find(|p| p.exists())
        .expect("the plugin library is built beside the test")
}

fn registry() -> Registry {
    let mut r = Registry::new();
    r.load_file(&library()).expect("load the gran plugin");
    r
}

#[test]
fn the_plugin_lists_every_gran_law_with_its_kind() {
    let r = registry();
    let names = |k: LawKind| -> Vec<&str> {
        r.laws
            .iter()
            .filter(|l| l.info.kind == k)
            .map(|l| l.info.name.as_str())
            .collect()
    };
    let contact = names(LawKind::Contact);
    assert_eq!(contact.len(), 21, "{contact:?}");
    for n in ["hooke", "hertz", "hertz-material"] {
        for d in [
            "velocity",
            "mass-velocity",
            "viscoelastic",
            "tsuji",
            "coeff-restitution",
        ] {
            assert!(
                contact.contains(&format!("gran-{n}-{d}").as_str()),
                "gran-{n}-{d}"
            );
        }
    }
    for n in ["dmt", "jkr"] {
        for d in ["velocity", "mass-velocity", "viscoelastic"] {
            assert!(
                contact.contains(&format!("gran-{n}-{d}").as_str()),
                "gran-{n}-{d}"
            );
        }
    }
    assert_eq!(
        names(LawKind::Tangential),
        [
            "gran-linear-nohistory",
            "gran-linear-history",
            "gran-mindlin",
            "gran-mindlin-rescale",
            "gran-mindlin-force",
            "gran-mindlin-rescale-force",
            "gran-linear-history-classic",
            "gran-mindlin-classic",
            "gran-wall-history-classic",
        ]
    );
    assert_eq!(names(LawKind::Rolling), ["gran-rolling-sds"]);
    assert_eq!(
        names(LawKind::Twisting),
        ["gran-twisting-sds", "gran-twisting-marshall"]
    );
    let info = |n: &str| &r.laws.iter().find(|l| l.info.name == n).unwrap().info;
    let p: Vec<&str> = info("gran-hooke-tsuji")
        .params
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(p, ["k", "damp", "limit_damping"]);
    let p: Vec<&str> = info("gran-jkr-viscoelastic")
        .params
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert_eq!(p, ["damp", "cohesion"]);
    assert_eq!(info("gran-jkr-viscoelastic").history.len(), 1);
    assert_eq!(info("gran-mindlin-rescale").history.len(), 4);
    assert!(info("gran-mindlin").doc.contains("mindlin k|NULL"));
}

#[test]
fn bad_parameters_are_refused_naming_them() {
    let r = registry();
    let err = |name: &str, p: &[(&str, f64)]| {
        let v: Vec<ParamValue> = p.iter().map(|(n, x)| ParamValue::new(n, *x)).collect();
        let kind = r.laws.iter().find(|l| l.info.name == name).unwrap().info.kind;
        let refused = match kind {
            LawKind::Contact => r.contact(name, &v).err(),
            _ => r.tangential(name, &v).err(),
        };
        refused
            .unwrap_or_else(|| panic!("{name} {p:?} accepted"))
            .to_string()
    };
    let e = err("gran-hooke-velocity", &[("damp", 1.0)]);
    assert!(e.contains("'k'") && e.contains("N/m"), "{e}");
    let e = err("gran-hooke-coeff-restitution", &[("k", 1e4), ("damp", 1.5)]);
    assert!(e.contains("damp") && e.contains("(0, 1]"), "{e}");
    let e = err("gran-hertz-velocity", &[("k", 1e8), ("limit_damping", 0.5)]);
    assert!(e.contains("limit_damping") && e.contains("0 or 1"), "{e}");
    let e = err("gran-jkr-velocity", &[("damp", 0.0)]);
    assert!(e.contains("cohesion"), "{e}");
    let e = err("gran-linear-history", &[("xt", 1.0), ("mu", 0.3)]);
    assert!(e.contains("'kt'"), "{e}");
    let e = err("gran-mindlin", &[("xt", 1.0), ("mu", -0.3)]);
    assert!(e.contains("mu") && e.contains("-0.3"), "{e}");
}

#[test]
fn a_collision_through_the_plugin_is_the_law_linked_in() {
    let r = registry();
    let pair = Pair::new(1e-6, 3e-4, 5e7).unwrap();
    let opt = Options::default();
    let params = [ParamValue::new("damp", 0.6)];
    let c = collide_named(
        &r,
        "gran-hertz-material-coeff-restitution",
        &params,
        &pair,
        0.5,
        EndCriterion::Overlap,
        &opt,
    )
    .expect("collide through the plugin");
    let law = GranHertzMaterialCoeffRestitution::from_values(&params).unwrap();
    let linked = compiled(&law, &pair.materials(0.3).unwrap()).unwrap();
    let d = collide(
        &PairLaw::new(linked, pair.mass, pair.radius),
        pair.mass,
        0.5,
        EndCriterion::Overlap,
        &opt,
    )
    .unwrap();
    assert_eq!(c.restitution, d.restitution);
    assert_eq!(c.contact_time, d.contact_time);
    assert!((c.restitution - 0.6).abs() < 1e-7, "{}", c.restitution);
}

/// Six contacts of a JKR pair, in and beyond contact: overlaps (m) and rates (m/s).
const DELTA: [f64; 6] = [1e-6, 3e-7, 0.0, -2e-8, -5e-8, 2e-6];
const RATE: [f64; 6] = [0.1, -0.2, 0.05, -0.3, 0.0, 0.7];
const MASS: [f64; 6] = [1e-6; 6];
const RADIUS: [f64; 6] = [2.7e-4; 6];

/// The forces and normal contexts of `l` on the six contacts, formed (JKR's `touch` = 1).
fn normal_through<L: dashpot_core::laws::NormalLaw + ?Sized>(l: &L) -> ([f64; 6], [NormalContext; 6]) {
    let (mut h, mut force, mut ctx) = ([1.0; 6], [0.0; 6], [NormalContext::default(); 6]);
    let b = NormalBatch {
        delta: &DELTA,
        rate: &RATE,
        mass: &MASS,
        radius: &RADIUS,
        slots: 1,
        history: &mut h,
        force: &mut force,
    };
    l.force_batch_context(b, None, &mut ctx, EnergyOut::none())
        .unwrap();
    (force, ctx)
}

/// The Mindlin forces and history of `l` on the six contacts under the contexts `ctx`.
fn tangential_through<L: dashpot_core::laws::TangentialForce + ?Sized>(
    l: &L,
    fnorm: &[f64; 6],
    ctx: &[NormalContext; 6],
) -> ([[f64; 3]; 6], [f64; 24]) {
    let (mut h, mut force) = ([0.0; 24], [[0.0; 3]; 6]);
    let b = TangentialBatch {
        dt: 1e-7,
        normal: &[[0.0, 0.0, 1.0]; 6],
        velocity: &[[0.3, -0.1, 0.0]; 6],
        normal_force: fnorm,
        delta: &DELTA,
        mass: &MASS,
        radius: &RADIUS,
        context: ctx,
        slots: 4,
        history: &mut h,
        force: &mut force,
    };
    l.force_batch(b).unwrap();
    (force, h)
}

/// The normal contexts of JKR contacts through the plugin, and the Mindlin forces they give
/// through the plugin, are those of the laws linked in, to the bit (sdk 0.4).
#[test]
fn contexts_travel_through_the_plugin_to_the_bit() {
    let r = registry();
    let m = MaterialPair::new(5e7, 2e7).unwrap();
    let np = [ParamValue::new("damp", 3e7), ParamValue::new("cohesion", 0.05)];
    let tp = [ParamValue::new("xt", 1.0), ParamValue::new("mu", 0.3)];
    let plugin = r.contact("gran-jkr-viscoelastic", &np).unwrap().bind(&m).unwrap();
    let linked = compiled(&GranJkrViscoelastic::from_values(&np).unwrap(), &m).unwrap();
    let (fp, cp) = normal_through(&plugin);
    assert_eq!((fp, cp), normal_through(&linked));
    assert!(
        cp.iter()
            .all(|c| c.contact_radius > 0.0 && c.damping > 0.0 && c.cap_force > 0.0),
        "{cp:?}"
    );
    let tplug = r.tangential("gran-mindlin", &tp).unwrap().bind(&m).unwrap();
    let tlink = compiled_tangential(&GranMindlin::from_values(&tp).unwrap(), &m).unwrap();
    let (a, b) = (
        tangential_through(&tplug, &fp, &cp),
        tangential_through(&tlink, &fp, &cp),
    );
    assert_eq!(a, b);
    assert!(
        GranMindlin::READS_CONTEXT && a.0.iter().all(|f| f[0] < 0.0),
        "{a:?}"
    );
}
