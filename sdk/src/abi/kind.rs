//! One ABI shape for every law kind (sdk 0.3 and later): a configured law ([`FfiLaw`]) binds to a
//! material pair, giving a model ([`FfiModel`]) whose one hot-path entry evaluates a batch of
//! the kind's raw arrays (`K::Ffi`), with the same panic guard, fused input and output checks,
//! AVX2 dispatch and optional energy outputs for every kind. A kind is a [`Kind`]: its raw batch
//! type, its plain-Rust batch (what hosts pass), and how to turn one into the other and a fault
//! into an error; the law side is [`KindBound`] (the checked block loop over a bound law) and
//! [`KindLaw`] (configure and bind). Normal, tangential, rolling and twisting laws are instances
//! (see `kinds`); law authors implement only the plain traits ([`ContactLaw`](crate::ContactLaw),
//! [`RollingLaw`](crate::RollingLaw), ...).

use super::fault::{BatchFault, BatchStatus};
use super::ffi::{self, Coefficient};
use super::guard::{drop_box, finish, guard, hot, take_panic};
use super::object::ffi_object;
use crate::error::{ErrorKind, FfiError, LawError};
use crate::law::LawKind;
use crate::pair::MaterialPair;
use crate::params::{configure, LawParams, ParamValue};
use abi_stable::{
    std_types::{RResult, RSlice, RStr, RVec},
    StableAbi,
};
use std::ffi::c_void;

ffi_object!(law
    /// The functions of a configured law of the kind whose raw batch is `B`.
    LawVTable<B> {
        /// Binds the law at `obj` to a pair of materials.
        pub bind:
            unsafe extern "C" fn(obj: *const c_void, materials: &MaterialPair) -> RResult<FfiModel<B>, FfiError>,
    }
    /// A configured law owned by the plugin that made it.
    FfiLaw
);

ffi_object!(model_with_coefficients
    /// The hot-path functions of a law bound to a material pair.
    ModelVTable<B> {
        /// Evaluates a batch; checks inputs and outputs in blocks and stops at the first bad one,
        /// described in `*fault`. `*energy` is set to whether the energy outputs the batch asked
        /// for were written (false when the law does not account for energy).
        pub batch: unsafe extern "C" fn(
            obj: *const c_void,
            batch: &B,
            fault: &mut BatchFault,
            energy: &mut bool,
        ) -> BatchStatus,
    }
    /// A law bound to a pair of materials, owned by the plugin that made it.
    FfiModel
);

/// A root-module entry that creates a law of the kind whose raw batch is `B` by name.
pub type NewFn<B> =
    extern "C" fn(name: RStr<'_>, params: RSlice<'_, ffi::ParamValue>) -> RResult<FfiLaw<B>, FfiError>;

/// Optional per-contact energy outputs of a batch call (sdk 0.3): `None` when the host does not
/// want them (nothing is computed then).
#[derive(Debug, Default)]
pub struct EnergyOut<'a> {
    /// Dissipated power per contact (W, ≥ 0).
    pub power: Option<&'a mut [f64]>,
    /// Elastic energy stored per contact (J).
    pub elastic: Option<&'a mut [f64]>,
}

impl EnergyOut<'_> {
    /// No energy outputs.
    pub fn none() -> EnergyOut<'static> {
        EnergyOut::default()
    }

    /// Whether no output is wanted.
    pub fn is_none(&self) -> bool {
        self.power.is_none() && self.elastic.is_none()
    }

    pub(crate) fn raw(&mut self) -> (*mut f64, *mut f64) {
        (raw_out(&mut self.power), raw_out(&mut self.elastic))
    }

    pub(crate) fn lengths_ok(&self, n: usize) -> bool {
        self.power.as_ref().is_none_or(|p| p.len() == n) && self.elastic.as_ref().is_none_or(|e| e.len() == n)
    }
}

/// The pointer of an optional output array (null when not wanted).
pub(crate) fn raw_out(o: &mut Option<&mut [f64]>) -> *mut f64 {
    o.as_deref_mut().map_or(std::ptr::null_mut(), <[f64]>::as_mut_ptr)
}

/// A law kind: its raw batch and how a host speaks it.
pub trait Kind: 'static {
    /// The raw batch (`#[repr(C)]`, pointers).
    type Ffi: StableAbi + 'static;
    /// The kind's raw batch in sdk 0.3, which [`Kind::Ffi`] extends (its first field): what a
    /// law of a 0.3 plugin is called with. A kind new in sdk 0.4 (heat) has none: it names its
    /// own raw batch here, never used (no 0.3 plugin exports such a law).
    type Ffi03: StableAbi + 'static;
    /// The batch as a host passes it (slices).
    type Batch<'a>;
    /// Which kind (named in messages by [`LawKind::as_str`]).
    const KIND: LawKind;
    /// Number of contacts of a batch.
    fn len(b: &Self::Batch<'_>) -> usize;
    /// Checks the lengths of a batch's arrays against its contact count and the law's history
    /// `slots`.
    fn check_lengths(name: &str, slots: usize, b: &Self::Batch<'_>) -> Result<(), LawError>;
    /// The raw view of a batch (with the energy outputs, null when not wanted).
    fn raw(b: &mut Self::Batch<'_>, power: *mut f64, elastic: *mut f64) -> Self::Ffi;
    /// The sdk 0.3 part of a raw batch.
    fn ffi03(b: &Self::Ffi) -> &Self::Ffi03;
    /// Writes, after a law of an older sdk has evaluated batch `b`, what that law leaves
    /// unwritten as this sdk's defaults (the normal kind: each contact's context, when asked
    /// for); nothing by default.
    fn older_defaults(_b: &mut Self::Batch<'_>) {}
    /// The error for a bad input or output found by the plugin (`status` not `Ok`/`Panic`).
    fn fault_error(name: &str, b: &Self::Batch<'_>, status: BatchStatus, fault: BatchFault) -> LawError;
}

/// A bound law's checked block loop over the raw batch of kind `K`.
pub trait KindBound<K: Kind>: Send + Sync + 'static {
    /// Evaluates the batch, checking inputs and outputs: `Ok(written)` with whether energy was
    /// written, or the first bad contact and array.
    ///
    /// # Safety
    /// The batch's pointers are valid for its lengths.
    unsafe fn run(&self, b: &K::Ffi) -> Result<bool, (usize, u8)>;
    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<crate::Coefficient>;
}

/// A configurable law of kind `K` (a blanket implementation for every law of the kind's
/// trait).
pub trait KindLaw<K: Kind>: LawParams + Send + Sync + 'static {
    /// The bound law.
    type Bound: KindBound<K>;
    /// Its name.
    const NAME: &'static str;
    /// History slots per contact.
    const SLOTS: usize;
    /// Whether it reads the normal law's context (sdk 0.4).
    const READS_CONTEXT: bool;
    /// Its description.
    fn kind_info() -> crate::LawInfo;
    /// Checks its parameters together.
    fn kind_check(&self) -> Result<(), LawError>;
    /// Binds it.
    fn kind_bind(&self, m: &MaterialPair) -> Result<Self::Bound, LawError>;
}

/// Implements [`KindLaw`] of kind `$kind` for every law of trait `$law` (which reads the
/// normal context when `$reads`, an expression of the law `T`).
macro_rules! kind_law {
    ($kind:ty, $law:ident, $reads:expr) => {
        impl<T: $law> $crate::abi::kind::KindLaw<$kind> for T {
            type Bound = T::Bound;
            const NAME: &'static str = T::NAME;
            const SLOTS: usize = T::HISTORY.len();
            const READS_CONTEXT: bool = $reads;
            fn kind_info() -> $crate::LawInfo {
                T::info()
            }
            fn kind_check(&self) -> Result<(), LawError> {
                self.check()
            }
            fn kind_bind(&self, m: &MaterialPair) -> Result<T::Bound, LawError> {
                self.bind(m)
            }
        }
    };
}
pub(crate) use kind_law;

/// The batch trampoline of kind `K` for bound law `B` (what a plugin exports).
///
/// # Safety
/// `obj` points to a `B`; the batch's pointers are valid for its lengths.
pub unsafe extern "C" fn model_batch<K: Kind, B: KindBound<K>>(
    obj: *const c_void,
    b: &K::Ffi,
    fault: &mut BatchFault,
    energy: &mut bool,
) -> BatchStatus {
    let res = hot(|| unsafe {
        let law = &*(obj as *const B);
        #[cfg(target_arch = "x86_64")]
        if crate::simd::available() {
            return run_avx2::<K, B>(law, b);
        }
        law.run(b)
    });
    *energy = matches!(res, Some(Ok(true)));
    finish(res.map(|r| r.map(|_| ())), fault)
}

/// [`KindBound::run`] compiled for AVX2 (four f64 lanes instead of SSE2's two), chosen at run
/// time when the CPU has it; the law's code is inlined here and compiled for AVX2 too. The
/// results are the same bits: IEEE arithmetic is exactly rounded lane by lane, and Rust never
/// fuses a multiply and an add on its own.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<K: Kind, B: KindBound<K>>(law: &B, b: &K::Ffi) -> Result<bool, (usize, u8)> {
    unsafe { law.run(b) }
}

unsafe extern "C" fn model_coefficients<K: Kind, B: KindBound<K>>(
    obj: *const c_void,
    mass: f64,
    radius: f64,
) -> RResult<RVec<Coefficient>, FfiError> {
    guard("coefficients", || {
        Ok(ffi::to_ffi(
            &unsafe { &*(obj as *const B) }.kind_coefficients(mass, radius),
        ))
    })
}

unsafe extern "C" fn law_bind<K: Kind, T: KindLaw<K>>(
    obj: *const c_void,
    materials: &MaterialPair,
) -> RResult<FfiModel<K::Ffi>, FfiError> {
    guard(&format!("{} law '{}' (bind)", K::KIND.as_str(), T::NAME), || {
        materials.validate()?;
        let bound = unsafe { &*(obj as *const T) }.kind_bind(materials)?;
        Ok(FfiModel {
            obj: Box::into_raw(Box::new(bound)) as *mut c_void,
            vtable: ModelVt::<K, T::Bound>::VT,
        })
    })
}

struct ModelVt<K, B>(K, B);
impl<K: Kind, B: KindBound<K>> ModelVt<K, B> {
    const VT: &'static ModelVTable<K::Ffi> = &ModelVTable {
        batch: model_batch::<K, B>,
        coefficients: model_coefficients::<K, B>,
        take_panic,
        drop: drop_box::<B>,
    };
}

struct LawVt<K, T>(K, T);
impl<K: Kind, T: KindLaw<K>> LawVt<K, T> {
    const VT: &'static LawVTable<K::Ffi> = &LawVTable {
        bind: law_bind::<K, T>,
        drop: drop_box::<T>,
    };
}

/// One law of a plugin's table of kind `what`: its name, and what makes it (a constructor, or a
/// closed-form calibration).
pub struct Entry<F: 'static> {
    /// Its name.
    pub name: &'static str,
    /// What the table holds for it.
    pub make: F,
}

/// Creates a law object `F` from parameters.
pub type Create<F> = fn(&[ParamValue]) -> Result<F, LawError>;

/// Creates a law of the kind whose raw batch is `B` from parameters.
pub type CreateFn<B> = Create<FfiLaw<B>>;

impl<B: 'static> Entry<CreateFn<B>> {
    /// The entry of law `T` of kind `K`.
    pub const fn of<K: Kind<Ffi = B>, T: KindLaw<K>>() -> Entry<CreateFn<B>> {
        Entry {
            name: T::NAME,
            make: create::<K, T>,
        }
    }
}

/// Creates law `T` of kind `K` from parameters.
fn create<K: Kind, T: KindLaw<K>>(given: &[ParamValue]) -> Result<FfiLaw<K::Ffi>, LawError> {
    let law = configure::<T>(T::NAME, given, T::kind_check)?;
    Ok(FfiLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: LawVt::<K, T>::VT,
    })
}

/// The entry `name` of `table`, a plugin's laws of kind `what`; an error listing them if there
/// is none.
pub(crate) fn find<'a, F>(table: &'a [Entry<F>], what: &str, name: &str) -> Result<&'a F, LawError> {
    match table.iter().find(|e| e.name == name) {
        Some(e) => Ok(&e.make),
        None => {
            let names: Vec<&str> = table.iter().map(|e| e.name).collect();
            Err(LawError::new(
                ErrorKind::UnknownLaw,
                format!(
                    "this plugin has no {what} law '{name}'; it has: {}",
                    if names.is_empty() {
                        "(none)".to_string()
                    } else {
                        names.join(", ")
                    }
                ),
            ))
        }
    }
}

/// Creates the law `name` of kind `what` from the plugin's `table` (a root-module entry).
pub fn new_law<F>(
    table: &[Entry<Create<F>>],
    what: &str,
    name: RStr<'_>,
    params: RSlice<'_, ffi::ParamValue>,
) -> RResult<F, FfiError> {
    guard(&format!("{what} law '{name}' (new)"), || {
        let given: Vec<ParamValue> = params.iter().cloned().map(ParamValue::from).collect();
        find(table, what, name.as_str())?(&given)
    })
}

/// The block loop every kind shares: `blocks!(n, |lo, hi| body)` checks, evaluates and checks
/// the contacts `[lo, hi)` in blocks of [`CHECK_BLOCK`](super::checks::CHECK_BLOCK); `body` is a
/// `Result<(), (usize, u8)>` and its error (or a `?` inside it) returns from the enclosing
/// function. `blocks!(start => n, ...)` starts at contact `start`. A macro, not a function
/// taking a closure: the body must be compiled inline into the AVX2 copy of the batch loop
/// (`run_avx2`), and a closure LLVM declines to inline is compiled for the baseline target
/// (SSE2) alone, which made every batch ~1.6× slower.
macro_rules! blocks {
    ($n:expr, |$lo:ident, $hi:ident| $body:expr) => {
        $crate::abi::kind::blocks!(0 => $n, |$lo, $hi| $body)
    };
    ($start:expr => $n:expr, |$lo:ident, $hi:ident| $body:expr) => {{
        let n: usize = $n;
        let mut $lo: usize = $start;
        while $lo < n {
            let $hi = ($lo + $crate::abi::checks::CHECK_BLOCK).min(n);
            let r: Result<(), (usize, u8)> = $body;
            r?;
            $lo = $hi;
        }
    }};
}
pub(crate) use blocks;

/// The energy outputs of a raw batch of `n` contacts: `None` when neither is wanted; else both
/// as slices, a scratch array standing in for a null one (a host may want only one of them;
/// the law computes both).
///
/// # Safety
/// Non-null pointers are valid for `n` values and not aliased.
#[inline(always)]
pub(crate) unsafe fn energy_out(
    n: usize,
    power: *mut f64,
    elastic: *mut f64,
    scratch: &mut Vec<f64>,
) -> Option<(&mut [f64], &mut [f64])> {
    match (power.is_null(), elastic.is_null()) {
        (true, true) => None,
        (false, false) => Some(unsafe { (slice_mut(power, n), slice_mut(elastic, n)) }),
        (true, false) => {
            scratch.resize(n, 0.0);
            Some((scratch.as_mut_slice(), unsafe { slice_mut(elastic, n) }))
        }
        (false, true) => {
            scratch.resize(n, 0.0);
            Some((unsafe { slice_mut(power, n) }, scratch.as_mut_slice()))
        }
    }
}

/// Checks a block's energy outputs (`lo` its first contact): the first non-finite power or
/// elastic energy as a fault.
#[inline(always)]
pub(crate) fn check_energy(lo: usize, power: &[f64], elastic: &[f64]) -> Result<(), (usize, u8)> {
    use super::checks::first_non_finite;
    if let Some(i) = first_non_finite(power) {
        return Err((lo + i, BatchFault::POWER));
    }
    if let Some(i) = first_non_finite(elastic) {
        return Err((lo + i, BatchFault::ELASTIC));
    }
    Ok(())
}

/// A slice from a raw pointer, empty when `n == 0` (the pointer may then dangle or be null).
///
/// # Safety
/// For `n > 0`, `p` is valid for `n` values.
#[inline(always)]
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 {
        &[]
    } else {
        unsafe { std::slice::from_raw_parts(p, n) }
    }
}

/// A mutable slice from a raw pointer, empty when `n == 0`.
///
/// # Safety
/// For `n > 0`, `p` is valid for `n` values and not aliased.
#[inline(always)]
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 {
        &mut []
    } else {
        unsafe { std::slice::from_raw_parts_mut(p, n) }
    }
}
