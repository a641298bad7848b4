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

fn non_finite_output(what: &str, name: &str, field: u8, i: usize, value: String) -> LawError {
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

fn history_of(h: &[f64], slots: usize, i: usize) -> &[f64] {
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

// ---- tangential, rolling: the vector kinds ----

/// A raw batch of a vector kind (tangential, rolling): vectors are `n` `[x, y, z]` triples;
/// `history` is `n × slots`; `power` and `elastic` are optional outputs (null when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiVectorBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Unit normals (3n values).
    pub normal: *const f64,
    /// Relative velocities (m/s, 3n values): of the contact points (tangential) or rolling.
    pub velocity: *const f64,
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
    /// Output: forces (N, 3n values).
    pub force: *mut f64,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
}

/// The input slices of a raw vector batch.
struct VectorInputs<'a> {
    normal: &'a [[f64; 3]],
    velocity: &'a [[f64; 3]],
    fnorm: &'a [f64],
    delta: &'a [f64],
    mass: &'a [f64],
    radius: &'a [f64],
}

/// The slices of a raw vector batch.
struct VectorSlices<'a> {
    normal: &'a [[f64; 3]],
    velocity: &'a [[f64; 3]],
    fnorm: &'a [f64],
    delta: &'a [f64],
    mass: &'a [f64],
    radius: &'a [f64],
    history: &'a mut [f64],
    force: &'a mut [[f64; 3]],
}

impl<'a> VectorSlices<'a> {
    fn split(self) -> (VectorInputs<'a>, &'a mut [f64], &'a mut [[f64; 3]]) {
        (
            VectorInputs {
                normal: self.normal,
                velocity: self.velocity,
                fnorm: self.fnorm,
                delta: self.delta,
                mass: self.mass,
                radius: self.radius,
            },
            self.history,
            self.force,
        )
    }
}

/// # Safety
/// The batch's pointers are valid for its lengths.
unsafe fn vector_slices<'a>(b: &FfiVectorBatch) -> Result<VectorSlices<'a>, (usize, u8)> {
    if !(b.dt >= 0.0 && b.dt < f64::INFINITY) {
        return Err((0, BatchFault::DT));
    }
    let n = b.n;
    unsafe {
        Ok(VectorSlices {
            normal: slice(b.normal as *const [f64; 3], n),
            velocity: slice(b.velocity as *const [f64; 3], n),
            fnorm: slice(b.normal_force, n),
            delta: slice(b.delta, n),
            mass: slice(b.mass, n),
            radius: slice(b.radius, n),
            history: slice_mut(b.history, n * b.slots),
            force: slice_mut(b.force as *mut [f64; 3], n),
        })
    }
}

/// The read-only arrays of a vector batch as a host holds them (for checks and messages).
struct VectorRead<'v> {
    dt: f64,
    normal: &'v [[f64; 3]],
    velocity: &'v [[f64; 3]],
    normal_force: &'v [f64],
    delta: &'v [f64],
    mass: &'v [f64],
    radius: &'v [f64],
    slots: usize,
    history: usize,
    force: &'v [[f64; 3]],
}

macro_rules! vector_read {
    ($b:expr) => {
        VectorRead {
            dt: $b.dt,
            normal: $b.normal,
            velocity: $b.velocity,
            normal_force: $b.normal_force,
            delta: $b.delta,
            mass: $b.mass,
            radius: $b.radius,
            slots: $b.slots,
            history: $b.history.len(),
            force: &*$b.force,
        }
    };
}

macro_rules! vector_raw {
    ($b:expr, $power:expr, $elastic:expr) => {
        FfiVectorBatch {
            n: $b.force.len(),
            slots: $b.slots,
            dt: $b.dt,
            normal: $b.normal.as_ptr() as *const f64,
            velocity: $b.velocity.as_ptr() as *const f64,
            normal_force: $b.normal_force.as_ptr(),
            delta: $b.delta.as_ptr(),
            mass: $b.mass.as_ptr(),
            radius: $b.radius.as_ptr(),
            history: $b.history.as_mut_ptr(),
            force: $b.force.as_mut_ptr() as *mut f64,
            power: $power,
            elastic: $elastic,
        }
    };
}

impl VectorRead<'_> {
    fn check_lengths(&self, what: &str, name: &str, slots: usize) -> Result<(), LawError> {
        let n = self.force.len();
        let lens = [
            self.normal.len(),
            self.velocity.len(),
            self.normal_force.len(),
            self.delta.len(),
            self.mass.len(),
            self.radius.len(),
        ];
        if lens.iter().any(|&l| l != n) {
            return Err(length_error(
                &format!("{what} force_batch"),
                format!("normal, velocity, normal_force, delta, mass, radius {lens:?}, force {n}"),
            ));
        }
        if self.slots != slots || self.history != n * slots {
            return Err(length_error(
                &format!("{what} force_batch"),
                format!(
                    "history has {} values for {n} contacts of {} slots (law '{name}' keeps {slots})",
                    self.history, self.slots
                ),
            ));
        }
        Ok(())
    }

    fn fault_error(&self, what: &str, name: &str, st: BatchStatus, f: BatchFault) -> LawError {
        let i = f.index.min(self.force.len().saturating_sub(1));
        let vec_err = |arr: &str, v: [f64; 3]| {
            LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "{what} law '{name}': input {arr}[{i}] = {v:?} must be finite; refused before evaluation"
                ),
            )
        };
        match (st, f.field) {
            (BatchStatus::NonFiniteOutput, BatchFault::OUTPUT) => LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "{what} law '{name}' returned force {:?} on contact {i} (normal force {:e} N, overlap {:e} m, \
                     velocity {:?} m/s)",
                    self.force[i], self.normal_force[i], self.delta[i], self.velocity[i]
                ),
            ),
            (BatchStatus::NonFiniteOutput, field) => {
                non_finite_output(what, name, field, i, format!("(overlap {:e} m)", self.delta[i]))
            }
            (_, BatchFault::NORMAL) => vec_err("normal", self.normal[i]),
            (_, BatchFault::VELOCITY) => vec_err("velocity", self.velocity[i]),
            (_, field) => {
                let v = match field {
                    BatchFault::NORMAL_FORCE => self.normal_force[i],
                    BatchFault::DELTA => self.delta[i],
                    BatchFault::MASS => self.mass[i],
                    BatchFault::RADIUS => self.radius[i],
                    _ => self.dt,
                };
                bad_input(what, name, field, i, v)
            }
        }
    }
}

/// The tangential kind of sdk 0.3.
pub struct Tangential;

impl Kind for Tangential {
    type Ffi = FfiVectorBatch;
    type Batch<'a> = TangentialBatch<'a>;
    const KIND: LawKind = LawKind::Tangential;
    const WHAT: &'static str = "tangential";
    fn len(b: &TangentialBatch<'_>) -> usize {
        b.force.len()
    }
    fn check_lengths(name: &str, slots: usize, b: &TangentialBatch<'_>) -> Result<(), LawError> {
        vector_read!(b).check_lengths(Self::WHAT, name, slots)
    }
    fn raw(b: &mut TangentialBatch<'_>, power: *mut f64, elastic: *mut f64) -> FfiVectorBatch {
        vector_raw!(b, power, elastic)
    }
    fn fault_error(name: &str, b: &TangentialBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
        vector_read!(b).fault_error(Self::WHAT, name, st, f)
    }
}

impl<B: BoundTangential> KindBound<Tangential> for B {
    #[inline(always)]
    unsafe fn run(&self, b: &FfiVectorBatch) -> Result<bool, (usize, u8)> {
        let s = unsafe { vector_slices(b)? };
        let slots = b.slots;
        tangential_blocks(
            self,
            TangentialBlocks {
                dt: b.dt,
                normal: s.normal,
                velocity: s.velocity,
                fnorm: s.fnorm,
                delta: s.delta,
                mass: s.mass,
                radius: s.radius,
                slots,
                history: &mut *s.history,
                force: &mut *s.force,
            },
        )?;
        unsafe {
            energy_pass(b.n, b.power, b.elastic, |i| {
                let c = TangentialContact {
                    normal: s.normal[i],
                    velocity: s.velocity[i],
                    normal_force: s.fnorm[i],
                    delta: s.delta[i],
                    mass: s.mass[i],
                    radius: s.radius[i],
                    dt: b.dt,
                };
                self.energy(&c, history_of(s.history, slots, i), s.force[i])
            })
        }
    }
    fn kind_coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        Vec::new()
    }
}

impl<T: TangentialLaw> KindLaw<Tangential> for T {
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

/// Checks the inputs of a vector block, naming the first bad one.
#[inline(always)]
fn vector_block_inputs(s: &VectorInputs<'_>, lo: usize, hi: usize) -> Result<(), (usize, u8)> {
    if tangential_inputs_ok(
        s.normal[lo..hi].as_flattened(),
        s.velocity[lo..hi].as_flattened(),
        &s.fnorm[lo..hi],
        &s.delta[lo..hi],
        &s.mass[lo..hi],
        &s.radius[lo..hi],
    ) {
        return Ok(());
    }
    let checks: [(Option<usize>, u8); 6] = [
        (
            first_non_finite(s.normal[lo..hi].as_flattened()).map(|i| i / 3),
            BatchFault::NORMAL,
        ),
        (
            first_non_finite(s.velocity[lo..hi].as_flattened()).map(|i| i / 3),
            BatchFault::VELOCITY,
        ),
        (first_non_finite(&s.fnorm[lo..hi]), BatchFault::NORMAL_FORCE),
        (first_non_finite(&s.delta[lo..hi]), BatchFault::DELTA),
        (first_non_positive(&s.mass[lo..hi]), BatchFault::MASS),
        (first_non_positive(&s.radius[lo..hi]), BatchFault::RADIUS),
    ];
    for (i, f) in checks {
        if let Some(i) = i {
            return Err((lo + i, f));
        }
    }
    Ok(())
}

/// The rolling kind of sdk 0.3.
pub struct Rolling;

impl Kind for Rolling {
    type Ffi = FfiVectorBatch;
    type Batch<'a> = RollingBatch<'a>;
    const KIND: LawKind = LawKind::Rolling;
    const WHAT: &'static str = "rolling";
    fn len(b: &RollingBatch<'_>) -> usize {
        b.force.len()
    }
    fn check_lengths(name: &str, slots: usize, b: &RollingBatch<'_>) -> Result<(), LawError> {
        vector_read!(b).check_lengths(Self::WHAT, name, slots)
    }
    fn raw(b: &mut RollingBatch<'_>, power: *mut f64, elastic: *mut f64) -> FfiVectorBatch {
        vector_raw!(b, power, elastic)
    }
    fn fault_error(name: &str, b: &RollingBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
        vector_read!(b).fault_error(Self::WHAT, name, st, f)
    }
}

impl<B: BoundRolling> KindBound<Rolling> for B {
    #[inline(always)]
    unsafe fn run(&self, b: &FfiVectorBatch) -> Result<bool, (usize, u8)> {
        let (s, history, force) = unsafe { vector_slices(b)? }.split();
        let slots = b.slots;
        blocks(b.n, |lo, hi| {
            vector_block_inputs(&s, lo, hi)?;
            let out = &mut force[lo..hi];
            self.force_batch(RollingBatch {
                dt: b.dt,
                normal: &s.normal[lo..hi],
                velocity: &s.velocity[lo..hi],
                normal_force: &s.fnorm[lo..hi],
                delta: &s.delta[lo..hi],
                mass: &s.mass[lo..hi],
                radius: &s.radius[lo..hi],
                slots,
                history: &mut history[lo * slots..hi * slots],
                force: &mut *out,
            });
            match first_non_finite(out.as_flattened()) {
                Some(i) => Err((lo + i / 3, BatchFault::OUTPUT)),
                None => Ok(()),
            }
        })?;
        unsafe {
            energy_pass(b.n, b.power, b.elastic, |i| {
                let c = RollingContact {
                    normal: s.normal[i],
                    velocity: s.velocity[i],
                    normal_force: s.fnorm[i],
                    delta: s.delta[i],
                    mass: s.mass[i],
                    radius: s.radius[i],
                    dt: b.dt,
                };
                self.energy(&c, history_of(history, slots, i), force[i])
            })
        }
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

impl<T: RollingLaw> KindLaw<Rolling> for T {
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

// ---- twisting ----

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
    const WHAT: &'static str = "twisting";
    fn len(b: &TwistingBatch<'_>) -> usize {
        b.torque.len()
    }
    fn check_lengths(name: &str, slots: usize, b: &TwistingBatch<'_>) -> Result<(), LawError> {
        let n = b.torque.len();
        let lens = [
            b.normal.len(),
            b.rate.len(),
            b.normal_force.len(),
            b.delta.len(),
            b.mass.len(),
            b.radius.len(),
        ];
        if lens.iter().any(|&l| l != n) || b.slots != slots || b.history.len() != n * slots {
            return Err(length_error(
                "twisting torque_batch",
                format!(
                    "normal, rate, normal_force, delta, mass, radius {lens:?}, torque {n}, history {} of {} \
                     slots (law '{name}' keeps {slots})",
                    b.history.len(),
                    b.slots
                ),
            ));
        }
        Ok(())
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
                format!("(twisting rate {:e} rad/s, normal force {:e} N)", b.rate[i], b.normal_force[i]),
            ),
            (_, BatchFault::NORMAL) => LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "twisting law '{name}': input normal[{i}] = {:?} must be finite; refused before evaluation",
                    b.normal[i]
                ),
            ),
            (_, field) => {
                let v = match field {
                    BatchFault::RATE => b.rate[i],
                    BatchFault::NORMAL_FORCE => b.normal_force[i],
                    BatchFault::DELTA => b.delta[i],
                    BatchFault::MASS => b.mass[i],
                    BatchFault::RADIUS => b.radius[i],
                    _ => b.dt,
                };
                bad_input("twisting", name, field, i, v)
            }
        }
    }
}

impl<B: BoundTwisting> KindBound<Twisting> for B {
    #[inline(always)]
    unsafe fn run(&self, b: &FfiTwistingBatch) -> Result<bool, (usize, u8)> {
        if !(b.dt >= 0.0 && b.dt < f64::INFINITY) {
            return Err((0, BatchFault::DT));
        }
        let (n, slots) = (b.n, b.slots);
        let (history, torque) = unsafe { (slice_mut(b.history, n * slots), slice_mut(b.torque, n)) };
        let (normal, rate, fnorm, delta, mass, radius) = unsafe {
            (
                slice(b.normal as *const [f64; 3], n),
                slice(b.rate, n),
                slice(b.normal_force, n),
                slice(b.delta, n),
                slice(b.mass, n),
                slice(b.radius, n),
            )
        };
        blocks(n, |lo, hi| {
            let checks: [(Option<usize>, u8); 6] = [
                (
                    first_non_finite(normal[lo..hi].as_flattened()).map(|i| i / 3),
                    BatchFault::NORMAL,
                ),
                (first_non_finite(&rate[lo..hi]), BatchFault::RATE),
                (first_non_finite(&fnorm[lo..hi]), BatchFault::NORMAL_FORCE),
                (first_non_finite(&delta[lo..hi]), BatchFault::DELTA),
                (first_non_positive(&mass[lo..hi]), BatchFault::MASS),
                (first_non_positive(&radius[lo..hi]), BatchFault::RADIUS),
            ];
            for (i, f) in checks {
                if let Some(i) = i {
                    return Err((lo + i, f));
                }
            }
            let out = &mut torque[lo..hi];
            self.torque_batch(TwistingBatch {
                dt: b.dt,
                normal: &normal[lo..hi],
                rate: &rate[lo..hi],
                normal_force: &fnorm[lo..hi],
                delta: &delta[lo..hi],
                mass: &mass[lo..hi],
                radius: &radius[lo..hi],
                slots,
                history: &mut history[lo * slots..hi * slots],
                torque: &mut *out,
            });
            match first_non_finite(out) {
                Some(i) => Err((lo + i, BatchFault::OUTPUT)),
                None => Ok(()),
            }
        })?;
        unsafe {
            energy_pass(n, b.power, b.elastic, |i| {
                let c = TwistingContact {
                    normal: normal[i],
                    rate: rate[i],
                    normal_force: fnorm[i],
                    delta: delta[i],
                    mass: mass[i],
                    radius: radius[i],
                    dt: b.dt,
                };
                self.energy(&c, history_of(history, slots, i), torque[i])
            })
        }
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

impl<T: TwistingLaw> KindLaw<Twisting> for T {
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
