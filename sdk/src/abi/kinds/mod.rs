//! The law kinds of sdk 0.3 as instances of the one ABI shape of [`kind`](super::kind): normal
//! (0.2's contact batch plus reach and energy), tangential (0.2's batch plus energy), rolling
//! and twisting. Each instance is its raw batch, the host's view of it, and the block loop that
//! checks and evaluates it; everything else (vtables, trampolines, handles) is generic.

use super::checks::*;
use super::host::{bad_input, length_error, normal_non_finite};
use super::kind::{blocks, energy_pass, slice, slice_mut, Kind, KindBound, KindLaw};
use super::plugin::{normal_blocks, tangential_blocks, NormalBlocks, TangentialBlocks};
use super::{BatchFault, BatchStatus};
use crate::error::{ErrorKind, LawError};
use crate::law::{
    BoundContact, BoundTangential, Coefficient, Contact, ContactLaw, LawInfo, LawKind, NormalBatch,
    TangentialBatch, TangentialContact, TangentialLaw,
};
use crate::pair::MaterialPair;
use crate::params::{ParamSpec, Params};
use crate::rotation::{
    BoundRolling, BoundTwisting, RollingBatch, RollingContact, RollingLaw, TwistingBatch, TwistingContact,
    TwistingLaw,
};
use abi_stable::StableAbi;

mod twisting;
mod vector;

pub use twisting::{FfiTwistingBatch, Twisting};
pub use vector::{FfiVectorBatch, Rolling, Tangential};

pub(super) fn non_finite_output(what: &str, name: &str, field: u8, i: usize, value: String) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "{what} law '{name}' returned {} {value} on contact {i}{}",
            BatchFault::field_name(field),
            if field == BatchFault::REACH {
                " (the reach must be finite and ≥ 0, m)"
            } else {
                ""
            }
        ),
    )
}

// ---- normal ----

/// The normal kind of sdk 0.3.
pub struct Normal;

/// A raw 0.3 normal batch: 0.2's arrays, plus the optional outputs (null when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiNormalBatch3 {
    /// The 0.2 arrays.
    pub base: super::FfiNormalBatch,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
    /// Output: reach per contact (m, ≥ 0; the contact ends at δ < −reach), or null.
    pub reach: *mut f64,
}

/// A normal batch as a host passes it to a 0.3 law: the forces, and optionally each contact's
/// reach after the call.
#[derive(Debug)]
pub struct NormalCall<'a> {
    /// The batch.
    pub batch: NormalBatch<'a>,
    /// Output: each contact's reach (m).
    pub reach: Option<&'a mut [f64]>,
}

impl Kind for Normal {
    type Ffi = FfiNormalBatch3;
    type Batch<'a> = NormalCall<'a>;
    const KIND: LawKind = LawKind::Contact;
    const WHAT: &'static str = "contact";
    fn len(b: &NormalCall<'_>) -> usize {
        b.batch.force.len()
    }
    fn check_lengths(name: &str, slots: usize, c: &NormalCall<'_>) -> Result<(), LawError> {
        let b = &c.batch;
        let n = b.force.len();
        let lens = [b.delta.len(), b.rate.len(), b.mass.len(), b.radius.len()];
        if lens.iter().any(|&l| l != n) || c.reach.as_ref().is_some_and(|r| r.len() != n) {
            return Err(length_error(
                "force_batch",
                format!("delta, rate, mass, radius {lens:?}, force {n}"),
            ));
        }
        if b.slots != slots || b.history.len() != n * slots {
            return Err(length_error(
                "force_batch",
                format!(
                    "history has {} values for {n} contacts of {} slots (law '{name}' keeps {slots})",
                    b.history.len(),
                    b.slots
                ),
            ));
        }
        Ok(())
    }
    fn raw(c: &mut NormalCall<'_>, power: *mut f64, elastic: *mut f64) -> FfiNormalBatch3 {
        let b = &mut c.batch;
        FfiNormalBatch3 {
            base: super::FfiNormalBatch {
                n: b.force.len(),
                slots: b.slots,
                delta: b.delta.as_ptr(),
                rate: b.rate.as_ptr(),
                mass: b.mass.as_ptr(),
                radius: b.radius.as_ptr(),
                history: b.history.as_mut_ptr(),
                force: b.force.as_mut_ptr(),
            },
            power,
            elastic,
            reach: c
                .reach
                .as_deref_mut()
                .map_or(std::ptr::null_mut(), <[f64]>::as_mut_ptr),
        }
    }
    fn fault_error(name: &str, c: &NormalCall<'_>, st: BatchStatus, fault: BatchFault) -> LawError {
        let b = &c.batch;
        let i = fault.index.min(b.force.len().saturating_sub(1));
        let contact = Contact {
            delta: b.delta[i],
            rate: b.rate[i],
            mass: b.mass[i],
            radius: b.radius[i],
        };
        match (st, fault.field) {
            (BatchStatus::NonFiniteOutput, BatchFault::OUTPUT) => {
                normal_non_finite(name, b.force[i], contact)
            }
            (BatchStatus::NonFiniteOutput, f) => non_finite_output(
                "contact",
                name,
                f,
                i,
                format!("(at delta = {:e} m)", contact.delta),
            ),
            (_, f) => {
                let v = match f {
                    BatchFault::DELTA => contact.delta,
                    BatchFault::RATE => contact.rate,
                    BatchFault::MASS => contact.mass,
                    _ => contact.radius,
                };
                bad_input("contact", name, f, i, v)
            }
        }
    }
}

pub(super) fn history_of(h: &[f64], slots: usize, i: usize) -> &[f64] {
    if slots == 0 {
        &[]
    } else {
        &h[i * slots..(i + 1) * slots]
    }
}

impl<B: BoundContact> KindBound<Normal> for B {
    #[inline(always)]
    unsafe fn run(&self, b: &FfiNormalBatch3) -> Result<bool, (usize, u8)> {
        let (n, slots) = (b.base.n, b.base.slots);
        let (delta, rate, mass, radius, history, force) = unsafe {
            (
                slice(b.base.delta, n),
                slice(b.base.rate, n),
                slice(b.base.mass, n),
                slice(b.base.radius, n),
                slice_mut(b.base.history, n * slots),
                slice_mut(b.base.force, n),
            )
        };
        normal_blocks(
            self,
            NormalBlocks {
                delta,
                rate,
                mass,
                radius,
                slots,
                history: &mut *history,
                force: &mut *force,
            },
        )?;
        let contact = |i: usize| Contact {
            delta: delta[i],
            rate: rate[i],
            mass: mass[i],
            radius: radius[i],
        };
        if !b.reach.is_null() {
            for i in 0..n {
                let r = self.reach(&contact(i), history_of(history, slots, i));
                if !(0.0..f64::INFINITY).contains(&r) {
                    return Err((i, BatchFault::REACH));
                }
                unsafe { *b.reach.add(i) = r };
            }
        }
        unsafe {
            energy_pass(n, b.power, b.elastic, |i| {
                self.energy(&contact(i), history_of(history, slots, i), force[i])
            })
        }
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

impl<T: ContactLaw> KindLaw<Normal> for T {
    type Bound = T::Bound;
    const NAME: &'static str = T::NAME;
    const SLOTS: usize = T::HISTORY.len();
    fn kind_info() -> LawInfo {
        T::info()
    }
    fn kind_params() -> Vec<ParamSpec> {
        T::params()
    }
    fn kind_new(p: &Params) -> Result<Self, LawError> {
        T::new(p)
    }
    fn kind_bind(&self, m: &MaterialPair) -> Result<T::Bound, LawError> {
        self.bind(m)
    }
}
