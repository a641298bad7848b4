//! Linear spring-dashpot (LSD): F = k δ + 2 γ m δ̇ (Antypov & Elliott 2011, eqs. 3–8).
//!
//! The damping γ follows from the restitution ε by eq. (8), γ = −ln ε / √(ln²ε + π²) · w0 with
//! w0 = √(k/m), so that the collision ending when δ returns to 0 has restitution exactly ε,
//! at every impact speed. The stiffness k defaults to the one that maps the Hertz spring of the
//! same pair onto this one (k = (2/3) E_eff d for identical spheres; k = (8/3) E_eff r_eff in
//! general, see [`Pair::mapped_linear_stiffness`]).

use dashpot_sdk::{
    BoundContact, CalibrationTarget, Coefficient, Contact, ContactLaw, EndCriterion, Energy, LawError,
    MaterialPair, Pair, ParamValue, Params, Range,
};
use std::f64::consts::PI;

dashpot_sdk::law_params! {
    /// The configured law: restitution `eps` and optional stiffness `k` (N/m).
    #[derive(Debug, Clone)]
    pub struct Lsd {
        /// coefficient of restitution (contact ends when δ returns to 0)
        eps: f64 { unit: "1", default: 0.54, range: Range::open_closed(0.0, 1.0) },
        /// spring constant; default (8/3) E_eff r_eff = (2/3) E_eff d for identical spheres
        k: Option<f64> { unit: "N/m", range: Range::positive() },
    }
}

/// The law bound to a pair of materials.
#[derive(Debug, Clone)]
pub struct LsdBound {
    /// The spring constant k (N/m) if given; otherwise (8/3) E_eff r per contact.
    pub k: Option<f64>,
    /// (8/3) E_eff (Pa): the mapped stiffness per metre of effective radius.
    pub k_per_radius: f64,
    /// 2 ζ(ε) with ζ the damping ratio of eq. 8: the dashpot is 2 ζ √(k m).
    pub two_zeta: f64,
    eps: f64,
}

impl LsdBound {
    #[inline(always)]
    fn stiffness(&self, radius: f64) -> f64 {
        match self.k {
            Some(k) => k,
            None => self.k_per_radius * radius,
        }
    }
}

impl Lsd {
    /// The law with restitution `eps` and stiffness `k` (None: derived from the pair).
    pub fn with(eps: f64, k: Option<f64>) -> Lsd {
        Lsd { eps, k }
    }
}

impl ContactLaw for Lsd {
    type Bound = LsdBound;
    const NAME: &'static str = "lsd";
    const SUMMARY: &'static str =
        "linear spring-dashpot: F = k δ + 2γm δ̇, γ from ε by Antypov & Elliott eq. 8";
    const DOC: &'static str = "Linear spring-dashpot (LSD) normal force F = k δ + 2 γ m δ̇ for δ ≥ 0, \
        0 for δ < 0 (m: effective mass). The damping rate is \
        γ = −ln ε / √(ln²ε + π²) · √(k/m) (Antypov & Elliott 2011, eq. 8), so a collision that ends \
        when δ returns to 0 has restitution exactly ε and lasts τ = π/√(k/m − γ²), both independent \
        of the impact speed. k defaults to (8/3) E_eff r_eff, which is the paper's k = (2/3) E_eff d \
        for two identical spheres of diameter d: the stiffness whose phase trajectory maps onto \
        the Hertz spring of the same pair (eq. 19). Calibration in closed form: ε sets eps; a \
        contact time τ sets k = m (ln²ε + π²)/τ².";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;

    fn bind(&self, materials: &MaterialPair) -> Result<LsdBound, LawError> {
        Ok(LsdBound {
            k: self.k,
            k_per_radius: 8.0 / 3.0 * materials.young,
            two_zeta: 2.0 * dashpot_sdk::physics::lsd_damping_ratio(self.eps),
            eps: self.eps,
        })
    }

    fn calibrate(
        target: &CalibrationTarget,
        pair: &Pair,
        _fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        if target.end != EndCriterion::Overlap {
            return Ok(None);
        }
        let eps = target.restitution;
        let mut out = vec![ParamValue::new("eps", eps)];
        if let Some(tau) = target.contact_time {
            let l = eps.ln();
            out.push(ParamValue::new("k", pair.mass * (l * l + PI * PI) / (tau * tau)));
        }
        Ok(Some(out))
    }
}

impl BoundContact for LsdBound {
    #[inline(always)]
    fn force(&self, c: Contact, _history: &mut [f64]) -> f64 {
        if c.delta < 0.0 {
            0.0
        } else {
            let k = self.stiffness(c.radius);
            k * c.delta + self.two_zeta * (k * c.mass).sqrt() * c.rate
        }
    }

    /// Elastic k δ²/2 (J); power: the dashpot force times δ̇ (W); both 0 for δ < 0.
    fn energy(&self, c: &Contact, _history: &[f64], _force: f64) -> Option<Energy> {
        if c.delta < 0.0 {
            return Some(Energy::default());
        }
        let k = self.stiffness(c.radius);
        Some(Energy {
            power: self.two_zeta * (k * c.mass).sqrt() * c.rate * c.rate,
            elastic: 0.5 * k * c.delta * c.delta,
        })
    }

    fn coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        let k = self.stiffness(radius);
        let w0 = (k / mass).sqrt();
        let gamma = 0.5 * self.two_zeta * w0;
        let w1 = (w0 * w0 - gamma * gamma).sqrt();
        vec![
            Coefficient::new("k", "N/m", k, "spring constant"),
            Coefficient::new("m", "kg", mass, "effective mass"),
            Coefficient::new("w0", "1/s", w0, "undamped angular frequency √(k/m) (eq. 3)"),
            Coefficient::new("gamma", "1/s", gamma, "damping rate −ln ε/√(ln²ε+π²)·w0 (eq. 8)"),
            Coefficient::new("c", "N·s/m", 2.0 * gamma * mass, "dashpot coefficient 2γm"),
            Coefficient::new(
                "eps",
                "1",
                self.eps,
                "restitution under the overlap criterion (eq. 7)",
            ),
            Coefficient::new("contact_time", "s", PI / w1, "τ = π/√(w0² − γ²) (below eq. 8)"),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [Lsd]);
