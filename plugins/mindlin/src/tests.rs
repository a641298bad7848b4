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
    dashpot_testkit::assert_spring_history(&info);
    assert_eq!((info.history.len(), info.history[3].unit.as_str()), (7, "N/m"));
    assert_eq!(info.history[4].unit, "N");
    let l = Mindlin::from_values(&[]).unwrap();
    assert_eq!((l.mu, l.damping), (0.5, 0.0));
    assert!(Mindlin::from_values(&[ParamValue::new("mu", -0.1)]).is_err());
}
/// The SIMD batch gives the per-contact form's bits on every path: out of touch, fresh and
/// rotated springs, sticking and sliding, in tension, damped or not, and a ragged last lane;
/// with its energy outputs too, and force_energy the same forces as force.
#[test]
fn batch_is_the_per_contact_form_bit_for_bit() {
    let mut rnd = dashpot_testkit::uniform(0x2545_f491_4f6c_dd1d_u64);
    for damping in [0.0, 0.4] {
        let l = law(2.0e11, 0.3, damping);
        let n = 203;
        let (mut contacts, mut hist) = (Vec::new(), Vec::new());
        for i in 0..n {
            let (th, ph) = (PI * rnd(), 2.0 * PI * rnd());
            // (every 13th so fast that |F_t|² overflows: those lanes go one by one)
            let fast = if i % 13 == 6 { 1e160 } else { 1.0 };
            contacts.push(TangentialContact {
                normal: [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()],
                velocity: [fast * (rnd() - 0.5), rnd() - 0.5, rnd() - 0.5],
                normal_force: if i % 7 == 0 { -1.0 } else { 20.0 * rnd() },
                delta: if i % 11 == 0 { -1e-6 } else { 1e-5 * rnd() },
                mass: 1e-4 * (0.5 + rnd()),
                radius: 1e-3 * (0.5 + rnd()),
                context: Default::default(),
                dt: 1e-6,
            });
            for _ in 0..3 {
                hist.push(if i % 5 == 0 { 0.0 } else { 1e-6 * (rnd() - 0.5) });
            }
            // the stiffness of the last call: none at a first touch, else above or below this
            // call's (the spring's force kept, or its length)
            let c = contacts[i];
            let kt = l.stiffness(c.radius, c.delta);
            hist.push(if i % 5 == 0 { 0.0 } else { kt * (0.5 + rnd()) });
            // the dashpot's share of the last force
            for _ in 0..3 {
                hist.push(if i % 5 == 0 { 0.0 } else { 1e-3 * (rnd() - 0.5) });
            }
        }
        let what = format!("damping {damping}");
        let f1 = dashpot_testkit::batch_is_per_contact(
            &contacts,
            &hist,
            7,
            |c, h| l.force(c, h),
            |b| l.force_batch(b),
            &what,
        );
        // with the energy outputs, and force_energy's force and history those of force
        dashpot_testkit::batch_energy_is_per_contact(
            &contacts,
            &hist,
            7,
            |c, h| l.force_energy(c, h),
            |b, e| l.force_batch_energy(b, e),
            &what,
        );
        // every batch length (whole and partial lane groups and blocks, a remainder through the
        // per-contact form), through the dispatch (AVX2 where the CPU has it)
        for m in [1, 3, 4, 5, 9, 32, 37, 70] {
            let (c, h) = (&contacts[n - m..], &hist[7 * (n - m)..]);
            let what = format!("{what}, {m} contacts");
            dashpot_testkit::batch_is_per_contact(c, h, 7, |c, h| l.force(c, h), |b| l.force_batch(b), &what);
            dashpot_testkit::batch_energy_is_per_contact(
                c,
                h,
                7,
                |c, h| l.force_energy(c, h),
                |b, e| l.force_batch_energy(b, e),
                &format!("{what} with energy"),
            );
        }
        let slid = f1
            .iter()
            .zip(&contacts)
            .filter(|(f, c)| {
                (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
                    >= 0.3 * c.normal_force.max(0.0) * (1.0 - 1e-12)
            })
            .count();
        assert!(
            slid > 10 && slid < n - 10,
            "both regimes covered: {slid} of {n} at the cap"
        );
    }
}

/// The law never gives back more energy than the slip put into it, damped or not, sliding or
/// stuck, its stiffness growing or shrinking with the overlap, and its books close
/// ([`dashpot_sdk::testkit`]: random materials, random paths).
#[test]
fn never_gives_back_more_than_it_was_given() {
    for (mu, damping) in [(0.4, 0.0), (0.4, 2.0), (0.1, 5.0), (1.0, 0.3)] {
        dashpot_sdk::testkit::assert_dissipative_tangential(&Mindlin::with(mu, damping));
    }
}
