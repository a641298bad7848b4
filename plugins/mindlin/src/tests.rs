//! Tests of the Mindlin law: its schema, and the SIMD batch against the per-contact form. Its
//! closed forms (a sliding sphere, an oblique impact, the spring's rotation and cap) are tested
//! with linear-history's in `tests/tests/tangential_springs.rs`.

use super::*;
use dashpot_sdk::ParamValue;
use std::f64::consts::PI;

fn law(e: f64, mu: f64, damping: f64) -> MindlinBound {
    Mindlin::from_values(&[ParamValue::new("mu", mu), ParamValue::new("damping", damping)])
        .unwrap()
        .bind(&MaterialPair::of_moduli(e, 0.3, None).unwrap())
        .unwrap()
}

#[test]
fn schema_and_history_slots() {
    let info = Mindlin::info();
    assert_eq!(info.history.len(), 4);
    assert!(info.history[..3].iter().all(|h| h.unit == "m"));
    assert_eq!(info.history[3].unit, "N/m");
    let l = Mindlin::from_values(&[]).unwrap();
    assert_eq!((l.mu, l.damping), (0.5, 0.0));
    assert!(Mindlin::from_values(&[ParamValue::new("mu", -0.1)]).is_err());
}
/// The SIMD batch gives the per-contact form's bits on every path: out of touch, fresh and
/// rotated springs, sticking and sliding, in tension, damped or not, and a ragged last lane;
/// with its energy outputs too.
#[test]
fn batch_is_the_per_contact_form_bit_for_bit() {
    let mut x = 0x2545_f491_4f6c_dd1d_u64;
    let mut rnd = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    for damping in [0.0, 0.4] {
        let l = law(2.0e11, 0.3, damping);
        let n = 203;
        let mut normal = Vec::new();
        let mut velocity = Vec::new();
        let (mut fnorm, mut delta, mut mass, mut radius) = (vec![], vec![], vec![], vec![]);
        let mut hist = Vec::new();
        for i in 0..n {
            let (th, ph) = (PI * rnd(), 2.0 * PI * rnd());
            normal.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
            velocity.push([rnd() - 0.5, rnd() - 0.5, rnd() - 0.5]);
            fnorm.push(if i % 7 == 0 { -1.0 } else { 20.0 * rnd() });
            delta.push(if i % 11 == 0 { -1e-6 } else { 1e-5 * rnd() });
            mass.push(1e-4 * (0.5 + rnd()));
            radius.push(1e-3 * (0.5 + rnd()));
            for _ in 0..3 {
                hist.push(if i % 5 == 0 { 0.0 } else { 1e-6 * (rnd() - 0.5) });
            }
            // the stiffness of the last call: none at a first touch
            hist.push(if i % 5 == 0 { 0.0 } else { 1e5 * rnd() });
        }
        let dt = 1e-6;
        let mut h1 = hist.clone();
        let (f1, e1): (Vec<[f64; 3]>, Vec<Energy>) = (0..n)
            .map(|i| {
                let c = TangentialContact {
                    normal: normal[i],
                    velocity: velocity[i],
                    normal_force: fnorm[i],
                    delta: delta[i],
                    mass: mass[i],
                    radius: radius[i],
                    dt,
                };
                let mut h = [h1[4 * i], h1[4 * i + 1], h1[4 * i + 2], h1[4 * i + 3]];
                let f = l.force(&c, &mut h);
                let (fe, e) = l.force_energy(&c, &mut h1[4 * i..4 * i + 4]);
                assert_eq!(
                    f.map(f64::to_bits),
                    fe.map(f64::to_bits),
                    "force_energy's force {i}"
                );
                assert_eq!(h[..], h1[4 * i..4 * i + 4], "force_energy's spring {i}");
                (f, e.unwrap())
            })
            .unzip();
        let mut h2 = hist.clone();
        let mut f2 = vec![[0.0; 3]; n];
        l.force_batch(TangentialBatch {
            dt,
            normal: &normal,
            velocity: &velocity,
            normal_force: &fnorm,
            delta: &delta,
            mass: &mass,
            radius: &radius,
            slots: 4,
            history: &mut h2,
            force: &mut f2,
        });
        let (mut h3, mut f3) = (hist.clone(), vec![[0.0; 3]; n]);
        let (mut power, mut elastic) = (vec![0.0; n], vec![0.0; n]);
        let written = l.force_batch_energy(
            TangentialBatch {
                dt,
                normal: &normal,
                velocity: &velocity,
                normal_force: &fnorm,
                delta: &delta,
                mass: &mass,
                radius: &radius,
                slots: 4,
                history: &mut h3,
                force: &mut f3,
            },
            EnergyBatch {
                power: &mut power,
                elastic: &mut elastic,
            },
        );
        assert!(written);
        assert_eq!((&f2, &h2), (&f3, &h3), "force_batch_energy's forces and springs");
        for i in 0..n {
            assert_eq!(
                e1[i].power.to_bits(),
                power[i].to_bits(),
                "power {i}, damping {damping}"
            );
            assert_eq!(e1[i].elastic.to_bits(), elastic[i].to_bits(), "elastic {i}");
        }
        let slid = f1
            .iter()
            .zip(&fnorm)
            .filter(|(f, &fn_)| {
                (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt() >= 0.3 * fn_.max(0.0) * (1.0 - 1e-12)
            })
            .count();
        assert!(
            slid > 10 && slid < n - 10,
            "both regimes covered: {slid} of {n} at the cap"
        );
        for i in 0..n {
            for k in 0..3 {
                assert_eq!(
                    f1[i][k].to_bits(),
                    f2[i][k].to_bits(),
                    "force {i}.{k}, damping {damping}"
                );
            }
            for k in 0..4 {
                assert_eq!(
                    h1[4 * i + k].to_bits(),
                    h2[4 * i + k].to_bits(),
                    "history {i}.{k}"
                );
            }
        }
    }
}
