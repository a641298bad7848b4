//! Batchelor–O'Brien conduction corrected for a softened Young's modulus: what a plugin adds
//! that a compiled-in model cannot without a recompile.
//!
//! DEM runs soften the particles (a smaller E) to afford a larger time step; the contact radius
//! then grows, and with it every conductance written in a. At equal force a Hertzian contact's
//! radius is a = (3 F R / 4 E*)^(1/3), so the real contact radius is a (E*/E*_real)^(1/3).

use dashpot_sdk::{BoundHeat, Coefficient, HeatContact, HeatFlow, HeatLaw, LawError, MaterialPair, Range};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct HeatRadiusCorrected {
        /// thermal conductivity k of the solid (required: no default)
        k: Option<f64> { unit: "W/(m·K)", range: Range::non_negative() },
        /// the real effective Young's modulus E*_real of the pair (required: the simulation's E* is the bound materials')
        young_real: Option<f64> { unit: "Pa", range: Range::positive() },
        /// exponent x of the correction (E*/E*_real)^x: 1/3 at equal force (Hertz), 1/5 at equal impact speed
        exponent: f64 { unit: "1", default: 1.0 / 3.0, range: Range::closed(0.0, 1.0) },
    }
}

/// `heat-radius-corrected` bound to a pair of materials: the conductance per contact radius,
/// 2 k (E*/E*_real)^x (W/(m·K)).
#[derive(Debug, Clone, Copy)]
pub struct BoundHeatRadiusCorrected {
    /// H / a = 2 k (E*/E*_real)^x (W/(m·K)).
    pub per_radius: f64,
}

impl HeatLaw for HeatRadiusCorrected {
    type Bound = BoundHeatRadiusCorrected;
    const NAME: &'static str = "heat-radius-corrected";
    const SUMMARY: &'static str =
        "Heat conduction Q = 2 k a (E*/E*_real)^x (T_j − T_i): heat-radius with the real contact radius of softened particles";
    const DOC: &'static str = "Batchelor–O'Brien conduction (`heat-radius`, H = 2 k a) through the contact \
        radius the particles would have with their real stiffness: H = 2 k a (E*/E*_real)^x (W/K), \
        Q = H (T_j − T_i) (W), with a the normal law's contact radius (m), E* the effective Young's modulus \
        of the bound materials (Pa, the simulation's, usually softened for a larger time step) and \
        E*_real the real one (`young_real`, Pa). At equal force a Hertzian a = (3 F R/4 E*)^(1/3), hence \
        x = 1/3 (the default); at equal impact speed a ∝ E*^(-1/5), x = 1/5 (Morris, Pannala, Ma & Hrenya, \
        Int. J. Heat Mass Transf. 2016, used by Lethe; LIGGGHTS's area_correction scales δ instead). \
        With young_real = E* it is `heat-radius`. LAMMPS's heat models have no such correction: a plugin \
        adds it at run time. Stateless (no history).";
    const READS_CONTEXT: bool = true;

    fn check(&self) -> Result<(), LawError> {
        match (self.k, self.young_real) {
            (Some(_), Some(_)) => Ok(()),
            _ => Err(LawError::invalid_parameter(
                "heat-radius-corrected needs the conductivity k (W/(m·K), ≥ 0) and the real effective \
                 Young's modulus young_real (Pa, > 0); neither has a default",
            )),
        }
    }

    fn bind(&self, m: &MaterialPair) -> Result<BoundHeatRadiusCorrected, LawError> {
        let (k, e_real) = (self.k.unwrap_or(0.0), self.young_real.unwrap_or(m.young));
        Ok(BoundHeatRadiusCorrected {
            per_radius: 2.0 * k * (m.young / e_real).powf(self.exponent),
        })
    }
}

impl BoundHeat for BoundHeatRadiusCorrected {
    #[inline(always)]
    fn heat(&self, c: &HeatContact, _h: &mut [f64]) -> HeatFlow {
        HeatFlow::linear(
            self.per_radius * c.context.contact_radius,
            c.temperature,
            c.partner_temperature,
        )
    }

    fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        vec![Coefficient {
            name: "H/a".into(),
            unit: "W/(m·K)".into(),
            value: self.per_radius,
            doc: "conductance per contact radius, 2 k (E*/E*_real)^x".into(),
        }]
    }
}

dashpot_sdk::export_laws!(heat: [HeatRadiusCorrected]);
