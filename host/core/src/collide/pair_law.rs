//! A contact law as the two-body integrator sees it: F(δ, δ̇) for the collision's fixed pair.

use super::rk::{RhsError, Step};
use super::two_body::StepAsk;
use crate::laws::{EnergyOut, NormalLaw};
use dashpot_sdk::{Contact, LawError, NormalBatch};
use std::sync::{Mutex, OnceLock};

/// A contact law as the integrator sees it: F(δ, δ̇) in newtons for the collision's fixed pair,
/// or an error.
pub trait ContactForce {
    /// The normal force (N) at overlap `delta` (m) and rate `rate` (m/s), from the committed
    /// history (which it does not change).
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError>;

    /// `out[i] = F(delta[i], rate[i])`: the integrator evaluates independent states together,
    /// each from the committed history.
    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        for ((o, &d), &r) in out.iter_mut().zip(delta).zip(rate) {
            *o = self.force(d, r)?;
        }
        Ok(())
    }

    /// Whether the law keeps per-contact history (then the integrator commits it at accepted
    /// states, and restarts its step at the maximum overlap).
    fn has_history(&self) -> bool {
        false
    }

    /// Makes the history the law writes at state (δ, δ̇) the committed one.
    fn commit(&self, _delta: f64, _rate: f64) -> Result<(), LawError> {
        Ok(())
    }

    /// Forgets the history: a new first touch. [`collide`](crate::collide::collide) calls it first; a law with history
    /// holds the state of one collision at a time, so it must not serve concurrent collisions.
    fn reset(&self) {}

    /// How far beyond touching (m) the contact acts after a force call at (δ, δ̇) from the
    /// committed history (sdk 0.3's reach: the contact ends once δ < −reach). 0 for a law
    /// without one.
    fn reach(&self, _delta: f64, _rate: f64) -> Result<f64, LawError> {
        Ok(0.0)
    }

    /// The extrapolation step `ask` taken elsewhere, with the number of force evaluations it
    /// made; `None`
    /// (the default) lets the integrator take it. The collisions of a restitution curve take
    /// their steps together this way ([`crate::collide::lanes`]).
    #[doc(hidden)]
    fn lockstep_step(&self, _ask: &StepAsk) -> Option<(Result<Step<2>, RhsError>, usize)> {
        None
    }
}

/// A law bound to a collision's pair: its [`NormalLaw`] with the pair's effective mass (kg) and
/// radius (m) for every call, and the contact's committed history (zero at first touch).
pub struct PairLaw<L> {
    law: L,
    mass: f64,
    radius: f64,
    /// The pair's mass and radius for every contact of a call, built once: the integrator
    /// calls the law a few hundred times per collision with at most ten states, so the
    /// per-call work is kept to the call itself.
    masses: [f64; PAIR_CHUNK],
    radii: [f64; PAIR_CHUNK],
    slots: usize,
    committed: Mutex<Vec<f64>>,
    /// The same for the wide batches of a restitution curve's collisions in lockstep
    /// ([`crate::collide::lanes`]), made at the first.
    wide: OnceLock<(Vec<f64>, Vec<f64>)>,
}

impl<L: NormalLaw> PairLaw<L> {
    /// `law` for a contact of effective `mass` (kg) and `radius` (m), history zero.
    pub fn new(law: L, mass: f64, radius: f64) -> PairLaw<L> {
        let slots = law.history_slots();
        PairLaw {
            law,
            mass,
            radius,
            masses: [mass; PAIR_CHUNK],
            radii: [radius; PAIR_CHUNK],
            slots,
            committed: Mutex::new(vec![0.0; slots]),
            wide: OnceLock::new(),
        }
    }

    /// The law.
    pub fn law(&self) -> &L {
        &self.law
    }

    /// The committed history.
    pub fn history(&self) -> Vec<f64> {
        self.committed.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

impl PairLaw<crate::laws::ContactModelHandle> {
    /// Plugin law `law` bound to `pair`, both bodies of Poisson's ratio `poisson` (which sets
    /// the shear modulus; no normal law of the project uses it).
    pub fn bind(
        law: &crate::laws::ContactLawHandle,
        pair: &dashpot_sdk::Pair,
        poisson: f64,
    ) -> Result<Self, LawError> {
        pair.validate()?;
        Ok(PairLaw::new(
            law.bind(&pair.materials(poisson)?)?,
            pair.mass,
            pair.radius,
        ))
    }

    /// The law's derived constants for this pair.
    pub fn coefficients(&self) -> Result<Vec<dashpot_sdk::Coefficient>, LawError> {
        self.law.coefficients(self.mass, self.radius)
    }
}

/// Contacts evaluated per call of the law (stack arrays for the constant geometry).
const PAIR_CHUNK: usize = 16;

/// Contacts evaluated per call of a law without history in a wide batch.
const WIDE_CHUNK: usize = 256;

impl<L: NormalLaw> ContactForce for PairLaw<L> {
    #[inline]
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        let mut out = [0.0];
        self.force_batch(&[delta], &[rate], &mut out)?;
        Ok(out[0])
    }

    #[inline]
    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        if self.slots == 0 {
            let (masses, radii, chunk) = if delta.len() <= PAIR_CHUNK {
                (&self.masses[..], &self.radii[..], PAIR_CHUNK)
            } else {
                let (m, r) = self
                    .wide
                    .get_or_init(|| (vec![self.mass; WIDE_CHUNK], vec![self.radius; WIDE_CHUNK]));
                (&m[..], &r[..], WIDE_CHUNK)
            };
            for ((d, r), o) in delta
                .chunks(chunk)
                .zip(rate.chunks(chunk))
                .zip(out.chunks_mut(chunk))
            {
                let n = o.len();
                self.law.force_batch(NormalBatch {
                    delta: d,
                    rate: r,
                    mass: &masses[..n],
                    radius: &radii[..n],
                    slots: 0,
                    history: &mut [],
                    force: o,
                })?;
            }
            return Ok(());
        }
        // every state from the committed history, on a scratch copy
        let committed = self.history();
        let mut scratch = Vec::with_capacity(PAIR_CHUNK * self.slots);
        for ((d, r), o) in delta
            .chunks(PAIR_CHUNK)
            .zip(rate.chunks(PAIR_CHUNK))
            .zip(out.chunks_mut(PAIR_CHUNK))
        {
            let n = o.len();
            scratch.clear();
            for _ in 0..n {
                scratch.extend_from_slice(&committed);
            }
            self.law.force_batch(NormalBatch {
                delta: d,
                rate: r,
                mass: &self.masses[..n],
                radius: &self.radii[..n],
                slots: self.slots,
                history: &mut scratch,
                force: o,
            })?;
        }
        Ok(())
    }

    fn has_history(&self) -> bool {
        self.slots > 0
    }

    fn reach(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        let mut h = self.history();
        let (mut f, mut reach) = ([0.0], [0.0]);
        self.law.force_batch_with(
            NormalBatch {
                delta: &[delta],
                rate: &[rate],
                mass: &[self.mass],
                radius: &[self.radius],
                slots: self.slots,
                history: &mut h,
                force: &mut f,
            },
            Some(&mut reach),
            EnergyOut::none(),
        )?;
        Ok(reach[0])
    }

    fn reset(&self) {
        if self.slots > 0 {
            let mut h = self.committed.lock().unwrap_or_else(|p| p.into_inner());
            h.iter_mut().for_each(|v| *v = 0.0);
        }
    }

    fn commit(&self, delta: f64, rate: f64) -> Result<(), LawError> {
        if self.slots == 0 {
            return Ok(());
        }
        let mut h = self.history();
        self.law.force(
            Contact {
                delta,
                rate,
                mass: self.mass,
                radius: self.radius,
            },
            &mut h,
        )?;
        *self.committed.lock().unwrap_or_else(|p| p.into_inner()) = h;
        Ok(())
    }
}

impl<C: ContactForce + ?Sized> ContactForce for &C {
    #[inline]
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        (**self).force(delta, rate)
    }

    #[inline]
    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        (**self).force_batch(delta, rate, out)
    }

    fn has_history(&self) -> bool {
        (**self).has_history()
    }

    fn commit(&self, delta: f64, rate: f64) -> Result<(), LawError> {
        (**self).commit(delta, rate)
    }

    fn reset(&self) {
        (**self).reset()
    }

    fn reach(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        (**self).reach(delta, rate)
    }

    fn lockstep_step(&self, ask: &StepAsk) -> Option<(Result<Step<2>, RhsError>, usize)> {
        (**self).lockstep_step(ask)
    }
}
