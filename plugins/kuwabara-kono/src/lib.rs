//! Kuwabara–Kono viscoelastic contact: F = K (δ^{3/2} + (3/2) A √δ δ̇)
//! (Kuwabara & Kono 1987; Brilliantov, Spahn, Hertzsch & Pöschel, PRE 53, 5382, 1996).

use dashpot_sdk::{
    BoundContact, Coefficient, Contact, ContactLaw, EndCriterion, Energy, LawError, MaterialPair, Range,
};

dashpot_sdk::law_params! {
    /// The configured law: dissipative time constant `A` (s).
    #[derive(Debug, Clone)]
    #[allow(non_snake_case)]
    pub struct KuwabaraKono {
        /// dissipative time constant (0: elastic Hertz); the default is illustrative, not a material value
        A: f64 { unit: "s", default: 1.0e-6, range: Range::non_negative() },
    }
}

impl KuwabaraKono {
    /// The law with dissipative constant `a` (s).
    pub fn with(a: f64) -> KuwabaraKono {
        KuwabaraKono { A: a }
    }
}

/// Kuwabara–Kono bound to a pair.
#[derive(Debug, Clone)]
pub struct KuwabaraKonoBound {
    /// (4/3) E_eff (Pa): K = a √r for a contact of effective radius r.
    pub a: f64,
    /// The dissipative time constant A (s).
    pub time: f64,
}

impl ContactLaw for KuwabaraKono {
    type Bound = KuwabaraKonoBound;
    const NAME: &'static str = "kuwabara-kono";
    const SUMMARY: &'static str =
        "viscoelastic Hertz: F = K (δ^{3/2} + (3/2) A √δ δ̇), restitution falls with speed";
    const DOC: &'static str = "Kuwabara–Kono viscoelastic normal force F = K (δ^{3/2} + (3/2) A √δ δ̇) \
        for δ ≥ 0, 0 for δ < 0, with K = (4/3) E_eff √r_eff and A (s) the dissipative time constant \
        of the material (Kuwabara & Kono 1987; Brilliantov et al., PRE 53, 5382, 1996). The \
        restitution falls with impact speed, 1 − ε ∝ A (K/m)^{2/5} v0^{1/5} at small v0. The \
        published closed-form approximations (Schwager & Pöschel 2008) assume that contact ends \
        when the force returns to 0, the criterion this law is calibrated for. There is no \
        closed-form calibration: fit A to a measured restitution with the collision driver.";
    const END_CRITERION: EndCriterion = EndCriterion::Force;

    fn bind(&self, materials: &MaterialPair) -> Result<KuwabaraKonoBound, LawError> {
        Ok(KuwabaraKonoBound {
            a: 4.0 / 3.0 * materials.young,
            time: self.A,
        })
    }
}

impl BoundContact for KuwabaraKonoBound {
    /// One square root and a few products, no branch: the sdk evaluates the law eight contacts
    /// at a time between the checks of the next ones.
    const STRAIGHT_LINE: bool = true;

    /// K √δ (δ + (3/2) A δ̇) = a √(rδ) (δ + (3/2) A δ̇): one square root per contact.
    #[inline(always)]
    fn force(&self, c: Contact, _history: &mut [f64]) -> f64 {
        let d = c.delta.max(0.0);
        self.a * (c.radius * d).sqrt() * (d + 1.5 * self.time * c.rate)
    }

    /// Elastic (2/5) K δ^{5/2} (J); power: the damping force (3/2) K A √δ δ̇ times δ̇ (W).
    fn energy(&self, c: &Contact, _history: &[f64], _force: f64) -> Option<Energy> {
        let d = c.delta.max(0.0);
        let s = self.a * (c.radius * d).sqrt();
        Some(Energy {
            power: s * 1.5 * self.time * c.rate * c.rate,
            elastic: 0.4 * s * d * d,
        })
    }

    fn coefficients(&self, _mass: f64, radius: f64) -> Vec<Coefficient> {
        let k = self.a * radius.sqrt();
        vec![
            Coefficient::new("K", "N/m^(3/2)", k, "Hertz stiffness (4/3) E_eff √r_eff"),
            Coefficient::new("A", "s", self.time, "dissipative time constant"),
            Coefficient::new(
                "c",
                "N·s/m^(3/2)",
                1.5 * k * self.time,
                "damping coefficient (3/2) K A of √δ δ̇",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [KuwabaraKono]);
