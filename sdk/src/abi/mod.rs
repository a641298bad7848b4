//! The stable binary interface between a host and a law plugin (a cdylib).
//!
//! # Layout
//! A plugin exports one root module, [`PluginModule`], through abi_stable's `LibHeader`; the
//! [`export_laws!`](crate::export_laws) macro writes it. It is an abi_stable *prefix type*, so
//! that a later 0.4 release may append fields. sdk 0.1, 0.2 and 0.3 plugins export the root
//! modules of their series, which this host reads through frozen copies ([`v1`], [`v2`],
//! [`v3`]).
//!
//! The host checks, in this order, before running any of the plugin's code:
//! 1. the dashpot-sdk version the plugin was built against (its `LibHeader`, a static):
//!    this host ([`ABI_VERSION`]) loads plugins of sdk 0.1, 0.2, 0.3 and 0.4 and refuses any
//!    other series (0.5, 1.x, ...) with both versions named;
//! 2. abi_stable's layout check of every type reachable from the root module. A 0.1, 0.2 or 0.3
//!    plugin is checked against the frozen root module of its series ([`v1`], [`v2`], [`v3`]),
//!    and the only difference it may report is the sdk's package version (0.1, 0.2 or 0.3 vs
//!    0.4) of types whose layout is otherwise identical: anything else refuses the plugin.
//!
//! Then it reads the list of laws. Libraries are never unloaded; every object is freed by the
//! library that allocated it (through its vtable's `drop`).
//!
//! # Modules, from the bottom up
//! Each imports only modules listed before it (this file only declares and re-exports).
//! - `version` ([`ABI_VERSION`], [`abi_compatible`]), `fault` ([`BatchStatus`], [`BatchFault`]:
//!   how a batch call fails), [`ffi`] (the stable mirrors of the plain types: law descriptions,
//!   parameters, coefficients, calibration targets, frozen since 0.1 except the 0.3 law
//!   description), `object` (the macros that declare a plugin object's vtable and handle);
//! - `guard` (the panic guard) and `checks` (the fused input and output checks);
//! - `series`: what every series shares (the restitution ABI, unchanged since 0.1, and the
//!   macros of a series' law description and root module);
//! - [`v1`], [`v2`]: the frozen types of sdk 0.1 (contact laws bound to one pair) and 0.2 (its
//!   law list, root module, contact and tangential vtables and batches), still spoken to the
//!   plugins of those series;
//! - [`kind`]: the one generic shape of every law kind (its traits, vtables, trampolines and
//!   export entries); [`v3`]: the frozen types of sdk 0.3 (its law list, root module and raw
//!   batches, called through the generic vtables); [`kinds`]: the shape's instances (normal,
//!   tangential, rolling, twisting, whose raw batches extend 0.3's; heat, new in 0.4);
//! - `handle`: the generic host-side handles of a law of any kind;
//! - `module`: the root module of this series; `restitution`: the plugin side of restitution
//!   laws; `export`: the law tables of a plugin and the export macro;
//! - `loader`: [`LoadedPlugin`] and the series-aware handles a host calls.
//!
//! # What breaks the ABI
//! Any change to a `#[repr(C)]` type of this crate, a vtable, or the meaning of a field. Such a
//! change starts a new series (0.5 while the major is 0). Appending fields to
//! [`PluginModule`] does not.
//!
//! # Panics and bad numbers
//! Every function a plugin exports runs inside `catch_unwind`: a panicking law becomes an
//! [`ErrorKind::Panic`](crate::ErrorKind::Panic) error in the host. Batch calls check every
//! input (finite overlaps, rates and vectors; finite positive masses and radii) and every output
//! inside the plugin, fused with the computation in blocks of 64, and report the first bad
//! index, which the host turns into an error naming the index, the input and its value.

mod checks;
#[doc(hidden)]
pub mod export;
mod fault;
pub mod ffi;
mod guard;
mod handle;
pub mod kind;
pub mod kinds;
mod loader;
mod module;
mod object;
mod restitution;
mod series;
pub mod v1;
pub mod v2;
pub mod v3;
mod version;

pub use crate::error::FfiError;
#[doc(hidden)]
pub use export as __private;
pub use fault::{BatchFault, BatchStatus};
pub use handle::{BoundModel, LawHandle, ModelHandle, StaticModel};
pub use kind::EnergyOut;
pub use kinds::{Heat, Normal, NormalCall, Rolling, Tangential, Twisting};
pub use loader::{
    BoundRestitutionHandle, ContactLawHandle, ContactModelHandle, LoadedPlugin, RestitutionLawHandle,
    SdkSeries, TangentialLawHandle, TangentialModelHandle,
};
pub use module::{PluginModule, PluginModuleRef};
pub use series::{BoundRestitutionVTable, FfiBoundRestitution, FfiRestitutionLaw, RestitutionLawVTable};
pub use version::{abi_compatible, ABI_VERSION};
