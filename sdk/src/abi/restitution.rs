//! Restitution laws, plugin side: the trampolines of the 0.1 restitution ABI (unchanged since),
//! compiled into every plugin for each law it exports.

use super::checks::{first_non_finite, CHECK_BLOCK};
use super::guard::{drop_box, guard, hot, take_panic};
use super::kind::{Create, Entry};
use super::series::{
    BoundRestitutionVTable, CallStatus, FfiBoundRestitution, FfiRestitutionLaw, RestitutionLawVTable,
};
use crate::error::{FfiError, LawError};
use crate::law::{BoundRestitution, RestitutionLaw};
use crate::pair::Pair;
use crate::params::{configure, ParamValue};
use abi_stable::std_types::RResult;
use std::ffi::c_void;

/// Creates a restitution law from parameters.
pub type CreateRestitution = Create<FfiRestitutionLaw>;

impl Entry<CreateRestitution> {
    /// The entry of restitution law `T`.
    pub const fn restitution<T: RestitutionLaw>() -> Entry<CreateRestitution> {
        Entry {
            name: T::NAME,
            make: create::<T>,
        }
    }
}

fn create<T: RestitutionLaw>(given: &[ParamValue]) -> Result<FfiRestitutionLaw, LawError> {
    let law = configure::<T>(T::NAME, given, T::check)?;
    Ok(FfiRestitutionLaw {
        obj: Box::into_raw(Box::new(law)) as *mut c_void,
        vtable: RestitutionVt::<T>::VT,
    })
}

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
    match hot(|| unsafe { *out = (*(obj as *const B)).restitution(speed) }) {
        Some(()) => CallStatus::Ok,
        None => CallStatus::Panic,
    }
}

unsafe extern "C" fn bound_restitution_batch<B: BoundRestitution>(
    obj: *const c_void,
    speed: *const f64,
    out: *mut f64,
    n: usize,
    first_bad: *mut usize,
) -> CallStatus {
    if n == 0 {
        return CallStatus::Ok;
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
        None => CallStatus::Panic,
        Some(None) => CallStatus::Ok,
        Some(Some(i)) => {
            if !first_bad.is_null() {
                unsafe { *first_bad = i };
            }
            CallStatus::NonFinite
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
