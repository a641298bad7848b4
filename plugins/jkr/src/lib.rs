//! Johnson–Kendall–Roberts adhesive elastic contact, with optional Tsuji-type damping.

use dashpot_sdk::{
    BoundContact, Coefficient, Contact, ContactLaw, EndCriterion, Energy, History, LawError, MaterialPair,
    NormalContext, Range,
};
use std::f64::consts::PI;

dashpot_sdk::law_params! {
    /// The configured law: work of adhesion `w` (J/m²) and restitution parameter `eps`.
    #[derive(Debug, Clone)]
    pub struct Jkr {
        /// work of adhesion w
        w: f64 { unit: "J/m^2", default: 0.1, range: Range::positive() },
        /// restitution parameter of the Tsuji damping α(ε) (1: undamped)
        eps: f64 { unit: "1", default: 1.0, range: Range::open_closed(0.0, 1.0) },
    }
}

/// JKR bound to a pair of materials.
#[derive(Debug, Clone)]
pub struct JkrBound {
    /// Effective Young's modulus E (Pa).
    pub young: f64,
    /// Work of adhesion w (J/m²).
    pub w: f64,
    /// c = √(2π w / E) (√m), so that δ(a) = a²/R − c √a.
    pub c: f64,
    /// Tsuji factor α(ε).
    pub alpha: f64,
}

impl JkrBound {
    /// The zero-load contact radius a0 = (9π w R² / (2E))^{1/3} (m).
    pub fn a0(&self, radius: f64) -> f64 {
        (9.0 * PI * self.w * radius * radius / (2.0 * self.young)).cbrt()
    }

    /// The overlap at which the contact breaks, δ_c = −(3/4) (π² w² R / E²)^{1/3} (m, ≤ 0),
    /// where dδ/da = 0 (a = a0 / 6^{2/3}).
    pub fn delta_c(&self, radius: f64) -> f64 {
        -0.75 * (PI * PI * self.w * self.w * radius / (self.young * self.young)).cbrt()
    }

    /// The contact radius (m) at overlap δ ≥ δ_c on the stable branch a ≥ a0/6^{2/3}: the root
    /// x = √a of x⁴ − cR x − δR = 0 right of the minimum, by Newton's method from the right
    /// (monotone: f is convex and increasing there).
    pub fn contact_radius(&self, radius: f64, delta: f64) -> f64 {
        let (cr, dr) = (self.c * radius, delta * radius);
        let xmin = (cr / 4.0).cbrt();
        let mut x = (2.0 * cr).cbrt().max((2.0 * dr.abs()).sqrt().sqrt()).max(xmin);
        for _ in 0..100 {
            let f = x * x * x * x - cr * x - dr;
            let df = 4.0 * x * x * x - cr;
            if f <= 0.0 || df <= 0.0 {
                break;
            }
            let next = (x - f / df).max(xmin);
            if next >= x {
                break;
            }
            x = next;
        }
        x * x
    }

    /// The elastic JKR force F(a) = 4E a³/(3R) − √(8π w E a³) (N).
    pub fn force_at(&self, radius: f64, a: f64) -> f64 {
        4.0 * self.young * a * a * a / (3.0 * radius) - (8.0 * PI * self.w * self.young * a * a * a).sqrt()
    }

    /// W(a) = ∫ F dδ along the JKR curve: 8E a⁵/(15R²) − (4/3)(E c/R) a^{7/2} + E c² a²/2 (J,
    /// up to a constant).
    fn work(&self, radius: f64, a: f64) -> f64 {
        let e = self.young;
        8.0 * e * a.powi(5) / (15.0 * radius * radius) - 4.0 / 3.0 * e * self.c / radius * a.powf(3.5)
            + 0.5 * e * self.c * self.c * a * a
    }

    /// The damping coefficient α(ε) √((4/3) E a m) (N·s/m) at contact radius a.
    fn damping(&self, a: f64, mass: f64) -> f64 {
        self.alpha * (4.0 / 3.0 * self.young * a * mass).sqrt()
    }
}

impl ContactLaw for Jkr {
    type Bound = JkrBound;
    const NAME: &'static str = "jkr";
    const SUMMARY: &'static str =
        "Johnson–Kendall–Roberts adhesive elastic contact: forms at touch, hysteretic, breaks at δ_c; pull-off (3/2)π w R";
    const DOC: &'static str = "Johnson–Kendall–Roberts (JKR) adhesive contact of elastic spheres (Johnson, \
        Kendall & Roberts 1971, Proc. R. Soc. Lond. A 324, 301; as used in DEM by Thornton & Ning 1998, Powder \
        Technol. 99, 154). E is the pair's effective Young's modulus (Pa), R the contact's effective radius (m), \
        w the work of adhesion (J/m²). Contact radius a (m) and overlap δ (m): δ(a) = a²/R − √(2π w a/E); \
        elastic force F(a) = 4E a³/(3R) − √(8π w E a³) (N, > 0 repulsive); zero-load radius \
        a0 = (9π w R²/(2E))^{1/3}. The law solves δ(a) for a on the stable branch a ≥ a0/6^{2/3} (Newton's \
        method on x = √a). Most tensile force on that branch: −(3/2)π w R, at a = a0/4^{1/3} (the pull-off force \
        under load control). The contact breaks where dδ/da = 0: at δ_c = −(3/4)(π² w² R/E²)^{1/3}, \
        a = a0/6^{2/3}, with F = −(5/6)π w R. Hysteresis: the contact forms only at touch (δ ≥ 0); once formed \
        it acts in tension down to δ_c (its reach, |δ_c|), and breaks there (history reset), so an approach at \
        δ < 0 feels no force. History: 'formed' (1 once touched, 0 before and after rupture). Damping (optional): \
        F_d = α(ε) √((4/3) E a m) δ̇ (N), m the effective mass, α(ε) = −√5 ln ε/√(ln²ε + π²) the Tsuji factor \
        of the hsd law (eps = 1, the default, is undamped); as w → 0 the law tends to hsd (Hertz with Tsuji damping). \
        Energy: elastic = W(a) − W(a_t) (J), the work the contact gives back when unloaded \
        quasi-statically to touch, with W(a) = 8E a⁵/(15R²) − (4/3)(E c/R) a^{7/2} + E c² a²/2, \
        c = √(2π w/E), a_t = (2π w R²/E)^{1/3} the contact radius at touch (Hertz's (2/5) K δ^{5/2} at \
        w = 0): nothing appears as the contact forms, it is negative in tension past touch, and at rupture \
        it holds W(a0/6^{2/3}) − W(a_t) > 0, the adhesion hysteresis of the cycle, which is lost with the \
        contact (a host books it dissipated); power = F_d δ̇ (W). Callers that end contacts at δ = 0 (end \
        criterion 'overlap') see only its compressive part. Context (what the contact's other laws read, \
        sdk 0.4): the contact radius a above (positive past touching, until rupture; 0 when the contact is not \
        formed), the cap force F_e + 3π w R = F_e + 2 F_po (N, with F_e the elastic force F(a) and F_po = \
        (3/2)π w R the pull-off force: Thornton & Yin 1991, Powder Technol. 65, 153, so that friction keeps \
        acting in tension; positive on the stable branch) and the damping coefficient α(ε) √((4/3) E a m) \
        (N·s/m).";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;
    const HISTORY: &'static [History] = &[History::new(
        "formed",
        "1",
        "1 once the contact has formed at touch, 0 before and after it breaks",
    )];

    fn bind(&self, m: &MaterialPair) -> Result<JkrBound, LawError> {
        Ok(JkrBound {
            young: m.young,
            w: self.w,
            c: (2.0 * PI * self.w / m.young).sqrt(),
            alpha: dashpot_sdk::physics::tsuji_alpha(self.eps),
        })
    }
}

impl BoundContact for JkrBound {
    fn force(&self, c: Contact, history: &mut [f64]) -> f64 {
        if c.delta >= 0.0 {
            history[0] = 1.0;
        }
        if history[0] == 0.0 {
            return 0.0;
        }
        if c.delta < self.delta_c(c.radius) {
            history[0] = 0.0;
            return 0.0;
        }
        let a = self.contact_radius(c.radius, c.delta);
        self.force_at(c.radius, a) + self.damping(a, c.mass) * c.rate
    }

    fn reach(&self, c: &Contact, history: &[f64]) -> f64 {
        if history[0] == 0.0 {
            0.0
        } else {
            -self.delta_c(c.radius)
        }
    }

    fn context(&self, c: &Contact, history: &[f64], _force: f64) -> NormalContext {
        if history[0] == 0.0 {
            return NormalContext::default();
        }
        let a = self.contact_radius(c.radius, c.delta);
        NormalContext {
            contact_radius: a,
            cap_force: (self.force_at(c.radius, a) + 3.0 * PI * self.w * c.radius).max(0.0),
            damping: self.damping(a, c.mass),
        }
    }

    fn energy(&self, c: &Contact, history: &[f64], _force: f64) -> Option<Energy> {
        if history[0] == 0.0 {
            return Some(Energy::default());
        }
        let a = self.contact_radius(c.radius, c.delta);
        // relative to the contact as it forms at touch (a(0)³ = 2π w R²/E): no energy appears
        // when it forms; what it holds when it breaks at δ_c (the adhesion hysteresis) is lost
        let touch = (2.0 * PI * self.w * c.radius * c.radius / self.young).cbrt();
        Some(Energy {
            power: self.damping(a, c.mass) * c.rate * c.rate,
            elastic: self.work(c.radius, a) - self.work(c.radius, touch),
        })
    }

    fn coefficients(&self, _mass: f64, radius: f64) -> Vec<Coefficient> {
        vec![
            Coefficient::new(
                "a0",
                "m",
                self.a0(radius),
                "zero-load contact radius (9π w R²/(2E))^{1/3}",
            ),
            Coefficient::new(
                "delta_c",
                "m",
                self.delta_c(radius),
                "rupture overlap −(3/4)(π² w² R/E²)^{1/3}",
            ),
            Coefficient::new(
                "F_pulloff",
                "N",
                -1.5 * PI * self.w * radius,
                "pull-off force −(3/2)π w R",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [Jkr]);

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> JkrBound {
        Jkr { w: 0.05, eps: 1.0 }
            .bind(&MaterialPair::new(1e8, 4e7).unwrap())
            .unwrap()
    }

    /// The contact radius found for δ gives back δ through δ(a) = a²/R − √(2π w a/E), on the
    /// stable branch, from rupture to deep compression.
    #[test]
    fn contact_radius_inverts_the_overlap() {
        let b = law();
        let r = 1e-4;
        let ac = b.a0(r) / 6f64.powf(2.0 / 3.0);
        let dc = b.delta_c(r);
        for i in 0..=1000 {
            let d = dc + (1e-6 - dc) * (i as f64 / 1000.0).powi(3);
            let a = b.contact_radius(r, d);
            assert!(a >= ac * (1.0 - 1e-12), "stable branch at δ = {d:e}");
            let back = a * a / r - (2.0 * PI * b.w * a / b.young).sqrt();
            assert!((back - d).abs() <= 1e-9 * dc.abs(), "δ = {d:e}: δ(a) = {back:e}");
        }
        // a0 is the zero-load radius: F(a0) = 0
        assert!(b.force_at(r, b.a0(r)).abs() < 1e-12 * 1.5 * PI * b.w * r);
    }
}
