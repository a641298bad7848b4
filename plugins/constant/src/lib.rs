//! A constant coefficient of restitution, r(v) = r.

use dashpot_sdk::{BoundRestitution, LawError, Pair, Range, RestitutionLaw};

dashpot_sdk::law_params! {
    /// r(v) = r for every impact speed.
    #[derive(Debug, Clone, Copy)]
    pub struct Constant {
        /// coefficient of restitution
        pub r: f64 { unit: "1", default: 0.95, range: Range::closed(0.0, 1.0) },
    }
}

impl RestitutionLaw for Constant {
    type Bound = Self;
    const NAME: &'static str = "constant";
    const SUMMARY: &'static str = "constant coefficient of restitution r(v) = r";
    const DOC: &'static str = "The classical inelastic hard-sphere model: every collision has the \
        same normal restitution r, whatever the impact speed. With many particles and r < 1 an \
        event-driven simulation can reach inelastic collapse (infinitely many collisions in finite \
        time); use the bed driver's TC model against it. Independent of the pair.";

    fn bind(&self, _pair: &Pair) -> Result<Self, LawError> {
        Ok(*self)
    }
}

impl BoundRestitution for Constant {
    #[inline]
    fn restitution(&self, _speed: f64) -> f64 {
        self.r
    }
}

dashpot_sdk::export_laws!(restitution: [Constant]);
