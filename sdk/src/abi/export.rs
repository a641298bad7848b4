//! The law tables the export macro builds, the root-module functions that read them, and the
//! export macro itself. Implementation details of [`export_laws!`](crate::export_laws); not a
//! stable API.

use super::ffi;
use super::kind::{find, Entry};
use crate::error::{FfiError, LawError};
use crate::law::{CalibrationTarget, ContactLaw, LawInfo};
use crate::pair::Pair;
use crate::params::{ParamValue, Params};
use abi_stable::std_types::{ROption, RResult, RSlice, RStr, RVec};

pub use super::guard::{guard, install_quiet_panic_hook};
pub use super::kind::{new_law, CreateFn};
pub use super::restitution::CreateRestitution;
pub use abi_stable;

/// A contact law's closed-form calibration, as stored in the export tables.
pub type CalibrateFn =
    fn(&CalibrationTarget, &Pair, &[ParamValue]) -> Result<Option<Vec<ParamValue>>, LawError>;

impl Entry<CalibrateFn> {
    /// The calibration of contact law `T`.
    pub const fn calibration<T: ContactLaw>() -> Entry<CalibrateFn> {
        Entry {
            name: T::NAME,
            make: calibrate_contact::<T>,
        }
    }
}

fn calibrate_contact<T: ContactLaw>(
    target: &CalibrationTarget,
    pair: &Pair,
    fixed: &[ParamValue],
) -> Result<Option<Vec<ParamValue>>, LawError> {
    pair.validate()?;
    let params = Params::resolve(T::NAME, &T::schema(), fixed)?;
    T::calibrate(target, pair, &params)
}

/// Every law's description (the root module's `laws`).
pub fn laws(infos: &[fn() -> LawInfo]) -> RResult<RVec<ffi::LawInfo>, FfiError> {
    guard("listing laws", || {
        Ok(infos.iter().map(|f| ffi::LawInfo::from(&f())).collect())
    })
}

/// A contact law's closed-form calibration, by name (the root module's `calibrate`).
pub fn calibrate(
    table: &[Entry<CalibrateFn>],
    name: RStr<'_>,
    target: &ffi::CalibrationTarget,
    pair: &Pair,
    fixed: RSlice<'_, ffi::ParamValue>,
) -> RResult<ROption<RVec<ffi::ParamValue>>, FfiError> {
    guard(&format!("contact law '{name}' (calibrate)"), || {
        let fixed: Vec<ParamValue> = fixed.iter().cloned().map(ParamValue::from).collect();
        let found = find(table, "contact", name.as_str())?(&(*target).into(), pair, &fixed)?;
        Ok(found.map(|v| ffi::to_ffi(&v)).into())
    })
}

/// Exports laws from a plugin crate (`crate-type = ["cdylib"]`). Use once per crate, naming
/// the laws of each kind it exports (any of the five groups, in this order):
///
/// ```text
/// dashpot_sdk::export_laws!(contact: [MyLaw]);
/// dashpot_sdk::export_laws!(restitution: [MyRestitution]);
/// dashpot_sdk::export_laws!(tangential: [MyFriction]);
/// dashpot_sdk::export_laws!(rolling: [MyRolling], twisting: [MyTwisting]);
/// dashpot_sdk::export_laws!(contact: [A, B], restitution: [C], tangential: [D]);
/// ```
#[macro_export]
macro_rules! export_laws {
    (
        $(contact: [$($c:ty),* $(,)?])? $(,)?
        $(restitution: [$($r:ty),* $(,)?])? $(,)?
        $(tangential: [$($t:ty),* $(,)?])? $(,)?
        $(rolling: [$($ro:ty),* $(,)?])? $(,)?
        $(twisting: [$($tw:ty),* $(,)?])? $(,)?
    ) => {
        #[doc(hidden)]
        mod __dashpot_export {
            #[allow(unused_imports)]
            use super::*;
            use $crate::abi::__private as p;
            use $crate::abi::__private::abi_stable::{
                library::{LibHeader, RootModuleResult, CheckTypeLayout},
                prefix_type::PrefixTypeTrait,
                std_types::{ROption, RResult, RSlice, RStr, RVec},
            };
            use $crate::abi::{self, ffi, kind::Entry, kinds, FfiError, Normal, Rolling, Tangential, Twisting};

            static INFO: &[fn() -> $crate::LawInfo] = &[
                $($(<$c as $crate::ContactLaw>::info,)*)?
                $($(<$r as $crate::RestitutionLaw>::info,)*)?
                $($(<$t as $crate::TangentialLaw>::info,)*)?
                $($(<$ro as $crate::RollingLaw>::info,)*)?
                $($(<$tw as $crate::TwistingLaw>::info,)*)?
            ];
            static CONTACT: &[Entry<p::CreateFn<kinds::FfiNormalBatch3>>] =
                &[$($(Entry::of::<Normal, $c>()),*)?];
            static CALIBRATE: &[Entry<p::CalibrateFn>] = &[$($(Entry::calibration::<$c>()),*)?];
            static RESTITUTION: &[Entry<p::CreateRestitution>] = &[$($(Entry::restitution::<$r>()),*)?];
            static TANGENTIAL: &[Entry<p::CreateFn<kinds::FfiVectorBatch>>] =
                &[$($(Entry::of::<Tangential, $t>()),*)?];
            static ROLLING: &[Entry<p::CreateFn<kinds::FfiVectorBatch>>] =
                &[$($(Entry::of::<Rolling, $ro>()),*)?];
            static TWISTING: &[Entry<p::CreateFn<kinds::FfiTwistingBatch>>] =
                &[$($(Entry::of::<Twisting, $tw>()),*)?];

            extern "C" fn laws() -> RResult<RVec<ffi::LawInfo>, FfiError> {
                p::laws(INFO)
            }
            extern "C" fn new_contact(
                name: RStr<'_>,
                params: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<kinds::FfiNormalBatch3>, FfiError> {
                p::new_law(CONTACT, "contact", name, params)
            }
            extern "C" fn new_tangential(
                name: RStr<'_>,
                params: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<kinds::FfiVectorBatch>, FfiError> {
                p::new_law(TANGENTIAL, "tangential", name, params)
            }
            extern "C" fn new_rolling(
                name: RStr<'_>,
                params: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<kinds::FfiVectorBatch>, FfiError> {
                p::new_law(ROLLING, "rolling", name, params)
            }
            extern "C" fn new_twisting(
                name: RStr<'_>,
                params: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<kinds::FfiTwistingBatch>, FfiError> {
                p::new_law(TWISTING, "twisting", name, params)
            }
            extern "C" fn new_restitution(
                name: RStr<'_>,
                params: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<abi::FfiRestitutionLaw, FfiError> {
                p::new_law(RESTITUTION, "restitution", name, params)
            }
            extern "C" fn calibrate(
                name: RStr<'_>,
                target: &ffi::CalibrationTarget,
                pair: &$crate::Pair,
                fixed: RSlice<'_, ffi::ParamValue>,
            ) -> RResult<ROption<RVec<ffi::ParamValue>>, FfiError> {
                p::calibrate(CALIBRATE, name, target, pair, fixed)
            }

            fn root_module() -> abi::PluginModuleRef {
                p::install_quiet_panic_hook();
                abi::PluginModule {
                    name: RStr::from_str(env!("CARGO_PKG_NAME")),
                    version: RStr::from_str(env!("CARGO_PKG_VERSION")),
                    sdk_version: RStr::from_str(abi::ABI_VERSION),
                    laws,
                    new_contact,
                    new_tangential,
                    new_rolling,
                    new_twisting,
                    new_restitution,
                    calibrate,
                }
                .leak_into_prefix()
            }

            // The symbol abi_stable looks for (`abi_stable::library::ROOT_MODULE_LOADER_NAME`;
            // a test in dashpot-sdk pins the spelling).
            #[no_mangle]
            pub static _1as_0lib_1header_0root_bmodule_bloader: LibHeader = {
                extern "C" fn erased() -> RootModuleResult {
                    p::abi_stable::library::__call_root_module_loader(root_module)
                }
                unsafe { LibHeader::from_constructor::<abi::PluginModuleRef>(erased, CheckTypeLayout::Yes) }
            };
        }
    };
}
