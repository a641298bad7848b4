//! Thornton's elastic–perfectly plastic normal contact of spheres (C. Thornton, "Coefficient of
//! restitution for collinear collisions of elastic-perfectly plastic spheres", J. Appl. Mech. 64,
//! 383–386, 1997).
//!
//! Conventions: δ (m) the overlap, r (m) the effective radius r1 r2/(r1 + r2) (the particle's
//! radius against a flat wall), m (kg) the effective mass, E (Pa) the effective modulus
//! 1/E = (1 − ν1²)/E1 + (1 − ν2²)/E2 of the bound [`MaterialPair`], p_y (Pa) the limiting
//! contact pressure (parameter `py`, > 0, default 1e9, illustrative). With
//! K = (4/3) E √r and δ_max (m) the largest overlap this contact has reached:
//!
//! - **elastic loading**, δ ≤ δ_y: Hertz, F = K δ^{3/2}. The maximum contact pressure
//!   2 E a/(π r), a = √(r δ), reaches p_y at the yield overlap δ_y = (π p_y / (2 E))² r, where
//!   F_y = K δ_y^{3/2};
//! - **plastic loading**, δ = δ_max > δ_y: F = F_y + π p_y r (δ − δ_y) (its slope π p_y r equals
//!   the Hertz slope 2 E a_y at δ_y: force and stiffness are continuous);
//! - **unloading and reloading**, δ < δ_max: Hertzian with a larger radius R_p from
//!   (δ_max, F_max) down to the residual overlap δ_p, F = (4/3) E √R_p (δ − δ_p)^{3/2} for
//!   δ > δ_p and 0 below (no adhesion). Thornton's R_p = (4 E / (3 F_max)) ((2 F_max + F_y) /
//!   (2 π p_y))^{3/2} reduces, with F_max = F_y + π p_y r (δ_max − δ_y), to
//!   R_p = 4 E a_p³ / (3 F_max) with a_p = √(r δ_max): the unloading curve passes through F_max
//!   at δ_max with the elastic stiffness 2 E a_p of the contact radius reached. Then
//!   δ_max − δ_p = a_p²/R_p = 3 F_max / (4 E a_p), and F = F_max ((δ − δ_p)/(δ_max − δ_p))^{3/2}.
//!   Below yield (δ_max ≤ δ_y) unloading is the Hertz curve itself (R_p = r, δ_p = 0).
//!
//! No rate dependence and no viscous damping: all dissipation is plastic. With contact ending
//! when the force returns to 0 ([`EndCriterion::Force`], at δ = δ_p), the restitution of a
//! collision at normal impact speed v is 1 for v ≤ V_y and, above,
//! e = √(6√3/5) √(1 − x²/6) (x / (x + 2 √(6/5 − x²/5)))^{1/4}, x = V_y/v ([`restitution`]),
//! which falls as v^{−1/4} far above V_y. The yield speed follows from ½ m V_y² = ∫₀^{δ_y} K δ^{3/2}
//! dδ = (2/5) K δ_y^{5/2}: V_y = √(π⁵ p_y⁵ r³ / (30 E⁴ m)) ([`ThorntonBound::yield_speed`]; for a
//! sphere of density ρ on a wall, Thornton's 1.56 √(p_y⁵/(E⁴ρ))).
//!
//! History: one slot, `delta_max` (m), zero at first touch. Each call uses
//! δ_max = max(`history[0]`, δ) and writes it back: the force is a pure function of the contact
//! and the history passed in, so a trial evaluation on a scratch copy is safe. δ ≤ 0 leaves the
//! history unchanged (the dent stays while the caller keeps the contact).

#![warn(missing_docs)]

use dashpot_sdk::{
    BoundContact, Coefficient, Contact, ContactLaw, EndCriterion, Energy, History, LawError, MaterialPair,
    Range,
};
use std::f64::consts::PI;

/// Thornton's restitution (1997) at x = V_y/v ∈ (0, 1] (dimensionless):
/// e = √(6√3/5) √(1 − x²/6) (x / (x + 2 √(6/5 − x²/5)))^{1/4}; 1 for x ≥ 1 (elastic impact).
/// Exact for this law under the force end criterion.
pub fn restitution(x: f64) -> f64 {
    dashpot_sdk::physics::thornton_restitution(x)
}

dashpot_sdk::law_params! {
    /// The configured law: limiting contact pressure `py` (Pa).
    #[derive(Debug, Clone)]
    pub struct Thornton {
        /// limiting (yield) contact pressure p_y; the default is illustrative, not a material value
        py: f64 { unit: "Pa", default: 1.0e9, range: Range::positive() },
    }
}

impl Thornton {
    /// The law with limiting contact pressure `py` (Pa, > 0).
    pub fn with(py: f64) -> Thornton {
        Thornton { py }
    }
}

/// Thornton's law bound to a pair of materials. Per contact, δ_y = c_y r with
/// c_y = (π p_y / (2E))².
#[derive(Debug, Clone)]
pub struct ThorntonBound {
    /// Effective Young's modulus E (Pa).
    pub young: f64,
    /// Limiting contact pressure p_y (Pa).
    pub py: f64,
    /// (π p_y / (2 E))² (1): the yield overlap per metre of effective radius.
    pub cy: f64,
}

/// The unloading curve from a largest overlap δ_max (all SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unloading {
    /// The force at δ_max on the loading curve (N).
    pub f_max: f64,
    /// The unloading radius R_p = 4 E a_p³ / (3 F_max), a_p = √(r δ_max) (m).
    pub radius_p: f64,
    /// The residual overlap δ_p = δ_max − 3 F_max / (4 E a_p) where the force returns to 0 (m).
    pub delta_p: f64,
}

impl ThorntonBound {
    /// The yield overlap δ_y = (π p_y / (2E))² r (m) for effective radius `radius` (m).
    pub fn yield_overlap(&self, radius: f64) -> f64 {
        self.cy * radius
    }

    /// The yield force F_y = (4/3) E √r δ_y^{3/2} (N).
    pub fn yield_force(&self, radius: f64) -> f64 {
        let dy = self.yield_overlap(radius);
        4.0 / 3.0 * self.young * (radius * dy).sqrt() * dy
    }

    /// The yield impact speed V_y = √(π⁵ p_y⁵ r³ / (30 E⁴ m)) (m/s) for effective mass `mass`
    /// (kg) and radius `radius` (m): ½ m V_y² = (2/5) K δ_y^{5/2}.
    pub fn yield_speed(&self, mass: f64, radius: f64) -> f64 {
        (PI.powi(5) * self.py.powi(5) * radius.powi(3) / (30.0 * self.young.powi(4) * mass)).sqrt()
    }

    /// The loading curve (Hertz, then linear plastic) at overlap `delta` ≥ 0 (N).
    #[inline(always)]
    fn loading(&self, radius: f64, delta: f64) -> f64 {
        let dy = self.cy * radius;
        if delta <= dy {
            4.0 / 3.0 * self.young * (radius * delta).sqrt() * delta
        } else {
            4.0 / 3.0 * self.young * (radius * dy).sqrt() * dy + PI * self.py * radius * (delta - dy)
        }
    }

    /// The unloading curve of a contact of effective radius `radius` (m) whose largest overlap
    /// is `delta_max` (m, > 0).
    pub fn unloading(&self, radius: f64, delta_max: f64) -> Unloading {
        let f_max = self.loading(radius, delta_max);
        if delta_max <= self.cy * radius {
            return Unloading {
                f_max,
                radius_p: radius,
                delta_p: 0.0,
            };
        }
        let ap = (radius * delta_max).sqrt();
        Unloading {
            f_max,
            radius_p: 4.0 * self.young * ap * ap * ap / (3.0 * f_max),
            delta_p: delta_max - 3.0 * f_max / (4.0 * self.young * ap),
        }
    }
}

impl ContactLaw for Thornton {
    type Bound = ThorntonBound;
    const NAME: &'static str = "thornton";
    const SUMMARY: &'static str =
        "elastic–perfectly plastic spheres (Thornton 1997): Hertz, linear plastic loading above p_y, Hertzian unloading";
    const DOC: &'static str = "Thornton (J. Appl. Mech. 64, 383, 1997) elastic–perfectly plastic normal \
        force, K = (4/3) E_eff √r_eff. Loading: Hertz F = K δ^{3/2} up to the yield overlap \
        δ_y = (π p_y / (2 E_eff))² r_eff, where the maximum contact pressure reaches p_y; above, \
        F = F_y + π p_y r_eff (δ − δ_y), F_y = K δ_y^{3/2}. Unloading and reloading below the \
        largest overlap δ_max: F = (4/3) E_eff √R_p (δ − δ_p)^{3/2} above the residual overlap δ_p, \
        0 below (no adhesion), with R_p = 4 E_eff a_p³/(3 F_max), a_p = √(r_eff δ_max) (Thornton's \
        R_p = (4E/(3F_max))((2F_max + F_y)/(2π p_y))^{3/2}) and δ_p = δ_max − 3 F_max/(4 E_eff a_p); \
        below yield R_p = r_eff and δ_p = 0. Parameter: py (Pa, > 0), the limiting contact \
        pressure; the default is illustrative. History: 1 slot, delta_max (m), updated to \
        max(delta_max, δ) at each call (δ ≤ 0 leaves it unchanged). No rate dependence, no viscous \
        damping. With contact ending when the force returns to 0 (at δ_p), restitution is 1 below \
        the yield speed V_y = √(π⁵ p_y⁵ r_eff³/(30 E_eff⁴ m)) (m the effective mass) and \
        e = √(6√3/5) √(1 − x²/6) (x/(x + 2√(6/5 − x²/5)))^{1/4}, x = V_y/v, above it (e ∝ v^{−1/4} \
        far above). No closed-form calibration.";
    const END_CRITERION: EndCriterion = EndCriterion::Force;
    const HISTORY: &'static [History] = &[History::new(
        "delta_max",
        "m",
        "largest overlap reached by this contact (0 at first touch)",
    )];

    fn bind(&self, materials: &MaterialPair) -> Result<ThorntonBound, LawError> {
        let s = PI * self.py / (2.0 * materials.young);
        Ok(ThorntonBound {
            young: materials.young,
            py: self.py,
            cy: s * s,
        })
    }
}

impl BoundContact for ThorntonBound {
    #[inline]
    fn force(&self, c: Contact, history: &mut [f64]) -> f64 {
        let d = c.delta;
        let dmax = history[0].max(d);
        history[0] = dmax;
        if d <= 0.0 {
            return 0.0;
        }
        if d >= dmax || dmax <= self.cy * c.radius {
            // On the loading curve, or below yield where unloading retraces Hertz.
            return self.loading(c.radius, d);
        }
        let u = self.unloading(c.radius, dmax);
        if d <= u.delta_p {
            0.0
        } else {
            u.f_max * ((d - u.delta_p) / (dmax - u.delta_p)).powf(1.5)
        }
    }

    /// Elastic (J): the work unloading gives back from this state,
    /// (2/5) F_max (δ_max − δ_p) x^{5/2}, x = (δ − δ_p)/(δ_max − δ_p) (Hertz's (2/5) K δ^{5/2}
    /// below yield). Power (W): on the plastic loading branch (δ = δ_max > δ_y, δ̇ > 0), where the
    /// elastic part is E(δ) = (3/10) F²/(E √(Rδ)), the plastic work rate (F − dE/dδ) δ̇; 0
    /// otherwise.
    fn energy(&self, c: &Contact, history: &[f64], force: f64) -> Option<Energy> {
        let (d, dmax) = (c.delta, history[0]);
        if d <= 0.0 || dmax <= 0.0 {
            return Some(Energy::default());
        }
        let u = self.unloading(c.radius, dmax);
        let span = dmax - u.delta_p;
        let elastic = if d <= u.delta_p {
            0.0
        } else {
            0.4 * u.f_max * span * ((d - u.delta_p) / span).powf(2.5)
        };
        let dy = self.cy * c.radius;
        let power = if d >= dmax && d > dy && c.rate > 0.0 {
            let s = (c.radius * d).sqrt();
            let slope = PI * self.py * c.radius;
            let de = 0.3 * force / (self.young * s) * (2.0 * slope - force / (2.0 * d));
            ((force - de) * c.rate).max(0.0)
        } else {
            0.0
        };
        Some(Energy { power, elastic })
    }

    fn coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        vec![
            Coefficient::new(
                "K",
                "N/m^(3/2)",
                4.0 / 3.0 * self.young * radius.sqrt(),
                "Hertz stiffness (4/3) E_eff √r_eff",
            ),
            Coefficient::new(
                "delta_y",
                "m",
                self.yield_overlap(radius),
                "yield overlap (π p_y/(2 E_eff))² r_eff",
            ),
            Coefficient::new("F_y", "N", self.yield_force(radius), "yield force K δ_y^{3/2}"),
            Coefficient::new(
                "V_y",
                "m/s",
                self.yield_speed(mass, radius),
                "yield impact speed √(π⁵ p_y⁵ r³/(30 E⁴ m)), from ½ m V_y² = (2/5) K δ_y^{5/2}",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [Thornton]);

#[cfg(test)]
mod tests {
    use super::*;

    const E: f64 = 1.0e8;
    const R: f64 = 5.0e-3;
    const M: f64 = 1.0e-3;

    /// The law with p_y chosen so that V_y = 1 m/s for (M, R, E).
    fn law() -> ThorntonBound {
        let py = (30.0 * E.powi(4) * M / (PI.powi(5) * R.powi(3))).powf(0.2);
        Thornton::with(py)
            .bind(&MaterialPair::new(E, E / 3.0).unwrap())
            .unwrap()
    }

    fn c(delta: f64) -> Contact {
        Contact {
            delta,
            rate: 0.0,
            mass: M,
            radius: R,
        }
    }

    /// Velocity Verlet on the overlap, history kept at every accepted step; the contact ends
    /// when the force returns to 0 on rebound. Returns (restitution, largest overlap).
    fn collide(b: &ThorntonBound, v0: f64) -> (f64, f64) {
        // The stiffest point of the collision is the unloading tangent 2 E √(r δ_max) at the
        // largest overlap, which energy balance bounds by the Hertz or the plastic estimate.
        let k = 4.0 / 3.0 * E * R.sqrt();
        let d_hertz = (1.25 * M * v0 * v0 / k).powf(0.4);
        let d_plastic = (M * v0 * v0 / (PI * b.py * R)).sqrt() + b.yield_overlap(R);
        let k_max = 2.0 * E * (R * d_hertz.max(d_plastic)).sqrt();
        let dt = 2.0 * PI * (M / k_max).sqrt() / 20_000.0;
        let mut h = [0.0];
        let e = dashpot_testkit::verlet_rebound(b, M, R, v0, dt, &mut h);
        (e, h[0])
    }

    #[test]
    fn yield_speed_is_the_elastic_energy_at_yield() {
        let b = law();
        let vy = b.yield_speed(M, R);
        assert!((vy - 1.0).abs() < 1e-12, "V_y = {vy}");
        // ½ m V_y² = ∫₀^δy K δ^{3/2} dδ = (2/5) K δ_y^{5/2}
        let k = 4.0 / 3.0 * E * R.sqrt();
        let w = 0.4 * k * b.yield_overlap(R).powf(2.5);
        assert!((0.5 * M * vy * vy / w - 1.0).abs() < 1e-12);
        // The maximum Hertz pressure 2 E a/(π r) equals p_y at δ_y.
        let a = (R * b.yield_overlap(R)).sqrt();
        assert!((2.0 * E * a / (PI * R) / b.py - 1.0).abs() < 1e-12);
        // By integration: 1 % below V_y the contact stays elastic, 1 % above it yields.
        let (e, dmax) = collide(&b, 0.99 * vy);
        assert!(dmax < b.yield_overlap(R) && (e - 1.0).abs() < 1e-6, "e = {e}");
        let (e, dmax) = collide(&b, 1.01 * vy);
        assert!(dmax > b.yield_overlap(R) && e < 1.0 - 1e-6, "e = {e}");
        let names: Vec<_> = b.coefficients(M, R).iter().map(|c| c.name.to_string()).collect();
        assert_eq!(names, ["K", "delta_y", "F_y", "V_y"]);
        assert_eq!(b.coefficients(M, R)[3].value, vy);
    }

    #[test]
    fn force_and_stiffness_are_continuous_at_yield() {
        let b = law();
        let dy = b.yield_overlap(R);
        let fy = b.yield_force(R);
        let eps = 1e-9;
        let below = b.force(c(dy * (1.0 - eps)), &mut [0.0]);
        let above = b.force(c(dy * (1.0 + eps)), &mut [0.0]);
        assert!((below / fy - 1.0).abs() < 2e-9 && (above / fy - 1.0).abs() < 2e-9);
        // Slopes: Hertz (3/2) K √δ_y against the plastic π p_y r.
        let h = 1e-6 * dy;
        let s_below = (fy - b.force(c(dy - h), &mut [0.0])) / h;
        let s_above = (b.force(c(dy + h), &mut [0.0]) - fy) / h;
        assert!((s_below / (PI * b.py * R) - 1.0).abs() < 1e-5, "{s_below}");
        assert!((s_above / (PI * b.py * R) - 1.0).abs() < 1e-9, "{s_above}");
    }

    #[test]
    fn unloading_curve_meets_f_max_and_returns_to_zero_at_delta_p() {
        let b = law();
        let dy = b.yield_overlap(R);
        let dmax = 7.0 * dy;
        let mut h = [0.0];
        // Load step by step up to δ_max.
        let mut f_load = 0.0;
        for i in 1..=70 {
            f_load = b.force(c(dmax * i as f64 / 70.0), &mut h);
        }
        assert_eq!(h[0], dmax);
        let u = b.unloading(R, dmax);
        let f_max = b.yield_force(R) + PI * b.py * R * (dmax - dy);
        assert!((f_load / f_max - 1.0).abs() < 1e-14 && (u.f_max / f_max - 1.0).abs() < 1e-14);
        // Both branches give F_max at δ_max; the Hertzian form with R_p agrees.
        assert!((b.force(c(dmax), &mut h) / f_max - 1.0).abs() < 1e-14);
        let hertz_p = |d: f64| 4.0 / 3.0 * E * u.radius_p.sqrt() * (d - u.delta_p).powf(1.5);
        assert!((hertz_p(dmax) / f_max - 1.0).abs() < 1e-12);
        // Thornton's printed R_p.
        let fy = b.yield_force(R);
        let rp = 4.0 * E / (3.0 * f_max) * ((2.0 * f_max + fy) / (2.0 * PI * b.py)).powf(1.5);
        assert!((u.radius_p / rp - 1.0).abs() < 1e-12, "{} {rp}", u.radius_p);
        // Unloading stiffness at δ_max is 2 E a_p.
        let hd = 1e-7 * dmax;
        let mut hh = h;
        let s = (f_max - b.force(c(dmax - hd), &mut hh)) / hd;
        assert!((s / (2.0 * E * (R * dmax).sqrt()) - 1.0).abs() < 1e-6, "{s}");
        // δ_p: 0 at and below, positive just above, history untouched.
        assert!(u.delta_p > 0.0 && u.delta_p < dmax);
        assert_eq!(b.force(c(u.delta_p), &mut h), 0.0);
        assert!(b.force(c(u.delta_p * (1.0 + 1e-3)), &mut h) > 0.0);
        assert_eq!(b.force(c(0.5 * u.delta_p), &mut h), 0.0);
        assert_eq!(b.force(c(-1e-9), &mut h), 0.0);
        assert_eq!(h[0], dmax);
        // Intermediate point against the Hertzian form.
        let d = 0.5 * (u.delta_p + dmax);
        assert!((b.force(c(d), &mut h) / hertz_p(d) - 1.0).abs() < 1e-12);
        // Below yield there is no residual overlap.
        assert_eq!(b.unloading(R, 0.5 * dy).delta_p, 0.0);
    }

    #[test]
    fn reloading_below_delta_max_follows_the_unloading_curve() {
        let b = law();
        let dmax = 4.0 * b.yield_overlap(R);
        let mut h = [0.0];
        b.force(c(dmax), &mut h);
        let u = b.unloading(R, dmax);
        let unload = |d: f64| u.f_max * ((d - u.delta_p) / (dmax - u.delta_p)).powf(1.5);
        // Unload to halfway, reload to 90 %: the same curve, history unchanged.
        let d1 = 0.5 * (u.delta_p + dmax);
        let d2 = u.delta_p + 0.9 * (dmax - u.delta_p);
        for d in [d1, d2, d1, d2] {
            assert!((b.force(c(d), &mut h) / unload(d) - 1.0).abs() < 1e-14);
            assert_eq!(h[0], dmax);
        }
        // Past δ_max: back on the plastic loading line, δ_max grows.
        let d3 = 1.1 * dmax;
        let f3 = b.force(c(d3), &mut h);
        let dy = b.yield_overlap(R);
        assert!((f3 / (b.yield_force(R) + PI * b.py * R * (d3 - dy)) - 1.0).abs() < 1e-14);
        assert_eq!(h[0], d3);
        // A trial on a scratch copy does not move the kept history.
        let mut scratch = h;
        b.force(c(2.0 * dmax), &mut scratch);
        assert_eq!(h[0], d3);
    }

    #[test]
    fn restitution_is_one_below_yield_and_thorntons_above() {
        let b = law();
        let vy = b.yield_speed(M, R);
        for v in [0.1 * vy, 0.5 * vy, 0.95 * vy] {
            let (e, _) = collide(&b, v);
            println!("v/V_y = {:.3}: e = {e:.12} (e − 1 = {:.1e})", v / vy, e - 1.0);
            assert!((e - 1.0).abs() < 1e-6, "v = {v}: e = {e}");
        }
        for v in [1.5 * vy, 10.0 * vy, 100.0 * vy, 1000.0 * vy] {
            let (e, _) = collide(&b, v);
            let want = restitution(vy / v);
            println!(
                "v/V_y = {:.1}: e = {e:.9}, closed form {want:.9} (relative error {:.1e})",
                v / vy,
                e / want - 1.0
            );
            assert!(
                (e / want - 1.0).abs() < 1e-6,
                "v = {v}: e = {e}, closed form {want}"
            );
        }
    }

    #[test]
    fn closed_form_falls_as_v_to_the_minus_quarter() {
        assert_eq!(restitution(1.0), 1.0);
        assert!((restitution(1.0 - 1e-12) - 1.0).abs() < 1e-9);
        // d ln e / d ln v at v = 1000 V_y, central difference in ln v.
        let h: f64 = 1e-4;
        let x = 1e-3;
        let slope = -((restitution(x * h.exp()).ln() - restitution(x * (-h).exp()).ln()) / (2.0 * h));
        println!("d ln e / d ln v at 1000 V_y = {slope}");
        assert!((slope + 0.25).abs() < 1e-3, "{slope}");
    }
}
