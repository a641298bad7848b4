//! The stable binary interface between a host and a law plugin (a cdylib).
//!
//! # Layout
//! A plugin exports one root module, [`PluginModule`], through abi_stable's `LibHeader`; the
//! [`export_laws!`](crate::export_laws) macro writes it. It is an abi_stable *prefix type*: the
//! fields of sdk 0.1 come first and never change; sdk 0.2 appended its own after them
//! (`laws2`, `new_contact2`, `new_tangential`), and sdk 0.3 its own after those (`laws3`, ...).
//!
//! The host checks, in this order, before running any of the plugin's code:
//! 1. the dashpot-sdk version the plugin was built against (its `LibHeader`, a static):
//!    this host ([`ABI_VERSION`]) loads plugins of sdk 0.1, 0.2 and 0.3 and refuses any other
//!    series (0.4, 1.x, ...) with both versions named;
//! 2. abi_stable's layout check of every type reachable from the root module. A 0.1 or 0.2
//!    plugin is checked against the frozen root module of its series ([`v1`], [`v2`]), and the
//!    only difference it may report is the sdk's package version (0.1 or 0.2 vs 0.3) of types
//!    whose layout is otherwise identical: anything else refuses the plugin.
//!
//! Then it reads the list of laws. Libraries are never unloaded; every object is freed by the
//! library that allocated it (through its vtable's `drop`).
//!
//! # Modules
//! - [`v1`]: the frozen types of sdk 0.1 (contact laws bound to one pair), still spoken to 0.1
//!   plugins;
//! - [`v2`]: the frozen types of sdk 0.2 that 0.3 changed (the law list, whose kinds 0.3
//!   extended) and 0.2's root module;
//! - this module: the types shared by 0.2 and 0.3 (contact laws bound to a material pair with per-contact geometry
//!   and history, tangential laws, restitution laws unchanged since 0.1) and the root module;
//! - `plugin`: the trampolines compiled into every plugin and the export macro;
//! - `host`: [`LoadedPlugin`] and the safe handles a host calls.
//!
//! # What breaks the ABI
//! Any change to a `#[repr(C)]` type of this crate, a vtable, or the meaning of a field. Such a
//! change starts a new series (0.4 while the major is 0). Appending fields to
//! [`PluginModule`] does not.
//!
//! # Panics and bad numbers
//! Every function a plugin exports runs inside `catch_unwind`: a panicking law becomes an
//! [`ErrorKind::Panic`](crate::ErrorKind::Panic) error in the host. Batch calls check every
//! input (finite overlaps, rates and vectors; finite positive masses and radii) and every output
//! inside the plugin, fused with the computation in blocks of 64, and report the first bad
//! index, which the host turns into an error naming the index, the input and its value.

mod checks;
mod export;
mod handle;
mod host;
pub mod kind;
pub mod kinds;
#[doc(hidden)]
pub mod plugin;
pub mod v1;
pub mod v2;

pub use handle::{LawHandle, ModelHandle, StaticModel};
pub use host::{
    BoundRestitutionHandle, ContactLawHandle, ContactModelHandle, LoadedPlugin, RestitutionLawHandle,
    SdkSeries, StaticContact, StaticTangential, TangentialLawHandle, TangentialModelHandle,
};
pub use kind::EnergyOut;
pub use kinds::{Normal, NormalCall, Rolling, Tangential, Twisting};
#[doc(hidden)]
pub use plugin as __private;

use crate::error::FfiError;
use crate::law::{CalibrationTarget, Coefficient, LawInfo};
use crate::pair::{MaterialPair, Pair};
use crate::params::ParamValue;
use abi_stable::{
    library::RootModule,
    sabi_types::VersionStrings,
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};
use std::ffi::c_void;

/// The dashpot-sdk version a plugin or host is built against (`major.minor.patch`).
///
/// The override variable exists only so the test suite can build a deliberately incompatible
/// plugin; never set it otherwise.
pub const ABI_VERSION: &str = match option_env!("DASHPOT_SDK_FAKE_ABI_VERSION") {
    Some(v) => v,
    None => env!("CARGO_PKG_VERSION"),
};

fn series(v: &str) -> Option<(u64, u64)> {
    let mut it = v.split('.').map(|p| p.trim().parse::<u64>());
    let major = it.next()?.ok()?;
    let minor = it.next()?.ok()?;
    Some(if major == 0 { (0, minor) } else { (major, 0) })
}

/// Whether a plugin built against sdk `plugin` may be loaded by a host built against `host`:
/// the same series (the major version, or the minor while the major is 0), or, for a 0.3 host,
/// a plugin of sdk 0.1 or 0.2 (spoken to through the frozen [`v1`] and [`v2`] types).
pub fn abi_compatible(host: &str, plugin: &str) -> bool {
    match (series(host), series(plugin)) {
        (Some(a), Some(b)) if a == b => true,
        (Some((0, 3)), Some((0, 1) | (0, 2))) => true,
        _ => false,
    }
}

/// Outcome of a 0.2 batch call.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq)]
pub enum BatchStatus {
    /// Every output was written.
    Ok = 0,
    /// The law panicked; the message is available from the vtable's `take_panic`.
    Panic = 1,
    /// An output is NaN or infinite; [`BatchFault`] names the contact.
    NonFiniteOutput = 2,
    /// An input is not finite (or a mass or radius not > 0); [`BatchFault`] names the contact
    /// and the input. Nothing was computed for that block.
    BadInput = 3,
}

/// Where a batch call found a bad number.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BatchFault {
    /// Index of the contact.
    pub index: usize,
    /// Which array: [`BatchFault::OUTPUT`] or one of the input codes.
    pub field: u8,
}

impl BatchFault {
    /// The output (force).
    pub const OUTPUT: u8 = 0;
    /// Input `delta`.
    pub const DELTA: u8 = 1;
    /// Input `rate`.
    pub const RATE: u8 = 2;
    /// Input `mass`.
    pub const MASS: u8 = 3;
    /// Input `radius`.
    pub const RADIUS: u8 = 4;
    /// Input `normal`.
    pub const NORMAL: u8 = 5;
    /// Input `velocity`.
    pub const VELOCITY: u8 = 6;
    /// Input `normal_force`.
    pub const NORMAL_FORCE: u8 = 7;
    /// Input `dt`.
    pub const DT: u8 = 8;
    /// Output `power` (sdk 0.3).
    pub const POWER: u8 = 9;
    /// Output `elastic` (sdk 0.3).
    pub const ELASTIC: u8 = 10;
    /// Output `reach` (sdk 0.3).
    pub const REACH: u8 = 11;
    /// Output `torque` (sdk 0.3).
    pub const TORQUE: u8 = 12;

    /// The name of array `field`.
    pub fn field_name(field: u8) -> &'static str {
        match field {
            Self::OUTPUT => "force",
            Self::DELTA => "delta",
            Self::RATE => "rate",
            Self::MASS => "mass",
            Self::RADIUS => "radius",
            Self::NORMAL => "normal",
            Self::VELOCITY => "velocity",
            Self::NORMAL_FORCE => "normal_force",
            Self::DT => "dt",
            Self::POWER => "power",
            Self::ELASTIC => "elastic",
            Self::REACH => "reach",
            Self::TORQUE => "torque",
            _ => "?",
        }
    }
}

/// A batch of contacts for a normal law, as raw arrays (see [`NormalBatch`](crate::NormalBatch)).
/// All pointers refer to `n` values except `history` (`n × slots`); they may dangle when
/// `n == 0`.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiNormalBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Overlaps δ (m).
    pub delta: *const f64,
    /// Overlap rates δ̇ (m/s), > 0 approaching.
    pub rate: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history (`n × slots`), updated in place.
    pub history: *mut f64,
    /// Output: normal forces (N).
    pub force: *mut f64,
}

/// A batch of contacts for a tangential law, as raw arrays (see
/// [`TangentialBatch`](crate::TangentialBatch)); vectors are `n` `[x, y, z]` triples.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiTangentialBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Unit normals (3n values).
    pub normal: *const f64,
    /// Relative contact-point velocities (m/s, 3n values).
    pub velocity: *const f64,
    /// Normal forces (N).
    pub normal_force: *const f64,
    /// Overlaps (m).
    pub delta: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history (`n × slots`), updated in place.
    pub history: *mut f64,
    /// Output: tangential forces (N, 3n values).
    pub force: *mut f64,
}

/// The functions of a configured 0.2 contact law (not yet bound to materials).
#[repr(C)]
#[derive(StableAbi)]
pub struct ContactLawVTable {
    /// Binds the law at `obj` to a pair of materials.
    pub bind: unsafe extern "C" fn(
        obj: *const c_void,
        materials: &MaterialPair,
    ) -> RResult<FfiContactModel, FfiError>,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A configured 0.2 contact law owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiContactLaw {
    /// Opaque pointer to the law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static ContactLawVTable,
}

/// The hot-path functions of a contact law bound to a pair of materials.
#[repr(C)]
#[derive(StableAbi)]
pub struct ContactModelVTable {
    /// Evaluates a batch; checks inputs and outputs in blocks as it goes and stops at the first
    /// bad one, described in `*fault`.
    pub force_batch: unsafe extern "C" fn(
        obj: *const c_void,
        batch: &FfiNormalBatch,
        fault: &mut BatchFault,
    ) -> BatchStatus,
    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub coefficients: unsafe extern "C" fn(
        obj: *const c_void,
        mass: f64,
        radius: f64,
    ) -> RResult<RVec<Coefficient>, FfiError>,
    /// The message of the last panic caught on this thread by this plugin (empty if none).
    pub take_panic: extern "C" fn() -> RString,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A contact law bound to a pair of materials, owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiContactModel {
    /// Opaque pointer.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static ContactModelVTable,
}

/// The functions of a configured tangential law.
#[repr(C)]
#[derive(StableAbi)]
pub struct TangentialLawVTable {
    /// Binds the law at `obj` to a pair of materials.
    pub bind: unsafe extern "C" fn(
        obj: *const c_void,
        materials: &MaterialPair,
    ) -> RResult<FfiTangentialModel, FfiError>,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A configured tangential law owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiTangentialLaw {
    /// Opaque pointer.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static TangentialLawVTable,
}

/// The hot-path functions of a tangential law bound to a pair of materials.
#[repr(C)]
#[derive(StableAbi)]
pub struct TangentialModelVTable {
    /// Evaluates a batch, checked like [`ContactModelVTable::force_batch`].
    pub force_batch: unsafe extern "C" fn(
        obj: *const c_void,
        batch: &FfiTangentialBatch,
        fault: &mut BatchFault,
    ) -> BatchStatus,
    /// The message of the last panic caught on this thread by this plugin (empty if none).
    pub take_panic: extern "C" fn() -> RString,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A tangential law bound to a pair of materials, owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiTangentialModel {
    /// Opaque pointer.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static TangentialModelVTable,
}

/// The functions of a configured restitution law (unchanged since sdk 0.1).
#[repr(C)]
#[derive(StableAbi)]
pub struct RestitutionLawVTable {
    /// Binds the law at `obj` to `pair`.
    pub bind: unsafe extern "C" fn(obj: *const c_void, pair: &Pair) -> RResult<FfiBoundRestitution, FfiError>,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A configured restitution law owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiRestitutionLaw {
    /// Opaque pointer to the law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static RestitutionLawVTable,
}

/// The hot-path functions of a restitution law bound to a pair (unchanged since sdk 0.1).
#[repr(C)]
#[derive(StableAbi)]
pub struct BoundRestitutionVTable {
    /// `*out = r(speed)` for normal impact speed `speed` (m/s).
    pub restitution: unsafe extern "C" fn(obj: *const c_void, speed: f64, out: *mut f64) -> v1::CallStatus,
    /// `out[i] = r(speed[i])` for `i < n`; outputs checked in blocks, the first bad index in
    /// `*first_bad`.
    pub restitution_batch: unsafe extern "C" fn(
        obj: *const c_void,
        speed: *const f64,
        out: *mut f64,
        n: usize,
        first_bad: *mut usize,
    ) -> v1::CallStatus,
    /// The message of the last panic caught on this thread by this plugin (empty if none).
    pub take_panic: extern "C" fn() -> RString,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A restitution law bound to a pair, owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiBoundRestitution {
    /// Opaque pointer to the bound law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static BoundRestitutionVTable,
}

/// The root module every plugin exports (an abi_stable prefix type: fields are appended after
/// the last prefix field without breaking older plugins, whose missing fields read as `None`).
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = PluginModuleRef)))]
#[sabi(missing_field(panic))]
pub struct PluginModule {
    /// The plugin crate's name.
    pub name: RStr<'static>,
    /// The plugin crate's version.
    pub version: RStr<'static>,
    /// The dashpot-sdk version it was built against ([`ABI_VERSION`] on its side).
    pub sdk_version: RStr<'static>,
    /// sdk 0.1: the contact and restitution laws, in 0.1's description.
    pub laws: extern "C" fn() -> RResult<RVec<v1::LawInfo>, FfiError>,
    /// sdk 0.1: creates a contact law bound later to one [`Pair`]. A 0.2 plugin answers with an
    /// error (its contact laws are created by `new_contact2`).
    pub new_contact:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<v1::FfiContactLaw, FfiError>,
    /// Creates the restitution law `name` from parameters (validated against its schema).
    pub new_restitution:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiRestitutionLaw, FfiError>,
    /// Closed-form parameters of contact law `name` that reproduce `target` for `pair`, given the
    /// parameters the user fixed; `RNone` when the law has no closed form for it.
    #[sabi(last_prefix_field)]
    pub calibrate: extern "C" fn(
        name: RStr<'_>,
        target: &CalibrationTarget,
        pair: &Pair,
        fixed: RSlice<'_, ParamValue>,
    ) -> RResult<ROption<RVec<ParamValue>>, FfiError>,
    /// sdk 0.2: the contact, restitution and tangential laws, in 0.2's description.
    #[sabi(missing_field(option))]
    pub laws2: extern "C" fn() -> RResult<RVec<v2::LawInfo>, FfiError>,
    /// sdk 0.2: creates contact law `name` (bound later to a [`MaterialPair`]).
    #[sabi(missing_field(option))]
    pub new_contact2:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiContactLaw, FfiError>,
    /// sdk 0.2: creates tangential law `name`.
    #[sabi(missing_field(option))]
    pub new_tangential:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiTangentialLaw, FfiError>,
    /// sdk 0.3: every law the plugin exports, of every kind.
    #[sabi(missing_field(option))]
    pub laws3: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
    /// sdk 0.3: creates contact law `name` (reach and energy outputs).
    #[sabi(missing_field(option))]
    pub new_contact3: extern "C" fn(
        name: RStr<'_>,
        params: RSlice<'_, ParamValue>,
    ) -> RResult<kind::FfiLaw<kinds::FfiNormalBatch3>, FfiError>,
    /// sdk 0.3: creates tangential law `name` (energy outputs).
    #[sabi(missing_field(option))]
    pub new_tangential3: extern "C" fn(
        name: RStr<'_>,
        params: RSlice<'_, ParamValue>,
    ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch>, FfiError>,
    /// sdk 0.3: creates rolling law `name`.
    #[sabi(missing_field(option))]
    pub new_rolling: extern "C" fn(
        name: RStr<'_>,
        params: RSlice<'_, ParamValue>,
    ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch>, FfiError>,
    /// sdk 0.3: creates twisting law `name`.
    #[sabi(missing_field(option))]
    pub new_twisting: extern "C" fn(
        name: RStr<'_>,
        params: RSlice<'_, ParamValue>,
    ) -> RResult<kind::FfiLaw<kinds::FfiTwistingBatch>, FfiError>,
}

impl RootModule for PluginModuleRef {
    abi_stable::declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "dashpot_plugin";
    const NAME: &'static str = "dashpot plugin";
    const VERSION_STRINGS: VersionStrings = VersionStrings::new(ABI_VERSION);
}

// SAFETY: the objects behind these handles are `Send + Sync` (the law traits require it), and the
// vtables are immutable statics.
unsafe impl Send for FfiContactLaw {}
unsafe impl Sync for FfiContactLaw {}
unsafe impl Send for FfiContactModel {}
unsafe impl Sync for FfiContactModel {}
unsafe impl Send for FfiTangentialLaw {}
unsafe impl Sync for FfiTangentialLaw {}
unsafe impl Send for FfiTangentialModel {}
unsafe impl Sync for FfiTangentialModel {}
unsafe impl Send for FfiRestitutionLaw {}
unsafe impl Sync for FfiRestitutionLaw {}
unsafe impl Send for FfiBoundRestitution {}
unsafe impl Sync for FfiBoundRestitution {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn export_macro_uses_abi_stables_symbol_name() {
        assert_eq!(
            abi_stable::library::ROOT_MODULE_LOADER_NAME,
            "_1as_0lib_1header_0root_bmodule_bloader"
        );
    }

    #[test]
    fn abi_compatibility_rule() {
        assert!(abi_compatible("0.3.0", "0.3.7"));
        assert!(abi_compatible("0.3.7", "0.3.0"));
        // a 0.3 host speaks 0.1 and 0.2 through the frozen v1 and v2 types; older hosts cannot
        // speak 0.3
        assert!(abi_compatible("0.3.0", "0.1.0"));
        assert!(abi_compatible("0.3.0", "0.2.5"));
        assert!(!abi_compatible("0.1.0", "0.3.0"));
        assert!(!abi_compatible("0.2.0", "0.3.0"));
        assert!(!abi_compatible("0.3.0", "0.4.0"));
        assert!(!abi_compatible("0.3.0", "0.0.9"));
        assert!(!abi_compatible("0.3.0", "1.0.0"));
        assert!(abi_compatible("1.2.0", "1.0.3"));
        assert!(!abi_compatible("1.0.0", "2.0.0"));
        assert!(!abi_compatible("0.2.0", "garbage"));
    }
}
