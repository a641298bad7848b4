//! The twisting kind.

use super::*;
use crate::rotation::{BoundTwisting, TwistingBatch, TwistingLaw};

/// A raw twisting batch: `normal` is `n` `[x, y, z]` triples, the rest `n` values, `history`
/// `n × slots`; `power` and `elastic` optional outputs (null when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiTwistingBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Unit normals (3n values).
    pub normal: *const f64,
    /// Relative twisting rates (rad/s).
    pub rate: *const f64,
    /// Normal forces (N).
    pub normal_force: *const f64,
    /// Overlaps (m).
    pub delta: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history, updated in place.
    pub history: *mut f64,
    /// Output: twisting torques about n̂ (N·m).
    pub torque: *mut f64,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
}

/// The twisting kind of sdk 0.3.
pub struct Twisting;

impl Kind for Twisting {
    type Ffi = FfiTwistingBatch;
    type Batch<'a> = TwistingBatch<'a>;
    const KIND: LawKind = LawKind::Twisting;
    fn len(b: &TwistingBatch<'_>) -> usize {
        b.torque.len()
    }
    fn check_lengths(name: &str, slots: usize, b: &TwistingBatch<'_>) -> Result<(), LawError> {
        b.lengths().check("twisting", name, slots)
    }
    fn raw(b: &mut TwistingBatch<'_>, power: *mut f64, elastic: *mut f64) -> FfiTwistingBatch {
        FfiTwistingBatch {
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
        }
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
    unsafe fn run(&self, b: &FfiTwistingBatch) -> Result<bool, (usize, u8)> {
        motion_run!(
            b,
            b.power,
            b.elastic,
            TwistingBatch { rate: f64 => torque: f64 },
            |lo, nl: &[[f64; 3]], ml: &[f64], f: &[f64], d: &[f64], m: &[f64], a: &[f64]| {
                first_bad_motion(lo, nl.as_flattened(), (first_non_finite(ml), BatchFault::RATE), f, d, m, a)
            },
            |batch| self.torque_batch(batch),
            |batch, out| self.torque_batch_energy(batch, out),
            first_non_finite,
        )
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

kind_law!(Twisting, TwistingLaw);
