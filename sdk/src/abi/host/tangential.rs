//! Tangential-law handles: a plugin's (0.2 or 0.3) and a law compiled into the host.

use super::*;

/// A configured tangential law from a plugin.
pub struct TangentialLawHandle {
    pub(super) ffi: FfiTangentialLaw,
    pub(super) info: LawInfo,
    pub(super) v3: Option<LawHandle<Tangential>>,
}

impl TangentialLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<TangentialModelHandle, LawError> {
        materials.validate()?;
        match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, materials) } {
            RResult::ROk(ffi) => Ok(TangentialModelHandle {
                ffi,
                name: self.info.name.to_string(),
                slots: self.info.history.len(),
                v3: match &self.v3 {
                    Some(l) => Some(l.bind(materials)?),
                    None => None,
                },
            }),
            RResult::RErr(e) => Err(e.into()),
        }
    }
}

impl Drop for TangentialLawHandle {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

/// A tangential law bound to a pair of materials, every input and output checked.
pub struct TangentialModelHandle {
    ffi: FfiTangentialModel,
    name: String,
    slots: usize,
    /// The same law through the 0.3 entry (energy), for a 0.3 plugin.
    v3: Option<ModelHandle<Tangential>>,
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
        match &self.v3 {
            Some(m) => m.batch(b, energy),
            None => self.force_batch(b).map(|()| false),
        }
    }

    /// Evaluates every contact of `b` (see [`TangentialBatch`]).
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        let ffi = &self.ffi;
        run_tangential_batch(&self.name, self.slots, b, |fb, fault| unsafe {
            match (ffi.vtable.force_batch)(ffi.obj, fb, fault) {
                BatchStatus::Panic => Err((ffi.vtable.take_panic)()),
                st => Ok(st),
            }
        })
    }
}

/// A tangential law compiled into the host, called through the trampoline a plugin exports.
pub struct StaticTangential<B> {
    law: B,
    name: String,
    slots: usize,
}

impl<B: crate::law::BoundTangential> StaticTangential<B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: crate::law::TangentialLaw<Bound = B>>(
        law: &L,
        materials: &MaterialPair,
    ) -> Result<Self, LawError> {
        materials.validate()?;
        Ok(StaticTangential {
            law: law.bind(materials)?,
            name: L::NAME.to_string(),
            slots: L::HISTORY.len(),
        })
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

    /// As [`TangentialModelHandle::force_batch`].
    #[inline]
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        let obj = &self.law as *const B as *const c_void;
        run_tangential_batch(&self.name, self.slots, b, |fb, fault| unsafe {
            match super::plugin::tangential_force_batch::<B>(obj, fb, fault) {
                BatchStatus::Panic => Err(super::plugin::take_panic()),
                st => Ok(st),
            }
        })
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
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}
