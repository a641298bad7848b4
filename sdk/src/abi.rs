//! The stable binary interface between a host and a law plugin (a cdylib).
//!
//! # Layout
//! A plugin exports one root module, [`PluginModule`], through abi_stable's `LibHeader`; the
//! [`export_laws!`](crate::export_laws) macro writes it. The host checks, in this order:
//! 1. the dashpot-sdk version the plugin was built against ([`ABI_VERSION`]): same major version
//!    (same minor while the major is 0), both directions, else the plugin is refused with both
//!    versions named;
//! 2. abi_stable's layout check of every type reachable from the root module;
//!
//! then it reads the list of laws. Libraries are never unloaded; every object is freed by the
//! library that allocated it (through its vtable's `drop`).
//!
//! # What breaks the ABI
//! Any change to a `#[repr(C)]` type of this crate, a vtable, or the meaning of a field. Such a
//! change bumps the sdk's minor version while it is 0.x (its major version afterwards). Adding a
//! field at the end of [`PluginModule`] after its last prefix field does not.
//!
//! # Panics and bad numbers
//! Every function a plugin exports runs inside `catch_unwind`: a panicking law becomes an
//! [`ErrorKind::Panic`] error in the host. The host-side handles ([`BoundContactHandle`],
//! [`BoundRestitutionHandle`]) check every number a law returns (batches inside the plugin, fused
//! with the computation) and turn NaN or infinity into an
//! [`ErrorKind::NonFinite`] error that names the inputs.

use crate::error::{ErrorKind, FfiError, LawError};
use crate::law::{
    BoundContact, BoundRestitution, CalibrationTarget, Coefficient, ContactLaw, LawInfo, LawKind,
    RestitutionLaw,
};
use crate::pair::Pair;
use crate::params::{ParamValue, Params};
use abi_stable::{
    library::RootModule,
    sabi_types::VersionStrings,
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// The dashpot-sdk version a plugin or host is built against (`major.minor.patch`).
///
/// Two sides are compatible when they share the major version (the minor while major is 0).
/// The override variable exists only so the test suite can build a deliberately incompatible
/// plugin; never set it otherwise.
pub const ABI_VERSION: &str = match option_env!("DASHPOT_SDK_FAKE_ABI_VERSION") {
    Some(v) => v,
    None => env!("CARGO_PKG_VERSION"),
};

/// Whether a plugin built against sdk `plugin` may be loaded by a host built against `host`.
pub fn abi_compatible(host: &str, plugin: &str) -> bool {
    fn series(v: &str) -> Option<(u64, u64)> {
        let mut it = v.split('.').map(|p| p.trim().parse::<u64>());
        let major = it.next()?.ok()?;
        let minor = it.next()?.ok()?;
        Some(if major == 0 { (0, minor) } else { (major, 0) })
    }
    matches!((series(host), series(plugin)), (Some(a), Some(b)) if a == b)
}

/// Outcome of a hot-path call (per pair or batch).
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

/// The functions of a configured contact law (not yet bound to a pair).
#[repr(C)]
#[derive(StableAbi)]
pub struct ContactLawVTable {
    /// Binds the law at `obj` to `pair`.
    pub bind: unsafe extern "C" fn(obj: *const c_void, pair: &Pair) -> RResult<FfiBoundContact, FfiError>,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A configured contact law owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiContactLaw {
    /// Opaque pointer to the law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static ContactLawVTable,
}

/// The hot-path functions of a contact law bound to a pair.
#[repr(C)]
#[derive(StableAbi)]
pub struct BoundContactVTable {
    /// `*out = F(delta, rate)` (N) for overlap `delta` (m) and rate `rate` (m/s).
    pub force: unsafe extern "C" fn(obj: *const c_void, delta: f64, rate: f64, out: *mut f64) -> CallStatus,
    /// `out[i] = F(delta[i], rate[i])` for `i < n`. The plugin checks the outputs as it goes
    /// (fused with the computation, so the check is nearly free) and returns
    /// [`CallStatus::NonFinite`] with the first bad index in `*first_bad`.
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
    /// The message of the last panic caught on this thread by this plugin (empty if none).
    pub take_panic: extern "C" fn() -> RString,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A contact law bound to a pair, owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiBoundContact {
    /// Opaque pointer to the bound law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static BoundContactVTable,
}

/// The functions of a configured restitution law.
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

/// The hot-path functions of a restitution law bound to a pair.
#[repr(C)]
#[derive(StableAbi)]
pub struct BoundRestitutionVTable {
    /// `*out = r(speed)` for normal impact speed `speed` (m/s).
    pub restitution: unsafe extern "C" fn(obj: *const c_void, speed: f64, out: *mut f64) -> CallStatus,
    /// `out[i] = r(speed[i])` for `i < n`; checked like `BoundContactVTable::force_batch`.
    pub restitution_batch: unsafe extern "C" fn(
        obj: *const c_void,
        speed: *const f64,
        out: *mut f64,
        n: usize,
        first_bad: *mut usize,
    ) -> CallStatus,
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

/// The root module every plugin exports (an abi_stable prefix type: fields may be appended
/// after the last prefix field without breaking older hosts).
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
    /// Descriptions of every law the plugin exports.
    pub laws: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
    /// Creates the contact law `name` from parameters (validated against its schema).
    pub new_contact:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiContactLaw, FfiError>,
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
unsafe impl Send for FfiBoundContact {}
unsafe impl Sync for FfiBoundContact {}
unsafe impl Send for FfiRestitutionLaw {}
unsafe impl Sync for FfiRestitutionLaw {}
unsafe impl Send for FfiBoundRestitution {}
unsafe impl Sync for FfiBoundRestitution {}

// ---------------------------------------------------------------------------------------------
// Plugin side: trampolines compiled into the plugin, generic over the law type.
// ---------------------------------------------------------------------------------------------

/// Implementation details of [`export_laws!`](crate::export_laws). Not a stable API.
#[doc(hidden)]
pub mod __private {
    use super::*;
    use std::cell::RefCell;

    pub use abi_stable;

    thread_local! {
        static LAST_PANIC: RefCell<String> = const { RefCell::new(String::new()) };
        static PANIC_LOCATION: RefCell<String> = const { RefCell::new(String::new()) };
    }

    /// Called once when a plugin library is loaded (from its root-module constructor, so only in
    /// the cdylib, whose standard library is its own): panics inside the plugin no longer print
    /// to stderr; their message and location travel to the host as an error instead.
    pub fn install_quiet_panic_hook() {
        std::panic::set_hook(Box::new(|info| {
            let loc = info
                .location()
                .map(|l| format!("{}:{}", l.file(), l.line()))
                .unwrap_or_default();
            PANIC_LOCATION.with(|s| *s.borrow_mut() = loc);
        }));
    }

    fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
        let msg = if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "(non-string panic payload)".to_string()
        };
        match PANIC_LOCATION.with(|s| std::mem::take(&mut *s.borrow_mut())) {
            loc if loc.is_empty() => msg,
            loc => format!("{msg} (at {loc})"),
        }
    }

    /// Runs `f`, turning a panic into an `ErrorKind::Panic` error.
    pub fn guard<T>(what: &str, f: impl FnOnce() -> Result<T, LawError>) -> RResult<T, FfiError> {
        match catch_unwind(AssertUnwindSafe(f)) {
            Ok(Ok(v)) => RResult::ROk(v),
            Ok(Err(e)) => RResult::RErr(e.into()),
            Err(p) => RResult::RErr(FfiError {
                kind: ErrorKind::Panic,
                message: format!("{what} panicked: {}", panic_message(p)).into(),
            }),
        }
    }

    /// Runs a hot-path call, stashing a panic's message for `take_panic`.
    #[inline(always)]
    fn hot(f: impl FnOnce()) -> CallStatus {
        match catch_unwind(AssertUnwindSafe(f)) {
            Ok(()) => CallStatus::Ok,
            Err(p) => {
                let msg = panic_message(p);
                LAST_PANIC.with(|s| *s.borrow_mut() = msg);
                CallStatus::Panic
            }
        }
    }

    pub extern "C" fn take_panic() -> RString {
        LAST_PANIC.with(|s| std::mem::take(&mut *s.borrow_mut())).into()
    }

    // ---- contact ----
    unsafe extern "C" fn contact_drop<T>(obj: *mut c_void) {
        // A panic in a destructor is swallowed here rather than unwinding into the host.
        let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(obj as *mut T) })));
    }

    unsafe extern "C" fn contact_bind<T: ContactLaw>(
        obj: *const c_void,
        pair: &Pair,
    ) -> RResult<FfiBoundContact, FfiError> {
        guard(&format!("contact law '{}' (bind)", T::NAME), || {
            pair.validate()?;
            let law = unsafe { &*(obj as *const T) };
            let bound = law.bind(pair)?;
            Ok(FfiBoundContact {
                obj: Box::into_raw(Box::new(bound)) as *mut c_void,
                vtable: BoundContactVt::<T::Bound>::VT,
            })
        })
    }

    unsafe extern "C" fn bound_force<B: BoundContact>(
        obj: *const c_void,
        delta: f64,
        rate: f64,
        out: *mut f64,
    ) -> CallStatus {
        hot(|| unsafe { *out = (*(obj as *const B)).force(delta, rate) })
    }

    /// Outputs are checked in blocks this small, right after they are computed: the block's
    /// forces and its check then sit together in the CPU's out-of-order window, so the check
    /// runs in the shadow of the law's arithmetic (square roots) instead of costing a second
    /// pass. Measured on HSD: blocks of 256 cost ~8 % of the force, blocks of 16 ~1 %.
    const CHECK_BLOCK: usize = 16;

    /// Index of the first non-finite value of `o`, if any.
    #[inline(always)]
    fn first_non_finite(o: &[f64]) -> Option<usize> {
        if super::all_finite(o) {
            None
        } else {
            o.iter().position(|v| !v.is_finite())
        }
    }

    unsafe extern "C" fn bound_force_batch<B: BoundContact>(
        obj: *const c_void,
        delta: *const f64,
        rate: *const f64,
        out: *mut f64,
        n: usize,
        first_bad: *mut usize,
    ) -> CallStatus {
        let mut bad = None;
        let st = hot(|| unsafe {
            if n == 0 {
                return;
            }
            let (d, r, o) = (
                std::slice::from_raw_parts(delta, n),
                std::slice::from_raw_parts(rate, n),
                std::slice::from_raw_parts_mut(out, n),
            );
            let law = &*(obj as *const B);
            for (k, ((d, r), o)) in d
                .chunks(CHECK_BLOCK)
                .zip(r.chunks(CHECK_BLOCK))
                .zip(o.chunks_mut(CHECK_BLOCK))
                .enumerate()
            {
                law.force_batch(d, r, o);
                if let Some(i) = first_non_finite(o) {
                    bad = Some(k * CHECK_BLOCK + i);
                    return;
                }
            }
        });
        finish_batch(st, bad, first_bad)
    }

    #[inline(always)]
    fn finish_batch(st: CallStatus, bad: Option<usize>, first_bad: *mut usize) -> CallStatus {
        match (st, bad) {
            (CallStatus::Ok, Some(i)) => {
                if !first_bad.is_null() {
                    unsafe { *first_bad = i };
                }
                CallStatus::NonFinite
            }
            (st, _) => st,
        }
    }

    unsafe extern "C" fn bound_coefficients<B: BoundContact>(
        obj: *const c_void,
    ) -> RResult<RVec<Coefficient>, FfiError> {
        guard("coefficients", || {
            Ok(unsafe { &*(obj as *const B) }.coefficients().into())
        })
    }

    struct ContactVt<T>(T);
    impl<T: ContactLaw> ContactVt<T> {
        const VT: &'static ContactLawVTable = &ContactLawVTable {
            bind: contact_bind::<T>,
            drop: contact_drop::<T>,
        };
    }

    struct BoundContactVt<B>(B);
    impl<B: BoundContact> BoundContactVt<B> {
        const VT: &'static BoundContactVTable = &BoundContactVTable {
            force: bound_force::<B>,
            force_batch: bound_force_batch::<B>,
            coefficients: bound_coefficients::<B>,
            take_panic,
            drop: contact_drop::<B>,
        };
    }

    // ---- restitution ----
    unsafe extern "C" fn restitution_bind<T: RestitutionLaw>(
        obj: *const c_void,
        pair: &Pair,
    ) -> RResult<FfiBoundRestitution, FfiError> {
        guard(&format!("restitution law '{}' (bind)", T::NAME), || {
            pair.validate()?;
            let law = unsafe { &*(obj as *const T) };
            let bound = law.bind(pair)?;
            Ok(FfiBoundRestitution {
                obj: Box::into_raw(Box::new(bound)) as *mut c_void,
                vtable: BoundRestitutionVt::<T::Bound>::VT,
            })
        })
    }

    unsafe extern "C" fn bound_restitution<B: BoundRestitution>(
        obj: *const c_void,
        speed: f64,
        out: *mut f64,
    ) -> CallStatus {
        hot(|| unsafe { *out = (*(obj as *const B)).restitution(speed) })
    }

    unsafe extern "C" fn bound_restitution_batch<B: BoundRestitution>(
        obj: *const c_void,
        speed: *const f64,
        out: *mut f64,
        n: usize,
        first_bad: *mut usize,
    ) -> CallStatus {
        let mut bad = None;
        let st = hot(|| unsafe {
            if n == 0 {
                return;
            }
            let (v, o) = (
                std::slice::from_raw_parts(speed, n),
                std::slice::from_raw_parts_mut(out, n),
            );
            let law = &*(obj as *const B);
            for (k, (v, o)) in v.chunks(CHECK_BLOCK).zip(o.chunks_mut(CHECK_BLOCK)).enumerate() {
                law.restitution_batch(v, o);
                if let Some(i) = first_non_finite(o) {
                    bad = Some(k * CHECK_BLOCK + i);
                    return;
                }
            }
        });
        finish_batch(st, bad, first_bad)
    }

    struct RestitutionVt<T>(T);
    impl<T: RestitutionLaw> RestitutionVt<T> {
        const VT: &'static RestitutionLawVTable = &RestitutionLawVTable {
            bind: restitution_bind::<T>,
            drop: contact_drop::<T>,
        };
    }

    struct BoundRestitutionVt<B>(B);
    impl<B: BoundRestitution> BoundRestitutionVt<B> {
        const VT: &'static BoundRestitutionVTable = &BoundRestitutionVTable {
            restitution: bound_restitution::<B>,
            restitution_batch: bound_restitution_batch::<B>,
            take_panic,
            drop: contact_drop::<B>,
        };
    }

    // ---- law tables built by the export macro ----

    /// A law's closed-form calibration, as stored in the export tables.
    pub type CalibrateFn =
        fn(&CalibrationTarget, &Pair, &[ParamValue]) -> Result<Option<Vec<ParamValue>>, LawError>;

    /// One exported contact law.
    pub struct ContactEntry {
        pub name: &'static str,
        pub info: fn() -> LawInfo,
        pub create: fn(&[ParamValue]) -> Result<FfiContactLaw, LawError>,
        pub calibrate: CalibrateFn,
    }

    impl ContactEntry {
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

    /// One exported restitution law.
    pub struct RestitutionEntry {
        pub name: &'static str,
        pub info: fn() -> LawInfo,
        pub create: fn(&[ParamValue]) -> Result<FfiRestitutionLaw, LawError>,
    }

    impl RestitutionEntry {
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

    fn unknown(kind: &str, name: &str, names: Vec<&str>) -> LawError {
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

    pub fn laws(c: &[ContactEntry], r: &[RestitutionEntry]) -> RResult<RVec<LawInfo>, FfiError> {
        guard("listing laws", || {
            Ok(c.iter()
                .map(|e| (e.info)())
                .chain(r.iter().map(|e| (e.info)()))
                .collect())
        })
    }

    pub fn new_contact(
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
}

/// Exports laws from a plugin crate (`crate-type = ["cdylib"]`). Use once per crate:
///
/// ```text
/// dashpot_sdk::export_laws!(contact: [MyLaw]);
/// dashpot_sdk::export_laws!(restitution: [MyRestitution]);
/// dashpot_sdk::export_laws!(contact: [A, B], restitution: [C]);
/// ```
#[macro_export]
macro_rules! export_laws {
    (contact: [$($c:ty),* $(,)?] $(,)?) => {
        $crate::export_laws!(contact: [$($c),*], restitution: []);
    };
    (restitution: [$($r:ty),* $(,)?] $(,)?) => {
        $crate::export_laws!(contact: [], restitution: [$($r),*]);
    };
    (contact: [$($c:ty),* $(,)?], restitution: [$($r:ty),* $(,)?] $(,)?) => {
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

            static CONTACT: &[p::ContactEntry] = &[$(p::ContactEntry::of::<$c>()),*];
            static RESTITUTION: &[p::RestitutionEntry] = &[$(p::RestitutionEntry::of::<$r>()),*];

            extern "C" fn laws() -> RResult<RVec<LawInfo>, FfiError> {
                p::laws(CONTACT, RESTITUTION)
            }
            extern "C" fn new_contact(
                name: RStr<'_>,
                params: RSlice<'_, ParamValue>,
            ) -> RResult<abi::FfiContactLaw, FfiError> {
                p::new_contact(CONTACT, name, params)
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

// ---------------------------------------------------------------------------------------------
// Host side: loading and safe handles.
// ---------------------------------------------------------------------------------------------

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
    /// The laws it exports.
    pub laws: Vec<LawInfo>,
    module: PluginModuleRef,
}

impl std::fmt::Debug for LoadedPlugin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedPlugin")
            .field("path", &self.path)
            .field("name", &self.name)
            .field("version", &self.version)
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

impl LoadedPlugin {
    /// Loads the plugin at `path`, checking its sdk version and type layouts.
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
                     {ABI_VERSION}; the ABI versions are incompatible (they must share the \
                     major version, or the minor while the major is 0). Rebuild the plugin \
                     against dashpot-sdk {ABI_VERSION}."
                ),
            ));
        }
        let module = header
            .init_root_module::<PluginModuleRef>()
            .map_err(|e| match e {
                LibraryError::AbiInstability(_) => load_error(
                    path,
                    format!(
                        "its types do not have the layout this host expects (built against \
                         dashpot-sdk {plugin_sdk}, host {ABI_VERSION}): it is stale or was built \
                         from a different sdk. Rebuild it. {}",
                        layout_summary(&e.to_string())
                    ),
                ),
                other => load_error(path, other),
            })?;
        let laws: Vec<LawInfo> = match (module.laws())() {
            RResult::ROk(v) => v.into_vec(),
            RResult::RErr(e) => return Err(load_error(path, LawError::from(e))),
        };
        Ok(LoadedPlugin {
            path: path.to_path_buf(),
            name: module.name().to_string(),
            version: module.version().to_string(),
            sdk_version: module.sdk_version().to_string(),
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
        match (self.module.new_contact())(RStr::from_str(name), RSlice::from_slice(params)) {
            RResult::ROk(ffi) => Ok(ContactLawHandle { ffi, info }),
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
        match (self.module.new_restitution())(RStr::from_str(name), RSlice::from_slice(params)) {
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
        match (self.module.calibrate())(RStr::from_str(name), target, pair, RSlice::from_slice(fixed)) {
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

/// A configured contact law from a plugin.
pub struct ContactLawHandle {
    ffi: FfiContactLaw,
    info: LawInfo,
}

impl ContactLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to `pair` (validated first).
    pub fn bind(&self, pair: &Pair) -> Result<BoundContactHandle, LawError> {
        pair.validate()?;
        match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, pair) } {
            RResult::ROk(ffi) => Ok(BoundContactHandle {
                ffi,
                name: self.info.name.to_string(),
            }),
            RResult::RErr(e) => Err(e.into()),
        }
    }
}

impl Drop for ContactLawHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

#[inline]
#[allow(clippy::eq_op)] // v − v is the point: it is NaN exactly when v is not finite
fn all_finite(x: &[f64]) -> bool {
    // v − v is 0 for a finite v and NaN for ±inf or NaN. Eight independent accumulators let the
    // compiler vectorise with plain SSE2 (subpd/addpd), keeping the check to a fraction of a
    // nanosecond per value.
    let mut acc = [0.0f64; 8];
    let mut it = x.chunks_exact(8);
    for c in &mut it {
        for j in 0..8 {
            acc[j] += c[j] - c[j];
        }
    }
    let tail = it.remainder().iter().fold(0.0, |a, v| a + (v - v));
    acc.iter().sum::<f64>() + tail == 0.0
}

fn length_error(what: &str, lens: &[usize]) -> LawError {
    LawError::new(
        ErrorKind::Other,
        format!("{what}: input and output slices must have the same length, got {lens:?}"),
    )
}

/// A contact law bound to a pair: the hot path, with every output checked for NaN/infinity.
pub struct BoundContactHandle {
    ffi: FfiBoundContact,
    name: String,
}

impl BoundContactHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn panic_error(&self) -> LawError {
        let msg = (self.ffi.vtable.take_panic)();
        LawError::new(
            ErrorKind::Panic,
            format!("contact law '{}' panicked: {}", self.name, msg),
        )
    }

    fn non_finite(&self, value: f64, delta: f64, rate: f64) -> LawError {
        LawError::new(
            ErrorKind::NonFinite,
            format!(
                "contact law '{}' returned force {value} at delta = {delta:e} m, rate = {rate:e} m/s",
                self.name
            ),
        )
    }

    /// The normal force (N) at overlap `delta` (m) and rate `rate` (m/s).
    #[inline]
    pub fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        let mut out = 0.0;
        match unsafe { (self.ffi.vtable.force)(self.ffi.obj, delta, rate, &mut out) } {
            CallStatus::Ok if out.is_finite() => Ok(out),
            CallStatus::Ok | CallStatus::NonFinite => Err(self.non_finite(out, delta, rate)),
            CallStatus::Panic => Err(self.panic_error()),
        }
    }

    /// `out[i] = F(delta[i], rate[i])` (N) over slices of equal length.
    pub fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        if delta.len() != out.len() || rate.len() != out.len() {
            return Err(length_error("force_batch", &[delta.len(), rate.len(), out.len()]));
        }
        let mut bad = 0usize;
        let st = unsafe {
            (self.ffi.vtable.force_batch)(
                self.ffi.obj,
                delta.as_ptr(),
                rate.as_ptr(),
                out.as_mut_ptr(),
                out.len(),
                &mut bad,
            )
        };
        match st {
            CallStatus::Ok => Ok(()),
            CallStatus::Panic => Err(self.panic_error()),
            CallStatus::NonFinite => {
                let i = bad.min(out.len().saturating_sub(1));
                Err(self.non_finite(out[i], delta[i], rate[i]))
            }
        }
    }

    /// The bound law's derived constants (stiffness, damping, ...).
    pub fn coefficients(&self) -> Result<Vec<Coefficient>, LawError> {
        match unsafe { (self.ffi.vtable.coefficients)(self.ffi.obj) } {
            RResult::ROk(v) => Ok(v.into_vec()),
            RResult::RErr(e) => Err(e.into()),
        }
    }
}

impl Drop for BoundContactHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

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

/// A restitution law bound to a pair, with every output checked for NaN/infinity.
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

    /// r(v) at normal impact speed `speed` (m/s).
    #[inline]
    pub fn restitution(&self, speed: f64) -> Result<f64, LawError> {
        let mut out = 0.0;
        match unsafe { (self.ffi.vtable.restitution)(self.ffi.obj, speed, &mut out) } {
            CallStatus::Ok if out.is_finite() => Ok(out),
            CallStatus::Ok | CallStatus::NonFinite => Err(self.non_finite(out, speed)),
            CallStatus::Panic => Err(self.panic_error()),
        }
    }

    /// `out[i] = r(speed[i])` over slices of equal length.
    pub fn restitution_batch(&self, speed: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        if speed.len() != out.len() {
            return Err(length_error("restitution_batch", &[speed.len(), out.len()]));
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
            CallStatus::Ok => Ok(()),
            CallStatus::Panic => Err(self.panic_error()),
            CallStatus::NonFinite => {
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
        assert!(abi_compatible("0.1.0", "0.1.7"));
        assert!(abi_compatible("0.1.7", "0.1.0"));
        assert!(!abi_compatible("0.1.0", "0.2.0"));
        assert!(!abi_compatible("0.2.0", "0.1.0"));
        assert!(abi_compatible("1.2.0", "1.0.3"));
        assert!(!abi_compatible("1.0.0", "2.0.0"));
        assert!(!abi_compatible("0.1.0", "garbage"));
    }

    #[test]
    fn finiteness_check_finds_nan_and_inf() {
        assert!(all_finite(&[0.0, -1.0, f64::MAX, f64::MIN_POSITIVE]));
        assert!(!all_finite(&[0.0, f64::NAN]));
        assert!(!all_finite(&[f64::NEG_INFINITY, 1.0]));
        assert!(all_finite(&[]));
    }
}
