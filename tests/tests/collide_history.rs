//! Contact laws with memory through the two-body driver (plastic normal laws) and oblique
//! impacts with a tangential law (friction with a history spring), against closed forms.

use dashpot::collide::oblique::{oblique, Body, Impact, Target};
use dashpot::collide::{collide, Options, PairLaw};
use dashpot_sdk::{EndCriterion, MaterialPair, Pair, ParamValue, Particle};
use dashpot_tests::{assert_rel, full_registry};

/// A 2 mm steel sphere (the bed's disks) against a rigid wall.
fn steel() -> Particle {
    Particle {
        diameter: 0.002,
        density: 7800.0,
        young: 2.0e11,
        poisson: 0.3,
    }
}

fn tight() -> Options {
    Options {
        rtol: 1e-12,
        ..Options::default()
    }
}

#[test]
fn walton_braun_realizes_sqrt_k1_over_k2_at_every_speed() {
    let reg = full_registry();
    let p = steel();
    let pair = Pair::wall(&p).unwrap();
    let (k1, k2) = (2.0e6, 5.0e6);
    let law = reg
        .contact(
            "walton-braun",
            &[ParamValue::new("k1", k1), ParamValue::new("k2", k2)],
        )
        .unwrap();
    assert_eq!(law.info().history.len(), 1);
    for v0 in [0.01, 1.0, 30.0] {
        let b = PairLaw::bind(&law, &pair, p.poisson).unwrap();
        let c = collide(&b, pair.mass, v0, EndCriterion::Force, &tight()).unwrap();
        let want = (k1 / k2).sqrt();
        assert!(
            (c.restitution - want).abs() < 1e-9,
            "v0 = {v0}: e = {:.15} vs √(k1/k2) = {want:.15}",
            c.restitution
        );
        // the contact ends at the residual overlap δ_p = δ_max (1 − k1/k2), force 0
        assert!(b.history()[0] > 0.0);
        let dmax = v0 * (pair.mass / k1).sqrt();
        assert_rel(c.max_overlap, dmax, 1e-9, "largest overlap (m)");
    }
}

#[test]
fn thornton_is_elastic_below_yield_and_follows_its_closed_form_above() {
    let reg = full_registry();
    let p = steel();
    let pair = Pair::wall(&p).unwrap();
    let mat = MaterialPair::wall(&p).unwrap();
    let py = 1.0e9;
    let law = reg.contact("thornton", &[ParamValue::new("py", py)]).unwrap();
    let model = law.bind(&mat).unwrap();
    let vy = model
        .coefficients(pair.mass, pair.radius)
        .unwrap()
        .iter()
        .find(|c| c.name == "V_y")
        .map(|c| c.value)
        .unwrap();
    // V_y from energy: ½ m V_y² = (2/5) K δ_y^{5/2}, δ_y = (π p_y / (2E))² r
    let dy = (std::f64::consts::PI * py / (2.0 * mat.young)).powi(2) * pair.radius;
    let k = 4.0 / 3.0 * mat.young * pair.radius.sqrt();
    let vy_energy = (2.0 * 0.4 * k * dy.powf(2.5) / pair.mass).sqrt();
    assert!((vy / vy_energy - 1.0).abs() < 1e-12, "{vy} vs {vy_energy}");
    let e_of = |v0: f64| {
        let b = PairLaw::bind(&law, &pair, p.poisson).unwrap();
        collide(&b, pair.mass, v0, EndCriterion::Force, &tight())
            .unwrap()
            .restitution
    };
    for f in [0.1, 0.5, 0.99] {
        let e = e_of(f * vy);
        assert!((e - 1.0).abs() < 1e-6, "v = {f} V_y: e = {e}");
    }
    for f in [1.5, 10.0, 100.0, 1000.0] {
        let e = e_of(f * vy);
        let want = dashpot_thornton::restitution(1.0 / f);
        assert!((e / want - 1.0).abs() < 1e-6, "v = {f} V_y: e = {e} vs {want}");
    }
    // far above yield e ∝ v^{-1/4}: the local exponent at 1000 V_y, from the integrator
    let h = 0.02;
    let slope = (e_of(1000.0 * vy * (1.0 + h)).ln() - e_of(1000.0 * vy * (1.0 - h)).ln())
        / ((1.0 + h).ln() - (1.0 - h).ln());
    assert!((slope + 0.25).abs() < 1e-3, "d ln e / d ln v = {slope}");
}

/// Alumina (Chung & Ooi 2011, test 4; Kharaz et al. 2001): d = 5.1 mm... here R = 2.55 mm.
fn alumina() -> Particle {
    Particle {
        diameter: 0.0051,
        density: 4000.0,
        young: 3.8e11,
        poisson: 0.23,
    }
}

struct Oblique {
    e: f64,
    dvt: f64,
    omega: f64,
    vn: f64,
    vcp_out: f64,
    vcp_in: f64,
}

fn oblique_impact(p: &Particle, wall: bool, eps: f64, mu: f64, v0: f64, angle_deg: f64) -> Oblique {
    let reg = full_registry();
    let mat = if wall {
        MaterialPair::wall(p).unwrap()
    } else {
        MaterialPair::spheres(p, p).unwrap()
    };
    let normal = reg
        .contact("hsd", &[ParamValue::new("eps", eps)])
        .unwrap()
        .bind(&mat)
        .unwrap();
    let tangential = reg
        .tangential("mindlin", &[ParamValue::new("mu", mu)])
        .unwrap()
        .bind(&mat)
        .unwrap();
    let body = Body::solid_sphere(p.mass(), p.radius());
    let target = if wall { Target::Wall } else { Target::Sphere(body) };
    let impact = Impact {
        speed: v0,
        angle: angle_deg.to_radians(),
        spin: 0.0,
        end: EndCriterion::Force,
        steps: 20_000,
    };
    let c = oblique(&normal, Some(&tangential), &body, &target, &impact).unwrap();
    Oblique {
        e: c.restitution,
        dvt: c.tangential_velocity_in - c.tangential_velocity_out,
        omega: c.angular_velocity_out,
        vn: c.normal_velocity_in,
        vcp_out: c.contact_point_velocity_out,
        vcp_in: c.tangential_velocity_in,
    }
}

#[test]
fn gross_sliding_obeys_coulombs_closed_form() {
    let p = alumina();
    let (mu, r) = (0.092, p.radius());
    for (wall, angle) in [(true, 80.0), (true, 70.0), (false, 80.0)] {
        let o = oblique_impact(&p, wall, 0.8, mu, 3.9, angle);
        let tan = angle.to_radians().tan();
        assert!(tan > 3.5 * mu * (1.0 + o.e), "not in gross sliding: {tan}");
        // the tangential impulse is μ times the normal one, m_eff μ (1 + e) v_n: relative
        // velocity changes by μ(1+e)v_n, the particle's spin by m_eff μ(1+e)v_n R / I
        let m_eff = if wall { 1.0 } else { 0.5 };
        let want_dv = mu * (1.0 + o.e) * o.vn;
        let want_w = m_eff * 2.5 * mu * (1.0 + o.e) * o.vn / r;
        assert_rel(o.dvt, want_dv, 1e-3, &format!("{wall} {angle}: Δv_t"));
        assert_rel(o.omega, want_w, 1e-3, &format!("{wall} {angle}: ω"));
    }
}

/// Maw, Barber & Fawcett's normalisation (the one Chung & Ooi's benchmark plots use): with
/// scaled contact-point velocities Ψ = 2(1 − ν)/(μ(2 − ν)) · v_t,cp / v_n, the rebound Ψ2 of an
/// elastic Hertz–Mindlin impact is one function of the incidence Ψ1, whatever μ, E, R and the
/// speed (for one ν): two very different impacts at one Ψ1, one in the sticking regime, must
/// give one Ψ2; and in gross sliding Ψ2 = Ψ1 − 2(1 − ν)/(2 − ν) · 3.5 (1 + e) exactly.
#[test]
fn the_sticking_regime_collapses_in_maws_variables() {
    let a = alumina();
    let b = Particle {
        diameter: 0.02,
        density: 2700.0,
        young: 7.0e10,
        poisson: 0.23, // the collapse holds at fixed ν
    };
    let psi = |p: &Particle, mu: f64, o: &Oblique| {
        let f = 2.0 * (1.0 - p.poisson) / (mu * (2.0 - p.poisson));
        (f * o.vcp_in / o.vn, f * o.vcp_out / o.vn)
    };
    let chi = 2.0 * (1.0 - a.poisson) / (2.0 - a.poisson) * 3.5;
    for psi1 in [0.5, 1.5, 3.0, 6.0] {
        let mut got = Vec::new();
        for (p, mu, v0) in [(&a, 0.092, 3.9), (&b, 0.4, 0.7)] {
            let f = 2.0 * (1.0 - p.poisson) / (mu * (2.0 - p.poisson));
            let angle = (psi1 / f).atan().to_degrees();
            let o = oblique_impact(p, true, 1.0, mu, v0, angle);
            let (p1, p2) = psi(p, mu, &o);
            assert!((p1 - psi1).abs() < 1e-9);
            got.push(p2);
        }
        assert!(
            (got[0] - got[1]).abs() < 2e-3 * (1.0 + got[0].abs()),
            "Ψ1 = {psi1}: {got:?}"
        );
        if psi1 > 2.0 * chi {
            assert!(
                (got[0] - (psi1 - 2.0 * chi)).abs() < 2e-3 * psi1,
                "sliding: Ψ2 = {}",
                got[0]
            );
        }
    }
}
