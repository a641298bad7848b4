//! Plugin side: the trampolines compiled into every plugin, generic over the law types, and the
//! export macro. Implementation details of [`export_laws!`](crate::export_laws); not a stable API.

use super::checks::*;
use super::v1;
use super::*;
use crate::error::{ErrorKind, LawError};
use crate::law::{
    BoundContact, BoundRestitution, BoundTangential, ContactLaw, NormalBatch, RestitutionLaw,
    TangentialBatch, TangentialLaw,
};
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

pub(crate) struct ContactVt<T>(T);
impl<T: ContactLaw> ContactVt<T> {
    pub(crate) const VT: &'static ContactLawVTable = &ContactLawVTable {
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

pub(crate) struct TangentialVt<T>(T);
impl<T: TangentialLaw> TangentialVt<T> {
    pub(crate) const VT: &'static TangentialLawVTable = &TangentialLawVTable {
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

pub(crate) struct RestitutionVt<T>(T);
impl<T: RestitutionLaw> RestitutionVt<T> {
    pub(crate) const VT: &'static RestitutionLawVTable = &RestitutionLawVTable {
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

pub use super::export::*;
