//! Host side: loading plugins, with their checks, and the series-aware handles a host calls.

use super::checks::all_finite;
use super::fault::{bad_input, BatchFault};
use super::ffi;
use super::handle::{run_v2, BoundModel, LawHandle, ModelHandle};
use super::kind::{EnergyOut, Kind, NewFn};
use super::kinds::{Heat, Normal, NormalCall, Rolling, Tangential, Twisting};
use super::module::PluginModuleRef;
use super::object::{coefficients, FfiObject, Owned};
use super::series::{FfiBoundRestitution, FfiRestitutionLaw};
use super::version::{abi_compatible, series, ABI_VERSION};
use super::{v1, v2, v3};
use crate::error::FfiError;
use crate::error::{ErrorKind, LawError};
use crate::law::{CalibrationTarget, Coefficient, Contact, LawInfo, LawKind, NormalBatch};
use crate::lengths::length_error;
use crate::motion::TangentialBatch;
use crate::pair::{MaterialPair, Pair};
use crate::params::ParamValue;
use abi_stable::std_types::{RResult, RSlice, RStr, RString, RVec};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Declares `$handle`, a plugin's law of kind `$kind` bound to a pair of materials through the
/// ABI of its series (`ModelInner`: 0.2's model of type `$v2`, owned, 0.3's generic one, and
/// the older forms `$older` the kind had), with the law's name and history slots; and its
/// [`BoundModel`] implementation, whose batch call is the handle's `$batch`.
macro_rules! model_handle {
    (
        $(#[$doc:meta])* $handle:ident: $kind:ty, $batch:ident, v2: $v2:ty
        $(, $(#[$odoc:meta])* $older:ident $ofields:tt)*
    ) => {
        enum ModelInner {
            $($(#[$odoc])* $older $ofields,)*
            /// A 0.2 model.
            V2(Owned<$v2>),
            /// A 0.3 model, through the generic shape of its kind.
            V3(ModelHandle<$kind>),
        }

        $(#[$doc])*
        pub struct $handle {
            inner: ModelInner,
            name: String,
            slots: usize,
            reads_context: bool,
        }

        impl $handle {
            /// The model `inner` of the law described by `info`.
            fn new(inner: ModelInner, info: &LawInfo) -> $handle {
                $handle {
                    inner,
                    name: info.name.to_string(),
                    slots: info.history.len(),
                    reads_context: info.reads_context,
                }
            }

            $crate::abi::handle::identity_accessors!();
        }

        $crate::abi::handle::bound_model!(impl<> $kind => $handle, $batch);
    };
}

mod contact;
mod restitution;
mod tangential;

use contact::{ContactInner, V1Law};
pub use contact::{ContactLawHandle, ContactModelHandle};
pub use restitution::{BoundRestitutionHandle, RestitutionLawHandle};
use tangential::TangentialInner;
pub use tangential::{TangentialLawHandle, TangentialModelHandle};

/// The root-module entry of an sdk 0.3 plugin that creates a law of kind `K` by name.
type Entry03<K> = fn(v3::PluginModuleRef) -> NewFn<<K as Kind>::Ffi03>;

/// The sdk series a plugin was built against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdkSeries {
    /// sdk 0.1: contact laws bound to one pair (spoken to through [`v1`]); no history, no
    /// tangential laws.
    V0_1,
    /// sdk 0.2: material binding, per-contact geometry and history, tangential laws (its law
    /// list read through [`v2`]).
    V0_2,
    /// sdk 0.3: adhesive contact laws with a reach, rolling and twisting laws, energy outputs
    /// (its law list read through [`v3`]).
    V0_3,
    /// sdk 0.4: the normal context (what a normal law tells the other laws of its contact).
    V0_4,
}

/// A loaded plugin library. Libraries stay loaded for the life of the process.
#[derive(Clone)]
pub struct LoadedPlugin {
    /// The file it was loaded from.
    pub path: PathBuf,
    /// The plugin crate's name.
    pub name: String,
    /// The plugin crate's version.
    pub version: String,
    /// The sdk version it was built against.
    pub sdk_version: String,
    /// Its sdk series.
    pub series: SdkSeries,
    /// The laws it exports.
    pub laws: Vec<LawInfo>,
    module: Module,
}

/// A root module of any series.
#[derive(Clone, Copy)]
enum Module {
    V1(v1::PluginModuleRef),
    V2(v2::PluginModuleRef),
    V3(v3::PluginModuleRef),
    V4(PluginModuleRef),
}

/// The entry points every series shares (same types in every root module).
macro_rules! shared {
    ($module:expr, $field:ident) => {
        match $module {
            Module::V1(m) => m.$field(),
            Module::V2(m) => m.$field(),
            Module::V3(m) => m.$field(),
            Module::V4(m) => m.$field(),
        }
    };
}

/// Calls a root-module entry with a law name and parameters (converted to their mirrors): the
/// law it makes, owned here, or its error as a [`LawError`].
fn call<T: FfiObject>(
    f: extern "C" fn(RStr<'_>, RSlice<'_, ffi::ParamValue>) -> RResult<T, FfiError>,
    name: &str,
    params: &[ParamValue],
) -> Result<Owned<T>, LawError> {
    let params: RVec<ffi::ParamValue> = ffi::to_ffi(params);
    Owned::take(f(RStr::from_str(name), params.as_rslice()))
}

impl std::fmt::Debug for LoadedPlugin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedPlugin")
            .field("path", &self.path)
            .field("name", &self.name)
            .field("version", &self.version)
            .field("sdk_version", &self.sdk_version)
            .field(
                "laws",
                &self.laws.iter().map(|l| l.name.as_str()).collect::<Vec<_>>(),
            )
            .finish()
    }
}

/// The verdict of abi_stable's layout comparison without its pages of type dumps (all of it
/// with `DASHPOT_ABI_DETAILS=1`).
fn layout_summary(full: &str) -> String {
    if std::env::var_os("DASHPOT_ABI_DETAILS").is_some() {
        return format!("Details:\n{full}");
    }
    let lines: Vec<&str> = full.lines().collect();
    match lines.iter().position(|l| l.starts_with("Error:")) {
        Some(i) => {
            // the innermost type whose layouts were being compared when the first error was found
            let ty = lines[..i]
                .iter()
                .rposition(|l| l.contains("--- Type Layout ---"))
                .and_then(|j| lines.get(j + 1))
                .map(|l| l.trim().trim_start_matches("type:").trim())
                .filter(|t| !t.is_empty());
            format!(
                "First differences{}:\n{}\n(set DASHPOT_ABI_DETAILS=1 for the full layout comparison)",
                ty.map(|t| format!(", in type {t}")).unwrap_or_default(),
                lines[i..].iter().take(16).copied().collect::<Vec<_>>().join("\n")
            )
        }
        None => "(set DASHPOT_ABI_DETAILS=1 for the full layout comparison)".to_string(),
    }
}

fn load_error(path: &Path, msg: impl std::fmt::Display) -> LawError {
    LawError::new(
        ErrorKind::Load,
        format!("cannot load plugin {}: {msg}", path.display()),
    )
}

fn stale_error(path: &Path, plugin_sdk: &str, details: &str) -> LawError {
    load_error(
        path,
        format!(
            "its types do not have the layout this host expects (built against dashpot-sdk \
             {plugin_sdk}, host {ABI_VERSION}): it is stale or was built from a different sdk. \
             Rebuild it. {}",
            layout_summary(details)
        ),
    )
}

impl LoadedPlugin {
    /// Loads the plugin at `path`, checking its sdk version and type layouts before running any
    /// of its code.
    ///
    /// Loading runs the library's initialisers: load only files you trust, as with any shared
    /// library.
    pub fn load(path: &Path) -> Result<LoadedPlugin, LawError> {
        use abi_stable::library::{lib_header_from_path, LibraryError};
        let header = lib_header_from_path(path).map_err(|e| match e {
            LibraryError::OpenError { .. } => load_error(path, format!("the library cannot be opened ({e})")),
            LibraryError::GetSymbolError { .. } => load_error(
                path,
                "it is not a dashpot plugin (it exports no abi_stable root module; \
                 a law crate must call dashpot_sdk::export_laws!)",
            ),
            other => load_error(path, other),
        })?;
        let plugin_sdk = header.version_strings().version.as_str().to_string();
        if !abi_compatible(ABI_VERSION, &plugin_sdk) {
            return Err(load_error(
                path,
                format!(
                    "it was built against dashpot-sdk {plugin_sdk}, but this host uses dashpot-sdk \
                     {ABI_VERSION}, which loads plugins of sdk 0.1, 0.2, 0.3 and 0.4 only; the ABI versions \
                     are incompatible. Rebuild the plugin against dashpot-sdk {ABI_VERSION}."
                ),
            ));
        }
        let plugin_series = series(&plugin_sdk);
        let module = match plugin_series {
            // abi_stable would refuse every type of a 0.1, 0.2 or 0.3 plugin for its package
            // version alone (they are different semver series from 0.4). Run its full layout
            // comparison against the frozen root module of the plugin's series and accept exactly
            // that difference: every field of every type must still match.
            Some((0, 1)) => Module::V1(legacy_module::<v1::PluginModuleRef>(path, &plugin_sdk, header)?),
            Some((0, 2)) => Module::V2(legacy_module::<v2::PluginModuleRef>(path, &plugin_sdk, header)?),
            Some((0, 3)) => Module::V3(legacy_module::<v3::PluginModuleRef>(path, &plugin_sdk, header)?),
            _ => Module::V4(
                header
                    .init_root_module::<PluginModuleRef>()
                    .map_err(|e| match e {
                        LibraryError::AbiInstability(_) => stale_error(path, &plugin_sdk, &e.to_string()),
                        other => load_error(path, other),
                    })?,
            ),
        };
        fn read<T>(path: &Path, r: RResult<RVec<T>, FfiError>) -> Result<RVec<T>, LawError> {
            r.into_result().map_err(|e| load_error(path, LawError::from(e)))
        }
        let (series, laws, name, version, sdk_version) = match module {
            Module::V1(m) => {
                let laws = read(path, (m.laws())())?
                    .into_iter()
                    .map(v1::LawInfo::upgrade)
                    .collect();
                (SdkSeries::V0_1, laws, m.name(), m.version(), m.sdk_version())
            }
            Module::V2(m) => {
                let Some(laws2) = m.laws2() else {
                    return Err(load_error(path, "its root module lacks the sdk 0.2 law list"));
                };
                let laws = read(path, laws2())?
                    .into_iter()
                    .map(v2::LawInfo::upgrade)
                    .collect();
                (SdkSeries::V0_2, laws, m.name(), m.version(), m.sdk_version())
            }
            Module::V3(m) => {
                let laws = read(path, (m.laws())())?
                    .into_iter()
                    .map(v3::LawInfo::upgrade)
                    .collect();
                (SdkSeries::V0_3, laws, m.name(), m.version(), m.sdk_version())
            }
            Module::V4(m) => {
                let laws = ffi::to_plain(read(path, (m.laws())())?);
                (SdkSeries::V0_4, laws, m.name(), m.version(), m.sdk_version())
            }
        };
        Ok(LoadedPlugin {
            path: path.to_path_buf(),
            name: name.to_string(),
            version: version.to_string(),
            sdk_version: sdk_version.to_string(),
            series,
            laws,
            module,
        })
    }
    /// The description of law `name`, if this plugin exports it.
    pub fn info(&self, name: &str) -> Option<&LawInfo> {
        self.laws.iter().find(|l| l.name == name)
    }

    /// Creates contact law `name` from `params` (validated against its schema by the plugin).
    pub fn new_contact(&self, name: &str, params: &[ParamValue]) -> Result<ContactLawHandle, LawError> {
        let info = self.expect(name, LawKind::Contact)?;
        let inner = match self.module {
            Module::V1(m) => ContactInner::V1(Arc::new(V1Law::new(call(m.new_contact(), name, params)?))),
            Module::V2(m) => {
                let f = m.new_contact2().ok_or_else(|| missing(name, "new_contact2"))?;
                ContactInner::V2(call(f, name, params)?)
            }
            Module::V3(_) | Module::V4(_) => ContactInner::V3(self.new_kind::<Normal>(
                name,
                params,
                |m| m.new_contact(),
                Some(|m| m.new_contact()),
            )?),
        };
        Ok(ContactLawHandle {
            inner,
            info,
            series: self.series,
        })
    }

    /// Creates a law of a kind of the generic shape through its root-module entry: `entry` in
    /// a plugin of sdk 0.4, `entry03` in one of sdk 0.3 (`None`: a kind new in 0.4); an error
    /// for a plugin of an older sdk, which has no such kind.
    fn new_kind<K: Kind>(
        &self,
        name: &str,
        params: &[ParamValue],
        entry: fn(PluginModuleRef) -> NewFn<K::Ffi>,
        entry03: Option<Entry03<K>>,
    ) -> Result<LawHandle<K>, LawError> {
        let info = self.expect(name, K::KIND)?;
        match (self.module, entry03) {
            (Module::V4(m), _) => Ok(LawHandle::new(call(entry(m), name, params)?, info)),
            (Module::V3(m), Some(entry03)) => Ok(LawHandle::new_v3(call(entry03(m), name, params)?, info)),
            _ => Err(missing(
                name,
                &format!(
                    "of {} laws (the plugin's sdk {} is older)",
                    K::KIND.as_str(),
                    self.sdk_version
                ),
            )),
        }
    }

    /// Creates rolling law `name` from `params` (sdk 0.3 and later).
    pub fn new_rolling(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Rolling>, LawError> {
        self.new_kind::<Rolling>(name, params, |m| m.new_rolling(), Some(|m| m.new_rolling()))
    }

    /// Creates twisting law `name` from `params` (sdk 0.3 and later).
    pub fn new_twisting(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Twisting>, LawError> {
        self.new_kind::<Twisting>(name, params, |m| m.new_twisting(), Some(|m| m.new_twisting()))
    }

    /// Creates heat law `name` from `params` (sdk 0.4 and later).
    pub fn new_heat(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Heat>, LawError> {
        self.new_kind::<Heat>(name, params, |m| m.new_heat(), None)
    }

    /// Creates tangential law `name` from `params`.
    pub fn new_tangential(&self, name: &str, params: &[ParamValue]) -> Result<TangentialLawHandle, LawError> {
        let inner = match self.module {
            Module::V3(_) | Module::V4(_) => TangentialInner::V3(self.new_kind::<Tangential>(
                name,
                params,
                |m| m.new_tangential(),
                Some(|m| m.new_tangential()),
            )?),
            Module::V2(m) => {
                let info = self.expect(name, LawKind::Tangential)?;
                let f = m
                    .new_tangential()
                    .ok_or_else(|| missing(name, "new_tangential"))?;
                TangentialInner::V2 {
                    ffi: call(f, name, params)?,
                    info,
                }
            }
            Module::V1(_) => {
                self.expect(name, LawKind::Tangential)?;
                return Err(missing(name, "new_tangential"));
            }
        };
        Ok(TangentialLawHandle(inner))
    }

    /// Creates restitution law `name` from `params` (validated against its schema by the plugin).
    pub fn new_restitution(
        &self,
        name: &str,
        params: &[ParamValue],
    ) -> Result<RestitutionLawHandle, LawError> {
        let info = self.expect(name, LawKind::Restitution)?;
        let ffi = call(shared!(self.module, new_restitution), name, params)?;
        Ok(RestitutionLawHandle { ffi, info })
    }

    /// Closed-form parameters of contact law `name` reproducing `target` for `pair`.
    pub fn calibrate(
        &self,
        name: &str,
        target: &CalibrationTarget,
        pair: &Pair,
        fixed: &[ParamValue],
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        self.expect(name, LawKind::Contact)?;
        let f = shared!(self.module, calibrate);
        let fixed: RVec<ffi::ParamValue> = ffi::to_ffi(fixed);
        let found = f(RStr::from_str(name), &target.into(), pair, fixed.as_rslice()).into_result()?;
        Ok(found.into_option().map(ffi::to_plain))
    }

    fn expect(&self, name: &str, kind: LawKind) -> Result<LawInfo, LawError> {
        match self.info(name) {
            Some(i) if i.kind == kind => Ok(i.clone()),
            Some(i) => Err(LawError::new(
                ErrorKind::UnknownLaw,
                format!("law '{name}' is a {:?} law, not a {:?} law", i.kind, kind).to_lowercase(),
            )),
            None => Err(LawError::new(
                ErrorKind::UnknownLaw,
                format!("plugin {} has no law '{name}'", self.path.display()),
            )),
        }
    }
}

fn missing(name: &str, what: &str) -> LawError {
    LawError::new(
        ErrorKind::Load,
        format!("law '{name}': its plugin lacks the entry point {what}"),
    )
}

/// The root module of a 0.1 or 0.2 plugin, read through the frozen module `M` of its series
/// after abi_stable's full layout comparison, in which only package versions may differ.
fn legacy_module<M: abi_stable::prefix_type::PrefixRefTrait + abi_stable::StableAbi>(
    path: &Path,
    plugin_sdk: &str,
    header: &'static abi_stable::library::LibHeader,
) -> Result<M, LawError> {
    use abi_stable::abi_stability::abi_checking::{check_layout_compatibility, AbiInstability};
    let Some(layout) = header.layout() else {
        return Err(load_error(path, "it records no type layout to check"));
    };
    if let Err(e) = check_layout_compatibility(<M as abi_stable::StableAbi>::LAYOUT, layout) {
        let only_versions = e.errors.iter().all(|err| {
            err.errs
                .iter()
                .all(|a| matches!(a, AbiInstability::PackageVersion(_)))
        });
        if !only_versions {
            return Err(stale_error(path, plugin_sdk, &e.to_string()));
        }
    }
    // SAFETY: the layout was checked just above, to the package version.
    unsafe { header.unchecked_layout::<M>() }.map_err(|e| load_error(path, e))
}
