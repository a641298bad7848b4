//! Contact heat conduction through the contact disc's radius: Q = 2 k a (T_j − T_i), the
//! Batchelor–O'Brien conductance for conductive solids, LAMMPS's `heat radius k`.

use dashpot_sdk::{BoundHeat, HeatContact, HeatFlow, HeatLaw, LawError, MaterialPair, Range};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct HeatRadius {
        /// thermal conductivity k of the solid (required: no default; LAMMPS's `heat radius k`)
        k: Option<f64> { unit: "W/(m·K)", range: Range::non_negative() },
    }
}

/// `heat-radius` bound to a pair of materials: its conductivity k (W/(m·K)).
#[derive(Debug, Clone, Copy)]
pub struct BoundHeatRadius {
    /// Thermal conductivity k (W/(m·K)).
    pub k: f64,
}

impl HeatLaw for HeatRadius {
    type Bound = BoundHeatRadius;
    const NAME: &'static str = "heat-radius";
    const SUMMARY: &'static str =
        "Heat conduction through the contact disc: Q = 2 k a (T_j − T_i) (LAMMPS `heat radius k`)";
    const DOC: &'static str = "Conduction of heat through the contact between two conductive solids: \
        H = 2 k a (W/K), Q = H (T_j − T_i) (W) into the particle, with a the contact radius the normal law \
        reports (m; the Hertzian √(R δ) for a law that reports none, JKR's own a, positive past touching \
        until rupture) and k the solid's thermal conductivity (W/(m·K), required). This is Batchelor & \
        O'Brien's conductance for k_solid ≫ k_fluid (Proc. R. Soc. A 355, 313, 1977), used by Vargas & \
        McCarthy (AIChE J. 47, 1052, 2001), and LAMMPS `pair_style granular ... heat radius k` (and \
        `fix wall/gran ... heat radius k`). Against a wall, pass the wall's temperature as T_j. For two \
        materials LAMMPS mixes k as √(k_i k_j); Batchelor–O'Brien's dissimilar form is 4 k_i k_j/(k_i + k_j) \
        per radius: give the mixed value as k. Stateless (no history).";
    const READS_CONTEXT: bool = true;

    fn check(&self) -> Result<(), LawError> {
        match self.k {
            Some(_) => Ok(()),
            None => Err(LawError::invalid_parameter(
                "heat-radius needs the conductivity k (W/(m·K), ≥ 0), e.g. k=1.0; it has no default",
            )),
        }
    }

    fn bind(&self, _m: &MaterialPair) -> Result<BoundHeatRadius, LawError> {
        Ok(BoundHeatRadius {
            k: self.k.unwrap_or(0.0),
        })
    }
}

impl BoundHeat for BoundHeatRadius {
    #[inline(always)]
    fn heat(&self, c: &HeatContact, _h: &mut [f64]) -> HeatFlow {
        HeatFlow::linear(
            2.0 * self.k * c.context.contact_radius,
            c.temperature,
            c.partner_temperature,
        )
    }
}

dashpot_sdk::export_laws!(heat: [HeatRadius]);
