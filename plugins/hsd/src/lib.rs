//! Hertz spring with Tsuji damping (HSD): F = K δ^{3/2} + α(ε) √(mK) δ^{1/4} δ̇
//! (Antypov & Elliott 2011, eqs. 9–11, 17).

use dashpot_sdk::{
    BoundContact, CalibrationTarget, Coefficient, ContactLaw, EndCriterion, LawError, Pair, ParamSpec,
    ParamValue, Params, Range,
};
use std::f64::consts::PI;

/// The exact Tsuji damping factor α(ε) = −√5 ln ε / √(ln²ε + π²) (Antypov & Elliott eq. 17).
pub fn alpha(eps: f64) -> f64 {
    let l = eps.ln();
    -(5.0f64).sqrt() * l / (l * l + PI * PI).sqrt()
}

/// The configured law: restitution `eps`.
#[derive(Debug, Clone)]
pub struct Hsd {
    eps: f64,
}

impl Hsd {
    /// The law with restitution `eps` ∈ (0, 1].
    pub fn with(eps: f64) -> Hsd {
        Hsd { eps }
    }
}

/// HSD bound to a pair.
#[derive(Debug, Clone)]
pub struct HsdBound {
    /// Hertz stiffness K = (4/3) E_eff √r_eff (N/m^{3/2}).
    pub k: f64,
    /// Damping coefficient α √(mK) (N·s/m^{5/4}).
    pub c: f64,
    mass: f64,
    alpha: f64,
}

impl ContactLaw for Hsd {
    type Bound = HsdBound;
    const NAME: &'static str = "hsd";
    const SUMMARY: &'static str =
        "Hertz + Tsuji damping: F = K δ^{3/2} + α(ε)√(mK) δ^{1/4} δ̇, exact α(ε) of Antypov & Elliott eq. 17";
    const DOC: &'static str = "Hertzian spring-dashpot (HSD) normal force \
        F = K δ^{3/2} + α(ε) √(m K) δ^{1/4} δ̇ for δ ≥ 0, 0 for δ < 0, with K = (4/3) E_eff √r_eff \
        (eq. 9), m the effective mass and α(ε) = −√5 ln ε / √(ln²ε + π²) (Antypov & Elliott 2011, \
        eq. 17). Its phase trajectory is that of the linear spring-dashpot with k = (2/3) E_eff d \
        mapped by δ_H/d = (5/4)^{2/5} (δ_L/d)^{4/5} (eq. 19), so a collision ending when δ returns \
        to 0 has restitution exactly ε at every impact speed, and its contact time scales as \
        v0^{-1/5}. Calibration in closed form: ε sets eps (the stiffness is the pair's E_eff).";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;

    fn params() -> Vec<ParamSpec> {
        vec![ParamSpec::new(
            "eps",
            "1",
            0.54,
            Range::open_closed(0.0, 1.0),
            "coefficient of restitution (contact ends when δ returns to 0)",
        )]
    }

    fn new(p: &Params) -> Result<Self, LawError> {
        Ok(Hsd { eps: p.get("eps")? })
    }

    fn bind(&self, pair: &Pair) -> Result<HsdBound, LawError> {
        let k = pair.hertz_stiffness();
        let a = alpha(self.eps);
        Ok(HsdBound {
            k,
            c: a * (pair.mass * k).sqrt(),
            mass: pair.mass,
            alpha: a,
        })
    }

    fn calibrate(
        target: &CalibrationTarget,
        _pair: &Pair,
        _fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        // ε alone has a closed form; a contact time needs the integrator (τ ∝ v0^{-1/5}).
        if target.end != EndCriterion::Overlap || target.contact_time.is_some() {
            return Ok(None);
        }
        Ok(Some(vec![ParamValue::new("eps", target.restitution)]))
    }
}

impl BoundContact for HsdBound {
    #[inline(always)]
    fn force(&self, delta: f64, rate: f64) -> f64 {
        let d = delta.max(0.0);
        let s = d.sqrt();
        self.k * d * s + self.c * s.sqrt() * rate
    }

    fn coefficients(&self) -> Vec<Coefficient> {
        vec![
            Coefficient::new(
                "K",
                "N/m^(3/2)",
                self.k,
                "Hertz stiffness (4/3) E_eff √r_eff (eq. 9)",
            ),
            Coefficient::new("m", "kg", self.mass, "effective mass"),
            Coefficient::new(
                "alpha",
                "1",
                self.alpha,
                "Tsuji factor −√5 ln ε/√(ln²ε+π²) (eq. 17)",
            ),
            Coefficient::new("c", "N·s/m^(5/4)", self.c, "damping coefficient α√(mK) (eq. 10)"),
            Coefficient::new(
                "Omega0",
                "1/(s·m^(1/4))",
                (self.k / self.mass).sqrt(),
                "√(K/m) (eq. 11)",
            ),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [Hsd]);
