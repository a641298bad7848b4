//! Calibration and contact laws used as restitution laws, through the real plugins.

use dashpot::collide::calibrate::{calibrate, CalibrateSpec};
use dashpot::collide::{collide, Options, TabulatedRestitution};
use dashpot::{Registry, SearchPath};
use dashpot_sdk::{BoundRestitution, EndCriterion, Pair, ParamValue, Particle};
use dashpot_tests::BindPair as _;
use dashpot_tests::{pair_law, seed_registry, within_1e6_of_the_driver};

fn mcc() -> Pair {
    Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap()
}

fn spec(law: &str, e: f64, tau: Option<f64>, end: EndCriterion) -> CalibrateSpec {
    CalibrateSpec {
        law: law.into(),
        fixed: vec![],
        pair: mcc(),
        shear: mcc().materials(0.3).unwrap().shear,
        restitution: e,
        contact_time: tau,
        v0: 1.0,
        end,
        fit: None,
        options: Options::default(),
    }
}

fn param(c: &dashpot::collide::calibrate::Calibration, n: &str) -> f64 {
    c.params.iter().find(|(k, _)| k == n).map(|(_, v)| *v).unwrap()
}

#[test]
fn lsd_closed_form_calibration_hits_eps_and_tau() {
    let reg = seed_registry();
    let c = calibrate(&reg, &spec("lsd", 0.6, Some(2e-5), EndCriterion::Overlap)).unwrap();
    assert_eq!(c.method, "closed form");
    assert_eq!(c.collisions, 1, "closed form: the only collision is the check");
    let m = mcc().mass;
    let l = 0.6f64.ln();
    assert!((param(&c, "k") / (m * (l * l + std::f64::consts::PI.powi(2)) / 4e-10) - 1.0).abs() < 1e-14);
    assert!(c.restitution_residual.abs() < 1e-10);
    assert!(c.contact_time_residual.unwrap().abs() < 1e-10 * 2e-5);
}

#[test]
fn kuwabara_kono_dissipation_constant_is_fitted_numerically() {
    let reg = seed_registry();
    for end in [EndCriterion::Force, EndCriterion::Overlap] {
        let c = calibrate(&reg, &spec("kuwabara-kono", 0.75, None, end)).unwrap();
        assert_eq!(c.method, "numerical");
        assert!(
            c.restitution_residual.abs() < 1e-9,
            "{end:?}: residual {}",
            c.restitution_residual
        );
        // an independent check of the fitted A
        let b = reg
            .contact("kuwabara-kono", &[ParamValue::new("A", param(&c, "A"))])
            .unwrap()
            .bind_pair(&mcc())
            .unwrap();
        let r = collide(&b, mcc().mass, 1.0, end, &Options::default()).unwrap();
        assert!((r.restitution - 0.75).abs() < 1e-9);
    }
}

#[test]
fn hsd_contact_time_fixes_the_modulus_by_the_hertz_scaling() {
    // τ ∝ K^{-2/5} at fixed ε and v0, so E_eff must scale as (τ_0/τ)^{5/2}.
    let reg = seed_registry();
    let tau0 = collide(
        &reg.contact("hsd", &[ParamValue::new("eps", 0.3)])
            .unwrap()
            .bind_pair(&mcc())
            .unwrap(),
        mcc().mass,
        1.0,
        EndCriterion::Overlap,
        &Options::default(),
    )
    .unwrap()
    .contact_time;
    let target = 1.7 * tau0;
    let c = calibrate(&reg, &spec("hsd", 0.3, Some(target), EndCriterion::Overlap)).unwrap();
    assert!(
        (c.young_factor / (1.0f64 / 1.7).powf(2.5) - 1.0).abs() < 1e-8,
        "factor {}",
        c.young_factor
    );
    assert!((param(&c, "eps") - 0.3).abs() < 1e-9);
    assert!((c.contact_time_residual.unwrap() / target).abs() < 1e-9);
}

#[test]
fn hsd_under_the_force_criterion_needs_a_smaller_eps() {
    let reg = seed_registry();
    let c = calibrate(&reg, &spec("hsd", 0.54, None, EndCriterion::Force)).unwrap();
    assert!(param(&c, "eps") < 0.54);
    assert!(c.restitution_residual.abs() < 1e-9);
    // and the LSD with the same eps realizes the same restitution (the phase map)
    let b = reg
        .contact("lsd", &[ParamValue::new("eps", param(&c, "eps"))])
        .unwrap()
        .bind_pair(&mcc())
        .unwrap();
    let l = collide(&b, mcc().mass, 3.0, EndCriterion::Force, &Options::default()).unwrap();
    assert!((l.restitution - 0.54).abs() < 1e-8);
}

#[test]
fn unreachable_targets_and_bad_input_are_errors() {
    let reg = seed_registry();
    let e = calibrate(&reg, &spec("hsd", 1.5, None, EndCriterion::Overlap)).unwrap_err();
    assert!(e.to_string().contains("(0, 1]"), "{e}");
    let e = calibrate(&reg, &spec("constant", 0.5, None, EndCriterion::Overlap)).unwrap_err();
    assert!(e.to_string().contains("restitution law"), "{e}");
    let mut s = spec("kuwabara-kono", 0.5, None, EndCriterion::Force);
    s.fit = Some("B".into());
    assert!(calibrate(&reg, &s)
        .unwrap_err()
        .to_string()
        .contains("no such parameter"));
}

#[test]
fn a_contact_law_tabulated_as_a_restitution_law_is_within_1e6() {
    let reg = seed_registry();
    let pair = Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap();
    let b = pair_law(&reg, "kuwabara-kono", &[ParamValue::new("A", 2e-6)], &pair);
    let opt = Options {
        rtol: 1e-10,
        ..Options::default()
    };
    let t = TabulatedRestitution::build(&b, pair.mass, EndCriterion::Force, 1e-3, 10.0, 1e-6, &opt).unwrap();
    assert!(t.max_error <= 1e-6, "{}", t.max_error);
    // at speeds that are not nodes, against the integrator
    within_1e6_of_the_driver(&t, &b, pair.mass, &[1.3e-3, 0.0071, 0.05, 0.33, 2.2, 9.7], &opt);
    // HSD is speed-independent: the table is flat at eps
    let h = pair_law(&reg, "hsd", &[ParamValue::new("eps", 0.4)], &pair);
    let t =
        TabulatedRestitution::build(&h, pair.mass, EndCriterion::Overlap, 1e-3, 10.0, 1e-6, &opt).unwrap();
    for v in [1e-5, 1e-3, 0.5, 10.0, 50.0] {
        assert!(
            (t.restitution(v) - 0.4).abs() < 1e-8,
            "v {v}: {}",
            t.restitution(v)
        );
    }
}

#[test]
fn the_third_party_plugin_runs_through_collide_and_calibrate_unchanged() {
    let path = dashpot_tests::third_party_plugin();
    let reg = Registry::discover(&SearchPath {
        files: vec![path],
        ..Default::default()
    })
    .unwrap();
    let pair = mcc();
    let b = pair_law(
        &reg,
        "hertz-linear-damping",
        &[ParamValue::new("eta", 5.0)],
        &pair,
    );
    let c = collide(&b, pair.mass, 1.0, EndCriterion::Force, &Options::default()).unwrap();
    assert!(c.restitution > 0.0 && c.restitution < 1.0);
    let s = CalibrateSpec {
        law: "hertz-linear-damping".into(),
        ..spec("hertz-linear-damping", 0.8, Some(8e-5), EndCriterion::Force)
    };
    let cal = calibrate(&reg, &s).unwrap();
    assert!(
        cal.restitution_residual.abs() < 1e-9 && (cal.contact_time_residual.unwrap() / 8e-5).abs() < 1e-9,
        "{cal:?}"
    );
}
