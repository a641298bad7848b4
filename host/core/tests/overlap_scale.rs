//! The collision driver's overlap-scale search asks a law only about overlaps the collision
//! comes near (issue 10): never more than twice the scale δ* where F·δ* = m v0², and δ* is at
//! most twice the collision's maximum overlap for these power laws.

use dashpot_core::collide::two_body::{overlap_scale, PROBE_START};
use dashpot_core::collide::{collide, ContactForce, Options};
use dashpot_sdk::{EndCriterion, LawError};
use std::sync::Mutex;

/// F = k δ^p + c δ̇, recording the largest overlap it was asked about.
struct PowerLaw {
    k: f64,
    p: f64,
    c: f64,
    largest: Mutex<f64>,
}

impl ContactForce for PowerLaw {
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        let mut l = self.largest.lock().unwrap();
        *l = l.max(delta);
        Ok(self.k * delta.max(0.0).powf(self.p) + self.c * rate)
    }
}

#[test]
fn the_search_never_goes_past_twice_the_scale() {
    let m = 3.9e-4;
    for (k, p) in [(1e6, 1.0), (1e9, 1.5), (1e3, 0.5), (1e12, 3.0), (5.0, 0.0)] {
        for v0 in [1e-3, 1.0, 30.0] {
            let law = PowerLaw {
                k,
                p,
                c: 0.0,
                largest: Mutex::new(0.0),
            };
            let d = overlap_scale(&law, m, v0).unwrap();
            let largest = *law.largest.lock().unwrap();
            // the scale is right: F(δ*)·δ* = m v0², to round-off for a power law (the search
            // interpolates the crossing as one)
            let w = k * d.powf(p) * d;
            assert!(
                (w / (m * v0 * v0) - 1.0).abs() <= 1e-9,
                "k = {k}, p = {p}, v0 = {v0}: F·δ* = {w}"
            );
            assert!(
                largest < 2.0 * d,
                "k = {k}, p = {p}, v0 = {v0}: probed {largest} m, scale {d} m"
            );
            assert!(d > PROBE_START);
            // and the whole collision stays near it: δ_max ≥ δ*/2
            *law.largest.lock().unwrap() = 0.0;
            let c = collide(&law, m, v0, EndCriterion::Overlap, &Options::default()).unwrap();
            let largest = *law.largest.lock().unwrap();
            assert!(
                largest <= 2.0 * c.max_overlap.max(d),
                "k = {k}, p = {p}, v0 = {v0}: probed {largest} m, δ_max = {} m",
                c.max_overlap
            );
            // ∫F dδ = m v0²/2 at δ_max, so δ* ≤ 2 δ_max for a non-decreasing force (equality for
            // a constant one)
            assert!(
                d <= 2.0 * (1.0 + 1e-9) * c.max_overlap,
                "δ* = {d} m, δ_max = {} m",
                c.max_overlap
            );
        }
    }
}

#[test]
fn the_scale_of_a_spring_and_dashpot_is_within_a_few_per_cent() {
    // F = k δ^{3/2} + c δ̇: the work F(δ, v0)·δ goes from the dashpot's δ¹ to the spring's δ^{5/2}
    let m = 3.9e-4;
    for c in [1e-3, 1.0, 30.0] {
        for v0 in [1e-3, 1.0, 30.0] {
            let law = PowerLaw {
                k: 1e9,
                p: 1.5,
                c,
                largest: Mutex::new(0.0),
            };
            let d = overlap_scale(&law, m, v0).unwrap();
            let w = (1e9 * d.powf(1.5) + c * v0) * d;
            assert!(
                (w / (m * v0 * v0) - 1.0).abs() <= 0.03,
                "c = {c}, v0 = {v0}: F·δ* = {w}, m v0² = {}",
                m * v0 * v0
            );
            assert!(*law.largest.lock().unwrap() < 2.0 * d);
        }
    }
}
