//! Derjaguin–Muller–Toporov adhesive contact: Hertz minus a constant adhesive force, with
//! optional Tsuji damping.

use dashpot_sdk::{
    BoundContact, Coefficient, Contact, ContactLaw, EndCriterion, Energy, LawError, MaterialPair, Range,
};
use std::f64::consts::PI;

dashpot_sdk::law_params! {
    /// The configured law: work of adhesion `w` (J/m²) and restitution parameter `eps`.
    #[derive(Debug, Clone)]
    pub struct Dmt {
        /// work of adhesion w
        w: f64 { unit: "J/m^2", default: 0.1, range: Range::positive() },
        /// restitution parameter of the Tsuji damping α(ε) (1: undamped)
        eps: f64 { unit: "1", default: 1.0, range: Range::open_closed(0.0, 1.0) },
    }
}

/// DMT bound to a pair of materials.
#[derive(Debug, Clone)]
pub struct DmtBound {
    /// (4/3) E (Pa).
    pub a: f64,
    /// α(ε) √((4/3) E) (√Pa).
    pub b: f64,
    /// 2π w (N/m).
    pub adhesion: f64,
}

impl ContactLaw for Dmt {
    type Bound = DmtBound;
    const NAME: &'static str = "dmt";
    const SUMMARY: &'static str =
        "Derjaguin–Muller–Toporov adhesion: Hertz − 2π w R while touching, Tsuji damping";
    const DOC: &'static str = "Derjaguin–Muller–Toporov (DMT) adhesive contact (Derjaguin, Muller & Toporov \
        1975, J. Colloid Interface Sci. 53, 314): for δ ≥ 0, F = K δ^{3/2} − 2π w R + α(ε) √(m K) δ^{1/4} δ̇ (N, \
        > 0 repulsive), K = (4/3) E √R, E the pair's effective Young's modulus (Pa), R the contact's effective \
        radius (m), m its effective mass (kg), w the work of adhesion (J/m²), α(ε) = −√5 ln ε/√(ln²ε + π²) the \
        Tsuji factor of the hsd law (eps = 1, the default, is undamped); F = 0 for δ < 0 (the contact ends at \
        touch: reach 0). Most tensile force: −2π w R, at δ = 0⁺ (the DMT pull-off force). No history. Energy: \
        elastic = (2/5) K δ^{5/2} − 2π w R δ (J: Hertz's, and the constant adhesive force's potential, \
        negative, which the contact gives back as it ends at touch), power = the damping force × δ̇ (W).";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;

    fn bind(&self, m: &MaterialPair) -> Result<DmtBound, LawError> {
        let a = 4.0 / 3.0 * m.young;
        Ok(DmtBound {
            a,
            b: dashpot_sdk::physics::tsuji_alpha(self.eps) * a.sqrt(),
            adhesion: 2.0 * PI * self.w,
        })
    }
}

impl DmtBound {
    /// The damping force (N) and its coefficient's factor √(m √(Rδ)).
    fn damping(&self, c: &Contact) -> f64 {
        let s1 = (c.radius * c.delta.max(0.0)).sqrt();
        self.b * (c.mass * s1).sqrt() * c.rate
    }
}

impl BoundContact for DmtBound {
    fn force(&self, c: Contact, _history: &mut [f64]) -> f64 {
        if c.delta < 0.0 {
            return 0.0;
        }
        let s1 = (c.radius * c.delta).sqrt();
        self.a * s1 * c.delta - self.adhesion * c.radius + self.damping(&c)
    }

    fn energy(&self, c: &Contact, _history: &[f64], _force: f64) -> Option<Energy> {
        if c.delta < 0.0 {
            return Some(Energy::default());
        }
        let d = c.delta;
        Some(Energy {
            power: self.damping(c) * c.rate,
            // Hertz's (2/5) K δ^{5/2}, and the adhesion's potential −2π w R δ
            elastic: 0.4 * self.a * (c.radius * d).sqrt() * d * d - self.adhesion * c.radius * d,
        })
    }

    fn coefficients(&self, _mass: f64, radius: f64) -> Vec<Coefficient> {
        vec![Coefficient::new(
            "F_pulloff",
            "N",
            -self.adhesion * radius,
            "pull-off force −2π w R",
        )]
    }
}

dashpot_sdk::export_laws!(contact: [Dmt]);
