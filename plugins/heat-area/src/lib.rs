//! Contact heat conduction through the contact disc's area: Q = h π a² (T_j − T_i), LAMMPS's
//! `heat area h`.

use dashpot_sdk::{BoundHeat, HeatContact, HeatFlow, HeatLaw, LawError, MaterialPair, Range};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct HeatArea {
        /// heat transfer coefficient h of the contact (required: no default; LAMMPS's `heat area h`)
        h: Option<f64> { unit: "W/(m²·K)", range: Range::non_negative() },
    }
}

/// `heat-area` bound to a pair of materials: its heat transfer coefficient h (W/(m²·K)).
#[derive(Debug, Clone, Copy)]
pub struct BoundHeatArea {
    /// Heat transfer coefficient h (W/(m²·K)).
    pub h: f64,
}

impl HeatLaw for HeatArea {
    type Bound = BoundHeatArea;
    const NAME: &'static str = "heat-area";
    const SUMMARY: &'static str =
        "Heat conduction through the contact area: Q = h π a² (T_j − T_i) (LAMMPS `heat area h`)";
    const DOC: &'static str = "Conduction of heat through the contact area A = π a²: H = h π a² (W/K), \
        Q = H (T_j − T_i) (W) into the particle, with a the contact radius the normal law reports (m; the \
        Hertzian √(R δ) for a law that reports none, JKR's own a, positive past touching until rupture) \
        and h the contact's heat transfer coefficient (W/(m²·K), required). LAMMPS `pair_style granular \
        ... heat area h` (and `fix wall/gran ... heat area h`), used by its example in.pour.heat \
        (`heat area 5.0`). Against a wall, pass the wall's temperature as T_j. For two materials LAMMPS \
        mixes h as √(h_i h_j): give the mixed value. With Hertzian contacts a ∝ F^(1/3), so H ∝ F^(2/3) \
        (`heat-radius`: F^(1/3)). Stateless (no history).";
    const READS_CONTEXT: bool = true;

    fn check(&self) -> Result<(), LawError> {
        match self.h {
            Some(_) => Ok(()),
            None => Err(LawError::invalid_parameter(
                "heat-area needs the heat transfer coefficient h (W/(m²·K), ≥ 0), e.g. h=5.0; it has no default",
            )),
        }
    }

    fn bind(&self, _m: &MaterialPair) -> Result<BoundHeatArea, LawError> {
        Ok(BoundHeatArea {
            h: self.h.unwrap_or(0.0),
        })
    }
}

impl BoundHeat for BoundHeatArea {
    #[inline(always)]
    fn heat(&self, c: &HeatContact, _h: &mut [f64]) -> HeatFlow {
        let a = c.context.contact_radius;
        HeatFlow::linear(
            self.h * std::f64::consts::PI * a * a,
            c.temperature,
            c.partner_temperature,
        )
    }
}

dashpot_sdk::export_laws!(heat: [HeatArea]);
