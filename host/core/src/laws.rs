//! The law-facing traits every driver uses: the only module that names ABI handles.
//!
//! A driver is generic over [`NormalLaw`] (and [`TangentialForce`], [`RollingResistance`],
//! [`TwistingResistance`] where it has friction and rotation, [`HeatConduction`] where it
//! conducts heat), so the same driver code runs a
//! plugin's handle or a law compiled into the program (benchmark baselines, tests) through the
//! very same checked trampoline. Each of these traits is the sdk's [`BoundModel`] of its kind
//! with the kind's own calls.

/// What every bound law of a kind offers a host (name, history slots, the checked batch call,
/// coefficients), implemented by the sdk for a plugin's handles and for laws compiled in; the
/// kinds' own traits below add their calls to it.
pub use dashpot_sdk::abi::BoundModel;
use dashpot_sdk::abi::StaticModel;
/// The law kinds, as the sdk's generic handles name them, and the energy outputs of a batch
/// call.
pub use dashpot_sdk::abi::{EnergyOut, Heat, Normal, NormalCall, Rolling, Tangential, Twisting};
use dashpot_sdk::{
    BoundRestitution, Contact, ContactLaw, HeatBatch, HeatLaw, LawError, MaterialPair, NormalBatch,
    NormalContext, RollingBatch, RollingLaw, TangentialBatch, TangentialLaw, TwistingBatch,
};

pub use dashpot_sdk::abi::SdkSeries;
/// The handles of laws loaded from plugins, before and after binding: the registry hands them
/// out, and the traits below are implemented for the bound ones.
pub use dashpot_sdk::abi::{
    ContactLawHandle, ContactModelHandle, LawHandle, LoadedPlugin, ModelHandle, RestitutionLawHandle,
    TangentialLawHandle, TangentialModelHandle,
};

/// A restitution law loaded from a plugin and bound to a pair (the sdk's handle).
pub type PluginRestitution = dashpot_sdk::abi::BoundRestitutionHandle;

/// A contact law bound to a pair of materials: normal forces for batches of contacts, each with
/// its own effective mass and radius and history. Every [`BoundModel`] of the normal kind is
/// one (a plugin's handle, a law compiled in, a reference or box of one).
pub trait NormalLaw: BoundModel<Normal> {
    /// Evaluates every contact of `b`: forces into `b.force` (N), history updated in place;
    /// a non-finite input or output is an error naming the contact.
    #[inline]
    fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        self.force_batch_with(b, None, EnergyOut::none()).map(|_| ())
    }

    /// [`NormalLaw::force_batch`] with each contact's reach (m: the contact ends at δ < −reach)
    /// and the energy outputs `energy` asks for; `Ok(true)` when those were written. A law of a
    /// plugin older than sdk 0.3: reach 0, energy not available.
    #[inline]
    fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        let context = None;
        self.batch(
            NormalCall {
                batch: b,
                reach,
                context,
            },
            energy,
        )
    }

    /// [`NormalLaw::force_batch_with`] with each contact's normal context (sdk 0.4: contact
    /// radius, cap force, damping; what the contact's other laws read) written to `context`, one
    /// per contact. A law of a plugin older than sdk 0.4, or one that keeps the default, gives
    /// [`NormalContext::default_for`] (the Hertzian radius, max(F, 0), no damping).
    #[inline]
    fn force_batch_context(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        context: &mut [NormalContext],
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        let context = Some(context);
        self.batch(
            NormalCall {
                batch: b,
                reach,
                context,
            },
            energy,
        )
    }

    /// The normal force (N) on one contact, history updated in place.
    fn force(&self, c: Contact, history: &mut [f64]) -> Result<f64, LawError> {
        c.force_through(history, |b| self.force_batch(b))
    }
}

impl<M: BoundModel<Normal> + ?Sized> NormalLaw for M {}

/// A tangential law bound to a pair of materials.
pub trait TangentialForce: BoundModel<Tangential> {
    /// Evaluates every contact of `b`: tangential forces into `b.force` (N), history advanced
    /// by `b.dt` in place.
    #[inline]
    fn force_batch(&self, b: TangentialBatch<'_>) -> Result<(), LawError> {
        self.batch(b, EnergyOut::none()).map(|_| ())
    }

    /// [`TangentialForce::force_batch`] with the energy outputs `energy` asks for; `Ok(true)`
    /// when they were written.
    #[inline]
    fn force_batch_with(&self, b: TangentialBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl<M: BoundModel<Tangential> + ?Sized> TangentialForce for M {}

/// A rolling-resistance law bound to a pair of materials (sdk 0.3).
pub trait RollingResistance: BoundModel<Rolling> {
    /// Evaluates every contact of `b`: rolling-resistance forces into `b.force` (N; the torque on
    /// the particle is R_eff n̂ × F), history advanced by `b.dt`, with the energy outputs
    /// `energy` asks for (`Ok(true)` when written).
    #[inline]
    fn force_batch(&self, b: RollingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl<M: BoundModel<Rolling> + ?Sized> RollingResistance for M {}

/// A twisting-resistance law bound to a pair of materials (sdk 0.3).
pub trait TwistingResistance: BoundModel<Twisting> {
    /// Evaluates every contact of `b`: twisting torques about n̂ into `b.torque` (N·m), history
    /// advanced by `b.dt`, with the energy outputs `energy` asks for (`Ok(true)` when written).
    #[inline]
    fn torque_batch(&self, b: TwistingBatch<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        self.batch(b, energy)
    }
}

impl<M: BoundModel<Twisting> + ?Sized> TwistingResistance for M {}

/// A heat-conduction law bound to a pair of materials (sdk 0.4).
pub trait HeatConduction: BoundModel<Heat> {
    /// Evaluates every contact of `b`: each contact's heat flow into particle i (W) and
    /// conductance (W/K) into `b.flow`, history advanced by `b.dt`. The caller adds the heat to
    /// i and its negative to j (Q_ji = −Q_ij exactly).
    #[inline]
    fn heat_batch(&self, b: HeatBatch<'_>) -> Result<(), LawError> {
        self.batch(b, EnergyOut::none()).map(|_| ())
    }
}

impl<M: BoundModel<Heat> + ?Sized> HeatConduction for M {}

/// A contact law compiled into the program, bound to `materials` (benchmark baselines and
/// tests), called through the very trampoline a plugin exports.
pub fn compiled<L: ContactLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticModel<Normal, L::Bound>, LawError> {
    StaticModel::bind(law, materials)
}

/// A tangential law compiled into the program, bound to `materials`.
pub fn compiled_tangential<L: TangentialLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticModel<Tangential, L::Bound>, LawError> {
    StaticModel::bind(law, materials)
}

/// A rolling-resistance law compiled into the program, bound to `materials`.
pub fn compiled_rolling<L: RollingLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticModel<Rolling, L::Bound>, LawError> {
    StaticModel::bind(law, materials)
}

/// A heat-conduction law compiled into the program, bound to `materials`.
pub fn compiled_heat<L: HeatLaw>(
    law: &L,
    materials: &MaterialPair,
) -> Result<StaticModel<Heat, L::Bound>, LawError> {
    StaticModel::bind(law, materials)
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
