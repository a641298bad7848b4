//! # dashpot-sdk: the contract between dashpot hosts and law plugins
//!
//! A *law* is one of
//! - a **contact law**: the normal force F (N) between two particles (or a particle and a wall)
//!   at overlap δ (m) and overlap rate δ̇ (m/s), for a contact of effective mass m (kg) and
//!   radius r (m), possibly remembering something per contact (a plastic law: its largest
//!   overlap);
//! - a **tangential law** (sdk 0.2): the friction force at the contact point (N), capped by
//!   Coulomb's μ|F_n|, from the contact points' relative velocity and a per-contact history (a
//!   spring's displacement), composable at run time with any contact law;
//! - a **rolling law** (sdk 0.3): a rolling-resistance force F_r (N) from the rolling velocity
//!   R_eff (ω_i − ω_j) × n̂ (m/s), with its own history; the torque on the particle is
//!   R_eff n̂ × F_r (see [`RollingLaw`] for the conventions);
//! - a **twisting law** (sdk 0.3): a twisting torque (N·m) about the normal from the twisting
//!   rate (ω_i − ω_j)·n̂ (rad/s), with its own history ([`TwistingLaw`]);
//! - a **heat law** (sdk 0.4): the heat flow Q (W) into the particle through the contact, and
//!   its conductance H (W/K), from the two temperatures (K) and the normal law's contact radius
//!   ([`HeatLaw`]; Q_ji = −Q_ij exactly, the host integrates the temperatures);
//! - a **restitution law**: the coefficient of restitution r(v) at normal impact speed v (m/s).
//!
//! sdk 0.4 couples the kinds of one contact: a contact law reports, per contact, a
//! [`NormalContext`] (its contact radius a, m; the force the caps of the other laws scale with,
//! N; its normal damping coefficient, N·s/m: [`BoundContact::context`], by default the Hertzian
//! a = √(R max(δ, 0)), max(F, 0) and 0), and a tangential, rolling or twisting law that declares
//! `READS_CONTEXT` receives it in its contact's `context` field; hosts compute the contexts only
//! for such laws.
//!
//! sdk 0.3 also lets a contact law be **adhesive**: its force may be tensile, and it declares its
//! reach ([`BoundContact::reach`], m): the contact lasts until δ < −reach, so callers keep it (and
//! its history) beyond touching. And every kind may report the **energy** of each contact
//! ([`Energy`]: dissipated power, W, and elastic energy stored, J) into optional output arrays
//! of a batch call; a law that does not (the trait default) reports it as not available.
//!
//! A law is its parameters: a plain struct declared once with [`law_params!`], which writes its
//! schema ([`ParamSpec`]: name, unit, default, range, doc) from the same list; the sdk validates
//! named values ([`Params`]) against the schema and reads the struct from them, so a law never
//! looks a parameter up by name. Then it is *bound* once to what
//! does not change from contact to contact: a [`MaterialPair`] (effective Young's and shear
//! moduli) for contact and tangential laws, a [`Pair`] for restitution laws. The hot path is a
//! batch call over structure-of-arrays ([`NormalBatch`], [`TangentialBatch`]) in which every
//! contact carries its own effective mass and radius and its own history slots, which the
//! caller stores (zero at first touch) and the law updates in place: laws stay stateless and
//! `Send + Sync`, and a DEM code with a continuous size distribution binds once per pair of
//! materials, not per pair of sizes.
//!
//! A plugin is a `cdylib` crate that implements [`ContactLaw`], [`TangentialLaw`],
//! [`RollingLaw`], [`TwistingLaw`], [`HeatLaw`] or [`RestitutionLaw`] and calls [`export_laws!`] once; it
//! sees plain Rust types only (`String`, `Vec`, `Option`). The [`abi`] module defines the stable
//! binary interface (abi_stable, one generic shape per law kind, and the stable mirrors of the
//! plain types) and the host-side loader with its checks; a host of sdk 0.4 still loads plugins
//! built against sdk 0.1, 0.2 and 0.3.
//!
//! ```
//! use dashpot_sdk::*;
//!
//! law_params! {
//!     /// F = k δ (a plain Hooke spring).
//!     pub struct Hooke {
//!         /// spring constant
//!         k: f64 { unit: "N/m", default: 1e5, range: Range::positive() },
//!     }
//! }
//!
//! impl ContactLaw for Hooke {
//!     type Bound = Self;
//!     const NAME: &'static str = "hooke";
//!     const SUMMARY: &'static str = "Hooke spring F = k δ, no damping";
//!     const DOC: &'static str = "F = k δ for δ > 0.";
//!     const END_CRITERION: EndCriterion = EndCriterion::Overlap;
//!     fn bind(&self, _materials: &MaterialPair) -> Result<Self, LawError> { Ok(Hooke { k: self.k }) }
//! }
//! impl BoundContact for Hooke {
//!     fn force(&self, c: Contact, _history: &mut [f64]) -> f64 { self.k * c.delta.max(0.0) }
//! }
//! dashpot_sdk::export_laws!(contact: [Hooke]);
//! # fn main() {}
//! ```

#![warn(missing_docs)]

pub mod abi;
mod context;
mod energy;
mod error;
mod heat;
mod law;
mod lengths;
mod motion;
mod pair;
mod params;
pub mod physics;
mod rotation;
#[cfg(target_arch = "x86_64")]
pub mod simd;
#[cfg(feature = "testkit")]
pub mod testkit;

/// The law author's guide, `docs/writing-a-law.md`: its Rust examples compile (and their laws
/// export) as doc tests, so the guide cannot drift from the sdk.
#[cfg(doctest)]
#[doc = include_str!("../../docs/writing-a-law.md")]
pub struct WritingALawGuide;

pub use context::NormalContext;
pub use error::{ErrorKind, LawError};
pub use heat::{BoundHeat, HeatBatch, HeatContact, HeatFlow, HeatLaw};
pub use law::{
    BoundContact, BoundRestitution, CalibrationTarget, Coefficient, Contact, ContactLaw, EndCriterion,
    Energy, EnergyBatch, History, HistorySlot, LawInfo, LawKind, NormalBatch, RestitutionLaw,
};
pub use motion::{
    BoundTangential, TangentialBatch, TangentialContact, TangentialLaw, VectorBatch, VectorContact,
};
pub use pair::{MaterialPair, Pair, Particle};
#[doc(hidden)]
pub use params::join_doc as __join_doc;
pub use params::{LawParams, ParamField, ParamSpec, ParamValue, Params, Range};
pub use rotation::{
    BoundRolling, BoundTwisting, RollingBatch, RollingContact, RollingLaw, TwistingBatch, TwistingContact,
    TwistingLaw,
};
