//! Kuwabara–Kono viscoelastic contact: F = K (δ^{3/2} + (3/2) A √δ δ̇)
//! (Kuwabara & Kono 1987; Brilliantov, Spahn, Hertzsch & Pöschel, PRE 53, 5382, 1996).

use dashpot_sdk::{
    BoundContact, Coefficient, ContactLaw, EndCriterion, LawError, Pair, ParamSpec, Params, Range,
};

/// The configured law: dissipative time constant `a` (s).
#[derive(Debug, Clone)]
pub struct KuwabaraKono {
    a: f64,
}

impl KuwabaraKono {
    /// The law with dissipative constant `a` (s).
    pub fn with(a: f64) -> KuwabaraKono {
        KuwabaraKono { a }
    }
}

/// Kuwabara–Kono bound to a pair.
#[derive(Debug, Clone)]
pub struct KuwabaraKonoBound {
    /// Hertz stiffness K = (4/3) E_eff √r_eff (N/m^{3/2}).
    pub k: f64,
    /// Dissipative constant A (s).
    pub a: f64,
    ka15: f64,
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

    fn params() -> Vec<ParamSpec> {
        vec![ParamSpec::new(
            "A",
            "s",
            1.0e-6,
            Range::non_negative(),
            "dissipative time constant (0: elastic Hertz); the default is illustrative, not a material value",
        )]
    }

    fn new(p: &Params) -> Result<Self, LawError> {
        Ok(KuwabaraKono { a: p.get("A")? })
    }

    fn bind(&self, pair: &Pair) -> Result<KuwabaraKonoBound, LawError> {
        let k = pair.hertz_stiffness();
        Ok(KuwabaraKonoBound {
            k,
            a: self.a,
            ka15: 1.5 * k * self.a,
        })
    }
}

impl BoundContact for KuwabaraKonoBound {
    #[inline(always)]
    fn force(&self, delta: f64, rate: f64) -> f64 {
        let d = delta.max(0.0);
        let s = d.sqrt();
        s * (self.k * d + self.ka15 * rate)
    }

    fn coefficients(&self) -> Vec<Coefficient> {
        vec![
            Coefficient::new("K", "N/m^(3/2)", self.k, "Hertz stiffness (4/3) E_eff √r_eff"),
            Coefficient::new("A", "s", self.a, "dissipative time constant"),
            Coefficient::new(
                "c",
                "N·s/m^(3/2)",
                self.ka15,
                "damping coefficient (3/2) K A of √δ δ̇",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [KuwabaraKono]);
