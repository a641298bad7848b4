//! The vector kinds: tangential and rolling laws share one batch ([`VectorBatch`]), one raw
//! batch and one checked block loop; they differ only in their law traits.

use super::*;
use crate::law::EnergyBatch;
use crate::motion::TangentialLaw;
use crate::motion::{BoundTangential, VectorBatch};
use crate::rotation::{BoundRolling, RollingLaw};

/// A raw 0.4 batch of a vector kind (tangential, rolling): 0.3's, plus the normal law's
/// contexts (null: none, the defaults).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiVectorBatch4 {
    /// The 0.3 arrays and outputs.
    pub base: v3::FfiVectorBatch,
    /// Input: each contact's normal context (`n` values), or null.
    pub context: *const NormalContext,
}

/// A bound law of a vector kind: its batch call and its energy.
trait VectorLaw {
    fn batch(&self, b: VectorBatch<'_>);
    fn batch_energy(&self, b: VectorBatch<'_>, out: EnergyBatch<'_>) -> bool;
}

/// Declares vector kind `$kind` (`$law_kind`) of bound-law trait `$bound` and law trait `$law`.
macro_rules! vector_kind {
    ($(#[$doc:meta])* $kind:ident, $law_kind:expr, $bound:ident, $law:ident, $coef:expr) => {
        $(#[$doc])*
        pub struct $kind;

        impl Kind for $kind {
            type Ffi = FfiVectorBatch4;
            type Ffi03 = v3::FfiVectorBatch;
            type Batch<'a> = VectorBatch<'a>;
            const KIND: LawKind = $law_kind;
            fn len(b: &VectorBatch<'_>) -> usize {
                b.force.len()
            }
            #[inline(always)]
            fn check_lengths(name: &str, slots: usize, b: &VectorBatch<'_>) -> Result<(), LawError> {
                b.lengths().check(Self::KIND.as_str(), name, slots)
            }
            #[inline]
            fn raw(b: &mut VectorBatch<'_>, power: *mut f64, elastic: *mut f64) -> FfiVectorBatch4 {
                FfiVectorBatch4 {
                    base: v3::FfiVectorBatch {
                        base: raw_base(b),
                        power,
                        elastic,
                    },
                    context: context_ptr(b.context),
                }
            }
            fn ffi03(b: &FfiVectorBatch4) -> &v3::FfiVectorBatch {
                &b.base
            }
            fn fault_error(name: &str, b: &VectorBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
                fault_error(Self::KIND.as_str(), name, b, st, f)
            }
        }

        impl<B: $bound> VectorLaw for Bound<'_, $kind, B> {
            #[inline(always)]
            fn batch(&self, b: VectorBatch<'_>) {
                self.0.force_batch(b)
            }
            #[inline(always)]
            fn batch_energy(&self, b: VectorBatch<'_>, out: EnergyBatch<'_>) -> bool {
                self.0.force_batch_energy(b, out)
            }
        }

        impl<B: $bound> KindBound<$kind> for B {
            #[inline(always)]
            unsafe fn run(&self, b: &FfiVectorBatch4) -> Result<bool, (usize, u8)> {
                unsafe { run(&Bound::<$kind, B>(self, std::marker::PhantomData), b) }
            }
            #[allow(clippy::redundant_closure_call)]
            fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
                ($coef)(self, mass, radius)
            }
        }

        kind_law!($kind, $law, T::READS_CONTEXT);
    };
}

/// A bound law seen as a law of vector kind `K` (a law may implement both vector traits).
struct Bound<'a, K, B>(&'a B, std::marker::PhantomData<K>);

vector_kind!(
    /// The tangential kind.
    Tangential,
    LawKind::Tangential,
    BoundTangential,
    TangentialLaw,
    |_: &B, _, _| Vec::new()
);

vector_kind!(
    /// The rolling kind.
    Rolling,
    LawKind::Rolling,
    BoundRolling,
    RollingLaw,
    |b: &B, mass, radius| b.coefficients(mass, radius)
);

/// The raw 0.2 arrays of a vector batch.
#[inline]
pub(crate) fn raw_base(b: &mut VectorBatch<'_>) -> v2::FfiTangentialBatch {
    v2::FfiTangentialBatch {
        n: b.force.len(),
        slots: b.slots,
        dt: b.dt,
        normal: b.normal.as_ptr() as *const f64,
        velocity: b.velocity.as_ptr() as *const f64,
        normal_force: b.normal_force.as_ptr(),
        delta: b.delta.as_ptr(),
        mass: b.mass.as_ptr(),
        radius: b.radius.as_ptr(),
        history: b.history.as_mut_ptr(),
        force: b.force.as_mut_ptr() as *mut f64,
    }
}

fn fault_error(what: &str, name: &str, b: &VectorBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
    let i = f.index.min(b.force.len().saturating_sub(1));
    match (st, f.field) {
        (BatchStatus::NonFiniteOutput, BatchFault::OUTPUT) => LawError::new(
            ErrorKind::NonFinite,
            format!(
                "{what} law '{name}' returned force {:?} on contact {i} (normal force {:e} N, overlap {:e} m, \
                 velocity {:?} m/s)",
                b.force[i], b.normal_force[i], b.delta[i], b.velocity[i]
            ),
        ),
        (BatchStatus::NonFiniteOutput, field) => {
            non_finite_output(what, name, field, i, format!("(overlap {:e} m)", b.delta[i]))
        }
        (_, BatchFault::NORMAL) => bad_vector(what, name, BatchFault::NORMAL, i, b.normal[i]),
        (_, BatchFault::VELOCITY) => bad_vector(what, name, BatchFault::VELOCITY, i, b.velocity[i]),
        (_, BatchFault::CONTEXT_INPUT) => bad_context(what, name, i, b.context),
        (_, field) => {
            let c = b.contact(i);
            let v = motion_input(field, [c.normal_force, c.delta, c.mass, c.radius, c.dt]);
            bad_input(what, name, field, i, v)
        }
    }
}

/// The checked block loop of a vector batch, with its energy outputs when wanted.
///
/// # Safety
/// The batch's pointers are valid for its lengths.
#[inline(always)]
unsafe fn run<L: VectorLaw>(law: &L, b4: &FfiVectorBatch4) -> Result<bool, (usize, u8)> {
    let b = &b4.base;
    motion_run!(
        &b.base,
        b.power,
        b.elastic,
        b4.context,
        VectorBatch { velocity: [f64; 3] => force: [f64; 3] },
        3,
        BatchFault::VELOCITY,
        |batch| law.batch(batch),
        |batch, out| law.batch_energy(batch, out),
    )
}
