//! The heat two spheres exchange over one impact (`dashpot collide --heat`, sdk 0.4), through
//! the real plugins: what one gains the other loses (C₁ΔT₁ + C₂ΔT₂ = 0 to rounding); swapping
//! the two temperatures negates the heat to the bit (Q₁₂ = −Q₂₁); with capacities so large the
//! temperatures barely move, the heat is ΔT ∫ H dt; and for an elastic Hertz impact
//! conducting through `heat-radius` (H = 2 k √(R δ)), ∫ H dt is the closed form
//! 2 k √R (4/5) B(3/5, 1/2) δ_m^{3/2}/v0, δ_m = (15 m v0²/(16 E √R))^{2/5}.

use dashpot::collide::heat::{impact_heat, HeatImpact};
use dashpot::collide::oblique::{Body, Target};
use dashpot_sdk::{EndCriterion, MaterialPair, ParamValue, Particle};
use dashpot_tests::registry_04;

const R: f64 = 1e-3;
const K: f64 = 40.0;

fn particle() -> Particle {
    Particle {
        diameter: 2.0 * R,
        density: 7800.0,
        young: 2.0e11,
        poisson: 0.3,
    }
}

/// Sphere on an equal sphere: `hsd` at `eps` and `heat-radius` (k = [`K`]), temperatures `t`
/// and capacities `c`.
fn impact(eps: f64, v0: f64, t: [f64; 2], c: [f64; 2]) -> dashpot::collide::heat::HeatExchange {
    let reg = registry_04();
    let p = particle();
    let mp = MaterialPair::spheres(&p, &p).unwrap();
    let normal = reg
        .contact("hsd", &[ParamValue::new("eps", eps)])
        .unwrap()
        .bind(&mp)
        .unwrap();
    let heat = reg
        .heat("heat-radius", &[ParamValue::new("k", K)])
        .unwrap()
        .bind(&mp)
        .unwrap();
    let body = Body::solid_sphere(p.mass(), R);
    let imp = HeatImpact {
        speed: v0,
        end: EndCriterion::Overlap,
        steps: 20_000,
        temperature: t,
        capacity: c,
    };
    impact_heat(&normal, &heat, &body, &Target::Sphere(body), &imp).unwrap()
}

fn capacity() -> f64 {
    particle().mass() * 500.0
}

#[test]
fn what_one_sphere_gains_the_other_loses_and_swapping_negates_it() {
    let c = capacity();
    for (eps, v0) in [(1.0, 0.5), (0.6, 2.0)] {
        let x = impact(eps, v0, [300.0, 400.0], [c, c]);
        assert!(x.heat > 0.0, "heat flows into the colder sphere ({})", x.heat);
        let (d1, d2) = (x.temperature[0] - 300.0, x.temperature[1] - 400.0);
        // to the rounding of the temperatures' steps: ε T per step
        let tol = c * x.steps as f64 * 400.0 * f64::EPSILON;
        assert!(
            (c * d1 + c * d2).abs() <= tol,
            "C₁ΔT₁ + C₂ΔT₂ = {} (heat {})",
            c * d1 + c * d2,
            x.heat
        );
        assert!(
            (c * d1 - x.heat).abs() <= tol,
            "the heat {} is C₁ΔT₁ = {}",
            x.heat,
            c * d1
        );
        assert!(x.heat > 1e3 * tol, "a heat well above the rounding");
        // the restitution is the law's: ε
        assert!(
            (x.restitution - eps).abs() < 2e-3,
            "restitution {}",
            x.restitution
        );
        let y = impact(eps, v0, [400.0, 300.0], [c, c]);
        assert_eq!(y.heat.to_bits(), (-x.heat).to_bits(), "Q₁₂ = −Q₂₁");
        assert_eq!(y.temperature[0].to_bits(), x.temperature[1].to_bits());
        assert_eq!(y.conductance_time.to_bits(), x.conductance_time.to_bits());
    }
}

#[test]
fn an_elastic_hertz_impact_conducts_the_closed_form_integral() {
    let v0 = 0.5;
    let p = particle();
    let mp = MaterialPair::spheres(&p, &p).unwrap();
    let (m, r) = (0.5 * p.mass(), 0.5 * R);
    // capacities so large that ΔT stays what it was: the heat is ΔT ∫ H dt
    let big = 1e12;
    let x = impact(1.0, v0, [300.0, 400.0], [big, big]);
    assert!((x.heat - 100.0 * x.conductance_time).abs() <= 1e-9 * x.heat);
    let dm = (15.0 * m * v0 * v0 / (16.0 * mp.young * r.sqrt())).powf(0.4);
    // B(3/5, 1/2) = Γ(3/5) Γ(1/2) / Γ(11/10)
    let beta = 1.489_192_248_812_817 * std::f64::consts::PI.sqrt() / 0.951_350_769_866_873;
    let want = 2.0 * K * r.sqrt() * 0.8 * beta * dm.powf(1.5) / v0;
    assert!(
        (x.conductance_time / want - 1.0).abs() < 1e-5,
        "∫ H dt = {} vs {want}",
        x.conductance_time
    );
    // a harder impact: ∫ H dt ∝ δ_m^{3/2}/v0 ∝ v0^{1/5} (δ_m ∝ v0^{4/5})
    let y = impact(1.0, 4.0 * v0, [300.0, 400.0], [big, big]);
    assert!((y.conductance_time / x.conductance_time / 4f64.powf(0.2) - 1.0).abs() < 1e-5);
}

#[test]
fn bad_input_is_refused_naming_it() {
    let reg = registry_04();
    let p = particle();
    let mp = MaterialPair::spheres(&p, &p).unwrap();
    let normal = reg.contact("hsd", &[]).unwrap().bind(&mp).unwrap();
    let heat = reg
        .heat("heat-area", &[ParamValue::new("h", 1e6)])
        .unwrap()
        .bind(&mp)
        .unwrap();
    let body = Body::solid_sphere(p.mass(), R);
    let ok = HeatImpact {
        speed: 1.0,
        end: EndCriterion::Overlap,
        steps: 1000,
        temperature: [300.0, 300.0],
        capacity: [1.0, 1.0],
    };
    for (imp, want) in [
        (
            HeatImpact {
                temperature: [f64::NAN, 300.0],
                ..ok
            },
            "temperature 1 = NaN K",
        ),
        (
            HeatImpact {
                capacity: [1.0, -2.0],
                ..ok
            },
            "heat capacity 2 = -2 J/K",
        ),
        (HeatImpact { steps: 10, ..ok }, "steps per contact = 10"),
        (HeatImpact { speed: 0.0, ..ok }, "impact speed = 0 m/s"),
    ] {
        let e = impact_heat(&normal, &heat, &body, &Target::Sphere(body), &imp).unwrap_err();
        assert!(e.to_string().contains(want), "{e}");
    }
    // against a wall the partner's capacity is not used, and its temperature stays
    let x = impact_heat(
        &normal,
        &heat,
        &body,
        &Target::Wall,
        &HeatImpact {
            temperature: [300.0, 500.0],
            capacity: [1e-3, f64::NAN],
            ..ok
        },
    )
    .unwrap();
    assert_eq!(x.temperature[1], 500.0);
    assert!(x.temperature[0] > 300.0 && x.heat > 0.0);
}
