//! Head-on impacts under the adhesive laws of sdk 0.3 (JKR, DMT) through the two-body driver and
//! the real plugins: sticking below a critical speed, rebound above it, the contact ending at
//! the pull-off separation, against the closed forms of the laws and Thornton & Ning (1998).

use dashpot::collide::{collide, Collision, Options, PairLaw};
use dashpot_sdk::{EndCriterion, Pair, ParamValue, Particle};
use dashpot_tests::registry_03;
use std::f64::consts::PI;

/// A 1 mm silica-like sphere (ρ = 2500 kg/m³, E = 7·10¹⁰ Pa, ν = 0.2).
fn particle() -> Particle {
    Particle {
        diameter: 1e-3,
        density: 2500.0,
        young: 7e10,
        poisson: 0.2,
    }
}

/// `law` with work of adhesion `w` (J/m²) bound to the sphere against a wall (`wall`) or an equal
/// sphere.
fn bound(law: &str, w: f64, wall: bool) -> (PairLaw<dashpot::laws::ContactModelHandle>, Pair) {
    let reg = registry_03();
    let handle = reg.contact(law, &[ParamValue::new("w", w)]).unwrap();
    let p = particle();
    let pair = if wall {
        Pair::wall(&p)
    } else {
        Pair::spheres(&p, &p)
    }
    .unwrap();
    (PairLaw::bind(&handle, &pair, p.poisson).unwrap(), pair)
}

fn impact(law: &PairLaw<dashpot::laws::ContactModelHandle>, pair: &Pair, v0: f64) -> Collision {
    let opt = Options {
        rtol: 1e-10,
        ..Options::default()
    };
    collide(law, pair.mass, v0, EndCriterion::Overlap, &opt).unwrap()
}

/// The speed (m/s) that separates sticking from rebound, by bisection on a log scale to 1e-6.
fn critical_speed(law: &PairLaw<dashpot::laws::ContactModelHandle>, pair: &Pair) -> f64 {
    let (mut lo, mut hi) = (1e-6, 10.0);
    assert!(impact(law, pair, lo).stuck, "the slowest impact must stick");
    assert!(!impact(law, pair, hi).stuck, "the fastest impact must rebound");
    while hi / lo > 1.0 + 1e-6 {
        let mid = (lo * hi).sqrt();
        if impact(law, pair, mid).stuck {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo * hi).sqrt()
}

/// JKR's energy balance: an undamped JKR contact is conservative while formed, so the energy an
/// impact loses is the work of pulling the formed contact from δ = 0 to rupture at δ_c,
/// ΔW = ∫ |F| dδ over [δ_c, 0] (the contact forms at touch), and the critical speed is
/// √(2 ΔW / m). Integrated here over the contact radius a with Johnson's parametric form
/// δ = a²/R − √(2π w a/E), F = 4E a³/(3R) − √(8π w E a³), independently of the plugin.
fn jkr_critical_speed(w: f64, r: f64, e: f64, m: f64) -> f64 {
    let delta = |a: f64| a * a / r - (2.0 * PI * w * a / e).sqrt();
    let force = |a: f64| 4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a.powi(3)).sqrt();
    let a0 = (9.0 * PI * w * r * r / (2.0 * e)).cbrt();
    let a_c = a0 / 6f64.powf(2.0 / 3.0);
    let a_touch = (2.0 * PI * w * r * r / e).cbrt();
    // Simpson's rule in a of |F| dδ/da
    let n = 20_000;
    let dd = |a: f64| {
        let h = 1e-7 * a;
        (delta(a + h) - delta(a - h)) / (2.0 * h)
    };
    let g = |a: f64| -force(a) * dd(a);
    let h = (a_touch - a_c) / n as f64;
    let mut s = g(a_c) + g(a_touch);
    for i in 1..n {
        s += g(a_c + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    (2.0 * s * h / 3.0 / m).sqrt()
}

#[test]
fn a_slow_jkr_impact_sticks_a_fast_one_rebounds_and_the_critical_speed_is_the_energy_balance() {
    let w = 0.1;
    for wall in [true, false] {
        let (law, pair) = bound("jkr", w, wall);
        let vc = critical_speed(&law, &pair);
        let exact = jkr_critical_speed(w, pair.radius, pair.young, pair.mass);
        assert!(
            (vc / exact - 1.0).abs() < 1e-4,
            "wall {wall}: critical speed {vc:e} m/s, energy balance {exact:e} m/s"
        );
        let slow = impact(&law, &pair, 0.5 * vc);
        assert!(slow.stuck && slow.restitution == 0.0, "{slow:?}");
        let fast = impact(&law, &pair, 2.0 * vc);
        assert!(
            !fast.stuck && fast.restitution > 0.0 && fast.restitution < 1.0,
            "{fast:?}"
        );
        // above it: ½ m v_out² = ½ m v0² − ΔW, so e² = 1 − (v_c/v0)²
        let e_exact = (1.0 - 0.25f64).sqrt();
        assert!(
            (fast.restitution - e_exact).abs() < 1e-4,
            "restitution {} against √(1 − (vc/v0)²) = {e_exact}",
            fast.restitution
        );
    }
}

/// Thornton & Ning (1998), Powder Technol. 99, 154, for elastic adhesive spheres against a
/// wall: V_s = 1.84 (Γ⁵ / (ρ³ E*² R*⁵))^{1/6}, with Γ read as the work of adhesion w (J/m²;
/// pull-off force (3/2) π Γ R*), ρ the density, E* the effective modulus, R* the radius. Their
/// coefficient 1.84 is JKR's energy balance rounded to three figures (that balance gives
/// 3.7662 (w⁵ R*⁴/(E*² m*³))^{1/6} = 1.8402 (w⁵/(ρ³ E*² R*⁵))^{1/6} for m* = (4/3) π ρ R*³).
#[test]
fn the_jkr_critical_speed_against_a_wall_is_thornton_and_nings() {
    for w in [0.05, 0.3] {
        let (law, pair) = bound("jkr", w, true);
        let vc = critical_speed(&law, &pair);
        let p = particle();
        let tn = 1.84
            * (w.powi(5) / (p.density.powi(3) * pair.young.powi(2) * pair.radius.powi(5))).powf(1.0 / 6.0);
        assert!(
            (vc / tn - 1.0).abs() < 1e-3,
            "w = {w}: dashpot's critical speed {vc:e} m/s, Thornton & Ning's {tn:e} m/s (ratio {})",
            vc / tn
        );
    }
}

#[test]
fn a_jkr_contact_ends_at_the_pull_off_separation_and_pulls_no_harder_than_its_pull_off_force() {
    let w = 0.1;
    let (law, pair) = bound("jkr", w, false);
    let vc = critical_speed(&law, &pair);
    let opt = Options {
        rtol: 1e-10,
        record: true,
        max_step_fraction: 0.002,
        ..Options::default()
    };
    let c = collide(&law, pair.mass, 1.5 * vc, EndCriterion::Overlap, &opt).unwrap();
    assert!(!c.stuck);
    let end = c.trajectory.last().unwrap();
    let delta_c = -0.75 * (PI * PI * w * w * pair.radius / (pair.young * pair.young)).cbrt();
    assert!(
        (end.delta / delta_c - 1.0).abs() < 1e-6,
        "the contact ends at δ = {:e} m, the pull-off separation is {delta_c:e} m",
        end.delta
    );
    let pull_off = -1.5 * PI * w * pair.radius;
    let peak = c.tensile_peak.unwrap();
    assert!(
        peak >= pull_off * (1.0 + 1e-9),
        "most tensile {peak:e} N beyond the pull-off force {pull_off:e} N"
    );
    assert!(
        peak < 0.999 * pull_off,
        "the unloading passes near the pull-off force: {peak:e} N against {pull_off:e} N"
    );
}

#[test]
fn an_undamped_dmt_impact_never_sticks_and_ends_at_touch_with_its_impact_speed() {
    // DMT: F = K δ^{3/2} − 2π w R while touching, and the contact ends at δ = 0. Undamped it is
    // conservative with U(0) = 0 at both ends, so the particle leaves at v0 whatever v0: the
    // work the adhesion does on the way in it takes back on the way out.
    let (law, pair) = bound("dmt", 0.1, false);
    for v0 in [1e-4, 1e-2, 1.0] {
        let c = impact(&law, &pair, v0);
        assert!(!c.stuck, "v0 = {v0}: {c:?}");
        assert!(
            (c.restitution - 1.0).abs() < 1e-6,
            "v0 = {v0}: restitution {}",
            c.restitution
        );
        let f_touch = -2.0 * PI * 0.1 * pair.radius;
        assert!(
            (c.tensile_peak.unwrap() / f_touch - 1.0).abs() < 1e-6,
            "{:?}",
            c.tensile_peak
        );
    }
}

/// DMT's force jumps at touch (−2π w R at δ = 0⁺, 0 beyond), and the driver ends its contact
/// there in u = δ^{1/4}, at u = 0 exactly, no step across the jump: the restitution meets the
/// `--rtol` promise (20 × rtol). Undamped, the law is conservative with U(0) = 0 at both ends
/// (the adhesion's work on the way in is taken back on the way out), so the exact restitution
/// is 1 (the driver once stepped across the jump: off by ~1e-6 at every rtol).
#[test]
fn an_undamped_dmt_impact_realizes_restitution_one_to_twenty_times_rtol() {
    for w in [0.1, 1.0] {
        let (law, pair) = bound("dmt", w, false);
        for v0 in [1e-3, 1e-2, 1.0] {
            for rtol in [1e-6, 1e-8, 1e-10, 1e-11] {
                let opt = Options {
                    rtol,
                    ..Options::default()
                };
                let c = collide(&law, pair.mass, v0, EndCriterion::Overlap, &opt).unwrap();
                let err = (c.restitution - 1.0).abs();
                assert!(
                    !c.stuck && err <= 20.0 * rtol,
                    "w {w}, v0 {v0} m/s, rtol {rtol:e}: restitution {} (off by {err:e})",
                    c.restitution
                );
            }
        }
    }
}

/// Damped DMT (Tsuji damping ∝ δ^{1/4} δ̇, not smooth in time at touch) from just above its
/// capture speed v_c (restitution ~0.01) to 10 v_c: the restitution at each rtol is within
/// 20 × rtol of a reference integrated by another method (Dormand–Prince 5(4) instead of the
/// extrapolation) at rtol 1e-12 (the driver once missed by 2e-4 at rtol 1e-6 and 8e-7 at 1e-11).
#[test]
fn a_damped_dmt_impact_meets_twenty_times_rtol_against_an_independent_reference() {
    let reg = registry_03();
    let p = particle();
    let pair = Pair::spheres(&p, &p).unwrap();
    for (w, eps) in [(0.1, 0.5), (1.0, 0.9), (1.0, 0.3)] {
        let params = [ParamValue::new("w", w), ParamValue::new("eps", eps)];
        let law = PairLaw::bind(&reg.contact("dmt", &params).unwrap(), &pair, p.poisson).unwrap();
        // the capture speed, by bisection (relative 1e-7)
        let (mut lo, mut hi) = (1e-4, 10.0);
        assert!(impact(&law, &pair, lo).stuck && !impact(&law, &pair, hi).stuck);
        while hi / lo > 1.0 + 1e-7 {
            let mid = (lo * hi).sqrt();
            if impact(&law, &pair, mid).stuck {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let reference = Options {
            rtol: 1e-12,
            method: dashpot::collide::outcome::Method::DormandPrince5,
            ..Options::default()
        };
        for factor in [1.001, 1.1, 2.0, 10.0] {
            let v0 = hi * factor;
            let r = collide(&law, pair.mass, v0, EndCriterion::Overlap, &reference).unwrap();
            assert!(!r.stuck && r.restitution > 0.005, "{r:?}");
            for rtol in [1e-6, 1e-8, 1e-10, 1e-11] {
                let opt = Options {
                    rtol,
                    ..Options::default()
                };
                let c = collide(&law, pair.mass, v0, EndCriterion::Overlap, &opt).unwrap();
                let err = (c.restitution - r.restitution).abs();
                assert!(
                    err <= 20.0 * rtol,
                    "w {w}, eps {eps}, v0 {v0} m/s ({factor} v_c), rtol {rtol:e}: restitution {} \
                     against {} (off by {err:e})",
                    c.restitution,
                    r.restitution
                );
            }
        }
    }
}
