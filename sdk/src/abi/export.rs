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

use super::guard::guard;
pub use super::guard::install_quiet_panic_hook;
pub use super::kind::CreateFn;
use super::kind::{new_law, Create, FfiLaw};
use super::kinds::{FfiHeatBatch, FfiNormalBatch4, FfiTwistingBatch4, FfiVectorBatch4};
use super::module::{PluginModule, PluginModuleRef};
pub use super::restitution::CreateRestitution;
use super::series::FfiRestitutionLaw;
use super::version::ABI_VERSION;
pub use abi_stable;
use abi_stable::prefix_type::PrefixTypeTrait;

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

/// The laws a plugin exports, kind by kind: what [`export_laws!`](crate::export_laws) writes.
/// Its root module's entries are generic over it.
pub trait Tables: 'static {
    /// The crate's name.
    const NAME: &'static str;
    /// The crate's version.
    const VERSION: &'static str;
    /// Every law's description, in the order of the macro's groups.
    const INFO: &'static [fn() -> LawInfo];
    /// The contact laws.
    const CONTACT: &'static [Entry<CreateFn<FfiNormalBatch4>>];
    /// The contact laws' closed-form calibrations.
    const CALIBRATE: &'static [Entry<CalibrateFn>];
    /// The tangential laws.
    const TANGENTIAL: &'static [Entry<CreateFn<FfiVectorBatch4>>];
    /// The rolling laws.
    const ROLLING: &'static [Entry<CreateFn<FfiVectorBatch4>>];
    /// The twisting laws.
    const TWISTING: &'static [Entry<CreateFn<FfiTwistingBatch4>>];
    /// The heat laws.
    const HEAT: &'static [Entry<CreateFn<FfiHeatBatch>>];
    /// The restitution laws.
    const RESTITUTION: &'static [Entry<CreateRestitution>];
}

/// The root module of the plugin whose laws are `T` (leaked once, on loading).
pub fn root_module<T: Tables>() -> PluginModuleRef {
    install_quiet_panic_hook();
    PluginModule {
        name: RStr::from_str(T::NAME),
        version: RStr::from_str(T::VERSION),
        sdk_version: RStr::from_str(ABI_VERSION),
        laws: laws::<T>,
        new_contact: new_kind::<T, FfiLaw<FfiNormalBatch4>, Contact>,
        new_tangential: new_kind::<T, FfiLaw<FfiVectorBatch4>, TangentialTable>,
        new_rolling: new_kind::<T, FfiLaw<FfiVectorBatch4>, RollingTable>,
        new_twisting: new_kind::<T, FfiLaw<FfiTwistingBatch4>, TwistingTable>,
        new_heat: new_kind::<T, FfiLaw<FfiHeatBatch>, HeatTable>,
        new_restitution: new_kind::<T, FfiRestitutionLaw, RestitutionTable>,
        calibrate: calibrate::<T>,
    }
    .leak_into_prefix()
}

extern "C" fn laws<T: Tables>() -> RResult<RVec<ffi::LawInfo>, FfiError> {
    guard("listing laws", || {
        Ok(T::INFO.iter().map(|f| ffi::LawInfo::from(&f())).collect())
    })
}

/// One table of [`Tables`]: the laws of kind `KIND`, made as `F`.
trait Table<T: Tables, F: 'static> {
    const KIND: crate::LawKind;
    fn table() -> &'static [Entry<Create<F>>];
}

macro_rules! table {
    ($name:ident, $kind:ident, $made:ty, $field:ident) => {
        struct $name;
        impl<T: Tables> Table<T, $made> for $name {
            const KIND: crate::LawKind = crate::LawKind::$kind;
            fn table() -> &'static [Entry<Create<$made>>] {
                T::$field
            }
        }
    };
}
table!(Contact, Contact, FfiLaw<FfiNormalBatch4>, CONTACT);
table!(TangentialTable, Tangential, FfiLaw<FfiVectorBatch4>, TANGENTIAL);
table!(RollingTable, Rolling, FfiLaw<FfiVectorBatch4>, ROLLING);
table!(TwistingTable, Twisting, FfiLaw<FfiTwistingBatch4>, TWISTING);
table!(HeatTable, Heat, FfiLaw<FfiHeatBatch>, HEAT);
table!(RestitutionTable, Restitution, FfiRestitutionLaw, RESTITUTION);

/// The root module's constructor of the laws of table `K` of plugin `T`.
extern "C" fn new_kind<T: Tables, F: 'static, K: Table<T, F>>(
    name: RStr<'_>,
    params: RSlice<'_, ffi::ParamValue>,
) -> RResult<F, FfiError> {
    new_law(K::table(), K::KIND.as_str(), name, params)
}

/// A contact law's closed-form calibration, by name (the root module's `calibrate`).
extern "C" fn calibrate<T: Tables>(
    name: RStr<'_>,
    target: &ffi::CalibrationTarget,
    pair: &Pair,
    fixed: RSlice<'_, ffi::ParamValue>,
) -> RResult<ROption<RVec<ffi::ParamValue>>, FfiError> {
    guard(&format!("contact law '{name}' (calibrate)"), || {
        let fixed: Vec<ParamValue> = fixed.iter().cloned().map(ParamValue::from).collect();
        let found = find(T::CALIBRATE, "contact", name.as_str())?(&(*target).into(), pair, &fixed)?;
        Ok(found.map(|v| ffi::to_ffi(&v)).into())
    })
}

/// Exports laws from a plugin crate (`crate-type = ["cdylib"]`). Use once per crate, naming
/// the laws of each kind it exports (any of the six groups, in this order, separated by
/// commas):
///
/// ```text
/// dashpot_sdk::export_laws!(contact: [MyLaw]);
/// dashpot_sdk::export_laws!(restitution: [MyRestitution]);
/// dashpot_sdk::export_laws!(tangential: [MyFriction]);
/// dashpot_sdk::export_laws!(rolling: [MyRolling], twisting: [MyTwisting]);
/// dashpot_sdk::export_laws!(contact: [A, B], restitution: [C], tangential: [D]);
/// dashpot_sdk::export_laws!(contact: [A], tangential: [D], twisting: [E]);
/// dashpot_sdk::export_laws!(heat: [MyConduction]);
/// dashpot_sdk::export_laws!(contact: [A], heat: [F, G]);
/// ```
#[macro_export]
macro_rules! export_laws {
    (
        $(contact: [$($c:ty),* $(,)?] $(,)?)?
        $(restitution: [$($r:ty),* $(,)?] $(,)?)?
        $(tangential: [$($t:ty),* $(,)?] $(,)?)?
        $(rolling: [$($ro:ty),* $(,)?] $(,)?)?
        $(twisting: [$($tw:ty),* $(,)?] $(,)?)?
        $(heat: [$($h:ty),* $(,)?] $(,)?)?
    ) => {
        #[doc(hidden)]
        mod __dashpot_export {
            #[allow(unused_imports)]
            use super::*;
            use $crate::abi::__private::{self as p, abi_stable::library::{CheckTypeLayout, LibHeader, RootModuleResult}};
            use $crate::abi::{kind::Entry, kinds, Heat, Normal, PluginModuleRef, Rolling, Tangential, Twisting};

            /// This crate's laws.
            pub struct Plugin;

            impl p::Tables for Plugin {
                const NAME: &'static str = env!("CARGO_PKG_NAME");
                const VERSION: &'static str = env!("CARGO_PKG_VERSION");
                const INFO: &'static [fn() -> $crate::LawInfo] = &[
                    $($(<$c as $crate::ContactLaw>::info,)*)?
                    $($(<$r as $crate::RestitutionLaw>::info,)*)?
                    $($(<$t as $crate::TangentialLaw>::info,)*)?
                    $($(<$ro as $crate::RollingLaw>::info,)*)?
                    $($(<$tw as $crate::TwistingLaw>::info,)*)?
                    $($(<$h as $crate::HeatLaw>::info,)*)?
                ];
                const CONTACT: &'static [Entry<p::CreateFn<kinds::FfiNormalBatch4>>] =
                    &[$($(Entry::of::<Normal, $c>()),*)?];
                const CALIBRATE: &'static [Entry<p::CalibrateFn>] = &[$($(Entry::calibration::<$c>()),*)?];
                const TANGENTIAL: &'static [Entry<p::CreateFn<kinds::FfiVectorBatch4>>] =
                    &[$($(Entry::of::<Tangential, $t>()),*)?];
                const ROLLING: &'static [Entry<p::CreateFn<kinds::FfiVectorBatch4>>] =
                    &[$($(Entry::of::<Rolling, $ro>()),*)?];
                const TWISTING: &'static [Entry<p::CreateFn<kinds::FfiTwistingBatch4>>] =
                    &[$($(Entry::of::<Twisting, $tw>()),*)?];
                const HEAT: &'static [Entry<p::CreateFn<kinds::FfiHeatBatch>>] =
                    &[$($(Entry::of::<Heat, $h>()),*)?];
                const RESTITUTION: &'static [Entry<p::CreateRestitution>] =
                    &[$($(Entry::restitution::<$r>()),*)?];
            }

            // The symbol abi_stable looks for (`abi_stable::library::ROOT_MODULE_LOADER_NAME`;
            // a test in dashpot-sdk pins the spelling).
            #[no_mangle]
            pub static _1as_0lib_1header_0root_bmodule_bloader: LibHeader = {
                extern "C" fn erased() -> RootModuleResult {
                    p::abi_stable::library::__call_root_module_loader(p::root_module::<Plugin>)
                }
                unsafe { LibHeader::from_constructor::<PluginModuleRef>(erased, CheckTypeLayout::Yes) }
            };
        }
    };
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
}
