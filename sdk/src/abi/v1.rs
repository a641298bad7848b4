//! The frozen types of sdk 0.1, through which a 0.2 host still talks to plugins built against
//! sdk 0.1: a contact law bound to one [`Pair`] (effective mass, radius and modulus), called
//! with (δ, δ̇) only. Their layout must never change: abi_stable compares it, field by field,
//! with the one recorded in every 0.1 plugin.

use super::ffi::Coefficient;
use super::object::ffi_object;
pub use super::series::CallStatus;
use super::series::{frozen_law_info, root_module};
use crate::error::FfiError;
use crate::law::EndCriterion;
use crate::pair::Pair;
use abi_stable::{
    std_types::{ROption, RResult, RString, RVec},
    StableAbi,
};
use std::ffi::c_void;

frozen_law_info!(
    "0.1",
    [
        Contact = 1: "A normal contact force F(δ, δ̇) (N).",
        Restitution = 2: "A restitution coefficient r(v)."
    ]
);

ffi_object!(law
    /// The functions of a configured 0.1 contact law.
    ContactLawVTable {
        /// Binds the law at `obj` to `pair`.
        pub bind: unsafe extern "C" fn(obj: *const c_void, pair: &Pair) -> RResult<FfiBoundContact, FfiError>,
    }
    /// A configured 0.1 contact law.
    FfiContactLaw
);

ffi_object!(model
    /// The hot-path functions of a 0.1 contact law bound to a pair.
    BoundContactVTable {
        /// `*out = F(delta, rate)` (N).
        pub force: unsafe extern "C" fn(obj: *const c_void, delta: f64, rate: f64, out: *mut f64) -> CallStatus,
        /// `out[i] = F(delta[i], rate[i])` for `i < n`, outputs checked, first bad index in
        /// `*first_bad`.
        pub force_batch: unsafe extern "C" fn(
            obj: *const c_void,
            delta: *const f64,
            rate: *const f64,
            out: *mut f64,
            n: usize,
            first_bad: *mut usize,
        ) -> CallStatus,
        /// The bound law's derived constants.
        pub coefficients: unsafe extern "C" fn(obj: *const c_void) -> RResult<RVec<Coefficient>, FfiError>,
    }
    /// A 0.1 contact law bound to a pair.
    FfiBoundContact
);

root_module!(
    /// The root module of an sdk 0.1 plugin, exactly as 0.1 declared it (abi_stable refuses to
    /// read a library whose prefix type has fewer fields than the host's, so 0.1 plugins are
    /// read through this frozen copy).
    {
        /// The laws.
        pub laws: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
        /// Creates a contact law.
        pub new_contact: extern "C" fn(
            name: abi_stable::std_types::RStr<'_>,
            params: abi_stable::std_types::RSlice<'_, super::ffi::ParamValue>,
        ) -> RResult<FfiContactLaw, FfiError>,
    }
);
