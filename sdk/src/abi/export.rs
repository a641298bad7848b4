//! The law tables the export macro builds and the root-module functions that read them, and
//! the export macro itself. Implementation details of [`export_laws!`](crate::export_laws).

use super::plugin::*;
use super::v1;
use super::*;
use crate::error::{ErrorKind, LawError};
use crate::law::{ContactLaw, LawKind, RestitutionLaw, TangentialLaw};
use crate::params::Params;

/// A law's closed-form calibration, as stored in the export tables.
pub type CalibrateFn =
    fn(&CalibrationTarget, &Pair, &[ParamValue]) -> Result<Option<Vec<ParamValue>>, LawError>;

/// One exported contact law.
pub struct ContactEntry {
    /// Its name.
    pub name: &'static str,
    /// Its description.
    pub info: fn() -> LawInfo,
    /// Creates it from parameters.
    pub create: fn(&[ParamValue]) -> Result<FfiContactLaw, LawError>,
    /// Its closed-form calibration.
    pub calibrate: CalibrateFn,
}

impl ContactEntry {
    /// The entry of law `T`.
    pub const fn of<T: ContactLaw>() -> ContactEntry {
        ContactEntry {
            name: T::NAME,
            info: T::info,
            create: create_contact::<T>,
            calibrate: calibrate_contact::<T>,
        }
    }
}

fn create_contact<T: ContactLaw>(given: &[ParamValue]) -> Result<FfiContactLaw, LawError> {
    let params = Params::resolve(T::NAME, &T::params(), given)?;
    let law = T::new(&params)?;
    Ok(FfiContactLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: ContactVt::<T>::VT,
    })
}

fn calibrate_contact<T: ContactLaw>(
    target: &CalibrationTarget,
    pair: &Pair,
    fixed: &[ParamValue],
) -> Result<Option<Vec<ParamValue>>, LawError> {
    pair.validate()?;
    let params = Params::resolve(T::NAME, &T::params(), fixed)?;
    T::calibrate(target, pair, &params)
}

/// One exported tangential law.
pub struct TangentialEntry {
    /// Its name.
    pub name: &'static str,
    /// Its description.
    pub info: fn() -> LawInfo,
    /// Creates it from parameters.
    pub create: fn(&[ParamValue]) -> Result<FfiTangentialLaw, LawError>,
}

impl TangentialEntry {
    /// The entry of law `T`.
    pub const fn of<T: TangentialLaw>() -> TangentialEntry {
        TangentialEntry {
            name: T::NAME,
            info: T::info,
            create: create_tangential::<T>,
        }
    }
}

fn create_tangential<T: TangentialLaw>(given: &[ParamValue]) -> Result<FfiTangentialLaw, LawError> {
    let params = Params::resolve(T::NAME, &T::params(), given)?;
    let law = T::new(&params)?;
    Ok(FfiTangentialLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: TangentialVt::<T>::VT,
    })
}

/// One exported restitution law.
pub struct RestitutionEntry {
    /// Its name.
    pub name: &'static str,
    /// Its description.
    pub info: fn() -> LawInfo,
    /// Creates it from parameters.
    pub create: fn(&[ParamValue]) -> Result<FfiRestitutionLaw, LawError>,
}

impl RestitutionEntry {
    /// The entry of law `T`.
    pub const fn of<T: RestitutionLaw>() -> RestitutionEntry {
        RestitutionEntry {
            name: T::NAME,
            info: T::info,
            create: create_restitution::<T>,
        }
    }
}

fn create_restitution<T: RestitutionLaw>(given: &[ParamValue]) -> Result<FfiRestitutionLaw, LawError> {
    let params = Params::resolve(T::NAME, &T::params(), given)?;
    let law = T::new(&params)?;
    Ok(FfiRestitutionLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: RestitutionVt::<T>::VT,
    })
}

pub(crate) fn unknown(kind: &str, name: &str, names: Vec<&str>) -> LawError {
    LawError::new(
        ErrorKind::UnknownLaw,
        format!(
            "this plugin has no {kind} law '{name}'; it has: {}",
            if names.is_empty() {
                "(none)".to_string()
            } else {
                names.join(", ")
            }
        ),
    )
}

/// Every law's 0.3 description (`more`: the rolling and twisting laws' `info`).
pub fn laws3(
    c: &[ContactEntry],
    r: &[RestitutionEntry],
    t: &[TangentialEntry],
    more: &[fn() -> LawInfo],
) -> RResult<RVec<LawInfo>, FfiError> {
    guard("listing laws", || {
        Ok(c.iter()
            .map(|e| (e.info)())
            .chain(r.iter().map(|e| (e.info)()))
            .chain(t.iter().map(|e| (e.info)()))
            .chain(more.iter().map(|f| f()))
            .collect())
    })
}

/// The 0.2 description of the laws of the kinds 0.2 knew (a 0.2 host refuses a 0.3 plugin
/// before it asks, but the field must answer).
pub fn laws2(
    c: &[ContactEntry],
    r: &[RestitutionEntry],
    t: &[TangentialEntry],
) -> RResult<RVec<v2::LawInfo>, FfiError> {
    match laws3(c, r, t, &[]) {
        RResult::ROk(v) => RResult::ROk(v.into_iter().filter_map(v2::LawInfo::downgrade).collect()),
        RResult::RErr(e) => RResult::RErr(e),
    }
}

/// The 0.1 description of the contact and restitution laws (a 0.1 host refuses a 0.2 plugin
/// before it asks, but the field must answer).
pub fn laws_v1(c: &[ContactEntry], r: &[RestitutionEntry]) -> RResult<RVec<v1::LawInfo>, FfiError> {
    guard("listing laws", || {
        Ok(c.iter()
            .map(|e| (e.info)())
            .chain(r.iter().map(|e| (e.info)()))
            .map(|i| v1::LawInfo {
                name: i.name,
                kind: if i.kind == LawKind::Restitution {
                    v1::LawKind::Restitution
                } else {
                    v1::LawKind::Contact
                },
                summary: i.summary,
                doc: i.doc,
                params: i.params,
                end_criterion: i.end_criterion,
            })
            .collect())
    })
}

/// The 0.1 contact-law constructor of a 0.2 plugin: always an error.
pub fn new_contact_v1(name: RStr<'_>) -> RResult<v1::FfiContactLaw, FfiError> {
    RResult::RErr(
        LawError::unsupported(format!(
            "contact law '{name}' was built against dashpot-sdk {ABI_VERSION}: create it with new_contact2"
        ))
        .into(),
    )
}

/// Creates a contact law by name.
pub fn new_contact2(
    c: &[ContactEntry],
    name: RStr<'_>,
    params: RSlice<'_, ParamValue>,
) -> RResult<FfiContactLaw, FfiError> {
    guard(&format!("contact law '{name}' (new)"), || {
        match c.iter().find(|e| e.name == name.as_str()) {
            Some(e) => (e.create)(params.as_slice()),
            None => Err(unknown(
                "contact",
                name.as_str(),
                c.iter().map(|e| e.name).collect(),
            )),
        }
    })
}

/// Creates a tangential law by name.
pub fn new_tangential(
    t: &[TangentialEntry],
    name: RStr<'_>,
    params: RSlice<'_, ParamValue>,
) -> RResult<FfiTangentialLaw, FfiError> {
    guard(&format!("tangential law '{name}' (new)"), || {
        match t.iter().find(|e| e.name == name.as_str()) {
            Some(e) => (e.create)(params.as_slice()),
            None => Err(unknown(
                "tangential",
                name.as_str(),
                t.iter().map(|e| e.name).collect(),
            )),
        }
    })
}

/// Creates a restitution law by name.
pub fn new_restitution(
    r: &[RestitutionEntry],
    name: RStr<'_>,
    params: RSlice<'_, ParamValue>,
) -> RResult<FfiRestitutionLaw, FfiError> {
    guard(&format!("restitution law '{name}' (new)"), || {
        match r.iter().find(|e| e.name == name.as_str()) {
            Some(e) => (e.create)(params.as_slice()),
            None => Err(unknown(
                "restitution",
                name.as_str(),
                r.iter().map(|e| e.name).collect(),
            )),
        }
    })
}

/// A contact law's closed-form calibration, by name.
pub fn calibrate(
    c: &[ContactEntry],
    name: RStr<'_>,
    target: &CalibrationTarget,
    pair: &Pair,
    fixed: RSlice<'_, ParamValue>,
) -> RResult<ROption<RVec<ParamValue>>, FfiError> {
    guard(&format!("contact law '{name}' (calibrate)"), || {
        match c.iter().find(|e| e.name == name.as_str()) {
            Some(e) => Ok((e.calibrate)(target, pair, fixed.as_slice())?
                .map(RVec::from)
                .into()),
            None => Err(unknown(
                "contact",
                name.as_str(),
                c.iter().map(|e| e.name).collect(),
            )),
        }
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
            use $crate::{abi, CalibrationTarget, FfiError, LawInfo, Pair, ParamValue};

            static CONTACT: &[p::ContactEntry] = &[$($(p::ContactEntry::of::<$c>()),*)?];
            static RESTITUTION: &[p::RestitutionEntry] = &[$($(p::RestitutionEntry::of::<$r>()),*)?];
            static TANGENTIAL: &[p::TangentialEntry] = &[$($(p::TangentialEntry::of::<$t>()),*)?];
            static CONTACT3: &[$crate::abi::kind::Entry<$crate::abi::Normal>] =
                &[$($($crate::abi::kind::Entry::of::<$c>()),*)?];
            static TANGENTIAL3: &[$crate::abi::kind::Entry<$crate::abi::Tangential>] =
                &[$($($crate::abi::kind::Entry::of::<$t>()),*)?];
            static ROLLING: &[$crate::abi::kind::Entry<$crate::abi::Rolling>] =
                &[$($($crate::abi::kind::Entry::of::<$ro>()),*)?];
            static TWISTING: &[$crate::abi::kind::Entry<$crate::abi::Twisting>] =
                &[$($($crate::abi::kind::Entry::of::<$tw>()),*)?];
            static ROLLING_INFO: &[fn() -> LawInfo] = &[$($(<$ro as $crate::RollingLaw>::info),*)?];
            static TWISTING_INFO: &[fn() -> LawInfo] = &[$($(<$tw as $crate::TwistingLaw>::info),*)?];

            extern "C" fn laws() -> RResult<RVec<abi::v1::LawInfo>, FfiError> {
                p::laws_v1(CONTACT, RESTITUTION)
            }
            extern "C" fn laws2() -> RResult<RVec<abi::v2::LawInfo>, FfiError> {
                p::laws2(CONTACT, RESTITUTION, TANGENTIAL)
            }
            extern "C" fn laws3() -> RResult<RVec<LawInfo>, FfiError> {
                p::laws3(CONTACT, RESTITUTION, TANGENTIAL, &[ROLLING_INFO, TWISTING_INFO].concat())
            }
            extern "C" fn new_contact3(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<abi::kinds::FfiNormalBatch3>, FfiError> {
                abi::kind::new_law(CONTACT3, name, params)
            }
            extern "C" fn new_tangential3(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<abi::kinds::FfiVectorBatch>, FfiError> {
                abi::kind::new_law(TANGENTIAL3, name, params)
            }
            extern "C" fn new_rolling(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<abi::kinds::FfiVectorBatch>, FfiError> {
                abi::kind::new_law(ROLLING, name, params)
            }
            extern "C" fn new_twisting(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::kind::FfiLaw<abi::kinds::FfiTwistingBatch>, FfiError> {
                abi::kind::new_law(TWISTING, name, params)
            }
            extern "C" fn new_contact(
                name: RStr<'_>,
                _params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::v1::FfiContactLaw, FfiError> {
                p::new_contact_v1(name)
            }
            extern "C" fn new_contact2(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::FfiContactLaw, FfiError> {
                p::new_contact2(CONTACT, name, params)
            }
            extern "C" fn new_tangential(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::FfiTangentialLaw, FfiError> {
                p::new_tangential(TANGENTIAL, name, params)
            }
            extern "C" fn new_restitution(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::FfiRestitutionLaw, FfiError> {
                p::new_restitution(RESTITUTION, name, params)
            }
            extern "C" fn calibrate(
                name: RStr<'_>,
                target: &CalibrationTarget,
                pair: &Pair,
                fixed: RSlice<'_, ParamValue>,
            ) -> RResult<ROption<RVec<ParamValue>>, FfiError> {
                p::calibrate(CONTACT, name, target, pair, fixed)
            }

            fn root_module() -> abi::PluginModuleRef {
                p::install_quiet_panic_hook();
                abi::PluginModule {
                    name: RStr::from_str(env!("CARGO_PKG_NAME")),
                    version: RStr::from_str(env!("CARGO_PKG_VERSION")),
                    sdk_version: RStr::from_str(abi::ABI_VERSION),
                    laws,
                    new_contact,
                    new_restitution,
                    calibrate,
                    laws2,
                    new_contact2,
                    new_tangential,
                    laws3,
                    new_contact3,
                    new_tangential3,
                    new_rolling,
                    new_twisting,
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
