//! Host side: loading plugins, with their checks, and the safe handles a host calls.

use super::checks::all_finite;
use super::kind::{self, EnergyOut, Kind};
use super::v1;
use super::*;
use super::{LawHandle, ModelHandle, Normal, NormalCall, Rolling, Tangential, Twisting};
use crate::error::{ErrorKind, LawError};
use crate::law::{Contact, LawKind, NormalBatch, TangentialBatch};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The sdk series a plugin was built against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdkSeries {
    /// sdk 0.1: contact laws bound to one pair (spoken to through [`v1`]); no history, no
    /// tangential laws.
    V0_1,
    /// sdk 0.2: material binding, per-contact geometry and history, tangential laws (its law
    /// list read through [`v2`]).
    V0_2,
    /// sdk 0.3: adhesive contact laws with a reach, rolling and twisting laws, energy outputs.
    V0_3,
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
    V3(PluginModuleRef),
}

/// The entry points 0.2 and 0.3 share (same types in both root modules).
macro_rules! shared {
    ($module:expr, $field:ident, $v1:expr) => {
        match $module {
            Module::V1(m) => $v1(m),
            Module::V2(m) => m.$field(),
            Module::V3(m) => m.$field(),
        }
    };
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
                     {ABI_VERSION}, which loads plugins of sdk 0.1, 0.2 and 0.3 only; the ABI versions \
                     are incompatible. Rebuild the plugin against dashpot-sdk {ABI_VERSION}."
                ),
            ));
        }
        let plugin_series = series(&plugin_sdk);
        let module = match plugin_series {
            // abi_stable would refuse every type of a 0.1 or 0.2 plugin for its package version
            // alone (they are different semver series from 0.3). Run its full layout comparison
            // against the frozen root module of the plugin's series and accept exactly that
            // difference: every field of every type must still match.
            Some((0, 1)) => Module::V1(legacy_module::<v1::PluginModuleRef>(path, &plugin_sdk, header)?),
            Some((0, 2)) => Module::V2(legacy_module::<v2::PluginModuleRef>(path, &plugin_sdk, header)?),
            _ => Module::V3(
                header
                    .init_root_module::<PluginModuleRef>()
                    .map_err(|e| match e {
                        LibraryError::AbiInstability(_) => stale_error(path, &plugin_sdk, &e.to_string()),
                        other => load_error(path, other),
                    })?,
            ),
        };
        let read = |r: RResult<RVec<LawInfo>, FfiError>| match r {
            RResult::ROk(v) => Ok(v.into_vec()),
            RResult::RErr(e) => Err(load_error(path, LawError::from(e))),
        };
        let (series, laws, name, version, sdk_version) = match module {
            Module::V1(m) => {
                let laws = match (m.laws())() {
                    RResult::ROk(v) => v.into_iter().map(from_v1_info).collect(),
                    RResult::RErr(e) => return Err(load_error(path, LawError::from(e))),
                };
                (SdkSeries::V0_1, laws, m.name(), m.version(), m.sdk_version())
            }
            Module::V2(m) => {
                let Some(laws2) = m.laws2() else {
                    return Err(load_error(path, "its root module lacks the sdk 0.2 law list"));
                };
                let laws = match laws2() {
                    RResult::ROk(v) => v.into_iter().map(v2::LawInfo::upgrade).collect(),
                    RResult::RErr(e) => return Err(load_error(path, LawError::from(e))),
                };
                (SdkSeries::V0_2, laws, m.name(), m.version(), m.sdk_version())
            }
            Module::V3(m) => {
                let Some(laws3) = m.laws3() else {
                    return Err(load_error(path, "its root module lacks the sdk 0.3 law list"));
                };
                (
                    SdkSeries::V0_3,
                    read(laws3())?,
                    m.name(),
                    m.version(),
                    m.sdk_version(),
                )
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
        let (n, p) = (RStr::from_str(name), RSlice::from_slice(params));
        let inner = match self.module {
            Module::V1(m) => match (m.new_contact())(n, p) {
                RResult::ROk(ffi) => ContactInner::V1(Arc::new(V1Law {
                    ffi,
                    bound: Mutex::new(Vec::new()),
                })),
                RResult::RErr(e) => return Err(e.into()),
            },
            Module::V2(_) | Module::V3(_) => {
                let f = shared!(self.module, new_contact2, |_| None)
                    .ok_or_else(|| missing(name, "new_contact2"))?;
                match f(n, p) {
                    RResult::ROk(ffi) => ContactInner::V2(ffi),
                    RResult::RErr(e) => return Err(e.into()),
                }
            }
        };
        let v3 = match self.module {
            Module::V3(_) => {
                Some(self.new_kind::<Normal>(name, params, LawKind::Contact, |m| m.new_contact3())?)
            }
            _ => None,
        };
        Ok(ContactLawHandle {
            inner,
            info,
            series: self.series,
            v3,
        })
    }

    /// Creates a law of a kind of sdk 0.3 through its root-module entry `entry`; an error for
    /// a plugin of an older sdk, which has no such kind.
    fn new_kind<K: Kind>(
        &self,
        name: &str,
        params: &[ParamValue],
        kind: LawKind,
        entry: impl FnOnce(
            PluginModuleRef,
        ) -> Option<
            extern "C" fn(RStr<'_>, RSlice<'_, ParamValue>) -> RResult<kind::FfiLaw<K::Ffi>, FfiError>,
        >,
    ) -> Result<LawHandle<K>, LawError> {
        let info = self.expect(name, kind)?;
        let Module::V3(m) = self.module else {
            return Err(missing(name, "of sdk 0.3 (the plugin is older)"));
        };
        let f = entry(m).ok_or_else(|| missing(name, K::WHAT))?;
        match f(RStr::from_str(name), RSlice::from_slice(params)) {
            RResult::ROk(ffi) => Ok(LawHandle::new(ffi, info)),
            RResult::RErr(e) => Err(e.into()),
        }
    }

    /// Creates rolling law `name` from `params` (sdk 0.3 plugins).
    pub fn new_rolling(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Rolling>, LawError> {
        self.new_kind::<Rolling>(name, params, LawKind::Rolling, |m| m.new_rolling())
    }

    /// Creates twisting law `name` from `params` (sdk 0.3 plugins).
    pub fn new_twisting(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Twisting>, LawError> {
        self.new_kind::<Twisting>(name, params, LawKind::Twisting, |m| m.new_twisting())
    }

    /// Creates tangential law `name` from `params`.
    pub fn new_tangential(&self, name: &str, params: &[ParamValue]) -> Result<TangentialLawHandle, LawError> {
        let info = self.expect(name, LawKind::Tangential)?;
        let f =
            shared!(self.module, new_tangential, |_| None).ok_or_else(|| missing(name, "new_tangential"))?;
        match f(RStr::from_str(name), RSlice::from_slice(params)) {
            RResult::ROk(ffi) => {
                let v3 = match self.module {
                    Module::V3(_) => Some(self.new_kind::<Tangential>(
                        name,
                        params,
                        LawKind::Tangential,
                        |m| m.new_tangential3(),
                    )?),
                    _ => None,
                };
                Ok(TangentialLawHandle { ffi, info, v3 })
            }
            RResult::RErr(e) => Err(e.into()),
        }
    }

    /// Creates restitution law `name` from `params` (validated against its schema by the plugin).
    pub fn new_restitution(
        &self,
        name: &str,
        params: &[ParamValue],
    ) -> Result<RestitutionLawHandle, LawError> {
        let info = self.expect(name, LawKind::Restitution)?;
        let f = shared!(self.module, new_restitution, |m: v1::PluginModuleRef| m
            .new_restitution());
        match f(RStr::from_str(name), RSlice::from_slice(params)) {
            RResult::ROk(ffi) => Ok(RestitutionLawHandle { ffi, info }),
            RResult::RErr(e) => Err(e.into()),
        }
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
        let f = shared!(self.module, calibrate, |m: v1::PluginModuleRef| m.calibrate());
        match f(RStr::from_str(name), target, pair, RSlice::from_slice(fixed)) {
            RResult::ROk(v) => Ok(v.into_option().map(RVec::into_vec)),
            RResult::RErr(e) => Err(e.into()),
        }
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

fn from_v1_info(i: v1::LawInfo) -> LawInfo {
    LawInfo {
        name: i.name,
        kind: match i.kind {
            v1::LawKind::Contact => LawKind::Contact,
            v1::LawKind::Restitution => LawKind::Restitution,
        },
        summary: i.summary,
        doc: i.doc,
        params: i.params,
        end_criterion: i.end_criterion,
        history: RVec::new(),
    }
}

// ------------------------------------------------------------------------------------------
// Contact laws
// ------------------------------------------------------------------------------------------

/// A 0.1 contact law and the pairs it has been bound to (one per distinct effective mass and
/// radius: sdk 0.1 had no per-contact geometry).
struct V1Law {
    ffi: v1::FfiContactLaw,
    bound: Mutex<Vec<V1Entry>>,
}

impl Drop for V1Law {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

/// (mass, radius, young) bits and the 0.1 law bound to that pair.
type V1Entry = (u64, u64, u64, Arc<V1Bound>);

struct V1Bound {
    ffi: v1::FfiBoundContact,
}

impl Drop for V1Bound {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

impl V1Law {
    /// The law bound to the pair (mass, radius, young), binding it the first time.
    fn bound(&self, mass: f64, radius: f64, young: f64) -> Result<Arc<V1Bound>, LawError> {
        let key = (mass.to_bits(), radius.to_bits(), young.to_bits());
        let mut cache = self.bound.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((.., b)) = cache.iter().find(|(m, r, e, _)| (*m, *r, *e) == key) {
            return Ok(b.clone());
        }
        let pair = Pair::new(mass, radius, young)?;
        let b = match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, &pair) } {
            RResult::ROk(ffi) => Arc::new(V1Bound { ffi }),
            RResult::RErr(e) => return Err(e.into()),
        };
        cache.push((key.0, key.1, key.2, b.clone()));
        Ok(b)
    }
}

enum ContactInner {
    V1(Arc<V1Law>),
    V2(FfiContactLaw),
}

/// A configured contact law from a plugin.
pub struct ContactLawHandle {
    inner: ContactInner,
    info: LawInfo,
    series: SdkSeries,
    v3: Option<LawHandle<Normal>>,
}

impl ContactLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// The sdk series of the plugin it came from.
    pub fn series(&self) -> SdkSeries {
        self.series
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<ContactModelHandle, LawError> {
        materials.validate()?;
        let inner = match &self.inner {
            ContactInner::V2(ffi) => match unsafe { (ffi.vtable.bind)(ffi.obj, materials) } {
                RResult::ROk(m) => ModelInner::V2(m),
                RResult::RErr(e) => return Err(e.into()),
            },
            ContactInner::V1(law) => ModelInner::V1 {
                law: law.clone(),
                young: materials.young,
            },
        };
        let v3 = match &self.v3 {
            Some(l) => Some(l.bind(materials)?),
            None => None,
        };
        Ok(ContactModelHandle {
            inner,
            name: self.info.name.to_string(),
            slots: self.info.history.len(),
            v3,
        })
    }
}

impl Drop for ContactLawHandle {
    fn drop(&mut self) {
        if let ContactInner::V2(ffi) = &self.inner {
            unsafe { (ffi.vtable.drop)(ffi.obj) }
        }
    }
}

enum ModelInner {
    V1 { law: Arc<V1Law>, young: f64 },
    V2(FfiContactModel),
}

pub(crate) fn length_error(what: &str, detail: String) -> LawError {
    LawError::new(
        ErrorKind::Other,
        format!("{what}: the batch's arrays disagree in length: {detail}"),
    )
}

pub(crate) fn bad_input(kind: &str, name: &str, field: u8, index: usize, value: f64) -> LawError {
    let what = BatchFault::field_name(field);
    let rule = match field {
        BatchFault::MASS => "must be finite and > 0 (kg)",
        BatchFault::RADIUS => "must be finite and > 0 (m)",
        BatchFault::DT => "must be finite and ≥ 0 (s)",
        _ => "must be finite",
    };
    LawError::new(
        ErrorKind::NonFinite,
        format!("{kind} law '{name}': input {what}[{index}] = {value} {rule}; refused before evaluation"),
    )
}

pub(crate) fn normal_non_finite(name: &str, value: f64, c: Contact) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "contact law '{name}' returned force {value} at delta = {:e} m, rate = {:e} m/s \
             (effective mass {:e} kg, radius {:e} m)",
            c.delta, c.rate, c.mass, c.radius
        ),
    )
}

/// Runs a checked normal batch through `call` (a plugin's vtable entry, or the same trampoline
/// compiled into the host) and turns its status into a result. Lengths are checked by the
/// caller.
fn run_normal_batch(
    name: &str,
    b: NormalBatch<'_>,
    call: impl FnOnce(&FfiNormalBatch, &mut BatchFault) -> Result<BatchStatus, RString>,
) -> Result<(), LawError> {
    let n = b.force.len();
    let ffi = FfiNormalBatch {
        n,
        slots: b.slots,
        delta: b.delta.as_ptr(),
        rate: b.rate.as_ptr(),
        mass: b.mass.as_ptr(),
        radius: b.radius.as_ptr(),
        history: b.history.as_mut_ptr(),
        force: b.force.as_mut_ptr(),
    };
    let mut fault = BatchFault::default();
    let st = call(&ffi, &mut fault)
        .map_err(|msg| LawError::new(ErrorKind::Panic, format!("contact law '{name}' panicked: {msg}")))?;
    if st == BatchStatus::Ok {
        return Ok(());
    }
    let i = fault.index.min(n - 1);
    let c = Contact {
        delta: b.delta[i],
        rate: b.rate[i],
        mass: b.mass[i],
        radius: b.radius[i],
    };
    if st == BatchStatus::NonFiniteOutput {
        return Err(normal_non_finite(name, b.force[i], c));
    }
    let v = match fault.field {
        BatchFault::DELTA => c.delta,
        BatchFault::RATE => c.rate,
        BatchFault::MASS => c.mass,
        _ => c.radius,
    };
    Err(bad_input("contact", name, fault.field, i, v))
}

fn check_normal_lengths(name: &str, slots: usize, b: &NormalBatch<'_>) -> Result<(), LawError> {
    let n = b.force.len();
    if b.delta.len() != n || b.rate.len() != n || b.mass.len() != n || b.radius.len() != n {
        return Err(length_error(
            "force_batch",
            format!(
                "delta {}, rate {}, mass {}, radius {}, force {}",
                b.delta.len(),
                b.rate.len(),
                b.mass.len(),
                b.radius.len(),
                n
            ),
        ));
    }
    if b.slots != slots || b.history.len() != n * slots {
        return Err(length_error(
            "force_batch",
            format!(
                "history has {} values for {n} contacts of {} slots (law '{name}' keeps {slots})",
                b.history.len(),
                b.slots,
            ),
        ));
    }
    Ok(())
}

/// A contact law compiled into the host (tests, benchmarks, baselines), bound to a pair of
/// materials, and called through the very trampoline a plugin exports: the same input and
/// output checks, statically dispatched.
pub struct StaticContact<B> {
    law: B,
    name: String,
    slots: usize,
}

impl<B: crate::law::BoundContact> StaticContact<B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: crate::law::ContactLaw<Bound = B>>(
        law: &L,
        materials: &MaterialPair,
    ) -> Result<Self, LawError> {
        materials.validate()?;
        Ok(StaticContact {
            law: law.bind(materials)?,
            name: L::NAME.to_string(),
            slots: L::HISTORY.len(),
        })
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    /// The bound law.
    pub fn law(&self) -> &B {
        &self.law
    }

    /// As [`ContactModelHandle::force_batch`].
    #[inline]
    pub fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        check_normal_lengths(&self.name, self.slots, &b)?;
        let obj = &self.law as *const B as *const c_void;
        run_normal_batch(&self.name, b, |ffi, fault| unsafe {
            match super::plugin::model_force_batch::<B>(obj, ffi, fault) {
                BatchStatus::Panic => Err(super::plugin::take_panic()),
                st => Ok(st),
            }
        })
    }
}

/// A contact law bound to a pair of materials: the hot path, per-contact geometry and history,
/// every input and output checked.
pub struct ContactModelHandle {
    inner: ModelInner,
    name: String,
    slots: usize,
    /// The same law through the 0.3 entry (reach and energy), for a 0.3 plugin.
    v3: Option<ModelHandle<Normal>>,
}

impl ContactModelHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    fn panic_error(&self, msg: RString) -> LawError {
        LawError::new(
            ErrorKind::Panic,
            format!("contact law '{}' panicked: {}", self.name, msg),
        )
    }

    /// Evaluates every contact of `b` (see [`NormalBatch`]): forces into `b.force`, history
    /// updated in place. A non-finite input (or a mass or radius not > 0) is an error naming the
    /// contact, before anything of its block is computed; so is a non-finite output.
    pub fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        check_normal_lengths(&self.name, self.slots, &b)?;
        match &self.inner {
            ModelInner::V2(m) => run_normal_batch(&self.name, b, |ffi, fault| unsafe {
                match (m.vtable.force_batch)(m.obj, ffi, fault) {
                    BatchStatus::Panic => Err((m.vtable.take_panic)()),
                    st => Ok(st),
                }
            }),
            ModelInner::V1 { law, young } => self.force_batch_v1(law, *young, b),
        }
    }

    /// As [`ContactModelHandle::force_batch`], with each contact's reach (m, ≥ 0: the contact
    /// ends at δ < −reach) written to `reach` and the energy outputs `energy` asks for:
    /// `Ok(true)` when those were written. A law of a plugin older than sdk 0.3 has reach 0 and
    /// reports energy as not available (`Ok(false)`).
    pub fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        match &self.v3 {
            Some(m) => m.batch(NormalCall { batch: b, reach }, energy),
            None => {
                let n = b.force.len();
                if reach.as_ref().is_some_and(|r| r.len() != n) {
                    return Err(length_error("force_batch", format!("reach must hold {n} values")));
                }
                self.force_batch(b)?;
                if let Some(r) = reach {
                    r.fill(0.0);
                }
                Ok(false)
            }
        }
    }

    /// A 0.1 law: inputs checked here (0.1 plugins do not), then one 0.1 batch call per run of
    /// contacts with the same geometry.
    fn force_batch_v1(&self, law: &V1Law, young: f64, b: NormalBatch<'_>) -> Result<(), LawError> {
        let n = b.force.len();
        for i in 0..n {
            let checks = [
                (b.delta[i].is_finite(), BatchFault::DELTA, b.delta[i]),
                (b.rate[i].is_finite(), BatchFault::RATE, b.rate[i]),
                (
                    b.mass[i] > 0.0 && b.mass[i].is_finite(),
                    BatchFault::MASS,
                    b.mass[i],
                ),
                (
                    b.radius[i] > 0.0 && b.radius[i].is_finite(),
                    BatchFault::RADIUS,
                    b.radius[i],
                ),
            ];
            if let Some((_, f, v)) = checks.into_iter().find(|c| !c.0) {
                return Err(bad_input("contact", &self.name, f, i, v));
            }
        }
        let mut lo = 0;
        while lo < n {
            let (m, r) = (b.mass[lo], b.radius[lo]);
            let mut hi = lo + 1;
            while hi < n && b.mass[hi] == m && b.radius[hi] == r {
                hi += 1;
            }
            let bound = law.bound(m, r, young)?;
            let mut bad = 0usize;
            let st = unsafe {
                (bound.ffi.vtable.force_batch)(
                    bound.ffi.obj,
                    b.delta[lo..hi].as_ptr(),
                    b.rate[lo..hi].as_ptr(),
                    b.force[lo..hi].as_mut_ptr(),
                    hi - lo,
                    &mut bad,
                )
            };
            match st {
                v1::CallStatus::Ok => {}
                v1::CallStatus::Panic => return Err(self.panic_error((bound.ffi.vtable.take_panic)())),
                v1::CallStatus::NonFinite => {
                    let i = lo + bad.min(hi - lo - 1);
                    let c = Contact {
                        delta: b.delta[i],
                        rate: b.rate[i],
                        mass: m,
                        radius: r,
                    };
                    return Err(normal_non_finite(&self.name, b.force[i], c));
                }
            }
            lo = hi;
        }
        Ok(())
    }

    /// For benchmarks only: a 0.1 plugin's own bound-pair batch, called exactly as a 0.1 host
    /// called it (bound once to the pair of effective `mass` and `radius`, no input checks of
    /// the host), so that the 0.2 per-contact batch can be compared with it. `None` for a 0.2
    /// law.
    #[doc(hidden)]
    pub fn v1_bound_pair_batch(
        &self,
        mass: f64,
        radius: f64,
        d: &[f64],
        r: &[f64],
        o: &mut [f64],
    ) -> Option<Result<(), LawError>> {
        let ModelInner::V1 { law, young } = &self.inner else {
            return None;
        };
        let b = match law.bound(mass, radius, *young) {
            Ok(b) => b,
            Err(e) => return Some(Err(e)),
        };
        if d.len() != o.len() || r.len() != o.len() {
            return Some(Err(length_error(
                "force_batch",
                format!("{} {} {}", d.len(), r.len(), o.len()),
            )));
        }
        let mut bad = 0usize;
        Some(
            match unsafe {
                (b.ffi.vtable.force_batch)(
                    b.ffi.obj,
                    d.as_ptr(),
                    r.as_ptr(),
                    o.as_mut_ptr(),
                    o.len(),
                    &mut bad,
                )
            } {
                v1::CallStatus::Ok => Ok(()),
                _ => Err(LawError::new(ErrorKind::Other, "the 0.1 batch failed")),
            },
        )
    }

    /// The normal force (N) on one contact, history updated in place.
    pub fn force(&self, c: Contact, history: &mut [f64]) -> Result<f64, LawError> {
        let mut out = [0.0];
        self.force_batch(NormalBatch {
            delta: &[c.delta],
            rate: &[c.rate],
            mass: &[c.mass],
            radius: &[c.radius],
            slots: self.slots,
            history,
            force: &mut out,
        })?;
        Ok(out[0])
    }

    /// The law's derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        match &self.inner {
            ModelInner::V2(m) => match unsafe { (m.vtable.coefficients)(m.obj, mass, radius) } {
                RResult::ROk(v) => Ok(v.into_vec()),
                RResult::RErr(e) => Err(e.into()),
            },
            ModelInner::V1 { law, young } => {
                let b = law.bound(mass, radius, *young)?;
                match unsafe { (b.ffi.vtable.coefficients)(b.ffi.obj) } {
                    RResult::ROk(v) => Ok(v.into_vec()),
                    RResult::RErr(e) => Err(e.into()),
                }
            }
        }
    }
}

impl Drop for ContactModelHandle {
    fn drop(&mut self) {
        if let ModelInner::V2(m) = &self.inner {
            unsafe { (m.vtable.drop)(m.obj) }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Tangential laws
// ------------------------------------------------------------------------------------------

/// A configured tangential law from a plugin.
pub struct TangentialLawHandle {
    ffi: FfiTangentialLaw,
    info: LawInfo,
    v3: Option<LawHandle<Tangential>>,
}

impl TangentialLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<TangentialModelHandle, LawError> {
        materials.validate()?;
        match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, materials) } {
            RResult::ROk(ffi) => Ok(TangentialModelHandle {
                ffi,
                name: self.info.name.to_string(),
                slots: self.info.history.len(),
                v3: match &self.v3 {
                    Some(l) => Some(l.bind(materials)?),
                    None => None,
                },
            }),
            RResult::RErr(e) => Err(e.into()),
        }
    }
}

impl Drop for TangentialLawHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

/// A tangential law bound to a pair of materials, every input and output checked.
pub struct TangentialModelHandle {
    ffi: FfiTangentialModel,
    name: String,
    slots: usize,
    /// The same law through the 0.3 entry (energy), for a 0.3 plugin.
    v3: Option<ModelHandle<Tangential>>,
}

impl TangentialModelHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    /// As [`TangentialModelHandle::force_batch`], with the energy outputs `energy` asks for:
    /// `Ok(true)` when they were written, `Ok(false)` for a law that does not account for
    /// energy (every law of a plugin older than sdk 0.3).
    pub fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        match &self.v3 {
            Some(m) => m.batch(b, energy),
            None => self.force_batch(b).map(|()| false),
        }
    }

    /// Evaluates every contact of `b` (see [`TangentialBatch`]).
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        let ffi = &self.ffi;
        run_tangential_batch(&self.name, self.slots, b, |fb, fault| unsafe {
            match (ffi.vtable.force_batch)(ffi.obj, fb, fault) {
                BatchStatus::Panic => Err((ffi.vtable.take_panic)()),
                st => Ok(st),
            }
        })
    }
}

/// A tangential law compiled into the host, called through the trampoline a plugin exports.
pub struct StaticTangential<B> {
    law: B,
    name: String,
    slots: usize,
}

impl<B: crate::law::BoundTangential> StaticTangential<B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: crate::law::TangentialLaw<Bound = B>>(
        law: &L,
        materials: &MaterialPair,
    ) -> Result<Self, LawError> {
        materials.validate()?;
        Ok(StaticTangential {
            law: law.bind(materials)?,
            name: L::NAME.to_string(),
            slots: L::HISTORY.len(),
        })
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    /// As [`TangentialModelHandle::force_batch`].
    #[inline]
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        let obj = &self.law as *const B as *const c_void;
        run_tangential_batch(&self.name, self.slots, b, |fb, fault| unsafe {
            match super::plugin::tangential_force_batch::<B>(obj, fb, fault) {
                BatchStatus::Panic => Err(super::plugin::take_panic()),
                st => Ok(st),
            }
        })
    }
}

fn run_tangential_batch(
    name: &str,
    slots: usize,
    b: TangentialBatch<'_>,
    call: impl FnOnce(&FfiTangentialBatch, &mut BatchFault) -> Result<BatchStatus, RString>,
) -> Result<(), LawError> {
    let n = b.force.len();
    let lens = [
        b.normal.len(),
        b.velocity.len(),
        b.normal_force.len(),
        b.delta.len(),
        b.mass.len(),
        b.radius.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(length_error(
            "tangential force_batch",
            format!("normal, velocity, normal_force, delta, mass, radius {lens:?}, force {n}"),
        ));
    }
    if b.slots != slots || b.history.len() != n * slots {
        return Err(length_error(
            "tangential force_batch",
            format!(
                "history has {} values for {n} contacts of {} slots (law '{}' keeps {})",
                b.history.len(),
                b.slots,
                name,
                slots
            ),
        ));
    }
    let ffi = FfiTangentialBatch {
        n,
        slots,
        dt: b.dt,
        normal: b.normal.as_ptr() as *const f64,
        velocity: b.velocity.as_ptr() as *const f64,
        normal_force: b.normal_force.as_ptr(),
        delta: b.delta.as_ptr(),
        mass: b.mass.as_ptr(),
        radius: b.radius.as_ptr(),
        history: b.history.as_mut_ptr(),
        force: b.force.as_mut_ptr() as *mut f64,
    };
    let mut fault = BatchFault::default();
    let st = call(&ffi, &mut fault).map_err(|msg| {
        LawError::new(
            ErrorKind::Panic,
            format!("tangential law '{name}' panicked: {msg}"),
        )
    })?;
    match st {
        BatchStatus::Ok => Ok(()),
        BatchStatus::NonFiniteOutput | BatchStatus::Panic => {
            let i = fault.index.min(n - 1);
            Err(LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "tangential law '{}' returned force {:?} on contact {i} (normal force {:e} N, \
                     overlap {:e} m, velocity {:?} m/s)",
                    name, b.force[i], b.normal_force[i], b.delta[i], b.velocity[i]
                ),
            ))
        }
        BatchStatus::BadInput => {
            let i = fault.index.min(n - 1);
            let v = match fault.field {
                BatchFault::NORMAL => {
                    return Err(bad_vec("normal", name, i, b.normal[i]));
                }
                BatchFault::VELOCITY => {
                    return Err(bad_vec("velocity", name, i, b.velocity[i]));
                }
                BatchFault::NORMAL_FORCE => b.normal_force[i],
                BatchFault::DELTA => b.delta[i],
                BatchFault::MASS => b.mass[i],
                BatchFault::RADIUS => b.radius[i],
                _ => b.dt,
            };
            Err(bad_input("tangential", name, fault.field, i, v))
        }
    }
}

pub(crate) fn bad_vec(what: &str, name: &str, i: usize, v: [f64; 3]) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "tangential law '{name}': input {what}[{i}] = {v:?} must be finite; refused before evaluation"
        ),
    )
}

impl Drop for TangentialModelHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

// ------------------------------------------------------------------------------------------
// Restitution laws (unchanged since 0.1)
// ------------------------------------------------------------------------------------------

/// A configured restitution law from a plugin.
pub struct RestitutionLawHandle {
    ffi: FfiRestitutionLaw,
    info: LawInfo,
}

impl RestitutionLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to `pair` (validated first).
    pub fn bind(&self, pair: &Pair) -> Result<BoundRestitutionHandle, LawError> {
        pair.validate()?;
        match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, pair) } {
            RResult::ROk(ffi) => Ok(BoundRestitutionHandle {
                ffi,
                name: self.info.name.to_string(),
            }),
            RResult::RErr(e) => Err(e.into()),
        }
    }
}

impl Drop for RestitutionLawHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

/// A restitution law bound to a pair, with every input and output checked.
pub struct BoundRestitutionHandle {
    ffi: FfiBoundRestitution,
    name: String,
}

impl BoundRestitutionHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn panic_error(&self) -> LawError {
        let msg = (self.ffi.vtable.take_panic)();
        LawError::new(
            ErrorKind::Panic,
            format!("restitution law '{}' panicked: {}", self.name, msg),
        )
    }

    fn non_finite(&self, value: f64, speed: f64) -> LawError {
        LawError::new(
            ErrorKind::NonFinite,
            format!(
                "restitution law '{}' returned {value} at impact speed {speed:e} m/s",
                self.name
            ),
        )
    }

    fn bad_speed(&self, i: usize, speed: f64) -> LawError {
        bad_input("restitution", &self.name, BatchFault::RATE, i, speed)
            .with_message(|m| m.replace("rate[", "speed["))
    }

    /// r(v) at normal impact speed `speed` (m/s, finite).
    #[inline]
    pub fn restitution(&self, speed: f64) -> Result<f64, LawError> {
        if !speed.is_finite() {
            return Err(self.bad_speed(0, speed));
        }
        let mut out = 0.0;
        match unsafe { (self.ffi.vtable.restitution)(self.ffi.obj, speed, &mut out) } {
            v1::CallStatus::Ok if out.is_finite() => Ok(out),
            v1::CallStatus::Ok | v1::CallStatus::NonFinite => Err(self.non_finite(out, speed)),
            v1::CallStatus::Panic => Err(self.panic_error()),
        }
    }

    /// `out[i] = r(speed[i])` over slices of equal length.
    pub fn restitution_batch(&self, speed: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        if speed.len() != out.len() {
            return Err(length_error(
                "restitution_batch",
                format!("speed {}, out {}", speed.len(), out.len()),
            ));
        }
        if !all_finite(speed) {
            let i = speed.iter().position(|v| !v.is_finite()).unwrap_or(0);
            return Err(self.bad_speed(i, speed[i]));
        }
        let mut bad = 0usize;
        let st = unsafe {
            (self.ffi.vtable.restitution_batch)(
                self.ffi.obj,
                speed.as_ptr(),
                out.as_mut_ptr(),
                out.len(),
                &mut bad,
            )
        };
        match st {
            v1::CallStatus::Ok => Ok(()),
            v1::CallStatus::Panic => Err(self.panic_error()),
            v1::CallStatus::NonFinite => {
                let i = bad.min(out.len().saturating_sub(1));
                Err(self.non_finite(out[i], speed[i]))
            }
        }
    }
}

impl Drop for BoundRestitutionHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}
