//! Restitution curves ε(v0): the collisions of one law and pair at ten impact speeds, for each
//! of 40 parameter sets (a fit to a measured curve), one `collide` call per collision against
//! one `collide_many` call per curve, through the HSD plugin, same law handles, same speeds.
//! Prints the speed ratio (median of alternating pairs) and checks the results are the same
//! bits.
//!
//! Run: `cargo bench -p dashpot-tests --bench curve`

mod common;

use dashpot::collide::{collide, collide_many, Options, PairLaw};
use dashpot_sdk::{EndCriterion, Pair, ParamValue, Particle};
use dashpot_tests::seed_registry;

fn main() {
    let pair = Pair::spheres(&Particle::MCC, &Particle::MCC).expect("pair");
    let reg = seed_registry();
    let mut rnd = common::xorshift_uniform(0x2545_f491_4f6c_dd1d_u64);
    let sets: Vec<f64> = (0..20).map(|_| 0.01 + 0.98 * rnd()).collect();
    let speeds: Vec<f64> = (0..20)
        .map(|i| 10f64.powf(-3.0 + 4.0 * i as f64 / 19.0))
        .collect();
    let opt = Options {
        rtol: 1e-8,
        ..Options::default()
    };
    let end = EndCriterion::Overlap;
    let bind = |e: f64| {
        PairLaw::bind(
            &reg.contact("hsd", &[ParamValue::new("eps", e)]).expect("law"),
            &pair,
            0.3,
        )
        .expect("bind")
    };
    let one = || {
        let t = common::process_cpu_seconds();
        let mut s = 0.0;
        for &e in &sets {
            let law = bind(e);
            for &v in &speeds {
                s += collide(&law, pair.mass, v, end, &opt)
                    .expect("collision")
                    .restitution;
            }
        }
        (common::process_cpu_seconds() - t, s)
    };
    let many = || {
        let t = common::process_cpu_seconds();
        let mut s = 0.0;
        for &e in &sets {
            let law = bind(e);
            for c in collide_many(&law, pair.mass, &speeds, end, &opt) {
                s += c.expect("collision").restitution;
            }
        }
        (common::process_cpu_seconds() - t, s)
    };
    let n = (sets.len() * speeds.len()) as f64;
    let mut ratios = vec![];
    for _ in 0..7 {
        let (t1, s1) = one();
        let (t2, s2) = many();
        assert_eq!(s1.to_bits(), s2.to_bits());
        println!(
            "  one by one {:.2} us, curves {:.2} us a collision",
            t1 / n * 1e6,
            t2 / n * 1e6
        );
        ratios.push(t1 / t2);
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "curves / one by one (speed): median {:.2}  pairs {:?}",
        ratios[3], ratios
    );
}
