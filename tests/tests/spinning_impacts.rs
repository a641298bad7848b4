//! A spinning sphere dropped onto a rigid wall: the friction laws never give its tangential and
//! rotational motion more energy than it came with.
//!
//! An Al-alloy sphere (R = 0.1 m, E = 70 GPa, ν = 0.33, ρ = 2700 kg/m³) falls head-on onto a
//! wall at 0.2 m/s under HSD (ε = 0.5), spinning so that its contact point moves at 0.0175 to
//! 4.8 m/s, with `mindlin` (μ = 0.4) or `linear-history` friction of damping ratio 0 to 5. The
//! normal force does no work on the tangential and rotational motion, so its energy
//! ½ m v_t² + ½ I ω² after the impact can only be at most what it was before: LAMMPS's reset of a
//! damped spring (ξ = −(F + η v)/k), which dashpot's own laws used to take, breaks this: the
//! `mindlin` law of sdk 0.4's first release leaves it 1.017× higher at damping 2 and a contact
//! point at 0.0175 m/s.

use dashpot::collide::{oblique, Body, Impact, PairLaw, Target};
use dashpot_sdk::{EndCriterion, Pair, ParamValue, Particle};
use dashpot_tests::registry_03;

#[test]
fn a_spinning_sphere_hitting_a_wall_leaves_with_at_most_its_tangential_and_rotational_energy() {
    let reg = registry_03();
    let sphere = Particle {
        diameter: 0.2,
        density: 2700.0,
        young: 70e9,
        poisson: 0.33,
    };
    let pair = Pair::wall(&sphere).unwrap();
    let materials = pair.materials(sphere.poisson).unwrap();
    let normal = reg
        .contact("hsd", &[ParamValue::new("eps", 0.5)])
        .unwrap()
        .bind(&materials)
        .unwrap();
    let body = Body::solid_sphere(sphere.mass(), sphere.radius());
    let (speed, r) = (0.2, sphere.radius());
    let mut cases = 0;
    for (law, mu, stiffness) in [("mindlin", 0.4, None), ("linear-history", 0.4, Some(1e8))] {
        for damping in [0.0, 0.5, 1.0, 2.0, 3.0, 5.0] {
            let mut params = vec![ParamValue::new("mu", mu), ParamValue::new("damping", damping)];
            if let Some(kt) = stiffness {
                params.push(ParamValue::new("kt", kt));
            }
            let friction = reg.tangential(law, &params).unwrap().bind(&materials).unwrap();
            for point in [0.0175, 0.05, 0.15, 0.4, 1.2, 4.8] {
                for sign in [1.0, -1.0] {
                    let impact = Impact {
                        speed,
                        angle: 0.0,
                        spin: sign * point / r,
                        end: EndCriterion::Overlap,
                        steps: 2000,
                    };
                    let o = oblique(&normal, Some(&friction), &body, &Target::Wall, &impact)
                        .unwrap_or_else(|e| panic!("{law}, damping {damping}, {point} m/s: {e}"));
                    let energy = |v: f64, w: f64| 0.5 * body.mass * v * v + 0.5 * body.inertia * w * w;
                    let before = energy(o.tangential_velocity_in, impact.spin);
                    let after = energy(o.tangential_velocity_out, o.angular_velocity_out);
                    assert!(
                        after <= before * (1.0 + 1e-12),
                        "{law}, damping {damping}, contact point at {point} m/s: the tangential and \
                         rotational energy rose from {before:e} J to {after:e} J ({:.3}×)",
                        after / before
                    );
                    // the contact point moves against the friction: some energy is taken
                    assert!(
                        after < before,
                        "{law}, damping {damping}, {point} m/s: nothing taken"
                    );
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 2 * 6 * 6 * 2);
    // (the normal law of the pair: its restitution as HSD's, so the sweep is the impact)
    let head_on = dashpot::collide::collide(
        &PairLaw::bind(
            &reg.contact("hsd", &[ParamValue::new("eps", 0.5)]).unwrap(),
            &pair,
            sphere.poisson,
        )
        .unwrap(),
        pair.mass,
        speed,
        EndCriterion::Overlap,
        &Default::default(),
    )
    .unwrap();
    assert!(
        (head_on.restitution - 0.5).abs() < 1e-3,
        "e = {}",
        head_on.restitution
    );
}
