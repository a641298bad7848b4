//! A third-party contact law for dashpot: a Hertz spring with a constant (linear) dashpot,
//! F = K δ^{3/2} + η δ̇, the "Hertz + viscous" model found in many DEM codes.

use dashpot_sdk::*;

/// The law: damping coefficient η (N·s/m). K comes from the pair.
pub struct HertzLinearDamping {
    eta: f64,
    k: f64,
}

impl ContactLaw for HertzLinearDamping {
    type Bound = Self;
    const NAME: &'static str = "hertz-linear-damping";
    const SUMMARY: &'static str = "Hertz spring + constant dashpot: F = K δ^{3/2} + η δ̇";
    const DOC: &'static str = "F = K δ^{3/2} + η δ̇ for δ ≥ 0, 0 for δ < 0, K = (4/3) E_eff √r_eff.";
    const END_CRITERION: EndCriterion = EndCriterion::Force;

    fn params() -> Vec<ParamSpec> {
        vec![ParamSpec::new("eta", "N*s/m", 1.0, Range::non_negative(), "dashpot coefficient")]
    }

    fn new(p: &Params) -> Result<Self, LawError> {
        Ok(HertzLinearDamping { eta: p.get("eta")?, k: 0.0 })
    }

    fn bind(&self, pair: &Pair) -> Result<Self, LawError> {
        Ok(HertzLinearDamping { eta: self.eta, k: pair.hertz_stiffness() })
    }
}

impl BoundContact for HertzLinearDamping {
    fn force(&self, delta: f64, rate: f64) -> f64 {
        if delta < 0.0 {
            return 0.0;
        }
        self.k * delta * delta.sqrt() + self.eta * rate
    }
}

dashpot_sdk::export_laws!(contact: [HertzLinearDamping]);
