//! Walton–Braun bilinear hysteretic normal contact (Walton & Braun, J. Rheol. 30, 949, 1986).
//!
//! With δ (m) the overlap and δ_max (m) the largest overlap this contact has reached
//! (per-contact history, slot `delta_max`):
//!
//! - loading, δ ≥ δ_max: F = k1 δ;
//! - unloading and reloading, δ < δ_max: F = k2 (δ − δ_p) for δ > δ_p, 0 below, with the
//!   residual overlap δ_p = δ_max (1 − k1/k2) (m), so that both lines meet at (δ_max, k1 δ_max).
//!   Reloading runs up the unloading line until it meets the loading line at δ_max, then
//!   continues along the loading line (and δ_max grows).
//!
//! The force is never attractive and has no rate dependence. A collision of effective mass m
//! that ends when the force returns to 0 (at δ = δ_p > 0, [`EndCriterion::Force`]) has
//! restitution e = √(k1/k2) at every impact speed, and lasts t_c = (π/2)(√(m/k1) + √(m/k2)).
//!
//! Parameters: `k1` (N/m, > 0, default 1e5) the loading stiffness; `k2` (N/m, ≥ k1, default
//! 1.5e5) the unloading stiffness. The defaults are illustrative, not material values. The law
//! ignores the materials, the effective radius and the rate; the mass only enters
//! [`BoundContact::coefficients`].
//!
//! History: one slot, `delta_max` (m), zero at first touch. Each call uses
//! δ_max = max(`history[0]`, δ) and writes it back: the force is a pure function of the contact
//! and the history passed in, so a trial evaluation on a scratch copy is safe. The law never
//! forgets a plastic dent while the caller keeps the history (δ ≤ 0 leaves it unchanged); the
//! caller drops it when the contact ends.

#![warn(missing_docs)]

use dashpot_sdk::{
    BoundContact, Coefficient, Contact, ContactLaw, EndCriterion, Energy, History, LawError, MaterialPair,
    Range,
};
use std::f64::consts::FRAC_PI_2;

dashpot_sdk::law_params! {
    /// The configured law (also its binding: it does not depend on the materials).
    #[derive(Debug, Clone, PartialEq)]
    pub struct WaltonBraun {
        /// loading stiffness; the default is illustrative
        pub k1: f64 { unit: "N/m", default: 1.0e5, range: Range::positive() },
        /// unloading stiffness, must be ≥ k1; restitution is √(k1/k2)
        pub k2: f64 { unit: "N/m", default: 1.5e5, range: Range::positive() },
    }
}

impl WaltonBraun {
    /// The law with loading stiffness `k1` > 0 and unloading stiffness `k2` ≥ `k1` (N/m); an
    /// error naming both values otherwise.
    pub fn with(k1: f64, k2: f64) -> Result<WaltonBraun, LawError> {
        let law = WaltonBraun { k1, k2 };
        law.check()?;
        Ok(law)
    }

    /// The restitution √(k1/k2) under the force criterion, at every impact speed.
    pub fn restitution(&self) -> f64 {
        (self.k1 / self.k2).sqrt()
    }
}

impl ContactLaw for WaltonBraun {
    type Bound = WaltonBraun;
    const NAME: &'static str = "walton-braun";
    const SUMMARY: &'static str =
        "bilinear hysteretic: load k1 δ, unload k2 (δ − δ_p), restitution √(k1/k2) at every speed";
    const DOC: &'static str = "Walton–Braun bilinear normal force (Walton & Braun, J. Rheol. 30, 949, \
        1986). Loading (δ ≥ δ_max): F = k1 δ. Unloading and reloading (δ < δ_max): \
        F = k2 (δ − δ_p) above the residual overlap δ_p = δ_max (1 − k1/k2), 0 below (never \
        attractive); reloading follows the unloading line up to δ_max, then the loading line. \
        Parameters: k1 (N/m, > 0) loading stiffness, k2 (N/m, ≥ k1) unloading stiffness; defaults \
        are illustrative. History: 1 slot, delta_max (m), the largest overlap of the contact \
        (updated to max(delta_max, δ) at each call; δ ≤ 0 leaves it unchanged, the caller drops it \
        when the contact ends). No rate dependence, no use of the materials or the radius. With \
        contact ending when the force returns to 0 (at δ_p > 0), restitution is √(k1/k2) at every \
        impact speed and the contact lasts (π/2)(√(m/k1) + √(m/k2)), m the effective mass.";
    const END_CRITERION: EndCriterion = EndCriterion::Force;
    const HISTORY: &'static [History] = &[History::new(
        "delta_max",
        "m",
        "largest overlap reached by this contact (0 at first touch)",
    )];

    /// k1 and k2 finite and > 0 (also for a law made by [`WaltonBraun::with`]), and k2 ≥ k1.
    fn check(&self) -> Result<(), LawError> {
        let (k1, k2) = (self.k1, self.k2);
        if !(k1.is_finite() && k1 > 0.0 && k2.is_finite() && k2 > 0.0) {
            return Err(LawError::invalid_parameter(format!(
                "walton-braun: k1 = {k1} N/m and k2 = {k2} N/m must both be finite and > 0"
            )));
        }
        if k2 < k1 {
            return Err(LawError::invalid_parameter(format!(
                "walton-braun: the unloading stiffness k2 = {k2} N/m is smaller than the loading \
                 stiffness k1 = {k1} N/m; k2 must be ≥ k1 (restitution √(k1/k2) ≤ 1)"
            )));
        }
        Ok(())
    }

    fn bind(&self, _materials: &MaterialPair) -> Result<WaltonBraun, LawError> {
        Ok(self.clone())
    }
}

impl BoundContact for WaltonBraun {
    #[inline(always)]
    fn force(&self, c: Contact, history: &mut [f64]) -> f64 {
        let d = c.delta;
        let dmax = history[0].max(d);
        history[0] = dmax;
        if d <= 0.0 {
            0.0
        } else if d >= dmax {
            self.k1 * d
        } else {
            // k2 (δ − δ_p) with δ_p = δ_max (1 − k1/k2), written so that F(δ_max) = k1 δ_max.
            (self.k1 * dmax - self.k2 * (dmax - d)).max(0.0)
        }
    }

    /// Elastic F²/(2 k2) (J): what unloading along k2 gives back; power (W): on the loading
    /// branch (δ = δ_max, δ̇ > 0) the plastic work rate F δ̇ − d/dt(F²/(2 k2)) = k1 δ δ̇ (1 − k1/k2),
    /// 0 on unloading.
    fn energy(&self, c: &Contact, history: &[f64], force: f64) -> Option<Energy> {
        let loading = c.delta > 0.0 && c.delta >= history[0] && c.rate > 0.0;
        Some(Energy {
            power: if loading {
                (self.k1 * c.delta * c.rate * (1.0 - self.k1 / self.k2)).max(0.0)
            } else {
                0.0
            },
            elastic: force * force / (2.0 * self.k2),
        })
    }

    fn coefficients(&self, mass: f64, _radius: f64) -> Vec<Coefficient> {
        vec![
            Coefficient::new("k1", "N/m", self.k1, "loading stiffness"),
            Coefficient::new("k2", "N/m", self.k2, "unloading stiffness"),
            Coefficient::new(
                "e",
                "1",
                self.restitution(),
                "restitution √(k1/k2) (contact ends when F returns to 0)",
            ),
            Coefficient::new(
                "t_c",
                "s",
                FRAC_PI_2 * ((mass / self.k1).sqrt() + (mass / self.k2).sqrt()),
                "contact time (π/2)(√(m/k1) + √(m/k2)) (contact ends when F returns to 0)",
            ),
            Coefficient::new(
                "delta_p_ratio",
                "1",
                1.0 - self.k1 / self.k2,
                "residual overlap per unit largest overlap, δ_p/δ_max = 1 − k1/k2",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [WaltonBraun]);

#[cfg(test)]
mod tests {
    use super::*;
    use dashpot_sdk::ParamValue;

    fn law(k1: f64, k2: f64) -> WaltonBraun {
        WaltonBraun::from_values(&[ParamValue::new("k1", k1), ParamValue::new("k2", k2)])
            .unwrap()
            .bind(&MaterialPair::new(1e9, 1e9).unwrap())
            .unwrap()
    }

    fn c(delta: f64) -> Contact {
        Contact {
            delta,
            rate: 0.0,
            mass: 1.0,
            radius: 1.0,
        }
    }

    /// Velocity Verlet on the overlap, history kept at every (accepted) step; the contact ends
    /// when the force returns to 0 on rebound. Returns the rebound speed over the impact speed.
    fn restitution(b: &WaltonBraun, m: f64, v0: f64, dt: f64) -> f64 {
        dashpot_testkit::verlet_rebound(b, m, 1.0, v0, dt, &mut [0.0])
    }

    #[test]
    fn restitution_is_sqrt_k1_over_k2_at_every_speed() {
        let (k1, k2, m) = (1.0e5, 3.0e5, 0.01);
        let b = law(k1, k2);
        let dt = 1e-3 / (k2 / m).sqrt();
        let want = (k1 / k2).sqrt();
        for v0 in [0.01, 1.0, 100.0] {
            let e = restitution(&b, m, v0, dt);
            println!("v0 = {v0} m/s: e = {e:.9}, √(k1/k2) = {want:.9}");
            assert!((e - want).abs() < 1e-5, "v0 = {v0}: e = {e}, want {want}");
        }
        assert_eq!(b.coefficients(m, 1.0)[2].value, want);
    }

    #[test]
    fn equal_stiffnesses_are_elastic() {
        let b = law(2.0e5, 2.0e5);
        let e = restitution(&b, 0.01, 1.0, 1e-3 / (2.0e5f64 / 0.01).sqrt());
        assert!((e - 1.0).abs() < 1e-5, "e = {e}");
    }

    #[test]
    fn k2_below_k1_is_refused_naming_both() {
        let e = WaltonBraun::from_values(&[ParamValue::new("k1", 2.0e5), ParamValue::new("k2", 1.0e5)])
            .unwrap_err();
        assert_eq!(e.kind, dashpot_sdk::ErrorKind::InvalidParameter);
        assert!(
            e.message.contains("k1 = 200000") && e.message.contains("k2 = 100000"),
            "{}",
            e.message
        );
        // The defaults are valid.
        assert!(WaltonBraun::from_values(&[]).is_ok());
    }

    #[test]
    fn unloading_reloading_and_history() {
        let (k1, k2) = (1.0e5, 4.0e5);
        let b = law(k1, k2);
        let mut h = [0.0];
        // Loading.
        assert_eq!(b.force(c(1e-3), &mut h), k1 * 1e-3);
        assert_eq!(h[0], 1e-3);
        let dp = 1e-3 * (1.0 - k1 / k2);
        // Unloading line, continuous at δ_max, zero at δ_p and below, history kept.
        let f = b.force(c(0.9e-3), &mut h);
        assert!((f - k2 * (0.9e-3 - dp)).abs() < 1e-9 * k1 * 1e-3);
        assert_eq!(h[0], 1e-3);
        assert!(b.force(c(dp), &mut h).abs() < 1e-12);
        assert_eq!(b.force(c(0.5 * dp), &mut h), 0.0);
        assert_eq!(b.force(c(-1e-6), &mut h), 0.0);
        assert_eq!(h[0], 1e-3, "δ ≤ 0 leaves the dent");
        // Reloading runs up the unloading line ...
        let f = b.force(c(0.95e-3), &mut h);
        assert!((f - k2 * (0.95e-3 - dp)).abs() < 1e-9 * k1 * 1e-3);
        // ... then the loading line.
        assert_eq!(b.force(c(1.2e-3), &mut h), k1 * 1.2e-3);
        assert_eq!(h[0], 1.2e-3);
        // A trial on a scratch copy leaves the kept history alone.
        let mut scratch = h;
        b.force(c(2e-3), &mut scratch);
        assert_eq!((h[0], scratch[0]), (1.2e-3, 2e-3));
    }
}
