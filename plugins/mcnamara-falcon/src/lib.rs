//! The velocity-dependent restitution of McNamara & Falcon (PRE 71, 031302, 2005, eq. 1):
//! viscoelastic 1 − r ∝ v^{1/5} below the yield speed v_y, plastic r ∝ v^{−1/4} above.

use dashpot_sdk::{BoundRestitution, LawError, Pair, Range, RestitutionLaw};

dashpot_sdk::law_params! {
    /// r(v) = 1 − (1 − r0)(v/v_y)^{1/5} for v ≤ v_y; r0 (v/v_y)^{−1/4} for v ≥ v_y.
    #[derive(Debug, Clone, Copy)]
    pub struct McNamaraFalcon {
        /// restitution at the yield speed
        pub r0: f64 { unit: "1", default: 0.95, range: Range::open_closed(0.0, 1.0) },
        /// yield speed
        pub vy: f64 { unit: "m/s", default: 0.3, range: Range::positive() },
    }
}

impl RestitutionLaw for McNamaraFalcon {
    type Bound = Self;
    const NAME: &'static str = "mcnamara-falcon";
    const SUMMARY: &'static str =
        "r(v): 1 − (1 − r0)(v/vy)^{1/5} below the yield speed vy, r0 (v/vy)^{−1/4} above";
    const DOC: &'static str = "Velocity-dependent restitution of McNamara & Falcon (PRE 71, 031302, \
        2005, eq. 1), joining viscoelastic dissipation at low speed (1 − r ∝ v^{1/5}) and plastic \
        yield at high speed (r ∝ v^{−1/4}) at the yield speed vy, where r = r0. v is the normal \
        relative impact speed (its absolute value is used). r → 1 as v → 0, which keeps \
        event-driven simulations free of inelastic collapse. Defaults: stainless steel, r0 = 0.95, \
        vy = 0.3 m/s, giving r(1 m/s) ≈ 0.703. Independent of the pair.";

    fn bind(&self, _pair: &Pair) -> Result<Self, LawError> {
        Ok(*self)
    }
}

impl BoundRestitution for McNamaraFalcon {
    #[inline]
    fn restitution(&self, speed: f64) -> f64 {
        let x = speed.abs() / self.vy;
        if x <= 1.0 {
            1.0 - (1.0 - self.r0) * x.powf(0.2)
        } else {
            self.r0 * x.powf(-0.25)
        }
    }
}

dashpot_sdk::export_laws!(restitution: [McNamaraFalcon]);
