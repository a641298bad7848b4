//! The vector kinds: tangential and rolling laws share one raw batch (3-vectors).

use super::*;

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
