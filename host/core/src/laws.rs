//! The law-facing traits every driver uses: the only module that names ABI handles.
//!
//! A driver is generic over [`NormalLaw`] (and [`TangentialForce`] where it has friction), so
//! the same driver code runs a plugin's handle or a law compiled into the program (benchmark
//! baselines, tests) through the very same checked trampoline.

use dashpot_sdk::abi::kind::KindBound;
/// The rolling and twisting law kinds, as the sdk's generic handles name them, and the energy
/// outputs of a batch call.
pub use dashpot_sdk::abi::{EnergyOut, Rolling, Twisting};
use dashpot_sdk::abi::{ModelHandle, StaticContact, StaticModel, StaticTangential};
use dashpot_sdk::{
    BoundContact, BoundRestitution, BoundTangential, Coefficient, Contact, ContactLaw, LawError,
    MaterialPair, NormalBatch, RollingBatch, TangentialBatch, TangentialLaw, TwistingBatch,
};

pub use dashpot_sdk::abi::SdkSeries;
/// The handles of laws loaded from plugins, before and after binding: the registry hands them
/// out, and the traits below are implemented for the bound ones.
pub use dashpot_sdk::abi::{
    ContactLawHandle, ContactModelHandle, LawHandle, LoadedPlugin, RestitutionLawHandle, TangentialLawHandle,
    TangentialModelHandle,
};

/// A restitution law loaded from a plugin and bound to a pair (the sdk's handle).
pub type PluginRestitution = dashpot_sdk::abi::BoundRestitutionHandle;

/// A contact law bound to a pair of materials: normal forces for batches of contacts, each with
/// its own effective mass and radius and history.
pub trait NormalLaw: Send + Sync {
    /// The law's name.
    fn name(&self) -> &str;

    /// History slots per contact (0 for a memoryless law).
    fn history_slots(&self) -> usize;

    /// Evaluates every contact of `b`: forces into `b.force` (N), history updated in place;
    /// a non-finite input or output is an error naming the contact.
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError>;

    /// [`NormalLaw::force_batch`] with each contact's reach (m: the contact ends at δ < −reach)
    /// and the energy outputs `energy` asks for; `Ok(true)` when those were written. The
    /// default (a law without sdk 0.3's outputs): reach 0, energy not available.
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        _energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        self.force_batch(b)?;
        if let Some(r) = reach {
            r.fill(0.0);
        }
        Ok(false)
    }

    /// The normal force (N) on one contact, history updated in place.
    fn force(&self, c: Contact, history: &mut [f64]) -> Result<f64, LawError> {
        let mut out = [0.0];
        self.force_batch(NormalBatch {
            delta: &[c.delta],
            rate: &[c.rate],
            mass: &[c.mass],
            radius: &[c.radius],
            slots: self.history_slots(),
            history,
            force: &mut out,
        })?;
        Ok(out[0])
    }

    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn coefficients(&self, _mass: f64, _radius: f64) -> Result<Vec<Coefficient>, LawError> {
        Ok(Vec::new())
    }
}

impl NormalLaw for ContactModelHandle {
    fn name(&self) -> &str {
        ContactModelHandle::name(self)
    }
    fn history_slots(&self) -> usize {
        ContactModelHandle::history_slots(self)
    }
    #[inline]
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        ContactModelHandle::force_batch(self, b)
    }
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        ContactModelHandle::force_batch_with(self, b, reach, energy)
    }
    fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        ContactModelHandle::coefficients(self, mass, radius)
    }
}

impl<B: BoundContact> NormalLaw for StaticContact<B> {
    fn name(&self) -> &str {
        StaticContact::name(self)
    }
    fn history_slots(&self) -> usize {
        StaticContact::history_slots(self)
    }
    #[inline]
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        StaticContact::force_batch(self, b)
    }
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        StaticContact::force_batch_with(self, b, reach, energy)
    }
    fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        Ok(self.law().coefficients(mass, radius))
    }
}

impl<L: NormalLaw + ?Sized> NormalLaw for &L {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn history_slots(&self) -> usize {
        (**self).history_slots()
    }
    #[inline]
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        (**self).force_batch(b)
    }
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        (**self).force_batch_with(b, reach, energy)
    }
    fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        (**self).coefficients(mass, radius)
    }
}

impl<L: NormalLaw + ?Sized> NormalLaw for Box<L> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn history_slots(&self) -> usize {
        (**self).history_slots()
    }
    #[inline]
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        (**self).force_batch(b)
    }
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        (**self).force_batch_with(b, reach, energy)
    }
    fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        (**self).coefficients(mass, radius)
    }
}

/// A tangential law bound to a pair of materials.
pub trait TangentialForce: Send + Sync {
    /// The law's name.
    fn name(&self) -> &str;

    /// History slots per contact.
    fn history_slots(&self) -> usize;

    /// Evaluates every contact of `b`: tangential forces into `b.force` (N), history advanced
    /// by `b.dt` in place.
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError>;

    /// [`TangentialForce::force_batch`] with the energy outputs `energy` asks for; `Ok(true)`
    /// when they were written. The default: energy not available.
    fn force_batch_with(&self, b: TangentialBatch<'_>, _energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.force_batch(b).map(|()| false)
    }
}

impl TangentialForce for TangentialModelHandle {
    fn name(&self) -> &str {
        TangentialModelHandle::name(self)
    }
    fn history_slots(&self) -> usize {
        TangentialModelHandle::history_slots(self)
    }
    #[inline]
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        TangentialModelHandle::force_batch(self, b)
    }
    fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        TangentialModelHandle::force_batch_with(self, b, energy)
    }
}

impl<B: BoundTangential> TangentialForce for StaticTangential<B> {
    fn name(&self) -> &str {
        StaticTangential::name(self)
    }
    fn history_slots(&self) -> usize {
        StaticTangential::history_slots(self)
    }
    #[inline]
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        StaticTangential::force_batch(self, b)
    }
    fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        StaticTangential::force_batch_with(self, b, energy)
    }
}

impl<L: TangentialForce + ?Sized> TangentialForce for &L {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn history_slots(&self) -> usize {
        (**self).history_slots()
    }
    #[inline]
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        (**self).force_batch(b)
    }
    fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        (**self).force_batch_with(b, energy)
    }
}

impl<L: TangentialForce + ?Sized> TangentialForce for Box<L> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn history_slots(&self) -> usize {
        (**self).history_slots()
    }
    #[inline]
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        (**self).force_batch(b)
    }
    fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        (**self).force_batch_with(b, energy)
    }
}

/// A rolling-resistance law bound to a pair of materials (sdk 0.3).
pub trait RollingResistance: Send + Sync {
    /// The law's name.
    fn name(&self) -> &str;
    /// History slots per contact.
    fn history_slots(&self) -> usize;
    /// Evaluates every contact of `b`: rolling-resistance forces into `b.force` (N; the torque on
    /// the particle is R_eff n̂ × F), history advanced by `b.dt`, with the energy outputs
    /// `energy` asks for (`Ok(true)` when written).
    fn force_batch(&self, b: RollingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError>;
}

/// A twisting-resistance law bound to a pair of materials (sdk 0.3).
pub trait TwistingResistance: Send + Sync {
    /// The law's name.
    fn name(&self) -> &str;
    /// History slots per contact.
    fn history_slots(&self) -> usize;
    /// Evaluates every contact of `b`: twisting torques about n̂ into `b.torque` (N·m), history
    /// advanced by `b.dt`, with the energy outputs `energy` asks for (`Ok(true)` when written).
    fn torque_batch(&self, b: TwistingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError>;
}

impl RollingResistance for ModelHandle<Rolling> {
    fn name(&self) -> &str {
        ModelHandle::name(self)
    }
    fn history_slots(&self) -> usize {
        ModelHandle::history_slots(self)
    }
    fn force_batch(&self, b: RollingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl<B: KindBound<Rolling>> RollingResistance for StaticModel<Rolling, B> {
    fn name(&self) -> &str {
        StaticModel::name(self)
    }
    fn history_slots(&self) -> usize {
        StaticModel::history_slots(self)
    }
    fn force_batch(&self, b: RollingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl TwistingResistance for ModelHandle<Twisting> {
    fn name(&self) -> &str {
        ModelHandle::name(self)
    }
    fn history_slots(&self) -> usize {
        ModelHandle::history_slots(self)
    }
    fn torque_batch(&self, b: TwistingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl<B: KindBound<Twisting>> TwistingResistance for StaticModel<Twisting, B> {
    fn name(&self) -> &str {
        StaticModel::name(self)
    }
    fn history_slots(&self) -> usize {
        StaticModel::history_slots(self)
    }
    fn torque_batch(&self, b: TwistingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

/// A law compiled into the program, bound to `materials` (benchmark baselines and tests).
pub fn compiled<L: ContactLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticContact<L::Bound>, LawError> {
    StaticContact::bind(law, materials)
}

/// A tangential law compiled into the program, bound to `materials`.
pub fn compiled_tangential<L: TangentialLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticTangential<L::Bound>, LawError> {
    StaticTangential::bind(law, materials)
}

/// A coefficient of normal restitution as a function of the normal impact speed: what the engine
/// needs from a law.
pub trait Restitution: Sync {
    /// r(v) (dimensionless, expected in [0, 1]) at normal relative impact speed `v` ≥ 0 (m/s).
    fn r(&self, v: f64) -> Result<f64, LawError>;
}

impl Restitution for PluginRestitution {
    #[inline]
    fn r(&self, v: f64) -> Result<f64, LawError> {
        self.restitution(v)
    }
}

impl<T: Restitution + ?Sized> Restitution for Box<T> {
    #[inline]
    fn r(&self, v: f64) -> Result<f64, LawError> {
        (**self).r(v)
    }
}

impl<T: Restitution + ?Sized> Restitution for &T {
    #[inline]
    fn r(&self, v: f64) -> Result<f64, LawError> {
        (**self).r(v)
    }
}

/// A restitution law compiled into the program (no plugin), e.g.
/// `Compiled(dashpot_mcnamara_falcon::McNamaraFalcon { r0: 0.95, vy: 0.3 })`.
#[derive(Debug, Clone, Copy)]
pub struct Compiled<B>(pub B);

impl<B: BoundRestitution> Restitution for Compiled<B> {
    #[inline]
    fn r(&self, v: f64) -> Result<f64, LawError> {
        let r = self.0.restitution(v);
        if r.is_finite() {
            Ok(r)
        } else {
            Err(LawError::new(
                dashpot_sdk::ErrorKind::NonFinite,
                format!("restitution law returned {r} at impact speed {v:e} m/s"),
            ))
        }
    }
}
