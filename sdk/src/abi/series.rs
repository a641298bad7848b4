//! What every sdk series shares: the restitution ABI and the status of its calls (unchanged
//! since sdk 0.1), and the macros that declare each series' law description and root module
//! (each series' layout is the one it was released with).

use super::object::ffi_object;
use crate::error::FfiError;
use crate::pair::Pair;
use abi_stable::{std_types::RResult, StableAbi};
use std::ffi::c_void;

/// Outcome of a 0.1 hot-path call (also used by restitution laws, unchanged in 0.2).
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq)]
pub enum CallStatus {
    /// The output was written.
    Ok = 0,
    /// The law panicked; the message is available from the vtable's `take_panic`.
    Panic = 1,
    /// A batch output is NaN or infinite; its index was written to `first_bad`.
    NonFinite = 2,
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
            pub params: RVec<$crate::abi::ffi::ParamSpec>,
            /// End criterion of a contact law.
            pub end_criterion: ROption<EndCriterion>,
            $(
                /// Per-contact history slots.
                pub $history: RVec<$crate::abi::ffi::HistorySlot>,
            )?
        }

        impl LawInfo {
            #[doc = concat!("The plain description of an sdk ", $series, " law.")]
            pub fn upgrade(self) -> crate::LawInfo {
                let history = [Vec::new() $(, $crate::abi::ffi::to_plain(self.$history))?];
                crate::LawInfo {
                    name: self.name.into_string(),
                    kind: match self.kind {
                        $(LawKind::$kind => crate::LawKind::$kind,)*
                    },
                    summary: self.summary.into_string(),
                    doc: self.doc.into_string(),
                    params: $crate::abi::ffi::to_plain(self.params),
                    end_criterion: self.end_criterion.into_option(),
                    history: history.into_iter().last().unwrap_or_default(),
                    reads_context: false,
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
        pub restitution: unsafe extern "C" fn(obj: *const c_void, speed: f64, out: *mut f64) -> CallStatus,
        /// `out[i] = r(speed[i])` for `i < n`; outputs checked in blocks, the first bad index in
        /// `*first_bad`.
        pub restitution_batch: unsafe extern "C" fn(
            obj: *const c_void,
            speed: *const f64,
            out: *mut f64,
            n: usize,
            first_bad: *mut usize,
        ) -> CallStatus,
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
            ) -> abi_stable::std_types::RResult<$crate::abi::series::FfiRestitutionLaw, $crate::error::FfiError>,
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
