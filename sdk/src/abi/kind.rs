//! One ABI shape for every law kind of sdk 0.3: a configured law ([`FfiLaw`]) binds to a
//! material pair, giving a model ([`FfiModel`]) whose one hot-path entry evaluates a batch of
//! the kind's raw arrays (`K::Ffi`), with the same panic guard, fused input and output checks,
//! AVX2 dispatch and optional energy outputs for every kind. A kind is a [`Kind`]: its raw batch
//! type, its plain-Rust batch (what hosts pass), and how to turn one into the other and a fault
//! into an error; the law side is [`KindBound`] (the checked block loop over a bound law) and
//! [`KindLaw`] (create and bind). Normal, tangential, rolling and twisting laws are instances
//! (see `kinds`); law authors implement only the plain traits ([`ContactLaw`](crate::ContactLaw),
//! [`RollingLaw`](crate::RollingLaw), ...).

use super::checks::CHECK_BLOCK;
use super::plugin::{drop_box, finish, guard, hot, take_panic};
use super::{BatchFault, BatchStatus};
use crate::error::{FfiError, LawError};
use crate::law::{Coefficient, Energy, LawInfo, LawKind};
use crate::pair::MaterialPair;
use crate::params::{ParamSpec, ParamValue, Params};
use abi_stable::{
    std_types::{RResult, RString, RVec},
    StableAbi,
};
use std::ffi::c_void;

/// The functions of a configured law of the kind whose raw batch is `B`.
#[repr(C)]
#[derive(StableAbi)]
pub struct LawVTable<B: 'static> {
    /// Binds the law at `obj` to a pair of materials.
    pub bind:
        unsafe extern "C" fn(obj: *const c_void, materials: &MaterialPair) -> RResult<FfiModel<B>, FfiError>,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A configured law owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiLaw<B: 'static> {
    /// Opaque pointer to the law.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static LawVTable<B>,
}

/// The hot-path functions of a law bound to a material pair.
#[repr(C)]
#[derive(StableAbi)]
pub struct ModelVTable<B: 'static> {
    /// Evaluates a batch; checks inputs and outputs in blocks and stops at the first bad one,
    /// described in `*fault`. `*energy` is set to whether the energy outputs the batch asked
    /// for were written (false when the law does not account for energy).
    pub batch: unsafe extern "C" fn(
        obj: *const c_void,
        batch: &B,
        fault: &mut BatchFault,
        energy: &mut bool,
    ) -> BatchStatus,
    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub coefficients: unsafe extern "C" fn(
        obj: *const c_void,
        mass: f64,
        radius: f64,
    ) -> RResult<RVec<Coefficient>, FfiError>,
    /// The message of the last panic caught on this thread by this plugin (empty if none).
    pub take_panic: extern "C" fn() -> RString,
    /// Frees `obj`.
    pub drop: unsafe extern "C" fn(obj: *mut c_void),
}

/// A law bound to a pair of materials, owned by the plugin that made it.
#[repr(C)]
#[derive(StableAbi)]
pub struct FfiModel<B: 'static> {
    /// Opaque pointer.
    pub obj: *mut c_void,
    /// Its functions.
    pub vtable: &'static ModelVTable<B>,
}

// SAFETY: the objects are `Send + Sync` (the law traits require it); the vtables are statics.
unsafe impl<B> Send for FfiLaw<B> {}
unsafe impl<B> Sync for FfiLaw<B> {}
unsafe impl<B> Send for FfiModel<B> {}
unsafe impl<B> Sync for FfiModel<B> {}

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

    pub(crate) fn raw(&mut self) -> (*mut f64, *mut f64) {
        (
            self.power
                .as_deref_mut()
                .map_or(std::ptr::null_mut(), <[f64]>::as_mut_ptr),
            self.elastic
                .as_deref_mut()
                .map_or(std::ptr::null_mut(), <[f64]>::as_mut_ptr),
        )
    }

    pub(crate) fn lengths_ok(&self, n: usize) -> bool {
        self.power.as_ref().is_none_or(|p| p.len() == n) && self.elastic.as_ref().is_none_or(|e| e.len() == n)
    }
}

/// A law kind: its raw batch and how a host speaks it.
pub trait Kind: 'static {
    /// The raw batch (`#[repr(C)]`, pointers).
    type Ffi: StableAbi + 'static;
    /// The batch as a host passes it (slices).
    type Batch<'a>;
    /// Which kind.
    const KIND: LawKind;
    /// "contact", "tangential", ... for messages.
    const WHAT: &'static str;
    /// Number of contacts of a batch.
    fn len(b: &Self::Batch<'_>) -> usize;
    /// Checks the lengths of a batch's arrays against its contact count and the law's history
    /// `slots`.
    fn check_lengths(name: &str, slots: usize, b: &Self::Batch<'_>) -> Result<(), LawError>;
    /// The raw view of a batch (with the energy outputs, null when not wanted).
    fn raw(b: &mut Self::Batch<'_>, power: *mut f64, elastic: *mut f64) -> Self::Ffi;
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
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient>;
}

/// A configurable law of kind `K`.
pub trait KindLaw<K: Kind>: Sized + Send + Sync + 'static {
    /// The bound law.
    type Bound: KindBound<K>;
    /// Its name.
    const NAME: &'static str;
    /// History slots per contact.
    const SLOTS: usize;
    /// Its description.
    fn kind_info() -> LawInfo;
    /// Its parameter schema.
    fn kind_params() -> Vec<ParamSpec>;
    /// Creates it from validated parameters.
    fn kind_new(p: &Params) -> Result<Self, LawError>;
    /// Binds it.
    fn kind_bind(&self, m: &MaterialPair) -> Result<Self::Bound, LawError>;
}

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
        if super::checks::use_avx2() {
            return run_avx2::<K, B>(law, b);
        }
        law.run(b)
    });
    *energy = matches!(res, Some(Ok(true)));
    finish(res.map(|r| r.map(|_| ())), fault)
}

/// [`KindBound::run`] compiled for AVX2 (the law's code inlined into it): the same bits, four
/// lanes.
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
        Ok(unsafe { &*(obj as *const B) }
            .kind_coefficients(mass, radius)
            .into())
    })
}

unsafe extern "C" fn law_bind<K: Kind, T: KindLaw<K>>(
    obj: *const c_void,
    materials: &MaterialPair,
) -> RResult<FfiModel<K::Ffi>, FfiError> {
    guard(&format!("{} law '{}' (bind)", K::WHAT, T::NAME), || {
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

/// Creates a law of kind `K` from parameters.
pub type CreateFn<K> = fn(&[ParamValue]) -> Result<FfiLaw<<K as Kind>::Ffi>, LawError>;

/// One exported law of kind `K`, as the export macro lists it.
pub struct Entry<K: Kind> {
    /// Its name.
    pub name: &'static str,
    /// Its description.
    pub info: fn() -> LawInfo,
    /// Creates it from parameters.
    pub create: CreateFn<K>,
}

impl<K: Kind> Entry<K> {
    /// The entry of law `T`.
    pub const fn of<T: KindLaw<K>>() -> Entry<K> {
        Entry {
            name: T::NAME,
            info: T::kind_info,
            create: create::<K, T>,
        }
    }
}

/// Creates law `T` of kind `K` from parameters (validated against its schema).
pub fn create<K: Kind, T: KindLaw<K>>(given: &[ParamValue]) -> Result<FfiLaw<K::Ffi>, LawError> {
    let params = Params::resolve(T::NAME, &T::kind_params(), given)?;
    let law = T::kind_new(&params)?;
    Ok(FfiLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: LawVt::<K, T>::VT,
    })
}

/// Creates the law `name` of kind `K` from the plugin's table.
pub fn new_law<K: Kind>(
    table: &[Entry<K>],
    name: abi_stable::std_types::RStr<'_>,
    params: abi_stable::std_types::RSlice<'_, ParamValue>,
) -> RResult<FfiLaw<K::Ffi>, FfiError> {
    guard(&format!("{} law '{name}' (new)", K::WHAT), || {
        match table.iter().find(|e| e.name == name.as_str()) {
            Some(e) => (e.create)(params.as_slice()),
            None => Err(super::plugin::unknown(
                K::WHAT,
                name.as_str(),
                table.iter().map(|e| e.name).collect(),
            )),
        }
    })
}

/// The block loop every kind shares: `f(lo, hi)` checks, evaluates and checks the contacts
/// `[lo, hi)` in blocks of [`CHECK_BLOCK`].
#[inline(always)]
pub(crate) fn blocks(
    n: usize,
    mut f: impl FnMut(usize, usize) -> Result<(), (usize, u8)>,
) -> Result<(), (usize, u8)> {
    let mut lo = 0;
    while lo < n {
        let hi = (lo + CHECK_BLOCK).min(n);
        f(lo, hi)?;
        lo = hi;
    }
    Ok(())
}

/// The energy pass after a batch: `each(i)` is contact `i`'s energy; written to `power` and
/// `elastic` (either may be null). `Ok(false)` if a contact has none (the law does not account
/// for energy), the first non-finite value as a fault.
///
/// # Safety
/// Non-null pointers are valid for `n` values.
#[inline(always)]
pub(crate) unsafe fn energy_pass(
    n: usize,
    power: *mut f64,
    elastic: *mut f64,
    mut each: impl FnMut(usize) -> Option<Energy>,
) -> Result<bool, (usize, u8)> {
    if power.is_null() && elastic.is_null() {
        return Ok(false);
    }
    for i in 0..n {
        let Some(e) = each(i) else {
            return Ok(false);
        };
        if !power.is_null() {
            if !e.power.is_finite() {
                return Err((i, BatchFault::POWER));
            }
            unsafe { *power.add(i) = e.power };
        }
        if !elastic.is_null() {
            if !e.elastic.is_finite() {
                return Err((i, BatchFault::ELASTIC));
            }
            unsafe { *elastic.add(i) = e.elastic };
        }
    }
    Ok(true)
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
