//! Restitution curves: `collide_many` runs the collisions of one law at many impact speeds in
//! lockstep, their states evaluated together; each result must be the one `collide` returns for
//! that speed alone, bit for bit, errors included, for every contact law of the workspace.

use dashpot::collide::outcome::Method;
use dashpot::collide::{collide, collide_many, CollideError, Collision, ContactForce, Options};
use dashpot_sdk::{EndCriterion, ErrorKind, LawError, Pair, ParamValue, Particle};
use dashpot_tests::{pair_law, registry_03};

/// 23 impact speeds log-spaced over [1e-3, 10] m/s: more than the collisions run in lockstep at
/// once, so coroutines are reused.
fn speeds() -> Vec<f64> {
    (0..23)
        .map(|i| 10f64.powf(-3.0 + 4.0 * i as f64 / 22.0))
        .collect()
}

/// Every observable of `a` and `b` the same bits (or the same error message).
fn assert_same(a: &Result<Collision, CollideError>, b: &Result<Collision, CollideError>, what: &str) {
    match (a, b) {
        (Ok(a), Ok(b)) => {
            let bits = |c: &Collision| {
                (
                    c.v0.to_bits(),
                    c.restitution.to_bits(),
                    c.contact_time.to_bits(),
                    c.max_overlap.to_bits(),
                    c.max_overlap_time.to_bits(),
                    c.steps,
                    c.force_evals,
                    c.stuck,
                    c.tensile_peak.map(f64::to_bits),
                )
            };
            assert_eq!(bits(a), bits(b), "{what}: {a:?} against {b:?}");
        }
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{what}"),
        _ => panic!("{what}: {a:?} against {b:?}"),
    }
}

fn check_curve<C: ContactForce>(law: &C, mass: f64, end: EndCriterion, opt: &Options, what: &str) {
    let v0s = speeds();
    let many = collide_many(law, mass, &v0s, end, opt);
    assert_eq!(many.len(), v0s.len());
    for (m, &v0) in many.iter().zip(&v0s) {
        let one = collide(law, mass, v0, end, opt);
        assert_same(m, &one, &format!("{what}, v0 = {v0} m/s"));
    }
}

#[test]
fn a_curve_is_its_collisions_one_by_one_for_every_contact_law() {
    let reg = registry_03();
    let p = Particle::MCC;
    let pair = Pair::spheres(&p, &p).unwrap();
    let opt = Options {
        rtol: 1e-9,
        ..Options::default()
    };
    let laws: [(&str, Vec<ParamValue>); 7] = [
        ("hsd", vec![ParamValue::new("eps", 0.3)]),
        ("lsd", vec![ParamValue::new("eps", 0.7)]),
        ("kuwabara-kono", vec![ParamValue::new("A", 2e-6)]),
        ("thornton", vec![]),
        ("walton-braun", vec![]),
        (
            "jkr",
            vec![ParamValue::new("w", 0.5), ParamValue::new("eps", 0.8)],
        ),
        (
            "dmt",
            vec![ParamValue::new("w", 0.5), ParamValue::new("eps", 0.8)],
        ),
    ];
    for (name, params) in &laws {
        let law = pair_law(&reg, name, params, &pair);
        for end in [EndCriterion::Overlap, EndCriterion::Force] {
            check_curve(&law, pair.mass, end, &opt, &format!("{name}, end {end:?}"));
        }
    }
    // the Runge–Kutta method too (its steps are not taken in lockstep, its force calls are)
    let law = pair_law(&reg, "hsd", &[ParamValue::new("eps", 0.3)], &pair);
    let dp = Options {
        rtol: 1e-7,
        method: Method::DormandPrince5,
        ..Options::default()
    };
    check_curve(&law, pair.mass, EndCriterion::Overlap, &dp, "hsd, Dormand–Prince");
}

/// A linear spring-dashpot F = k δ + c δ̇ (N) that fails beyond the overlap `limit` (m): the
/// faster impacts of a curve fail, while it is integrated or while its scale is sought.
struct Breaks {
    k: f64,
    c: f64,
    limit: f64,
}

impl ContactForce for Breaks {
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        if delta > self.limit {
            return Err(LawError::new(
                ErrorKind::Other,
                format!("overlap {delta:e} m beyond the test's limit {:e} m", self.limit),
            ));
        }
        Ok(self.k * delta + self.c * rate)
    }
}

#[test]
fn a_failing_collision_fails_alone_and_as_alone() {
    let law = Breaks {
        k: 1e5,
        c: 2.0,
        limit: 2e-4,
    };
    let (mass, opt) = (1e-3, Options::default());
    let v0s = speeds();
    let many = collide_many(&law, mass, &v0s, EndCriterion::Overlap, &opt);
    let failed = many.iter().filter(|r| r.is_err()).count();
    assert!(
        failed > 0 && failed < v0s.len(),
        "{failed} of {} failed",
        v0s.len()
    );
    for (m, &v0) in many.iter().zip(&v0s) {
        let one = collide(&law, mass, v0, EndCriterion::Overlap, &opt);
        assert_same(m, &one, &format!("v0 = {v0} m/s"));
    }
}

/// Through the plugins, the physics of a curve: HSD and LSD realize their ε at every speed
/// (Antypov & Elliott: ε does not depend on v0 for either), and LSD's contact time is
/// π/√(k/m − γ²) with γ from eq. 8.
#[test]
fn hsd_and_lsd_curves_are_flat_at_their_epsilon() {
    let reg = registry_03();
    let p = Particle::MCC;
    let pair = Pair::spheres(&p, &p).unwrap();
    let opt = Options {
        rtol: 1e-10,
        ..Options::default()
    };
    let v0s = speeds();
    for (name, eps) in [("hsd", 0.2), ("lsd", 0.6)] {
        let law = pair_law(&reg, name, &[ParamValue::new("eps", eps)], &pair);
        let curve = collide_many(&law, pair.mass, &v0s, EndCriterion::Overlap, &opt);
        for (c, v0) in curve.iter().zip(&v0s) {
            let c = c.as_ref().unwrap();
            assert!(
                (c.restitution - eps).abs() < 1e-8,
                "{name} at {v0} m/s: ε = {}",
                c.restitution
            );
        }
        if name == "lsd" {
            let k = 2.0 / 3.0 * p.young / (2.0 * (1.0 - p.poisson * p.poisson)) * p.diameter;
            let w0 = (k / pair.mass).sqrt();
            let l = eps.ln();
            let gamma = -w0 * l / (std::f64::consts::PI.powi(2) + l * l).sqrt();
            let tc = std::f64::consts::PI / (w0 * w0 - gamma * gamma).sqrt();
            for c in &curve {
                let c = c.as_ref().unwrap();
                assert!(
                    (c.contact_time / tc - 1.0).abs() < 1e-8,
                    "{} against {tc}",
                    c.contact_time
                );
            }
        }
    }
}
