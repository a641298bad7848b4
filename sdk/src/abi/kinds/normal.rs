//! The normal kind: 0.2's contact batch plus 0.3's reach and energy outputs and 0.4's normal
//! contexts, evaluated block by block (or, for a straight-line law without history, through the
//! pipelined loop).

use super::pipelined::pipelined_blocks;
use super::*;

/// The normal kind.
pub struct Normal;

/// A raw 0.4 normal batch: 0.3's, plus the optional output of each contact's context (null
/// when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiNormalBatch4 {
    /// The 0.3 arrays and outputs.
    pub base: v3::FfiNormalBatch3,
    /// Output: each contact's normal context (`n` values), or null.
    pub context: *mut NormalContext,
}

/// A normal batch as a host passes it to a law: the forces, and optionally each contact's
/// reach and normal context after the call.
#[derive(Debug)]
pub struct NormalCall<'a> {
    /// The batch.
    pub batch: NormalBatch<'a>,
    /// Output: each contact's reach (m).
    pub reach: Option<&'a mut [f64]>,
    /// Output (sdk 0.4): each contact's normal context (contact radius, cap force, damping),
    /// what the contact's other laws read; a law of an older sdk gives the defaults
    /// ([`NormalContext::default_for`]).
    pub context: Option<&'a mut [NormalContext]>,
}

impl NormalCall<'_> {
    /// A call of batch `b` without the optional outputs.
    pub fn plain(b: NormalBatch<'_>) -> NormalCall<'_> {
        NormalCall {
            batch: b,
            reach: None,
            context: None,
        }
    }
}

/// The normal force (N) `value` of contact `c` is not finite.
pub(crate) fn normal_non_finite(name: &str, value: f64, c: Contact) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "contact law '{name}' returned force {value} at delta = {:e} m, rate = {:e} m/s \
             (effective mass {:e} kg, radius {:e} m)",
            c.delta, c.rate, c.mass, c.radius
        ),
    )
}

/// The error of [`Normal`]'s `check_lengths` when its fused test fails.
#[cold]
#[inline(never)]
fn bad_lengths(name: &str, slots: usize, c: &NormalCall<'_>) -> Result<(), LawError> {
    let n = c.batch.force.len();
    if let Some(r) = c.reach.as_ref().filter(|r| r.len() != n) {
        return Err(length_error(
            "contact force_batch",
            format!("reach {}, force {n}", r.len()),
        ));
    }
    if let Some(x) = c.context.as_ref().filter(|x| x.len() != n) {
        return Err(length_error(
            "contact force_batch",
            format!("context {}, force {n}", x.len()),
        ));
    }
    c.batch.lengths().check("contact", name, slots)
}

impl Kind for Normal {
    type Ffi = FfiNormalBatch4;
    type Ffi03 = v3::FfiNormalBatch3;
    type Batch<'a> = NormalCall<'a>;
    const KIND: LawKind = LawKind::Contact;
    fn len(b: &NormalCall<'_>) -> usize {
        b.batch.force.len()
    }
    #[inline(always)]
    fn check_lengths(name: &str, slots: usize, c: &NormalCall<'_>) -> Result<(), LawError> {
        let n = c.batch.force.len();
        let reach = c.reach.as_ref().is_none_or(|r| r.len() == n);
        let context = c.context.as_ref().is_none_or(|x| x.len() == n);
        if reach & context {
            return c.batch.lengths().check("contact", name, slots);
        }
        bad_lengths(name, slots, c)
    }
    #[inline]
    fn raw(c: &mut NormalCall<'_>, power: *mut f64, elastic: *mut f64) -> FfiNormalBatch4 {
        let b = &mut c.batch;
        FfiNormalBatch4 {
            base: v3::FfiNormalBatch3 {
                base: v2::FfiNormalBatch {
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
                reach: raw_out(&mut c.reach),
            },
            context: c
                .context
                .as_deref_mut()
                .map_or(std::ptr::null_mut(), <[NormalContext]>::as_mut_ptr),
        }
    }
    fn ffi03(b: &FfiNormalBatch4) -> &v3::FfiNormalBatch3 {
        &b.base
    }
    fn older_defaults(c: &mut NormalCall<'_>) {
        if let Some(x) = c.context.as_deref_mut() {
            for (i, x) in x.iter_mut().enumerate() {
                *x = NormalContext::default_for(&c.batch.contact(i), c.batch.force[i]);
            }
        }
    }
    fn fault_error(name: &str, c: &NormalCall<'_>, st: BatchStatus, fault: BatchFault) -> LawError {
        let b = &c.batch;
        let i = fault.index.min(b.force.len().saturating_sub(1));
        let contact = b.contact(i);
        match (st, fault.field) {
            (BatchStatus::NonFiniteOutput, BatchFault::OUTPUT) => {
                normal_non_finite(name, b.force[i], contact)
            }
            (BatchStatus::NonFiniteOutput, BatchFault::CONTEXT) => {
                let x = c.context.as_ref().map(|x| x[i]).unwrap_or_default();
                non_finite_output(
                    "contact",
                    name,
                    BatchFault::CONTEXT,
                    i,
                    format!("{x:?} (at delta = {:e} m)", contact.delta),
                )
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

/// Batches of at most this many contacts (a collision's integrator evaluates two to five states
/// at a time) skip the block loop's setup for vector code.
const FEW: usize = 8;

/// A batch of at most [`FEW`] contacts, as one block of the block loop (its inputs, then the
/// law, then its energy, then its forces), the law called contact by contact: the vector loop
/// of a law over a few contacts costs more to set up (alias checks, remainders) than it saves.
#[inline(always)]
fn few_contacts<B: BoundContact>(
    law: &B,
    b: NormalBatch<'_>,
    mut energy: Option<(&mut [f64], &mut [f64])>,
) -> Result<bool, (usize, u8)> {
    let (slots, n) = (b.slots, b.force.len());
    let (d, r, m, a) = (&b.delta[..n], &b.rate[..n], &b.mass[..n], &b.radius[..n]);
    let mut ok = true;
    for i in 0..n {
        ok &= contact_ok(d[i], r[i], m[i], a[i]);
    }
    if !ok {
        if let Some(fault) = check_normal_inputs(d, r, m, a) {
            return Err(fault);
        }
    }
    let (mut written, mut finite) = (energy.is_some(), true);
    for i in 0..n {
        let k = i + 1;
        let one = NormalBatch {
            delta: &d[i..k],
            rate: &r[i..k],
            mass: &m[i..k],
            radius: &a[i..k],
            slots,
            history: &mut b.history[i * slots..k * slots],
            force: &mut b.force[i..k],
        };
        written &= match energy.as_mut() {
            None => {
                law.force_batch(one);
                false
            }
            Some((p, e)) => law.force_batch_energy(
                one,
                EnergyBatch {
                    power: &mut p[i..k],
                    elastic: &mut e[i..k],
                },
            ),
        };
        finite &= is_finite(b.force[i]);
    }
    if let Some((p, e)) = energy.as_ref() {
        if written {
            check_energy(0, &p[..n], &e[..n])?;
        }
    }
    if !finite {
        if let Some(i) = first_non_finite(b.force) {
            return Err((i, BatchFault::OUTPUT));
        }
    }
    Ok(written)
}

/// The block loop of a normal batch: check a block's inputs, run the law on it (with its
/// energy outputs when `energy` is given), check its outputs. Returns whether every contact
/// reported its energy, or the first bad contact and what is wrong with it. The full blocks of
/// a straight-line law without history go through [`pipelined_blocks`].
#[inline(always)]
fn normal_blocks<B: BoundContact>(
    law: &B,
    b: NormalBatch<'_>,
    mut energy: Option<(&mut [f64], &mut [f64])>,
) -> Result<bool, (usize, u8)> {
    let (slots, n) = (b.slots, b.force.len());
    if n <= FEW {
        return few_contacts(law, b, energy);
    }
    let mut written = energy.is_some();
    let full = if B::STRAIGHT_LINE && slots == 0 {
        n - n % CHECK_BLOCK
    } else {
        0
    };
    if full > 0 {
        let (d, r, m, a) = (
            &b.delta[..full],
            &b.rate[..full],
            &b.mass[..full],
            &b.radius[..full],
        );
        let f = &mut b.force[..full];
        // one copy of the loop without energy outputs, one with them (a branch inside the loop
        // let the compiler hoist the first contact out of a step and split its vectors)
        written &= match energy.as_mut() {
            None => pipelined_blocks(law, (d, r, m, a), f, None)?,
            Some((p, e)) => pipelined_blocks(law, (d, r, m, a), f, Some((&mut p[..full], &mut e[..full])))?,
        };
    }
    blocks!(full => n, |lo, hi| {
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
        let block = NormalBatch {
            delta: d,
            rate: r,
            mass: m,
            radius: a,
            slots,
            history: &mut b.history[lo * slots..hi * slots],
            force: &mut *o,
        };
        written &= eval_block!(energy, lo, hi, block, |b| law.force_batch(b), |b, e| law
            .force_batch_energy(b, e));
        match first_non_finite(o) {
            Some(i) => Err((lo + i, BatchFault::OUTPUT)),
            None => Ok(()),
        }
    });
    Ok(written)
}

impl<B: BoundContact> KindBound<Normal> for B {
    #[inline(always)]
    unsafe fn run(&self, b4: &FfiNormalBatch4) -> Result<bool, (usize, u8)> {
        let b = &b4.base;
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
        let batch = NormalBatch {
            delta,
            rate,
            mass,
            radius,
            slots,
            history,
            force,
        };
        if B::CONTEXT_WITH_FORCE && !b4.context.is_null() && b.power.is_null() {
            let out = unsafe { slice_mut(b4.context, n) };
            let reach = (!b.reach.is_null()).then(|| unsafe { slice_mut(b.reach, n) });
            return with_contexts(self, batch, out, reach);
        }
        let mut scratch = Vec::new();
        let written = normal_blocks(
            self,
            NormalBatch {
                history: &mut *batch.history,
                force: &mut *batch.force,
                ..batch
            },
            unsafe { energy_out(n, b.power, b.elastic, &mut scratch) },
        )?;
        if !b.reach.is_null() {
            for i in 0..n {
                let r = self.reach(&batch.contact(i), history_of(batch.history, slots, i));
                if !(0.0..f64::INFINITY).contains(&r) {
                    return Err((i, BatchFault::REACH));
                }
                unsafe { *b.reach.add(i) = r };
            }
        }
        if !b4.context.is_null() {
            let out = unsafe { slice_mut(b4.context, n) };
            self.context_batch(&batch, out);
            if let Some(i) = first_invalid_context(out) {
                return Err((i, BatchFault::CONTEXT));
            }
        }
        Ok(written)
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

/// A normal batch of a law that evaluates each contact's force and context together
/// ([`BoundContact::CONTEXT_WITH_FORCE`]), with the checks of the block loop: the inputs, then
/// the forces, the reaches (into `reach` if given) and the contexts. Returns false: no energy
/// was written.
#[inline(always)]
fn with_contexts<B: BoundContact>(
    law: &B,
    mut b: NormalBatch<'_>,
    out: &mut [NormalContext],
    reach: Option<&mut [f64]>,
) -> Result<bool, (usize, u8)> {
    let n = b.force.len();
    let (d, r, m, a) = (&b.delta[..n], &b.rate[..n], &b.mass[..n], &b.radius[..n]);
    if !normal_inputs_ok(d, r, m, a) {
        if let Some(fault) = check_normal_inputs(d, r, m, a) {
            return Err(fault);
        }
    }
    law.force_context_batch(&mut b, &mut out[..n]);
    if let Some(i) = first_non_finite(b.force) {
        return Err((i, BatchFault::OUTPUT));
    }
    if let Some(reach) = reach {
        law.reach_batch(&b, &mut reach[..n]);
        if let Some(i) = reach[..n].iter().position(|x| !(0.0..f64::INFINITY).contains(x)) {
            return Err((i, BatchFault::REACH));
        }
    }
    match first_invalid_context(&out[..n]) {
        Some(i) => Err((i, BatchFault::CONTEXT)),
        None => Ok(false),
    }
}

kind_law!(Normal, ContactLaw, false);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::{EnergyOut, StaticModel};
    use crate::Energy;

    /// F = 1 N, with a NaN power.
    struct NanPower;

    impl BoundContact for NanPower {
        fn force(&self, _c: Contact, _h: &mut [f64]) -> f64 {
            1.0
        }
        fn energy(&self, _c: &Contact, _h: &[f64], _f: f64) -> Option<Energy> {
            Some(Energy {
                power: f64::NAN,
                elastic: 0.0,
            })
        }
    }

    /// A non-finite energy output is reported as an output of the law, not as a bad input.
    #[test]
    fn a_nan_power_is_the_laws_output() {
        let m = StaticModel::<Normal, NanPower>::of_bound("nan-power", 0, NanPower);
        let (mut f, mut p) = ([0.0; 2], [0.0; 2]);
        let call = NormalCall {
            batch: NormalBatch {
                delta: &[1e-6; 2],
                rate: &[0.0; 2],
                mass: &[1e-3; 2],
                radius: &[1e-3; 2],
                slots: 0,
                history: &mut [],
                force: &mut f,
            },
            reach: None,
            context: None,
        };
        let e = m
            .batch(
                call,
                EnergyOut {
                    power: Some(&mut p),
                    elastic: None,
                },
            )
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(
            e.message.contains("returned a non-finite power on contact 0"),
            "{}",
            e.message
        );
    }
}
