//! Contact laws as the bed's restitution laws: the table against the collision driver.

use dashpot::bed::{bed_particle, contact_laws, resolve_for, LawChoice, FROM_CONTACT};
use dashpot::collide::Options;
use dashpot_sdk::{BoundRestitution, ParamValue};
use dashpot_tests::BindPair as _;
use dashpot_tests::{seed_registry, within_1e6_of_the_driver};

#[test]
fn hsd_as_a_restitution_law_is_its_eps_at_every_speed() {
    let reg = seed_registry();
    let disks = bed_particle(0.002, 3.27e-5);
    let eps = vec![ParamValue::new("eps", 0.7)];
    let l = contact_laws(&reg, &LawChoice::new("hsd", eps.clone()), &disks).unwrap();
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
    let from_hsd = LawChoice::new(&format!("{FROM_CONTACT}hsd"), eps);
    let r = resolve_for(&reg, &from_hsd, &disks).unwrap();
    assert!((r.disk.r(2.0).unwrap() - 0.7).abs() < 1e-8);
}

#[test]
fn kuwabara_kono_as_a_restitution_law_matches_the_collision_driver() {
    let reg = seed_registry();
    let p = [ParamValue::new("A", 2e-6)];
    let kk = LawChoice::new("kuwabara-kono", p.to_vec());
    let l = contact_laws(&reg, &kk, &bed_particle(0.002, 3.27e-5)).unwrap();
    let (pp, pw) = dashpot::bed::bed_pairs(0.002, 3.27e-5).unwrap();
    let law = reg.contact("kuwabara-kono", &p).unwrap();
    for (pair, table) in [(pp, &l.disk), (pw, &l.wall)] {
        let b = law.bind_pair(&pair).unwrap();
        within_1e6_of_the_driver(table, &b, pair.mass, &[3e-4, 0.02, 0.7, 4.0], &Options::default());
    }
    // a wall is stiffer and heavier-partnered than a disk: it dissipates differently
    assert!((l.disk.restitution(1.0) - l.wall.restitution(1.0)).abs() > 1e-4);
}
