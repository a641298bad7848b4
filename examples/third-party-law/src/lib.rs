//! A third-party contact law for dashpot: a Hertz spring with a constant (linear) dashpot,
//! F = K δ^{3/2} + η δ̇, the "Hertz + viscous" model found in many DEM codes.

use dashpot_sdk::*;

law_params! {
    /// The law: damping coefficient η (N·s/m).
    pub struct HertzLinearDamping {
        /// dashpot coefficient
        eta: f64 { unit: "N*s/m", default: 1.0, range: Range::non_negative() },
    }
}

/// The law bound to a pair of materials: K = a √r for a contact of effective radius r.
pub struct Bound {
    eta: f64,
    /// (4/3) E_eff (Pa).
    a: f64,
}

impl ContactLaw for HertzLinearDamping {
    type Bound = Bound;
    const NAME: &'static str = "hertz-linear-damping";
    const SUMMARY: &'static str = "Hertz spring + constant dashpot: F = K δ^{3/2} + η δ̇";
    const DOC: &'static str = "F = K δ^{3/2} + η δ̇ for δ ≥ 0, 0 for δ < 0, K = (4/3) E_eff √r_eff.";
    const END_CRITERION: EndCriterion = EndCriterion::Force;

    fn bind(&self, materials: &MaterialPair) -> Result<Bound, LawError> {
        Ok(Bound {
            eta: self.eta,
            a: 4.0 / 3.0 * materials.young,
        })
    }
}

impl BoundContact for Bound {
    fn force(&self, c: Contact, _history: &mut [f64]) -> f64 {
        if c.delta < 0.0 {
            return 0.0;
        }
        self.a * (c.radius * c.delta).sqrt() * c.delta + self.eta * c.rate
    }
}

dashpot_sdk::export_laws!(contact: [HertzLinearDamping]);
