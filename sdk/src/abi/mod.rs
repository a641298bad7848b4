//! The stable binary interface between a host and a law plugin (a cdylib).
//!
//! # Layout
//! A plugin exports one root module, [`PluginModule`], through abi_stable's `LibHeader`; the
//! [`export_laws!`](crate::export_laws) macro writes it. It is an abi_stable *prefix type*, so
//! that a later 0.3 release may append fields. sdk 0.1 and 0.2 plugins export the root modules
//! of their series, which this host reads through frozen copies ([`v1`], [`v2`]).
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
//! - [`ffi`]: the stable mirrors of the plain types (law descriptions, parameters,
//!   coefficients, calibration targets), frozen since 0.1 except the 0.3 law description;
//! - [`v1`]: the frozen types of sdk 0.1 (contact laws bound to one pair), still spoken to 0.1
//!   plugins;
//! - [`v2`]: the frozen types of sdk 0.2 (its law list and root module), and here its contact and
//!   tangential vtables and batches, which the host still calls in 0.2 plugins;
//! - [`kind`] and [`kinds`]: the one generic shape of every 0.3 law kind (normal, tangential,
//!   rolling, twisting), plugin and host side;
//! - `restitution`: restitution laws, whose ABI is unchanged since 0.1;
//! - `export`: the law tables of a plugin and the export macro;
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
#[doc(hidden)]
pub mod export;
pub mod ffi;
mod guard;
mod handle;
mod host;
pub mod kind;
pub mod kinds;
mod restitution;
pub mod v1;
pub mod v2;

pub use crate::error::FfiError;
#[doc(hidden)]
pub use export as __private;
pub use handle::{BoundModel, LawHandle, ModelHandle, StaticModel};
pub(crate) use host::BatchLengths;
pub use host::{
    BoundRestitutionHandle, ContactLawHandle, ContactModelHandle, LoadedPlugin, RestitutionLawHandle,
    SdkSeries, TangentialLawHandle, TangentialModelHandle,
};
pub use kind::EnergyOut;
pub use kinds::{Normal, NormalCall, Rolling, Tangential, Twisting};

use crate::pair::{MaterialPair, Pair};
use abi_stable::{
    library::RootModule,
    sabi_types::VersionStrings,
    std_types::{RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};
use ffi::{LawInfo, ParamValue};
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

/// Outcome of a batch call (sdk 0.2 and 0.3).
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

    /// Whether array `field` is an output (the force, torque, power, elastic energy or reach)
    /// rather than an input.
    pub fn is_output(field: u8) -> bool {
        matches!(
            field,
            Self::OUTPUT | Self::POWER | Self::ELASTIC | Self::REACH | Self::TORQUE
        )
    }

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

/// Declares an object owned by a plugin: an opaque pointer and its functions (a static vtable).
/// `Send + Sync`: the objects behind them are (the law traits require it), and the vtables are
/// immutable statics.
macro_rules! ffi_handle {
    ($(#[$doc:meta])* $name:ident $(<$g:ident>)?, $vt:ty) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(abi_stable::StableAbi)]
        pub struct $name$(<$g: 'static>)? {
            /// Opaque pointer to the object.
            pub obj: *mut std::ffi::c_void,
            /// Its functions.
            pub vtable: &'static $vt,
        }

        // SAFETY: see above.
        unsafe impl$(<$g>)? Send for $name$(<$g>)? {}
        // SAFETY: see above.
        unsafe impl$(<$g>)? Sync for $name$(<$g>)? {}
    };
}
pub(crate) use ffi_handle;

/// Declares the functions of a plugin object and its handle ([`ffi_handle!`]-style): a
/// configured law (`law`: its entries, then `drop`) or a bound one (`model`: its entries, then
/// `take_panic` and `drop`; `model_with_coefficients`: its entries, `coefficients`,
/// `take_panic` and `drop`). The entries are written out (abi_stable reads function pointer types
/// from the tokens); the common ones are appended in this order.
macro_rules! ffi_object {
    (law $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::ffi_object!(@vtable $(#[$doc])* $vt $(<$g>)? { $($body)* });
        $crate::abi::ffi_handle!($(#[$hdoc])* $handle $(<$g>)?, $vt $(<$g>)?);
        $crate::abi::ffi_object!(@free $handle $(<$g>)?);
    };
    (model $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::ffi_object!(@vtable $(#[$doc])* $vt $(<$g>)? {
            $($body)*
            /// The message of the last panic caught on this thread by this plugin (empty if none).
            pub take_panic: extern "C" fn() -> abi_stable::std_types::RString,
        });
        $crate::abi::ffi_handle!($(#[$hdoc])* $handle $(<$g>)?, $vt $(<$g>)?);
        $crate::abi::ffi_object!(@free $handle $(<$g>)?);
    };
    (model_with_coefficients $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::ffi_object!(model $(#[$doc])* $vt $(<$g>)? {
            $($body)*
            /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
            pub coefficients: unsafe extern "C" fn(
                obj: *const std::ffi::c_void,
                mass: f64,
                radius: f64,
            ) -> abi_stable::std_types::RResult<
                abi_stable::std_types::RVec<$crate::abi::ffi::Coefficient>,
                $crate::abi::FfiError,
            >,
        } $(#[$hdoc])* $handle);
    };
    (@vtable $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* }) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(abi_stable::StableAbi)]
        pub struct $vt$(<$g: 'static>)? {
            $($body)*
            /// Frees `obj`.
            pub drop: unsafe extern "C" fn(obj: *mut std::ffi::c_void),
        }
    };
    (@free $handle:ident $(<$g:ident>)?) => {
        impl$(<$g: 'static>)? $crate::abi::FfiObject for $handle$(<$g>)? {
            unsafe fn free(&self) {
                // SAFETY: as the caller promises.
                unsafe { (self.vtable.drop)(self.obj) }
            }
        }
    };
}
pub(crate) use ffi_object;

/// A plugin object (every [`ffi_object!`] handle), which its vtable's `drop` frees.
pub(crate) trait FfiObject {
    /// Frees the object.
    ///
    /// # Safety
    /// Once, and the object is not used after.
    unsafe fn free(&self);
}

/// A plugin object this side owns: freed through its vtable when dropped.
pub(crate) struct Owned<H: FfiObject>(pub(crate) H);

impl<H: FfiObject> Owned<H> {
    /// The object a plugin's call returned, now owned here, or the call's error.
    pub(crate) fn take(r: RResult<H, FfiError>) -> Result<Owned<H>, crate::LawError> {
        r.into_result().map(Owned).map_err(Into::into)
    }
}

impl<H: FfiObject> std::ops::Deref for Owned<H> {
    type Target = H;
    fn deref(&self) -> &H {
        &self.0
    }
}

impl<H: FfiObject> Drop for Owned<H> {
    fn drop(&mut self) {
        // SAFETY: the object is this side's, freed here once, and unreachable after.
        unsafe { self.0.free() }
    }
}

/// Declares a frozen series' law description: its `LawKind` (the kinds it had) and `LawInfo`
/// (with the per-contact `history` slots from sdk 0.2 on), and the plain description of one.
macro_rules! frozen_law_info {
    ($series:literal, [$($kind:ident = $n:literal: $kdoc:literal),*] $(, $history:ident)?) => {
        #[doc = concat!("Which kind of law (sdk ", $series, ").")]
        #[repr(u8)]
        #[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum LawKind {
            $(#[doc = $kdoc] $kind = $n,)*
        }

        #[doc = concat!("A law's description (sdk ", $series, ").")]
        #[repr(C)]
        #[derive(StableAbi, Debug, Clone, PartialEq)]
        pub struct LawInfo {
            /// Name.
            pub name: RString,
            /// Kind.
            pub kind: LawKind,
            /// One line.
            pub summary: RString,
            /// Documentation.
            pub doc: RString,
            /// Parameter schema.
            pub params: RVec<super::ffi::ParamSpec>,
            /// End criterion of a contact law.
            pub end_criterion: ROption<EndCriterion>,
            $(
                /// Per-contact history slots.
                pub $history: RVec<super::ffi::HistorySlot>,
            )?
        }

        impl LawInfo {
            #[doc = concat!("The plain description of an sdk ", $series, " law.")]
            pub fn upgrade(self) -> crate::LawInfo {
                let history = [Vec::new() $(, super::ffi::to_plain(self.$history))?];
                crate::LawInfo {
                    name: self.name.into_string(),
                    kind: match self.kind {
                        $(LawKind::$kind => crate::LawKind::$kind,)*
                    },
                    summary: self.summary.into_string(),
                    doc: self.doc.into_string(),
                    params: super::ffi::to_plain(self.params),
                    end_criterion: self.end_criterion.into_option(),
                    history: history.into_iter().last().unwrap_or_default(),
                }
            }
        }
    };
}
pub(crate) use frozen_law_info;

ffi_object!(law
    /// The functions of a configured restitution law (unchanged since sdk 0.1).
    RestitutionLawVTable {
        /// Binds the law at `obj` to `pair`.
        pub bind: unsafe extern "C" fn(obj: *const c_void, pair: &Pair) -> RResult<FfiBoundRestitution, FfiError>,
    }
    /// A configured restitution law owned by the plugin that made it.
    FfiRestitutionLaw
);

ffi_object!(model
    /// The hot-path functions of a restitution law bound to a pair (unchanged since sdk 0.1).
    BoundRestitutionVTable {
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
    }
    /// A restitution law bound to a pair, owned by the plugin that made it.
    FfiBoundRestitution
);

/// Declares the root module of a series (an abi_stable prefix type, referred to by
/// `PluginModuleRef`): the plugin's identity, the series' own law list and constructors
/// (`$entries`), the two entries no series has changed (a restitution law's constructor and the
/// closed-form calibration, the last prefix field: what the host reads from a plugin of any
/// series), then the fields appended after the prefix (`$later`). Only tokens that every series
/// declared the same are written here: each series' layout is the one it was released with.
macro_rules! root_module {
    ($(#[$doc:meta])* { $($entries:tt)* } $($later:tt)*) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(abi_stable::StableAbi)]
        #[sabi(kind(Prefix(prefix_ref = PluginModuleRef)))]
        #[sabi(missing_field(panic))]
        pub struct PluginModule {
            /// The plugin crate's name.
            pub name: abi_stable::std_types::RStr<'static>,
            /// The plugin crate's version.
            pub version: abi_stable::std_types::RStr<'static>,
            /// The dashpot-sdk version it was built against (its `ABI_VERSION`).
            pub sdk_version: abi_stable::std_types::RStr<'static>,
            $($entries)*
            /// Creates restitution law `name` (the ABI of sdk 0.1).
            pub new_restitution: extern "C" fn(
                name: abi_stable::std_types::RStr<'_>,
                params: abi_stable::std_types::RSlice<'_, $crate::abi::ffi::ParamValue>,
            ) -> abi_stable::std_types::RResult<$crate::abi::FfiRestitutionLaw, $crate::error::FfiError>,
            /// Closed-form parameters of contact law `name` that reproduce `target` for `pair`,
            /// given the parameters the user fixed; `RNone` when the law has no closed form for
            /// it.
            #[sabi(last_prefix_field)]
            pub calibrate: extern "C" fn(
                name: abi_stable::std_types::RStr<'_>,
                target: &$crate::abi::ffi::CalibrationTarget,
                pair: &$crate::pair::Pair,
                fixed: abi_stable::std_types::RSlice<'_, $crate::abi::ffi::ParamValue>,
            ) -> abi_stable::std_types::RResult<
                abi_stable::std_types::ROption<abi_stable::std_types::RVec<$crate::abi::ffi::ParamValue>>,
                $crate::error::FfiError,
            >,
            $($later)*
        }
    };
}
pub(crate) use root_module;

root_module!(
    /// The root module every sdk 0.3 plugin exports (an abi_stable prefix type: a later 0.3
    /// release may append fields after the last prefix field without breaking older plugins,
    /// whose missing fields then read as `None`).
    {
        /// Every law the plugin exports, of every kind.
        pub laws: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
        /// Creates contact law `name` from parameters (validated against its schema).
        pub new_contact: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiNormalBatch3>, FfiError>,
        /// Creates tangential law `name`.
        pub new_tangential: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch>, FfiError>,
        /// Creates rolling law `name`.
        pub new_rolling: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch>, FfiError>,
        /// Creates twisting law `name`.
        pub new_twisting: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiTwistingBatch>, FfiError>,
    }
);

impl RootModule for PluginModuleRef {
    abi_stable::declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "dashpot_plugin";
    const NAME: &'static str = "dashpot plugin";
    const VERSION_STRINGS: VersionStrings = VersionStrings::new(ABI_VERSION);
}

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
