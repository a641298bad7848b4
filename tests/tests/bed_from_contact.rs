//! Contact laws as the bed's restitution laws: the table against the collision driver.

use dashpot::bed::{contact_laws, resolve, FROM_CONTACT};
use dashpot::collide::{collide, Options};
use dashpot_sdk::{BoundRestitution, EndCriterion, ParamValue};
use dashpot_tests::seed_registry;
use dashpot_tests::BindPair as _;

#[test]
fn hsd_as_a_restitution_law_is_its_eps_at_every_speed() {
    let reg = seed_registry();
    let l = contact_laws(&reg, "hsd", &[ParamValue::new("eps", 0.7)], 0.002, 3.27e-5).unwrap();
    for v in [1e-7, 1e-4, 0.01, 0.3, 1.0, 5.0, 20.0, 100.0] {
        assert!(
            (l.disk.restitution(v) - 0.7).abs() < 1e-8,
            "disk at {v}: {}",
            l.disk.restitution(v)
        );
        assert!(
            (l.wall.restitution(v) - 0.7).abs() < 1e-8,
            "wall at {v}: {}",
            l.wall.restitution(v)
        );
    }
    // and through the name the bed commands use
    let r = resolve(
        &reg,
        &format!("{FROM_CONTACT}hsd"),
        &[ParamValue::new("eps", 0.7)],
        0.002,
        3.27e-5,
    )
    .unwrap();
    assert!((r.disk.r(2.0).unwrap() - 0.7).abs() < 1e-8);
}

#[test]
fn kuwabara_kono_as_a_restitution_law_matches_the_collision_driver() {
    let reg = seed_registry();
    let p = [ParamValue::new("A", 2e-6)];
    let l = contact_laws(&reg, "kuwabara-kono", &p, 0.002, 3.27e-5).unwrap();
    let (pp, pw) = dashpot::bed::bed_pairs(0.002, 3.27e-5).unwrap();
    let law = reg.contact("kuwabara-kono", &p).unwrap();
    for (pair, table) in [(pp, &l.disk), (pw, &l.wall)] {
        let b = law.bind_pair(&pair).unwrap();
        for v in [3e-4, 0.02, 0.7, 4.0] {
            let exact = collide(&b, pair.mass, v, EndCriterion::Force, &Options::default())
                .unwrap()
                .restitution;
            assert!(
                (table.restitution(v) - exact).abs() <= 1e-6,
                "v {v}: {} vs {exact}",
                table.restitution(v)
            );
        }
    }
    // a wall is stiffer and heavier-partnered than a disk: it dissipates differently
    assert!((l.disk.restitution(1.0) - l.wall.restitution(1.0)).abs() > 1e-4);
}
