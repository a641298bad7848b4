//! The two kinds of law and what a law author implements.
//!
//! Both kinds have two stages, as in every DEM code: *configure* (from validated named
//! parameters) and *bind* (to a [`Pair`], once), so that the hot path is a pure function of the
//! contact state with every constant precomputed.

use crate::error::LawError;
use crate::pair::Pair;
use crate::params::{ParamSpec, ParamValue, Params};
use abi_stable::{
    std_types::{ROption, RString, RVec},
    StableAbi,
};

/// Which kind of law.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// A normal contact force F(δ, δ̇) (N).
    Contact = 1,
    /// A restitution coefficient r(v) at normal impact speed v.
    Restitution = 2,
}

/// When a two-body contact is over. Realized restitution and contact time depend on it, so every
/// number the project reports says which criterion produced it.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EndCriterion {
    /// Contact ends when the overlap δ returns to 0 (Antypov & Elliott's convention). A damped
    /// law then pulls the particles together at the very end (a fictitious attraction).
    Overlap = 1,
    /// Contact ends when the total normal force returns to 0 on rebound (no attraction).
    Force = 2,
}

impl EndCriterion {
    /// `"overlap"` or `"force"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            EndCriterion::Overlap => "overlap",
            EndCriterion::Force => "force",
        }
    }
}

/// Everything a host needs to know about a law without creating it.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, PartialEq, serde::Serialize)]
pub struct LawInfo {
    /// The name a user selects the law by (`--law NAME`); unique within a host.
    pub name: RString,
    /// Contact or restitution law.
    pub kind: LawKind,
    /// One line: what the law is.
    pub summary: RString,
    /// Longer documentation: the formula, the parameters' meaning, conventions, references.
    pub doc: RString,
    /// The parameter schema.
    pub params: RVec<ParamSpec>,
    /// For a contact law: the end-of-contact criterion its closed-form calibration assumes.
    pub end_criterion: ROption<EndCriterion>,
}

/// A derived constant of a bound law (for example a damping coefficient), for display and tests.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, PartialEq, serde::Serialize)]
pub struct Coefficient {
    /// Symbol, e.g. `"gamma"`.
    pub name: RString,
    /// SI unit.
    pub unit: RString,
    /// Value in `unit`.
    pub value: f64,
    /// One line: what it is, with the equation it comes from.
    pub doc: RString,
}

impl Coefficient {
    /// A coefficient.
    pub fn new(name: &str, unit: &str, value: f64, doc: &str) -> Coefficient {
        Coefficient {
            name: name.into(),
            unit: unit.into(),
            value,
            doc: doc.into(),
        }
    }
}

/// What a calibration must reproduce: a measured restitution and, optionally, a contact time.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CalibrationTarget {
    /// Measured coefficient of restitution, in (0, 1].
    pub restitution: f64,
    /// Measured contact time (s), if any.
    pub contact_time: ROption<f64>,
    /// Normal impact speed (m/s) of the measurement, if known. Needed by laws whose restitution
    /// or contact time depends on it.
    pub impact_speed: ROption<f64>,
    /// The end-of-contact criterion under which restitution and contact time were defined.
    pub end: EndCriterion,
}

/// A contact law bound to a pair: the normal force on the hot path.
///
/// Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while approaching), and the
/// returned force (N) is positive when repulsive. For δ < 0 (no contact) a law returns 0.
pub trait BoundContact: Send + Sync + 'static {
    /// The normal force F(δ, δ̇) (N) at overlap `delta` (m) and overlap rate `rate` (m/s).
    fn force(&self, delta: f64, rate: f64) -> f64;

    /// `out[i] = force(delta[i], rate[i])`. The three slices have the same length (the caller
    /// guarantees it). Override only if a hand-vectorised form is faster than this loop.
    #[inline]
    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) {
        for ((o, &d), &r) in out.iter_mut().zip(delta).zip(rate) {
            *o = self.force(d, r);
        }
    }

    /// Derived constants of the bound law (stiffness, damping coefficient, ...).
    fn coefficients(&self) -> Vec<Coefficient> {
        Vec::new()
    }
}

/// A restitution law bound to a pair.
pub trait BoundRestitution: Send + Sync + 'static {
    /// The coefficient of restitution r(v) (dimensionless) at normal impact speed `speed` ≥ 0 (m/s).
    fn restitution(&self, speed: f64) -> f64;

    /// `out[i] = restitution(speed[i])`; slices of equal length.
    #[inline]
    fn restitution_batch(&self, speed: &[f64], out: &mut [f64]) {
        for (o, &v) in out.iter_mut().zip(speed) {
            *o = self.restitution(v);
        }
    }
}

/// A configurable contact law. Implement this, then export with
/// [`export_laws!`](crate::export_laws).
pub trait ContactLaw: Sized + Send + Sync + 'static {
    /// The law bound to a pair (may be `Self`).
    type Bound: BoundContact;
    /// The name users select it by.
    const NAME: &'static str;
    /// One line.
    const SUMMARY: &'static str;
    /// The formula, conventions and references.
    const DOC: &'static str;
    /// The end-of-contact criterion the law's calibration (its `eps`, say) refers to.
    const END_CRITERION: EndCriterion;

    /// The parameter schema.
    fn params() -> Vec<ParamSpec>;

    /// Creates the law from parameters already validated against [`ContactLaw::params`].
    fn new(params: &Params) -> Result<Self, LawError>;

    /// Binds to a pair (already validated): precompute everything the force needs.
    fn bind(&self, pair: &Pair) -> Result<Self::Bound, LawError>;

    /// Parameters that reproduce `target` for `pair` in closed form, or `Ok(None)` if the law
    /// has no closed form for it (hosts then fit numerically). `fixed` are values the user set.
    fn calibrate(
        _target: &CalibrationTarget,
        _pair: &Pair,
        _fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        Ok(None)
    }

    /// The law's description, for registries.
    fn info() -> LawInfo {
        LawInfo {
            name: Self::NAME.into(),
            kind: LawKind::Contact,
            summary: Self::SUMMARY.into(),
            doc: Self::DOC.into(),
            params: Self::params().into(),
            end_criterion: ROption::RSome(Self::END_CRITERION),
        }
    }
}

/// A configurable restitution law. Implement this, then export with
/// [`export_laws!`](crate::export_laws).
pub trait RestitutionLaw: Sized + Send + Sync + 'static {
    /// The law bound to a pair (may be `Self`).
    type Bound: BoundRestitution;
    /// The name users select it by.
    const NAME: &'static str;
    /// One line.
    const SUMMARY: &'static str;
    /// The formula, conventions and references.
    const DOC: &'static str;

    /// The parameter schema.
    fn params() -> Vec<ParamSpec>;

    /// Creates the law from parameters already validated against [`RestitutionLaw::params`].
    fn new(params: &Params) -> Result<Self, LawError>;

    /// Binds to a pair (already validated).
    fn bind(&self, pair: &Pair) -> Result<Self::Bound, LawError>;

    /// The law's description, for registries.
    fn info() -> LawInfo {
        LawInfo {
            name: Self::NAME.into(),
            kind: LawKind::Restitution,
            summary: Self::SUMMARY.into(),
            doc: Self::DOC.into(),
            params: Self::params().into(),
            end_criterion: ROption::RNone,
        }
    }
}
