//! Backward compatibility with sdk 0.2: HSD, Mindlin and Thornton built against dashpot-sdk
//! 0.2.0, from this repository's own sources at the last 0.2 commit (not a copy in the tree),
//! load in the 0.4 host and give the same bits, forces and history alike, as the same laws
//! built against 0.4 (Mindlin: as the LAMMPS-order kernel it was built from), over load–unload
//! sequences that exercise their history (Thornton's largest overlap, Mindlin's spring through
//! stick and slip).

use dashpot_sdk::physics::spring_friction;
use dashpot_sdk::{LawKind, MaterialPair, NormalBatch, ParamValue, TangentialBatch, TangentialContact};
use dashpot_tests::{assert_same_bits, full_registry, memoryless_batch, sdk02_registry};

fn materials() -> MaterialPair {
    MaterialPair::new(7.0e10, 2.7e10).unwrap()
}

fn cycle(n: usize, steps: usize) -> dashpot_tests::Cycle {
    dashpot_tests::load_cycle(n, steps, |i| -1e-7 * (i % 3) as f64)
}

#[test]
fn sdk02_plugins_load_as_02_and_give_bit_identical_normal_forces_and_history() {
    let Some(old) = sdk02_registry("debug") else {
        return;
    };
    let new = full_registry();
    let kinds: Vec<(String, LawKind)> = old
        .laws
        .iter()
        .map(|l| (l.info.name.to_string(), l.info.kind))
        .collect();
    assert_eq!(
        kinds,
        [
            ("hsd".to_string(), LawKind::Contact),
            ("mindlin".to_string(), LawKind::Tangential),
            ("thornton".to_string(), LawKind::Contact),
        ]
    );
    let (n, steps) = (17, 120);
    let (mass, radius, delta, rate) = cycle(n, steps);
    let mut compared = 0;
    for (name, params) in [
        ("hsd", vec![ParamValue::new("eps", 0.6)]),
        ("thornton", vec![ParamValue::new("py", 3e8)]),
    ] {
        let mo = old.contact(name, &params).unwrap().bind(&materials()).unwrap();
        let mn = new.contact(name, &params).unwrap().bind(&materials()).unwrap();
        assert_eq!(mo.history_slots(), mn.history_slots());
        let slots = mo.history_slots();
        let (mut ho, mut hn) = (vec![0.0; n * slots], vec![0.0; n * slots]);
        let mut plastic = false;
        for s in 0..steps {
            let (mut fo, mut fnew) = (vec![0.0; n], vec![0.0; n]);
            for (m, h, f) in [(&mo, &mut ho, &mut fo), (&mn, &mut hn, &mut fnew)] {
                m.force_batch(NormalBatch {
                    delta: &delta[s],
                    rate: &rate[s],
                    mass: &mass,
                    radius: &radius,
                    slots,
                    history: h,
                    force: f,
                })
                .unwrap();
            }
            assert_same_bits(&fo, &fnew, |i| format!("{name} step {s} contact {i}"));
            assert_same_bits(&ho, &hn, |_| format!("{name} history, step {s}"));
            compared += n;
            // the cycle unloads after yield: Thornton's unloading branch is exercised
            plastic |= name == "thornton" && fo.iter().zip(&delta[s]).any(|(f, d)| *d > 0.0 && *f < 1.0);
        }
        assert!(name != "thornton" || plastic);
    }
    // Mindlin, with damping, through stick and slip: the 0.2 build against the kernel it was
    // built from (LAMMPS's order and reset, `physics::spring_friction` with k_t = 8 G a), for
    // today's `mindlin` takes dashpot's passive slider instead (it never does positive work)
    let params = [ParamValue::new("mu", 0.3), ParamValue::new("damping", 0.2)];
    let mo = old
        .tangential("mindlin", &params)
        .unwrap()
        .bind(&materials())
        .unwrap();
    let eight_g = 8.0 * materials().shear;
    let (mut ho, mut hn) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
    let mut slipped = false;
    for (s, delta_s) in delta.iter().enumerate() {
        let normal: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let a = 0.01 * (s + i) as f64;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let velocity: Vec<[f64; 3]> = (0..n)
            .map(|i| [0.01 * i as f64, -0.2 + 0.003 * s as f64, 0.05 * (i % 4) as f64])
            .collect();
        let fnorm: Vec<f64> = delta_s.iter().map(|d| 1e4 * d.max(0.0)).collect();
        let (mut fo, mut fnew) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        mo.force_batch(TangentialBatch {
            dt: 1e-6,
            normal: &normal,
            velocity: &velocity,
            normal_force: &fnorm,
            delta: delta_s,
            mass: &mass,
            radius: &radius,
            context: &[],
            slots: 3,
            history: &mut ho,
            force: &mut fo,
        })
        .unwrap();
        for i in 0..n {
            let c = TangentialContact {
                normal: normal[i],
                velocity: velocity[i],
                normal_force: fnorm[i],
                delta: delta_s[i],
                mass: mass[i],
                radius: radius[i],
                dt: 1e-6,
                context: Default::default(),
            };
            let kt = eight_g * dashpot_sdk::physics::contact_radius(radius[i], delta_s[i]);
            let eta = 2.0 * 0.2 * (mass[i] * kt).sqrt();
            fnew[i] = spring_friction(kt, eta, 0.3, &c, &mut hn[3 * i..3 * i + 3]);
        }
        assert_same_bits(fo.as_flattened(), fnew.as_flattened(), |k| {
            format!("mindlin step {s} contact {}", k / 3)
        });
        compared += n;
        for (f, fn_) in fo.iter().zip(&fnorm) {
            let mag = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
            slipped |= *fn_ > 0.0 && (mag - 0.3 * fn_).abs() <= 1e-12 * fn_;
        }
        assert_same_bits(&ho, &hn, |_| format!("mindlin spring, step {s}"));
    }
    assert!(slipped, "the sequence reaches the Coulomb cap");
    assert_eq!(compared, 3 * n * steps);
}

/// A 0.2 law through the 0.3 calls: reach 0 and energy reported as not available, forces as
/// before; the 0.4 build of the same law reports its energy.
#[test]
fn old_plugins_have_reach_zero_and_no_energy() {
    let Some(old) = sdk02_registry("debug") else {
        return;
    };
    let new = full_registry();
    let params = [ParamValue::new("eps", 0.6)];
    let mo = old.contact("hsd", &params).unwrap().bind(&materials()).unwrap();
    let mn = new.contact("hsd", &params).unwrap().bind(&materials()).unwrap();
    let (delta, rate, mass, radius) = ([2e-6, -1e-7], [0.3, -0.1], [1e-4, 1e-4], [1e-3, 1e-3]);
    let mut out = Vec::new();
    for m in [&mo, &mn] {
        let (mut f, mut reach, mut p, mut e) = ([0.0; 2], [f64::NAN; 2], [0.0; 2], [0.0; 2]);
        let written = m
            .force_batch_with(
                memoryless_batch(&delta, &rate, &mass, &radius, &mut f),
                Some(&mut reach),
                dashpot_sdk::abi::EnergyOut {
                    power: Some(&mut p),
                    elastic: Some(&mut e),
                },
            )
            .unwrap();
        assert_eq!(reach, [0.0, 0.0]);
        out.push((written, f, e));
    }
    assert!(!out[0].0, "a 0.2 law reports energy as not available");
    assert!(out[1].0 && out[1].2[0] > 0.0, "the 0.4 build reports it");
    assert_eq!(out[0].1.map(f64::to_bits), out[1].1.map(f64::to_bits));
}
