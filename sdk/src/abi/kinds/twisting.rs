//! The twisting kind.

use super::*;
use crate::rotation::{BoundTwisting, TwistingBatch, TwistingLaw};

/// A raw 0.4 twisting batch: 0.3's, plus the normal law's contexts (null: none, the
/// defaults).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiTwistingBatch4 {
    /// The 0.3 arrays and outputs.
    pub base: v3::FfiTwistingBatch,
    /// Input: each contact's normal context (`n` values), or null.
    pub context: *const NormalContext,
}

/// The twisting kind.
pub struct Twisting;

impl Kind for Twisting {
    type Ffi = FfiTwistingBatch4;
    type Ffi03 = v3::FfiTwistingBatch;
    type Batch<'a> = TwistingBatch<'a>;
    const KIND: LawKind = LawKind::Twisting;
    fn len(b: &TwistingBatch<'_>) -> usize {
        b.torque.len()
    }
    #[inline(always)]
    fn check_lengths(name: &str, slots: usize, b: &TwistingBatch<'_>) -> Result<(), LawError> {
        b.lengths().check("twisting", name, slots)
    }
    #[inline]
    fn raw(b: &mut TwistingBatch<'_>, power: *mut f64, elastic: *mut f64) -> FfiTwistingBatch4 {
        let base = v3::FfiTwistingBatch {
            n: b.torque.len(),
            slots: b.slots,
            dt: b.dt,
            normal: b.normal.as_ptr() as *const f64,
            rate: b.rate.as_ptr(),
            normal_force: b.normal_force.as_ptr(),
            delta: b.delta.as_ptr(),
            mass: b.mass.as_ptr(),
            radius: b.radius.as_ptr(),
            history: b.history.as_mut_ptr(),
            torque: b.torque.as_mut_ptr(),
            power,
            elastic,
        };
        FfiTwistingBatch4 {
            base,
            context: context_ptr(b.context),
        }
    }
    fn ffi03(b: &FfiTwistingBatch4) -> &v3::FfiTwistingBatch {
        &b.base
    }
    fn fault_error(name: &str, b: &TwistingBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
        let i = f.index.min(b.torque.len().saturating_sub(1));
        match (st, f.field) {
            (BatchStatus::NonFiniteOutput, field) => non_finite_output(
                "twisting",
                name,
                if field == BatchFault::OUTPUT {
                    BatchFault::TORQUE
                } else {
                    field
                },
                i,
                format!(
                    "(twisting rate {:e} rad/s, normal force {:e} N)",
                    b.rate[i], b.normal_force[i]
                ),
            ),
            (_, BatchFault::NORMAL) => bad_vector("twisting", name, BatchFault::NORMAL, i, b.normal[i]),
            (_, BatchFault::RATE) => bad_input("twisting", name, BatchFault::RATE, i, b.rate[i]),
            (_, BatchFault::CONTEXT_INPUT) => bad_context("twisting", name, i, b.context),
            (_, field) => {
                let c = b.contact(i);
                let v = motion_input(field, [c.normal_force, c.delta, c.mass, c.radius, c.dt]);
                bad_input("twisting", name, field, i, v)
            }
        }
    }
}

impl<B: BoundTwisting> KindBound<Twisting> for B {
    #[inline(always)]
    unsafe fn run(&self, b4: &FfiTwistingBatch4) -> Result<bool, (usize, u8)> {
        let b = &b4.base;
        motion_run!(
            b,
            b.power,
            b.elastic,
            b4.context,
            TwistingBatch { rate: f64 => torque: f64 },
            1,
            BatchFault::RATE,
            |batch| self.torque_batch(batch),
            |batch, out| self.torque_batch_energy(batch, out),
        )
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

kind_law!(Twisting, TwistingLaw, T::READS_CONTEXT);
