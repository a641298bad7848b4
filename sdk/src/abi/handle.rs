//! Host side of the generic shape: the safe handles of a law of any kind, from a plugin of sdk
//! 0.3 or 0.4 ([`LawHandle`], [`ModelHandle`]) or compiled into the host ([`StaticModel`]), each
//! calling the checked trampoline and turning its status into an error that names the contact;
//! and [`BoundModel`], what every bound law of a kind offers a host.

use super::fault::{BatchFault, BatchStatus};
use super::guard::take_panic;
use super::kind::{model_batch, EnergyOut, FfiLaw, FfiModel, Kind, KindBound, KindLaw};
use super::object::{FfiObject, Owned};
use crate::error::{ErrorKind, LawError};
use crate::law::{Coefficient, LawInfo};
use crate::pair::MaterialPair;
use abi_stable::std_types::RString;
use std::ffi::c_void;

/// A law of kind `K` bound to a pair of materials, as a host calls it: from a plugin of any sdk
/// series or compiled into the host, every input and output checked.
pub trait BoundModel<K: Kind>: Send + Sync {
    /// The law's name.
    fn name(&self) -> &str;
    /// History slots per contact (0 for a memoryless law).
    fn history_slots(&self) -> usize;
    /// Whether the law reads the normal law's context (sdk 0.4; see `READS_CONTEXT`): a host
    /// then computes the contexts and passes them in the batch. False by default.
    fn reads_context(&self) -> bool {
        false
    }
    /// Evaluates every contact of `b`, with the energy outputs `energy` asks for: `Ok(true)`
    /// when they were written, `Ok(false)` when the law does not account for energy (or none
    /// was asked for). A non-finite input or output is an error naming the contact.
    fn batch(&self, b: K::Batch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError>;
    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn coefficients(&self, _mass: f64, _radius: f64) -> Result<Vec<Coefficient>, LawError> {
        Ok(Vec::new())
    }
}

/// The accessors `name`, `history_slots` and `reads_context` of a handle keeping the fields
/// `name`, `slots` and `reads_context`.
macro_rules! identity_accessors {
    () => {
        /// The law's name.
        pub fn name(&self) -> &str {
            &self.name
        }

        /// History slots per contact.
        pub fn history_slots(&self) -> usize {
            self.slots
        }

        /// Whether the law reads the normal law's context (sdk 0.4).
        pub fn reads_context(&self) -> bool {
            self.reads_context
        }
    };
}
pub(crate) use identity_accessors;

/// Implements [`BoundModel`] of kind `$k` for `$t` by its inherent methods `name`,
/// `history_slots`, `$batch` and `coefficients`.
macro_rules! bound_model {
    (impl<$($g:ident $(: $b:path)?),*> $k:ty => $t:ty, $batch:ident) => {
        impl<$($g $(: $b)?),*> BoundModel<$k> for $t {
            fn name(&self) -> &str {
                <$t>::name(self)
            }
            fn history_slots(&self) -> usize {
                <$t>::history_slots(self)
            }
            fn reads_context(&self) -> bool {
                <$t>::reads_context(self)
            }
            #[inline]
            fn batch(&self, b: <$k as Kind>::Batch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
                <$t>::$batch(self, b, energy)
            }
            fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
                <$t>::coefficients(self, mass, radius)
            }
        }
    };
}
pub(crate) use bound_model;

bound_model!(impl<K: Kind> K => ModelHandle<K>, batch);
bound_model!(impl<K: Kind, B: KindBound<K>> K => StaticModel<K, B>, batch);

/// A reference or a box of a bound model is one.
macro_rules! forward {
    ($($t:ty),*) => {$(
        impl<K: Kind, M: BoundModel<K> + ?Sized> BoundModel<K> for $t {
            fn name(&self) -> &str {
                (**self).name()
            }
            fn history_slots(&self) -> usize {
                (**self).history_slots()
            }
            fn reads_context(&self) -> bool {
                (**self).reads_context()
            }
            #[inline]
            fn batch(&self, b: K::Batch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
                (**self).batch(b, energy)
            }
            fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
                (**self).coefficients(mass, radius)
            }
        }
    )*};
}
forward!(&M, Box<M>);

/// [`run`] for a plugin of sdk 0.2, whose batch entry `call` takes the 0.2 arrays and writes no
/// energy.
pub(crate) fn run_v2<K: Kind>(
    name: &str,
    slots: usize,
    b: &mut K::Batch<'_>,
    energy: EnergyOut<'_>,
    take_panic: extern "C" fn() -> RString,
    call: impl FnOnce(&K::Ffi, &mut BatchFault) -> BatchStatus,
) -> Result<(), LawError> {
    run::<K>(name, slots, b, energy, take_panic, |ffi, fault, written| {
        *written = false;
        call(ffi, fault)
    })
    .map(|_| ())
}

/// Runs a batch of kind `K` through `call` (a vtable entry or the compiled-in trampoline):
/// lengths checked first, then the status turned into a result; `Ok(true)` when the energy
/// outputs were written.
#[inline]
pub(crate) fn run<K: Kind>(
    name: &str,
    slots: usize,
    b: &mut K::Batch<'_>,
    mut energy: EnergyOut<'_>,
    take_panic: extern "C" fn() -> RString,
    call: impl FnOnce(&K::Ffi, &mut BatchFault, &mut bool) -> BatchStatus,
) -> Result<bool, LawError> {
    K::check_lengths(name, slots, b)?;
    let n = K::len(b);
    if !energy.lengths_ok(n) {
        return Err(crate::lengths::length_error(
            &format!("{} batch", K::KIND.as_str()),
            format!("the energy outputs must have one value per contact ({n})"),
        ));
    }
    if n == 0 {
        return Ok(energy.is_none());
    }
    let (power, elastic) = energy.raw();
    let ffi = K::raw(b, power, elastic);
    let mut fault = BatchFault::default();
    let mut written = false;
    let st = call(&ffi, &mut fault, &mut written);
    if st == BatchStatus::Panic {
        return Err(LawError::new(
            ErrorKind::Panic,
            format!("{} law '{name}' panicked: {}", K::KIND.as_str(), take_panic()),
        ));
    }
    match st {
        BatchStatus::Ok => Ok(written),
        st => Err(K::fault_error(name, b, st, fault)),
    }
}

/// A plugin object of kind `K` in the ABI of its series: 0.4's (`K::Ffi`), or 0.3's
/// (`K::Ffi03`, the part of 0.4's raw batch that 0.3 plugins read).
enum Series<K: Kind, O: FfiObject, O3: FfiObject> {
    V4(Owned<O>),
    V3(Owned<O3>, std::marker::PhantomData<fn() -> K>),
}

/// A configured law of kind `K` from a plugin of sdk 0.3 or 0.4.
pub struct LawHandle<K: Kind> {
    ffi: Series<K, FfiLaw<K::Ffi>, FfiLaw<K::Ffi03>>,
    info: LawInfo,
}

impl<K: Kind> LawHandle<K> {
    /// A law of an sdk 0.4 plugin.
    pub(crate) fn new(ffi: Owned<FfiLaw<K::Ffi>>, info: LawInfo) -> Self {
        LawHandle {
            ffi: Series::V4(ffi),
            info,
        }
    }

    /// A law of an sdk 0.3 plugin.
    pub(crate) fn new_v3(ffi: Owned<FfiLaw<K::Ffi03>>, info: LawInfo) -> Self {
        LawHandle {
            ffi: Series::V3(ffi, std::marker::PhantomData),
            info,
        }
    }

    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<ModelHandle<K>, LawError> {
        materials.validate()?;
        let ffi = match &self.ffi {
            Series::V4(l) => Series::V4(Owned::take(unsafe { (l.vtable.bind)(l.obj, materials) })?),
            Series::V3(l, k) => Series::V3(Owned::take(unsafe { (l.vtable.bind)(l.obj, materials) })?, *k),
        };
        Ok(ModelHandle {
            ffi,
            name: self.info.name.to_string(),
            slots: self.info.history.len(),
            reads_context: self.info.reads_context,
        })
    }
}

/// A law of kind `K` bound to a pair of materials: the hot path, every input and output
/// checked.
pub struct ModelHandle<K: Kind> {
    ffi: Series<K, FfiModel<K::Ffi>, FfiModel<K::Ffi03>>,
    name: String,
    slots: usize,
    reads_context: bool,
}

impl<K: Kind> ModelHandle<K> {
    identity_accessors!();

    /// Evaluates every contact of `b`, with the energy outputs `energy` asks for: `Ok(true)`
    /// when they were written, `Ok(false)` when the law does not account for energy (or none
    /// was asked for). A law of sdk 0.3 is called with the 0.3 part of the raw batch, and what
    /// it leaves unwritten gets this sdk's defaults ([`Kind::older_defaults`]).
    #[inline]
    pub fn batch(&self, mut b: K::Batch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        match &self.ffi {
            Series::V4(m) => run::<K>(
                &self.name,
                self.slots,
                &mut b,
                energy,
                m.vtable.take_panic,
                |ffi, fault, written| unsafe { (m.vtable.batch)(m.obj, ffi, fault, written) },
            ),
            Series::V3(m, _) => self.batch_v3(m, b, energy),
        }
    }

    /// [`ModelHandle::batch`] of a law of an sdk 0.3 plugin `m` (out of line: the hot path is
    /// a law of this sdk's series).
    #[inline(never)]
    fn batch_v3(
        &self,
        m: &FfiModel<K::Ffi03>,
        mut b: K::Batch<'_>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        let written = run::<K>(
            &self.name,
            self.slots,
            &mut b,
            energy,
            m.vtable.take_panic,
            |ffi, fault, written| unsafe { (m.vtable.batch)(m.obj, K::ffi03(ffi), fault, written) },
        )?;
        K::older_defaults(&mut b);
        Ok(written)
    }

    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        super::object::coefficients(match &self.ffi {
            Series::V4(m) => unsafe { (m.vtable.coefficients)(m.obj, mass, radius) },
            Series::V3(m, _) => unsafe { (m.vtable.coefficients)(m.obj, mass, radius) },
        })
    }
}

/// A law of kind `K` compiled into the host (tests, baselines), called through the very
/// trampoline a plugin exports.
pub struct StaticModel<K: Kind, B> {
    law: B,
    name: String,
    slots: usize,
    reads_context: bool,
    kind: std::marker::PhantomData<fn() -> K>,
}

impl<K: Kind, B: KindBound<K>> StaticModel<K, B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: KindLaw<K, Bound = B>>(law: &L, materials: &MaterialPair) -> Result<Self, LawError> {
        materials.validate()?;
        Ok(StaticModel {
            law: law.kind_bind(materials)?,
            name: L::NAME.to_string(),
            slots: L::SLOTS,
            reads_context: L::READS_CONTEXT,
            kind: std::marker::PhantomData,
        })
    }

    /// A bound law as it is, named `name`, keeping `slots` history slots (the sdk's own tests).
    #[cfg(test)]
    pub(crate) fn of_bound(name: &str, slots: usize, law: B) -> Self {
        StaticModel {
            law,
            name: name.to_string(),
            slots,
            reads_context: false,
            kind: std::marker::PhantomData,
        }
    }

    identity_accessors!();

    /// The bound law.
    pub fn law(&self) -> &B {
        &self.law
    }

    /// As [`ModelHandle::batch`].
    pub fn batch(&self, mut b: K::Batch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        let obj = &self.law as *const B as *const c_void;
        run::<K>(
            &self.name,
            self.slots,
            &mut b,
            energy,
            take_panic,
            |ffi, fault, written| unsafe { model_batch::<K, B>(obj, ffi, fault, written) },
        )
    }
}

impl<K: Kind, B: KindBound<K>> StaticModel<K, B> {
    /// The bound law's derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        Ok(self.law.kind_coefficients(mass, radius))
    }
}
