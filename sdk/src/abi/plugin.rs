//! Plugin side: the trampolines compiled into every plugin, generic over the law types, and the
//! export macro. Implementation details of [`export_laws!`](crate::export_laws); not a stable API.

use super::checks::*;
use super::v1;
use super::*;
use crate::error::{ErrorKind, LawError};
use crate::law::{
    BoundContact, BoundRestitution, BoundTangential, ContactLaw, LawKind, NormalBatch, RestitutionLaw,
    TangentialBatch, TangentialLaw,
};
use crate::params::Params;
use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};

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

/// Runs a hot-path call; on a panic stashes its message for `take_panic` and returns `None`.
#[inline(always)]
pub(crate) fn hot<T>(f: impl FnOnce() -> T) -> Option<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(v) => Some(v),
        Err(p) => {
            let msg = panic_message(p);
            LAST_PANIC.with(|s| *s.borrow_mut() = msg);
            None
        }
    }
}

/// The message of the last panic caught on this thread (and forgets it).
pub extern "C" fn take_panic() -> RString {
    LAST_PANIC.with(|s| std::mem::take(&mut *s.borrow_mut())).into()
}

pub(crate) unsafe extern "C" fn drop_box<T>(obj: *mut c_void) {
    // A panic in a destructor is swallowed here rather than unwinding into the host.
    let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(obj as *mut T) })));
}

// ---- contact (0.2) ----

unsafe extern "C" fn contact_bind<T: ContactLaw>(
    obj: *const c_void,
    materials: &MaterialPair,
) -> RResult<FfiContactModel, FfiError> {
    guard(&format!("contact law '{}' (bind)", T::NAME), || {
        materials.validate()?;
        let law = unsafe { &*(obj as *const T) };
        let bound = law.bind(materials)?;
        Ok(FfiContactModel {
            obj: Box::into_raw(Box::new(bound)) as *mut c_void,
            vtable: ContactModelVt::<T::Bound>::VT,
        })
    })
}

/// A normal batch's arrays, for the block loop.
pub(crate) struct NormalBlocks<'a> {
    pub(crate) delta: &'a [f64],
    pub(crate) rate: &'a [f64],
    pub(crate) mass: &'a [f64],
    pub(crate) radius: &'a [f64],
    pub(crate) slots: usize,
    pub(crate) history: &'a mut [f64],
    pub(crate) force: &'a mut [f64],
}

/// The block loop of [`model_force_batch`]: check a block's inputs, run the law on it, check
/// its outputs. Returns the first bad contact and what is wrong with it.
#[inline(always)]
pub(crate) fn normal_blocks<B: BoundContact>(law: &B, b: NormalBlocks<'_>) -> Result<(), (usize, u8)> {
    let n = b.force.len();
    let slots = b.slots;
    let mut lo = 0;
    while lo < n {
        let hi = (lo + CHECK_BLOCK).min(n);
        let (d, r, m, a) = (
            &b.delta[lo..hi],
            &b.rate[lo..hi],
            &b.mass[lo..hi],
            &b.radius[lo..hi],
        );
        if !normal_inputs_ok(d, r, m, a) {
            if let Some((i, f)) = check_normal_inputs(d, r, m, a) {
                return Err((lo + i, f));
            }
        }
        let o = &mut b.force[lo..hi];
        law.force_batch(NormalBatch {
            delta: d,
            rate: r,
            mass: m,
            radius: a,
            slots,
            history: &mut b.history[lo * slots..hi * slots],
            force: o,
        });
        if let Some(i) = first_non_finite(o) {
            return Err((lo + i, BatchFault::OUTPUT));
        }
        lo = hi;
    }
    Ok(())
}

/// [`normal_blocks`] compiled for AVX2 (four f64 lanes instead of SSE2's two), chosen at run
/// time when the CPU has it; the law's code is inlined here and compiled for AVX2 too. The
/// results are the same bits: IEEE arithmetic is exactly rounded lane by lane, and Rust never
/// fuses a multiply and an add on its own.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn normal_blocks_avx2<B: BoundContact>(law: &B, b: NormalBlocks<'_>) -> Result<(), (usize, u8)> {
    normal_blocks(law, b)
}

/// The batch trampoline of a contact model (what a plugin exports for `B`).
///
/// # Safety
/// `obj` points to a `B`; the batch's pointers are valid for its lengths.
pub unsafe extern "C" fn model_force_batch<B: BoundContact>(
    obj: *const c_void,
    b: &FfiNormalBatch,
    fault: &mut BatchFault,
) -> BatchStatus {
    let n = b.n;
    if n == 0 {
        return BatchStatus::Ok;
    }
    let slots = b.slots;
    let res = hot(|| unsafe {
        let delta = std::slice::from_raw_parts(b.delta, n);
        let rate = std::slice::from_raw_parts(b.rate, n);
        let mass = std::slice::from_raw_parts(b.mass, n);
        let radius = std::slice::from_raw_parts(b.radius, n);
        let force = std::slice::from_raw_parts_mut(b.force, n);
        let history: &mut [f64] = if slots == 0 {
            &mut []
        } else {
            std::slice::from_raw_parts_mut(b.history, n * slots)
        };
        let law = &*(obj as *const B);
        let blocks = NormalBlocks {
            delta,
            rate,
            mass,
            radius,
            slots,
            history,
            force,
        };
        #[cfg(target_arch = "x86_64")]
        if use_avx2() {
            return normal_blocks_avx2(law, blocks);
        }
        normal_blocks(law, blocks)
    });
    finish(res, fault)
}

#[inline(always)]
pub(crate) fn finish(res: Option<Result<(), (usize, u8)>>, fault: &mut BatchFault) -> BatchStatus {
    match res {
        None => BatchStatus::Panic,
        Some(Ok(())) => BatchStatus::Ok,
        Some(Err((index, field))) => {
            *fault = BatchFault { index, field };
            if field == BatchFault::OUTPUT {
                BatchStatus::NonFiniteOutput
            } else {
                BatchStatus::BadInput
            }
        }
    }
}

unsafe extern "C" fn model_coefficients<B: BoundContact>(
    obj: *const c_void,
    mass: f64,
    radius: f64,
) -> RResult<RVec<Coefficient>, FfiError> {
    guard("coefficients", || {
        Ok(unsafe { &*(obj as *const B) }.coefficients(mass, radius).into())
    })
}

struct ContactVt<T>(T);
impl<T: ContactLaw> ContactVt<T> {
    const VT: &'static ContactLawVTable = &ContactLawVTable {
        bind: contact_bind::<T>,
        drop: drop_box::<T>,
    };
}

struct ContactModelVt<B>(B);
impl<B: BoundContact> ContactModelVt<B> {
    const VT: &'static ContactModelVTable = &ContactModelVTable {
        force_batch: model_force_batch::<B>,
        coefficients: model_coefficients::<B>,
        take_panic,
        drop: drop_box::<B>,
    };
}

// ---- tangential ----

unsafe extern "C" fn tangential_bind<T: TangentialLaw>(
    obj: *const c_void,
    materials: &MaterialPair,
) -> RResult<FfiTangentialModel, FfiError> {
    guard(&format!("tangential law '{}' (bind)", T::NAME), || {
        materials.validate()?;
        let law = unsafe { &*(obj as *const T) };
        let bound = law.bind(materials)?;
        Ok(FfiTangentialModel {
            obj: Box::into_raw(Box::new(bound)) as *mut c_void,
            vtable: TangentialModelVt::<T::Bound>::VT,
        })
    })
}

/// A tangential batch's arrays, for the block loop.
pub(crate) struct TangentialBlocks<'a> {
    pub(crate) dt: f64,
    pub(crate) normal: &'a [[f64; 3]],
    pub(crate) velocity: &'a [[f64; 3]],
    pub(crate) fnorm: &'a [f64],
    pub(crate) delta: &'a [f64],
    pub(crate) mass: &'a [f64],
    pub(crate) radius: &'a [f64],
    pub(crate) slots: usize,
    pub(crate) history: &'a mut [f64],
    pub(crate) force: &'a mut [[f64; 3]],
}

/// The block loop of [`tangential_force_batch`] (see [`normal_blocks`]).
#[inline(always)]
pub(crate) fn tangential_blocks<B: BoundTangential>(
    law: &B,
    b: TangentialBlocks<'_>,
) -> Result<(), (usize, u8)> {
    let n = b.force.len();
    let slots = b.slots;
    let mut lo = 0;
    while lo < n {
        let hi = (lo + CHECK_BLOCK).min(n);
        if tangential_inputs_ok(
            b.normal[lo..hi].as_flattened(),
            b.velocity[lo..hi].as_flattened(),
            &b.fnorm[lo..hi],
            &b.delta[lo..hi],
            &b.mass[lo..hi],
            &b.radius[lo..hi],
        ) {
            // the common case: nothing to name
        } else {
            let checks: [(Option<usize>, u8); 6] = [
                (
                    first_non_finite(b.normal[lo..hi].as_flattened()).map(|i| i / 3),
                    BatchFault::NORMAL,
                ),
                (
                    first_non_finite(b.velocity[lo..hi].as_flattened()).map(|i| i / 3),
                    BatchFault::VELOCITY,
                ),
                (first_non_finite(&b.fnorm[lo..hi]), BatchFault::NORMAL_FORCE),
                (first_non_finite(&b.delta[lo..hi]), BatchFault::DELTA),
                (first_non_positive(&b.mass[lo..hi]), BatchFault::MASS),
                (first_non_positive(&b.radius[lo..hi]), BatchFault::RADIUS),
            ];
            for (i, f) in checks {
                if let Some(i) = i {
                    return Err((lo + i, f));
                }
            }
        }
        let o = &mut b.force[lo..hi];
        law.force_batch(TangentialBatch {
            dt: b.dt,
            normal: &b.normal[lo..hi],
            velocity: &b.velocity[lo..hi],
            normal_force: &b.fnorm[lo..hi],
            delta: &b.delta[lo..hi],
            mass: &b.mass[lo..hi],
            radius: &b.radius[lo..hi],
            slots,
            history: &mut b.history[lo * slots..hi * slots],
            force: o,
        });
        if let Some(i) = first_non_finite(o.as_flattened()) {
            return Err((lo + i / 3, BatchFault::OUTPUT));
        }
        lo = hi;
    }
    Ok(())
}

/// [`tangential_blocks`] compiled for AVX2 (see [`normal_blocks_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn tangential_blocks_avx2<B: BoundTangential>(law: &B, b: TangentialBlocks<'_>) -> Result<(), (usize, u8)> {
    tangential_blocks(law, b)
}

/// The batch trampoline of a tangential model (what a plugin exports for `B`).
///
/// # Safety
/// `obj` points to a `B`; the batch's pointers are valid for its lengths.
pub unsafe extern "C" fn tangential_force_batch<B: BoundTangential>(
    obj: *const c_void,
    b: &FfiTangentialBatch,
    fault: &mut BatchFault,
) -> BatchStatus {
    let n = b.n;
    if n == 0 {
        return BatchStatus::Ok;
    }
    if !(b.dt >= 0.0 && b.dt < f64::INFINITY) {
        *fault = BatchFault {
            index: 0,
            field: BatchFault::DT,
        };
        return BatchStatus::BadInput;
    }
    let slots = b.slots;
    let res = hot(|| unsafe {
        let normal = std::slice::from_raw_parts(b.normal as *const [f64; 3], n);
        let velocity = std::slice::from_raw_parts(b.velocity as *const [f64; 3], n);
        let fnorm = std::slice::from_raw_parts(b.normal_force, n);
        let delta = std::slice::from_raw_parts(b.delta, n);
        let mass = std::slice::from_raw_parts(b.mass, n);
        let radius = std::slice::from_raw_parts(b.radius, n);
        let force = std::slice::from_raw_parts_mut(b.force as *mut [f64; 3], n);
        let history: &mut [f64] = if slots == 0 {
            &mut []
        } else {
            std::slice::from_raw_parts_mut(b.history, n * slots)
        };
        let law = &*(obj as *const B);
        let blocks = TangentialBlocks {
            dt: b.dt,
            normal,
            velocity,
            fnorm,
            delta,
            mass,
            radius,
            slots,
            history,
            force,
        };
        #[cfg(target_arch = "x86_64")]
        if use_avx2() {
            return tangential_blocks_avx2(law, blocks);
        }
        tangential_blocks(law, blocks)
    });
    finish(res, fault)
}

struct TangentialVt<T>(T);
impl<T: TangentialLaw> TangentialVt<T> {
    const VT: &'static TangentialLawVTable = &TangentialLawVTable {
        bind: tangential_bind::<T>,
        drop: drop_box::<T>,
    };
}

struct TangentialModelVt<B>(B);
impl<B: BoundTangential> TangentialModelVt<B> {
    const VT: &'static TangentialModelVTable = &TangentialModelVTable {
        force_batch: tangential_force_batch::<B>,
        take_panic,
        drop: drop_box::<B>,
    };
}

// ---- restitution (unchanged since 0.1) ----

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
) -> v1::CallStatus {
    match hot(|| unsafe { *out = (*(obj as *const B)).restitution(speed) }) {
        Some(()) => v1::CallStatus::Ok,
        None => v1::CallStatus::Panic,
    }
}

unsafe extern "C" fn bound_restitution_batch<B: BoundRestitution>(
    obj: *const c_void,
    speed: *const f64,
    out: *mut f64,
    n: usize,
    first_bad: *mut usize,
) -> v1::CallStatus {
    if n == 0 {
        return v1::CallStatus::Ok;
    }
    let res = hot(|| unsafe {
        let (v, o) = (
            std::slice::from_raw_parts(speed, n),
            std::slice::from_raw_parts_mut(out, n),
        );
        let law = &*(obj as *const B);
        for (k, (v, o)) in v.chunks(CHECK_BLOCK).zip(o.chunks_mut(CHECK_BLOCK)).enumerate() {
            law.restitution_batch(v, o);
            if let Some(i) = first_non_finite(o) {
                return Some(k * CHECK_BLOCK + i);
            }
        }
        None
    });
    match res {
        None => v1::CallStatus::Panic,
        Some(None) => v1::CallStatus::Ok,
        Some(Some(i)) => {
            if !first_bad.is_null() {
                unsafe { *first_bad = i };
            }
            v1::CallStatus::NonFinite
        }
    }
}

struct RestitutionVt<T>(T);
impl<T: RestitutionLaw> RestitutionVt<T> {
    const VT: &'static RestitutionLawVTable = &RestitutionLawVTable {
        bind: restitution_bind::<T>,
        drop: drop_box::<T>,
    };
}

struct BoundRestitutionVt<B>(B);
impl<B: BoundRestitution> BoundRestitutionVt<B> {
    const VT: &'static BoundRestitutionVTable = &BoundRestitutionVTable {
        restitution: bound_restitution::<B>,
        restitution_batch: bound_restitution_batch::<B>,
        take_panic,
        drop: drop_box::<B>,
    };
}

// ---- law tables built by the export macro ----

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
