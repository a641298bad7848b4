//! The example third-party law, built from its own workspace and loaded by path.

use approx::assert_relative_eq;
use dashpot::collide::ContactForce as _;
use dashpot::{Registry, SearchPath};
use dashpot_sdk::{Pair, ParamValue, Particle};
use dashpot_tests::pair_law;

#[test]
fn the_example_plugin_builds_out_of_tree_and_loads_by_path() {
    let path = dashpot_tests::third_party_plugin();
    let sp = SearchPath {
        files: vec![path.clone()],
        ..Default::default()
    };
    let reg = Registry::discover(&sp).unwrap();
    let (_, plugin) = reg.find("hertz-linear-damping").unwrap();
    assert_eq!(plugin.name, "dashpot-example-law");
    assert_eq!(plugin.path, path);
    let pair = Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap();
    let b = pair_law(
        &reg,
        "hertz-linear-damping",
        &[ParamValue::new("eta", 2.0)],
        &pair,
    );
    let k = 4.0 / 3.0 * pair.young * pair.radius.sqrt();
    assert_relative_eq!(
        b.force(1e-5, 0.5).unwrap(),
        k * 1e-5f64.powf(1.5) + 1.0,
        max_relative = 1e-13
    );
}
