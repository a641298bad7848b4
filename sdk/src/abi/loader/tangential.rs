//! Tangential-law handles: a plugin's (0.2 or 0.3).

use super::*;

pub(super) enum TangentialInner {
    V2 {
        ffi: Owned<v2::FfiTangentialLaw>,
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
            TangentialInner::V2 { ffi, .. } => {
                ModelInner::V2(Owned::take(unsafe { (ffi.vtable.bind)(ffi.obj, materials) })?)
            }
            TangentialInner::V3(l) => ModelInner::V3(l.bind(materials)?),
        };
        Ok(TangentialModelHandle::new(inner, info))
    }
}

model_handle!(
    /// A tangential law bound to a pair of materials, every input and output checked.
    TangentialModelHandle: Tangential, force_batch_with, v2: v2::FfiTangentialModel
);

impl TangentialModelHandle {
    /// As [`TangentialModelHandle::force_batch`], with the energy outputs `energy` asks for:
    /// `Ok(true)` when they were written, `Ok(false)` for a law that does not account for
    /// energy (every law of a plugin older than sdk 0.3).
    #[inline]
    pub fn force_batch_with(
        &self,
        mut b: TangentialBatch<'_>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        match &self.inner {
            ModelInner::V3(m) => m.batch(b, energy),
            ModelInner::V2(m) => run_v2::<Tangential>(
                &self.name,
                self.slots,
                &mut b,
                energy,
                m.vtable.take_panic,
                |ffi, fault| unsafe { (m.vtable.force_batch)(m.obj, &ffi.base.base, fault) },
            )
            .map(|_| false),
        }
    }

    /// Evaluates every contact of `b` (see [`TangentialBatch`]).
    pub fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        self.force_batch_with(b, EnergyOut::none()).map(|_| ())
    }

    /// No derived constants (for the shape every kind shares).
    pub fn coefficients(&self, _mass: f64, _radius: f64) -> Result<Vec<Coefficient>, LawError> {
        Ok(Vec::new())
    }
}
