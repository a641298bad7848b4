//! Each seed law, loaded from its real `.so`, against its closed form in the papers.
//! The expected values are computed here from the equations, independently of the plugins.

use approx::assert_relative_eq;
use dashpot::collide::ContactForce as _;
use dashpot_sdk::{Coefficient, Pair, ParamValue, Particle};
use dashpot_tests::BindPair as _;
use dashpot_tests::{pair_law, seed_registry};
use std::f64::consts::PI;

fn coeff(c: &[Coefficient], name: &str) -> f64 {
    c.iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no coefficient {name}"))
        .value
}

fn mcc_pair() -> Pair {
    Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap()
}

/// (δ, δ̇) points spanning compression, rebound and a wide range of overlaps.
const STATES: [(f64, f64); 6] = [
    (1e-9, 1.0),
    (1e-6, 0.3),
    (2.5e-5, -0.7),
    (1e-4, 5.0),
    (3e-4, -2e-3),
    (0.0, 1.0),
];

#[test]
fn lsd_force_and_damping_follow_eq_8() {
    let reg = seed_registry();
    let pair = mcc_pair();
    // Independent derivation: identical MCC spheres, d = 1 cm.
    let d = 0.01;
    let e_eff = 6.0e9 / (2.0 * (1.0 - 0.3f64 * 0.3));
    let m = PI / 12.0 * 1500.0 * d * d * d;
    let k = 2.0 / 3.0 * e_eff * d; // the paper's mapping stiffness
    for eps in [0.01, 0.1, 0.54, 0.9, 0.999, 1.0] {
        let w0 = (k / m).sqrt();
        let l: f64 = f64::ln(eps);
        let gamma = -l / (l * l + PI * PI).sqrt() * w0; // eq. (8)
        let law = reg.contact("lsd", &[ParamValue::new("eps", eps)]).unwrap();
        let b = law.bind_pair(&pair).unwrap();
        let c = b.coefficients().unwrap();
        assert_relative_eq!(coeff(&c, "k"), k, max_relative = 1e-14);
        assert_relative_eq!(coeff(&c, "gamma"), gamma, max_relative = 1e-13, epsilon = 1e-300);
        // eq. (7) closes the loop: exp(−γπ/w1) = ε
        let w1 = (w0 * w0 - gamma * gamma).sqrt();
        assert_relative_eq!((-gamma * PI / w1).exp(), eps, max_relative = 1e-13);
        assert_relative_eq!(coeff(&c, "contact_time"), PI / w1, max_relative = 1e-13);
        for (delta, rate) in STATES {
            let f = b.force(delta, rate).unwrap();
            assert_relative_eq!(
                f,
                k * delta + 2.0 * gamma * m * rate,
                max_relative = 1e-13,
                epsilon = 1e-12
            );
        }
        assert_eq!(b.force(-1e-6, 1.0).unwrap(), 0.0, "no force out of contact");
    }
    // An explicit k replaces the mapped one.
    let b = pair_law(&reg, "lsd", &[ParamValue::new("k", 1e5)], &pair);
    assert_eq!(coeff(&b.coefficients().unwrap(), "k"), 1e5);
}

#[test]
fn lsd_against_a_wall_uses_the_particles_mass_and_radius() {
    let reg = seed_registry();
    let p = Particle::MCC;
    let wall = Pair::wall(&p).unwrap();
    let b = pair_law(&reg, "lsd", &[], &wall);
    let c = b.coefficients().unwrap();
    let m = PI / 6.0 * 1500.0 * 1e-6;
    assert_relative_eq!(coeff(&c, "m"), m, max_relative = 1e-14);
    // k = K √(4 r) with r = d/2 and E = E/(1 − ν²) for a rigid wall
    let k = 4.0 / 3.0 * (6.0e9 / 0.91) * (0.005f64).sqrt() * (0.02f64).sqrt();
    assert_relative_eq!(coeff(&c, "k"), k, max_relative = 1e-14);
}

#[test]
fn hsd_force_and_damping_follow_eqs_9_10_17() {
    let reg = seed_registry();
    let pair = mcc_pair();
    let d = 0.01;
    let e_eff = 6.0e9 / (2.0 * 0.91);
    let m = PI / 12.0 * 1500.0 * d * d * d;
    let big_k = 4.0 / 3.0 * e_eff * (d / 4.0f64).sqrt(); // eq. (9) = 2/3 E √d
    assert_relative_eq!(big_k, 2.0 / 3.0 * e_eff * d.sqrt(), max_relative = 1e-14);
    for eps in [0.01, 0.1, 0.54, 0.9, 0.999, 1.0] {
        let l: f64 = f64::ln(eps);
        let alpha = -(5.0f64).sqrt() * l / (l * l + PI * PI).sqrt(); // eq. (17)
        let b = pair_law(&reg, "hsd", &[ParamValue::new("eps", eps)], &pair);
        let c = b.coefficients().unwrap();
        assert_relative_eq!(coeff(&c, "K"), big_k, max_relative = 1e-14);
        assert_relative_eq!(coeff(&c, "alpha"), alpha, max_relative = 1e-14, epsilon = 1e-300);
        assert_relative_eq!(
            coeff(&c, "c"),
            alpha * (m * big_k).sqrt(),
            max_relative = 1e-14,
            epsilon = 1e-300
        );
        for (delta, rate) in STATES {
            // eq. (10) damping plus eq. (9) spring
            let f_expected = big_k * delta.powf(1.5) + alpha * (m * big_k).sqrt() * delta.powf(0.25) * rate;
            let f = b.force(delta, rate).unwrap();
            assert_relative_eq!(f, f_expected, max_relative = 1e-13, epsilon = 1e-12);
        }
        assert_eq!(b.force(-1e-6, 1.0).unwrap(), 0.0);
    }
}

#[test]
fn hsd_alpha_is_the_lsd_damping_through_the_mapping() {
    // Eq. (16) against eq. (3): 2γ/w0 of the LSD model equals (2/√5) α of the HSD model at the
    // same ε, an exact identity behind the phase-trajectory mapping.
    let reg = seed_registry();
    let pair = mcc_pair();
    for eps in [0.05, 0.3, 0.54, 0.8, 0.97] {
        let p = [ParamValue::new("eps", eps)];
        let l = pair_law(&reg, "lsd", &p, &pair).coefficients().unwrap();
        let h = pair_law(&reg, "hsd", &p, &pair).coefficients().unwrap();
        assert_relative_eq!(
            2.0 * coeff(&l, "gamma") / coeff(&l, "w0"),
            2.0 / 5f64.sqrt() * coeff(&h, "alpha"),
            max_relative = 1e-13
        );
    }
}

#[test]
fn kuwabara_kono_force_at_chosen_states() {
    let reg = seed_registry();
    let pair = mcc_pair();
    let big_k = 2.0 / 3.0 * (6.0e9 / 1.82) * (0.01f64).sqrt();
    for a in [0.0, 1e-7, 3.3e-6] {
        let b = pair_law(&reg, "kuwabara-kono", &[ParamValue::new("A", a)], &pair);
        for (delta, rate) in STATES {
            let f = b.force(delta, rate).unwrap();
            let expected = big_k * (delta.powf(1.5) + 1.5 * a * delta.sqrt() * rate);
            assert_relative_eq!(f, expected, max_relative = 1e-13, epsilon = 1e-12);
        }
    }
    // A hand-checked value: δ = 1e-5 m, δ̇ = 0.5 m/s, A = 1e-6 s:
    // K = 2.1978022e8 N/m^1.5; δ^1.5 = 3.16227766e-8; (3/2) A √δ δ̇ = 1.5e-6 · 3.16227766e-3 · 0.5
    let b = pair_law(&reg, "kuwabara-kono", &[], &pair);
    let f = b.force(1e-5, 0.5).unwrap();
    assert_relative_eq!(
        f,
        2.197802197802198e8 * (3.162_277_660_168_38e-8 + 2.371_708_245_126_28e-9),
        max_relative = 1e-12
    );
}

#[test]
fn mcnamara_falcon_eq_1() {
    let reg = seed_registry();
    let pair = mcc_pair();
    let b = reg
        .restitution("mcnamara-falcon", &[])
        .unwrap()
        .bind(&pair)
        .unwrap();
    assert_eq!(b.restitution(0.0).unwrap(), 1.0, "r → 1 as v → 0");
    assert_relative_eq!(b.restitution(0.3).unwrap(), 0.95, max_relative = 1e-15);
    // r(1 m/s) = 0.95 (1/0.3)^{-1/4} = 0.70308: the paper's "≈ 0.7"
    let r1 = b.restitution(1.0).unwrap();
    assert_relative_eq!(r1, 0.95 * (1.0f64 / 0.3).powf(-0.25), max_relative = 1e-14);
    assert!((r1 - 0.703).abs() < 5e-4, "r(1 m/s) = {r1}");
    // viscoelastic branch: 1 − r ∝ v^{1/5}
    let r_small = b.restitution(0.003).unwrap();
    assert_relative_eq!(1.0 - r_small, 0.05 * (0.01f64).powf(0.2), max_relative = 1e-12);
    // continuity at v_y: both branches meet at r0
    let (below, above) = (
        b.restitution(0.3 * (1.0 - 1e-12)).unwrap(),
        b.restitution(0.3 * (1.0 + 1e-12)).unwrap(),
    );
    assert!((below - above).abs() < 1e-12, "{below} vs {above}");
    // monotone decreasing over the whole range, and the batch call agrees bit for bit
    let v: Vec<f64> = (0..400).map(|i| 1e-4 * 1.03f64.powi(i)).collect();
    let mut r = vec![0.0; v.len()];
    b.restitution_batch(&v, &mut r).unwrap();
    for w in r.windows(2) {
        assert!(w[1] < w[0]);
    }
    for (vi, ri) in v.iter().zip(&r) {
        assert_eq!(b.restitution(*vi).unwrap().to_bits(), ri.to_bits());
    }
    // other parameters
    let b = reg
        .restitution(
            "mcnamara-falcon",
            &[ParamValue::new("r0", 0.8), ParamValue::new("vy", 2.0)],
        )
        .unwrap()
        .bind(&pair)
        .unwrap();
    assert_relative_eq!(b.restitution(32.0).unwrap(), 0.8 * 0.5, max_relative = 1e-14);
}

#[test]
fn constant_restitution() {
    let reg = seed_registry();
    let b = reg
        .restitution("constant", &[ParamValue::new("r", 0.7)])
        .unwrap()
        .bind(&mcc_pair())
        .unwrap();
    for v in [0.0, 1e-3, 1.0, 100.0] {
        assert_eq!(b.restitution(v).unwrap(), 0.7);
    }
}

#[test]
fn batch_equals_per_pair_for_every_contact_law() {
    let reg = seed_registry();
    let pair = mcc_pair();
    // 5000 states: more than two batch chunks, including δ < 0 (out of contact).
    let n = 5000;
    let delta: Vec<f64> = (0..n).map(|i| 1e-4 * ((i as f64 * 0.37).sin())).collect();
    let rate: Vec<f64> = (0..n).map(|i| 2.0 * ((i as f64 * 0.11).cos())).collect();
    for name in ["lsd", "hsd", "kuwabara-kono"] {
        let b = pair_law(&reg, name, &[], &pair);
        let mut out = vec![f64::NAN; n];
        b.force_batch(&delta, &rate, &mut out).unwrap();
        for i in 0..n {
            assert_eq!(
                out[i].to_bits(),
                b.force(delta[i], rate[i]).unwrap().to_bits(),
                "{name} at {i}"
            );
            if delta[i] < 0.0 {
                assert_eq!(out[i], 0.0);
            }
        }
    }
}
