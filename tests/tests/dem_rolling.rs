//! Rolling and twisting resistance in the DEM engine (sdk 0.3 laws through the real plugins):
//! a sphere launched rolling without slip on a floor stops as rigid-body mechanics says, in 3D
//! and as a 2D disk of a sphere's inertia; a spin about the normal decays as the twisting law
//! says.

use dashpot::dem::{Body, DiskMass, Engine, EngineConfig, Laws, Material, Vec3, VecD, Wall};
use dashpot_sdk::ParamValue;
use dashpot_tests::registry_03;

fn material() -> Material {
    Material {
        young: 1.0e8,
        poisson: 0.3,
        density: 1500.0,
        disk_mass: DiskMass::Sphere,
    }
}

const D: f64 = 0.01;
const G: f64 = 9.81;

/// HSD + Mindlin, with `rolling` and `twisting` laws (name, parameters) if given.
fn laws(rolling: Option<(&str, Vec<ParamValue>)>, twisting: Option<(&str, Vec<ParamValue>)>) -> Laws {
    let reg = registry_03();
    let mat = material();
    Laws::from_registry(
        &reg,
        ("hsd", &[ParamValue::new("eps", 0.3)]),
        Some(("mindlin", &[ParamValue::new("mu", 0.5)])),
        &mat,
    )
    .unwrap()
    .with_rotation(
        &reg,
        rolling.as_ref().map(|(n, p)| (*n, p.as_slice())),
        twisting.as_ref().map(|(n, p)| (*n, p.as_slice())),
        &mat,
    )
    .unwrap()
}

fn sds(mu: f64) -> Vec<ParamValue> {
    vec![
        ParamValue::new("k", 100.0),
        ParamValue::new("gamma", 0.0),
        ParamValue::new("mu", mu),
    ]
}

/// The sphere (or disk) resting on a floor at y (2D) or z (3D) = 0, launched rolling without
/// slip along x at `v0`; runs until its speed along x first reaches 0 and returns (time,
/// distance) from the launch.
fn roll<const N: usize>(v0: f64, mu_r: f64) -> (f64, f64) {
    let up = N - 1;
    let mut cfg = EngineConfig::<N>::new(material());
    let mut g = VecD::<N>::zeros();
    g[up] = -G;
    cfg.gravity = g;
    cfg.impact_speed = Some(0.1);
    let mut normal = VecD::<N>::zeros();
    normal[up] = 1.0;
    let floor = Wall::fixed(VecD::<N>::zeros(), normal);
    let mut x = VecD::<N>::zeros();
    x[up] = 0.5 * D;
    // settle first, at rest, then launch (the rolling spring starts unloaded)
    let body = Body {
        position: x,
        velocity: VecD::<N>::zeros(),
        angular_velocity: Vec3::zeros(),
        diameter: D,
    };
    let mut e = Engine::new(
        cfg,
        &[body],
        vec![floor],
        laws(Some(("rolling-sds", sds(mu_r))), None),
    )
    .unwrap();
    let settle = 0.02;
    while e.time() < settle {
        e.step().unwrap();
    }
    let r = 0.5 * D;
    let mut v = VecD::<N>::zeros();
    v[0] = v0;
    e.p.vel[0] = v;
    // ω such that the contact point (at −r n̂) does not slip: ω × (−r n̂) = −v
    if N == 3 {
        e.p.omega[1] = v0 / r;
    } else {
        e.p.omega[0] = -v0 / r;
    }
    e.invalidate_neighbours();
    let (t0, x0) = (e.time(), e.p.pos[0][0]);
    let mut last = (t0, x0, v0);
    loop {
        e.step().unwrap();
        let (t, xs, vx) = (e.time(), e.p.pos[0][0], e.p.vel[0][0]);
        if vx <= 0.0 {
            // linear interpolation of the stop inside the step
            let s = last.2 / (last.2 - vx);
            return (last.0 + s * (t - last.0) - t0, last.1 + s * (xs - last.1) - x0);
        }
        last = (t, xs, vx);
        assert!(t - t0 < 10.0, "no stop after 10 s: v = {vx}");
    }
}

#[test]
fn a_sphere_rolling_on_a_floor_stops_at_five_sevenths_mu_r_g_in_3d_and_2d() {
    let (v0, mu_r) = (0.05, 0.1);
    let a = 5.0 / 7.0 * mu_r * G;
    let x_exact = 7.0 * v0 * v0 / (10.0 * mu_r * G);
    for (dim, (t, x)) in [(3, roll::<3>(v0, mu_r)), (2, roll::<2>(v0, mu_r))] {
        assert!(
            (v0 / t / a - 1.0).abs() < 2e-3,
            "{dim}D: deceleration {} m/s² against (5/7) μ_r g = {a}",
            v0 / t
        );
        // the distance also carries the tangential spring's elastic give at launch and stop
        assert!(
            (x / x_exact - 1.0).abs() < 5e-3,
            "{dim}D: distance {x} m against 7 v0²/(10 μ_r g) = {x_exact} m"
        );
    }
}

/// A sphere resting on the floor, spun about the vertical at ω0 with `twisting-sds` (spring k,
/// no damping, cap μ_t |F_n| = μ_t m g as a torque): while the law slides at its cap the spin
/// decays linearly, dω/dt = −μ_t m g / I, and stops after I ω0 / (μ_t m g).
#[test]
fn a_spin_about_the_normal_decays_as_the_twisting_law_caps_it() {
    let mut cfg = EngineConfig::<3>::new(material());
    cfg.gravity = VecD::<3>::new(0.0, 0.0, -G);
    cfg.impact_speed = Some(0.1);
    let floor = Wall::fixed(VecD::<3>::zeros(), VecD::<3>::new(0.0, 0.0, 1.0));
    let body = Body {
        position: VecD::<3>::new(0.0, 0.0, 0.5 * D),
        velocity: VecD::<3>::zeros(),
        angular_velocity: Vec3::zeros(),
        diameter: D,
    };
    let mu_t = 1e-4; // m (torque per newton)
    let twist = vec![
        ParamValue::new("k", 1e-3),
        ParamValue::new("gamma", 0.0),
        ParamValue::new("mu", mu_t),
    ];
    let mut e = Engine::new(
        cfg,
        &[body],
        vec![floor],
        laws(None, Some(("twisting-sds", twist))),
    )
    .unwrap();
    while e.time() < 0.02 {
        e.step().unwrap();
    }
    let w0 = 20.0;
    e.p.omega[2] = w0;
    let t0 = e.time();
    let (m, r) = (e.p.mass[0], 0.5 * D);
    let inertia = 0.4 * m * r * r;
    let alpha = mu_t * m * G / inertia;
    let mut last = (t0, w0);
    loop {
        e.step().unwrap();
        let (t, w) = (e.time(), e.p.omega[2]);
        if w <= 0.0 {
            let s = last.1 / (last.1 - w);
            let t_stop = last.0 + s * (t - last.0) - t0;
            let exact = w0 / alpha;
            assert!(
                (t_stop / exact - 1.0).abs() < 2e-3,
                "spin stopped after {t_stop} s, I ω0/(μ_t m g) = {exact} s"
            );
            return;
        }
        last = (t, w);
        assert!(t - t0 < 10.0, "no stop after 10 s: ω = {w}");
    }
}
