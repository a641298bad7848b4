//! Backward compatibility: plugins built against dashpot-sdk 0.1.0, from this repository's own
//! sources at the last 0.1 commit (not a copy in the tree), keep loading in the 0.2 host and
//! give bit-identical forces and restitutions; a plugin of an incompatible future major is
//! refused before any of its code runs.

use dashpot::collide::{collide, Options, PairLaw};
use dashpot::Registry;
use dashpot_sdk::{Contact, EndCriterion, ErrorKind, Pair, ParamValue, Particle};
use dashpot_tests::{assert_same_bits, memoryless_batch, sdk01_registry, seed_registry};
use std::f64::consts::PI;

/// The sdk 0.1 plugins' registry and the seed plugins' of this build, or `None` (the test
/// skips) where the 0.1 plugins cannot be built.
fn old_and_new() -> Option<(Registry, Registry)> {
    Some((sdk01_registry("debug")?, seed_registry()))
}

/// Two MCC granules (Antypov & Elliott's particle).
fn mcc_pair() -> Pair {
    Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap()
}

fn pairs() -> Vec<(Pair, f64)> {
    let mcc = Particle::MCC;
    let big = Particle {
        diameter: 0.03,
        density: 2500.0,
        young: 7e10,
        poisson: 0.3,
    };
    vec![
        (Pair::spheres(&mcc, &mcc).unwrap(), 0.3),
        (Pair::spheres(&mcc, &big).unwrap(), 0.3),
        (Pair::wall(&big).unwrap(), 0.3),
    ]
}

/// (δ, δ̇) states of a contact list: overlaps up to 1e-4 m, rates of both signs, and δ < 0.
fn states() -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for i in 0..40 {
        let d = 1e-4 * (i as f64 / 39.0).powi(3) - if i == 0 { 1e-7 } else { 0.0 };
        for r in [-2.0, -0.01, 0.0, 0.3, 5.0] {
            v.push((d, r));
        }
    }
    v
}

/// sdk 0.1's HSD arithmetic, verbatim (bound to one pair).
fn hsd_01(eps: f64, pair: &Pair, d: f64, r: f64) -> f64 {
    let l = eps.ln();
    let alpha = -(5.0f64).sqrt() * l / (l * l + PI * PI).sqrt();
    let k = 4.0 / 3.0 * pair.young * pair.radius.sqrt();
    let c = alpha * (pair.mass * k).sqrt();
    let d = d.max(0.0);
    let s = d.sqrt();
    k * d * s + c * s.sqrt() * r
}

/// sdk 0.1's LSD arithmetic, verbatim.
fn lsd_01(eps: f64, pair: &Pair, d: f64, r: f64) -> f64 {
    let k = 8.0 / 3.0 * pair.young * pair.radius;
    let w0 = (k / pair.mass).sqrt();
    let l = eps.ln();
    let gamma = -l / (l * l + PI * PI).sqrt() * w0;
    let c = 2.0 * gamma * pair.mass;
    if d < 0.0 {
        0.0
    } else {
        k * d + c * r
    }
}

/// sdk 0.1's Kuwabara–Kono arithmetic, verbatim.
fn kk_01(a: f64, pair: &Pair, d: f64, r: f64) -> f64 {
    let k = 4.0 / 3.0 * pair.young * pair.radius.sqrt();
    let ka15 = 1.5 * k * a;
    let d = d.max(0.0);
    let s = d.sqrt();
    s * (k * d + ka15 * r)
}

#[test]
fn sdk01_plugins_load_and_give_bit_identical_forces() {
    let Some((old, new)) = old_and_new() else {
        return;
    };
    type Ref = fn(f64, &Pair, f64, f64) -> f64;
    let cases: [(&str, &str, f64, Ref); 3] = [
        ("hsd", "eps", 0.54, hsd_01),
        ("lsd", "eps", 0.3, lsd_01),
        ("kuwabara-kono", "A", 2e-6, kk_01),
    ];
    let mut compared = 0;
    for (name, pname, pv, reference) in cases {
        let params = [ParamValue::new(pname, pv)];
        let (lo, ln) = (
            old.contact(name, &params).unwrap(),
            new.contact(name, &params).unwrap(),
        );
        assert!(lo.info().history.is_empty());
        for (pair, nu) in pairs() {
            let mat = pair.materials(nu).unwrap();
            let (mo, mn) = (lo.bind(&mat).unwrap(), ln.bind(&mat).unwrap());
            let st = states();
            let delta: Vec<f64> = st.iter().map(|s| s.0).collect();
            let rate: Vec<f64> = st.iter().map(|s| s.1).collect();
            let (mass, radius) = (vec![pair.mass; st.len()], vec![pair.radius; st.len()]);
            let (mut fo, mut fnew) = (vec![0.0; st.len()], vec![0.0; st.len()]);
            for (m, f) in [(&mo, &mut fo), (&mn, &mut fnew)] {
                m.force_batch(memoryless_batch(&delta, &rate, &mass, &radius, f))
                    .unwrap();
            }
            for i in 0..st.len() {
                let want = reference(pv, &pair, delta[i], rate[i]);
                // the 0.1 plugin through the 0.2 host: bit for bit what 0.1 computed
                assert_eq!(fo[i].to_bits(), want.to_bits(), "{name} {i}: {} vs {want}", fo[i]);
                // one contact at a time: the same bits
                let one = mo
                    .force(
                        Contact {
                            delta: delta[i],
                            rate: rate[i],
                            mass: pair.mass,
                            radius: pair.radius,
                        },
                        &mut [],
                    )
                    .unwrap();
                assert_eq!(one.to_bits(), want.to_bits());
                // the 0.2 plugin (per-contact geometry) agrees to rounding
                let tol = 1e-14 * want.abs().max(1e-300) + 1e-300;
                assert!((fnew[i] - want).abs() <= tol, "{name} {i}: {} vs {want}", fnew[i]);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 3 * 3 * 200);
}

#[test]
fn sdk01_restitutions_are_bit_identical() {
    let Some((old, new)) = old_and_new() else {
        return;
    };
    let pair = mcc_pair();
    for (name, params) in [
        ("mcnamara-falcon", vec![]),
        ("constant", vec![ParamValue::new("r", 0.7)]),
    ] {
        let bo = old.restitution(name, &params).unwrap().bind(&pair).unwrap();
        let bn = new.restitution(name, &params).unwrap().bind(&pair).unwrap();
        let v: Vec<f64> = (0..300).map(|i| 1e-4 * 1.05f64.powi(i)).collect();
        let (mut ro, mut rn) = (vec![0.0; v.len()], vec![0.0; v.len()]);
        bo.restitution_batch(&v, &mut ro).unwrap();
        bn.restitution_batch(&v, &mut rn).unwrap();
        assert_same_bits(&ro, &rn, |i| format!("{name} at {} m/s", v[i]));
        let one: Vec<f64> = v.iter().map(|&v| bo.restitution(v).unwrap()).collect();
        assert_same_bits(&one, &ro, |i| format!("{name} at {} m/s, one call", v[i]));
    }
}

#[test]
fn sdk01_collisions_match_the_02_plugins() {
    let Some((old, new)) = old_and_new() else {
        return;
    };
    let pair = mcc_pair();
    for (name, params, end) in [
        ("hsd", vec![ParamValue::new("eps", 0.54)], EndCriterion::Overlap),
        ("lsd", vec![ParamValue::new("eps", 0.8)], EndCriterion::Overlap),
        (
            "kuwabara-kono",
            vec![ParamValue::new("A", 2e-6)],
            EndCriterion::Force,
        ),
    ] {
        let lo = PairLaw::bind(&old.contact(name, &params).unwrap(), &pair, 0.3).unwrap();
        let ln = PairLaw::bind(&new.contact(name, &params).unwrap(), &pair, 0.3).unwrap();
        let co = collide(&lo, pair.mass, 1.0, end, &Options::default()).unwrap();
        let cn = collide(&ln, pair.mass, 1.0, end, &Options::default()).unwrap();
        assert!((co.restitution - cn.restitution).abs() < 1e-12, "{name}");
        assert!((co.contact_time / cn.contact_time - 1.0).abs() < 1e-12, "{name}");
        assert!((co.max_overlap / cn.max_overlap - 1.0).abs() < 1e-12, "{name}");
    }
}

#[test]
fn a_nan_overlap_is_refused_through_the_01_path_too() {
    let Some(old) = sdk01_registry("debug") else {
        return;
    };
    let pair = mcc_pair();
    let m = old
        .contact("hsd", &[])
        .unwrap()
        .bind(&pair.materials(0.3).unwrap())
        .unwrap();
    let e = m
        .force(
            Contact {
                delta: f64::NAN,
                rate: 1.0,
                mass: pair.mass,
                radius: pair.radius,
            },
            &mut [],
        )
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(e.message.contains("delta[0] = NaN"), "{}", e.message);
}
