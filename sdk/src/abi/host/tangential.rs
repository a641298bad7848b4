//! Tangential-law handles: a plugin's (0.2 or 0.3) and a law compiled into the host.

use super::*;

pub(super) enum TangentialInner {
    V2 {
        ffi: FfiTangentialLaw,
        info: LawInfo,
    },
    /// A 0.3 law, through the generic shape of its kind.
    V3(LawHandle<Tangential>),
}

/// A configured tangential law from a plugin.
pub struct TangentialLawHandle(pub(super) TangentialInner);

impl TangentialLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        match &self.0 {
            TangentialInner::V2 { info, .. } => info,
            TangentialInner::V3(l) => l.info(),
        }
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<TangentialModelHandle, LawError> {
        materials.validate()?;
        let info = self.info();
        let inner = match &self.0 {
            TangentialInner::V2 { ffi, .. } => match unsafe { (ffi.vtable.bind)(ffi.obj, materials) } {
                RResult::ROk(ffi) => ModelInner::V2(ffi),
                RResult::RErr(e) => return Err(e.into()),
            },
            TangentialInner::V3(l) => ModelInner::V3(l.bind(materials)?),
        };
        Ok(TangentialModelHandle {
            inner,
            name: info.name.to_string(),
            slots: info.history.len(),
        })
    }
}

impl Drop for TangentialLawHandle {
    fn drop(&mut self) {
        if let TangentialInner::V2 { ffi, .. } = &self.0 {
            unsafe { (ffi.vtable.drop)(ffi.obj) }
        }
    }
}

enum ModelInner {
    V2(FfiTangentialModel),
    V3(ModelHandle<Tangential>),
}

/// A tangential law bound to a pair of materials, every input and output checked.
pub struct TangentialModelHandle {
    inner: ModelInner,
    name: String,
    slots: usize,
}

impl TangentialModelHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    /// As [`TangentialModelHandle::force_batch`], with the energy outputs `energy` asks for:
    /// `Ok(true)` when they were written, `Ok(false)` for a law that does not account for
    /// energy (every law of a plugin older than sdk 0.3).
    pub fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        match &self.inner {
            ModelInner::V3(m) => m.batch(b, energy),
            ModelInner::V2(_) => self.force_batch(b).map(|()| false),
        }
    }

    /// Evaluates every contact of `b` (see [`TangentialBatch`]).
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        let ffi = match &self.inner {
            ModelInner::V2(ffi) => ffi,
            ModelInner::V3(m) => return m.batch(b, EnergyOut::none()).map(|_| ()),
        };
        run_tangential_batch(&self.name, self.slots, b, |fb, fault| unsafe {
            match (ffi.vtable.force_batch)(ffi.obj, fb, fault) {
                BatchStatus::Panic => Err((ffi.vtable.take_panic)()),
                st => Ok(st),
            }
        })
    }
}

/// A tangential law compiled into the host, called through the trampoline a plugin exports.
pub struct StaticTangential<B>(StaticModel<Tangential, B>);

impl<B: crate::law::BoundTangential> StaticTangential<B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: crate::law::TangentialLaw<Bound = B>>(
        law: &L,
        materials: &MaterialPair,
    ) -> Result<Self, LawError> {
        Ok(StaticTangential(StaticModel::bind(law, materials)?))
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        self.0.name()
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.0.history_slots()
    }

    /// As [`TangentialModelHandle::force_batch`].
    #[inline]
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        self.0.batch(b, EnergyOut::none()).map(|_| ())
    }

    /// As [`TangentialModelHandle::force_batch_with`].
    pub fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.0.batch(b, energy)
    }
}

fn run_tangential_batch(
    name: &str,
    slots: usize,
    b: TangentialBatch<'_>,
    call: impl FnOnce(&FfiTangentialBatch, &mut BatchFault) -> Result<BatchStatus, RString>,
) -> Result<(), LawError> {
    let n = b.force.len();
    let lens = [
        b.normal.len(),
        b.velocity.len(),
        b.normal_force.len(),
        b.delta.len(),
        b.mass.len(),
        b.radius.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(length_error(
            "tangential force_batch",
            format!("normal, velocity, normal_force, delta, mass, radius {lens:?}, force {n}"),
        ));
    }
    if b.slots != slots || b.history.len() != n * slots {
        return Err(length_error(
            "tangential force_batch",
            format!(
                "history has {} values for {n} contacts of {} slots (law '{}' keeps {})",
                b.history.len(),
                b.slots,
                name,
                slots
            ),
        ));
    }
    let ffi = FfiTangentialBatch {
        n,
        slots,
        dt: b.dt,
        normal: b.normal.as_ptr() as *const f64,
        velocity: b.velocity.as_ptr() as *const f64,
        normal_force: b.normal_force.as_ptr(),
        delta: b.delta.as_ptr(),
        mass: b.mass.as_ptr(),
        radius: b.radius.as_ptr(),
        history: b.history.as_mut_ptr(),
        force: b.force.as_mut_ptr() as *mut f64,
    };
    let mut fault = BatchFault::default();
    let st = call(&ffi, &mut fault).map_err(|msg| {
        LawError::new(
            ErrorKind::Panic,
            format!("tangential law '{name}' panicked: {msg}"),
        )
    })?;
    match st {
        BatchStatus::Ok => Ok(()),
        BatchStatus::NonFiniteOutput | BatchStatus::Panic => {
            let i = fault.index.min(n - 1);
            Err(LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "tangential law '{}' returned force {:?} on contact {i} (normal force {:e} N, \
                     overlap {:e} m, velocity {:?} m/s)",
                    name, b.force[i], b.normal_force[i], b.delta[i], b.velocity[i]
                ),
            ))
        }
        BatchStatus::BadInput => {
            let i = fault.index.min(n - 1);
            let v = match fault.field {
                BatchFault::NORMAL => {
                    return Err(bad_vec("normal", name, i, b.normal[i]));
                }
                BatchFault::VELOCITY => {
                    return Err(bad_vec("velocity", name, i, b.velocity[i]));
                }
                BatchFault::NORMAL_FORCE => b.normal_force[i],
                BatchFault::DELTA => b.delta[i],
                BatchFault::MASS => b.mass[i],
                BatchFault::RADIUS => b.radius[i],
                _ => b.dt,
            };
            Err(bad_input("tangential", name, fault.field, i, v))
        }
    }
}

pub(crate) fn bad_vec(what: &str, name: &str, i: usize, v: [f64; 3]) -> LawError {
    LawError::new(
        ErrorKind::NonFinite,
        format!(
            "tangential law '{name}': input {what}[{i}] = {v:?} must be finite; refused before evaluation"
        ),
    )
}

impl Drop for TangentialModelHandle {
    fn drop(&mut self) {
        if let ModelInner::V2(ffi) = &self.inner {
            unsafe { (ffi.vtable.drop)(ffi.obj) }
        }
    }
}
