//! A sphere launched rolling without slip on a wall stops under `rolling-sds` as rigid-body
//! mechanics says: with the rolling force at its cap μ_r m g, the deceleration is
//! μ_r m g r²/(I + m r²) = (5/7) μ_r g for a solid sphere and the distance 7 v0²/(10 μ_r g),
//! through the real HSD, Mindlin and rolling-sds plugins.

use dashpot::collide::rolling::{roll, RollingSpec};
use dashpot_sdk::{Pair, ParamValue, Particle};
use dashpot_tests::registry_03;

fn particle() -> Particle {
    Particle {
        diameter: 0.01,
        density: 1500.0,
        young: 6e9,
        poisson: 0.3,
    }
}

/// (stop time, stop distance, largest slip) of a sphere of inertia factor `k` (I = k m r²)
/// launched at `v0` with rolling friction `mu_r` under gravity `g`.
fn stop(v0: f64, mu_r: f64, g: f64, k: f64) -> (f64, f64, f64) {
    let reg = registry_03();
    let p = particle();
    let mats = Pair::wall(&p).unwrap().materials(p.poisson).unwrap();
    let normal = reg
        .contact("hsd", &[ParamValue::new("eps", 0.5)])
        .unwrap()
        .bind(&mats)
        .unwrap();
    let tangential = reg
        .tangential("mindlin", &[ParamValue::new("mu", 0.5)])
        .unwrap()
        .bind(&mats)
        .unwrap();
    let rolling = reg
        .rolling(
            "rolling-sds",
            &[
                ParamValue::new("k", 1e3),
                ParamValue::new("gamma", 0.0),
                ParamValue::new("mu", mu_r),
            ],
        )
        .unwrap()
        .bind(&mats)
        .unwrap();
    let (m, r) = (p.mass(), p.radius());
    let spec = RollingSpec {
        mass: m,
        radius: r,
        inertia: k * m * r * r,
        v0,
        gravity: g,
        steps: 50,
    };
    let s = roll(&normal, &tangential, &rolling, &spec, 0).unwrap();
    (s.stop_time, s.stop_distance, s.max_slip)
}

#[test]
fn a_solid_sphere_decelerates_at_five_sevenths_mu_r_g_and_stops_after_seven_v0_squared_over_ten_mu_r_g() {
    for (v0, mu_r) in [(0.05, 0.1), (0.02, 0.05)] {
        let g = 9.81;
        let (t, x, slip) = stop(v0, mu_r, g, 0.4);
        let a = 5.0 / 7.0 * mu_r * g;
        assert!(
            (v0 / t / a - 1.0).abs() < 2e-3,
            "deceleration {} against (5/7) μ_r g = {a}",
            v0 / t
        );
        let x_exact = 7.0 * v0 * v0 / (10.0 * mu_r * g);
        assert!(
            (x / x_exact - 1.0).abs() < 2e-3,
            "distance {x} m against 7 v0²/(10 μ_r g) = {x_exact} m"
        );
        assert!(
            slip < 1e-2 * v0,
            "the sphere must roll without slip: slip speed {slip} m/s"
        );
    }
}

#[test]
fn a_hollow_sphere_decelerates_as_its_inertia_says() {
    // I = (2/3) m r²: a = μ_r g / (1 + 2/3) = (3/5) μ_r g
    let (v0, mu_r, g) = (0.05, 0.1, 9.81);
    let (t, _, _) = stop(v0, mu_r, g, 2.0 / 3.0);
    let a = 0.6 * mu_r * g;
    assert!(
        (v0 / t / a - 1.0).abs() < 2e-3,
        "deceleration {} against (3/5) μ_r g = {a}",
        v0 / t
    );
}
