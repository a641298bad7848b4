//! The root module of the current series: what every plugin of this sdk exports.

use super::ffi::{LawInfo, ParamValue};
use super::series::root_module;
use super::version::ABI_VERSION;
use super::{kind, kinds};
use crate::error::FfiError;
use abi_stable::{
    library::RootModule,
    sabi_types::VersionStrings,
    std_types::{RResult, RSlice, RStr, RVec},
};

root_module!(
    /// The root module every sdk 0.4 plugin exports (an abi_stable prefix type: a later 0.4
    /// release may append fields after the last prefix field without breaking older plugins,
    /// whose missing fields then read as `None`).
    {
        /// Every law the plugin exports, of every kind.
        pub laws: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
        /// Creates contact law `name` from parameters (validated against its schema).
        pub new_contact: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiNormalBatch4>, FfiError>,
        /// Creates tangential law `name`.
        pub new_tangential: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch4>, FfiError>,
        /// Creates rolling law `name`.
        pub new_rolling: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiVectorBatch4>, FfiError>,
        /// Creates twisting law `name`.
        pub new_twisting: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiTwistingBatch4>, FfiError>,
        /// Creates heat law `name`.
        pub new_heat: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<kind::FfiLaw<kinds::FfiHeatBatch>, FfiError>,
    }
);

impl RootModule for PluginModuleRef {
    abi_stable::declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "dashpot_plugin";
    const NAME: &'static str = "dashpot plugin";
    const VERSION_STRINGS: VersionStrings = VersionStrings::new(ABI_VERSION);
}
