//! The `gran-*` laws as a host sees them: the built plugin library loaded by the registry, its
//! laws listed with their kinds, schemas and history, bad parameters refused with a message
//! naming them, and a collision through the plugin equal to the law linked in.

use dashpot_core::collide::{collide, collide_named, Options, PairLaw};
use dashpot_core::laws::compiled;
use dashpot_core::Registry;
use dashpot_granular::normal_laws::GranHertzMaterialCoeffRestitution;
use dashpot_sdk::{ContactLaw, EndCriterion, LawKind, Pair, ParamValue};
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
