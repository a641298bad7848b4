//! # dashpot-sdk: the contract between dashpot hosts and law plugins
//!
//! A *law* is either
//! - a **contact law**: the normal force F(δ, δ̇) (N) between two particles (or a particle and a
//!   wall) at overlap δ (m) and overlap rate δ̇ (m/s), or
//! - a **restitution law**: the coefficient of restitution r(v) at normal impact speed v (m/s).
//!
//! Each law publishes a parameter schema ([`ParamSpec`]: name, unit, default, range, doc), is
//! configured from named values ([`Params`], validated by the sdk), then *bound* once to a
//! [`Pair`] (effective mass, radius and modulus) so that the hot path, per pair or in batches,
//! is a pure function with every constant precomputed.
//!
//! A plugin is a `cdylib` crate that implements [`ContactLaw`] or [`RestitutionLaw`] and calls
//! [`export_laws!`] once. The [`abi`] module defines the stable binary interface (abi_stable)
//! and the host-side loader with its checks.
//!
//! ```
//! use dashpot_sdk::*;
//!
//! /// F = k δ (a plain Hooke spring).
//! pub struct Hooke { k: f64 }
//!
//! impl ContactLaw for Hooke {
//!     type Bound = Self;
//!     const NAME: &'static str = "hooke";
//!     const SUMMARY: &'static str = "Hooke spring F = k δ, no damping";
//!     const DOC: &'static str = "F = k δ for δ > 0.";
//!     const END_CRITERION: EndCriterion = EndCriterion::Overlap;
//!     fn params() -> Vec<ParamSpec> {
//!         vec![ParamSpec::new("k", "N/m", 1e5, Range::positive(), "spring constant")]
//!     }
//!     fn new(p: &Params) -> Result<Self, LawError> { Ok(Hooke { k: p.get("k")? }) }
//!     fn bind(&self, _pair: &Pair) -> Result<Self, LawError> { Ok(Hooke { k: self.k }) }
//! }
//! impl BoundContact for Hooke {
//!     fn force(&self, delta: f64, _rate: f64) -> f64 { self.k * delta.max(0.0) }
//! }
//! dashpot_sdk::export_laws!(contact: [Hooke]);
//! # fn main() {}
//! ```

#![warn(missing_docs)]

pub mod abi;
mod error;
mod law;
mod pair;
mod params;

pub use error::{ErrorKind, FfiError, LawError};
pub use law::{
    BoundContact, BoundRestitution, CalibrationTarget, Coefficient, ContactLaw, EndCriterion, LawInfo,
    LawKind, RestitutionLaw,
};
pub use pair::{Pair, Particle};
pub use params::{ParamSpec, ParamValue, Params, Range};

/// Re-exported so plugins need no direct dependency on abi_stable.
pub use abi_stable::std_types::{ROption, RString, RVec};
