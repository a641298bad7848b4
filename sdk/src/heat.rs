//! The heat kind (sdk 0.4): conduction of heat through a contact.
//!
//! A heat law sees one contact of particle i with its partner j (another particle, or a wall):
//! the two temperatures T_i, T_j (K), the normal force (N), the overlap δ (m), the effective
//! radius R_eff (m), the normal law's [`NormalContext`] (its contact radius a, m; what most
//! conductance models are written in), the time step (s) and its own per-contact history. It
//! returns the heat flow Q into particle i (W) and the contact's conductance H (W/K). The host
//! adds Q to i's heat rate and −Q to j's (or tallies it as the wall's), so that Q_ij = −Q_ji
//! exactly and Σ C T changes only by what walls exchange; it then integrates the temperatures
//! (LAMMPS's `fix heat/flow`: T_i += dt Q_i / C_i, explicit Euler, C_i = m_i c_i in J/K), and
//! warns when dt exceeds the thermal stability limit min_i C_i / Σ_j H_ij.
//!
//! A law linear in the temperature difference returns [`HeatFlow::linear`]`(H, T_i, T_j)`, whose
//! Q = H (T_j − T_i) changes sign exactly when T_i and T_j are exchanged.

use crate::context::NormalContext;
use crate::law::{history_law, history_mut, law_info, law_trait, Coefficient, History, LawInfo, LawKind};
use crate::pair::MaterialPair;
use crate::params::{LawParams, ParamValue};
use crate::LawError;
use abi_stable::StableAbi;

/// What a heat law returns for one contact.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Default)]
pub struct HeatFlow {
    /// The heat flow into particle i from its partner j (W): positive when j is hotter. The
    /// partner receives exactly −`heat`.
    pub heat: f64,
    /// The contact's conductance H (W/K), finite and ≥ 0: ∂Q/∂T_j, Q = H (T_j − T_i) for a
    /// linear law. Hosts sum it per particle for the thermal stability limit dt < C / Σ H.
    pub conductance: f64,
}

impl HeatFlow {
    /// The flow of a law linear in the temperature difference: Q = H (T_j − T_i) (W) into the
    /// particle at `temperature` T_i (K) from its partner at `partner` T_j (K), through
    /// conductance `conductance` H (W/K). Exchanging T_i and T_j negates Q exactly.
    #[inline(always)]
    pub fn linear(conductance: f64, temperature: f64, partner: f64) -> HeatFlow {
        HeatFlow {
            heat: conductance * (partner - temperature),
            conductance,
        }
    }
}

/// The state of one contact as a heat law sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatContact {
    /// The particle's temperature T_i (K).
    pub temperature: f64,
    /// The partner's temperature T_j (K): another particle's, or a wall's.
    pub partner_temperature: f64,
    /// The normal force on the contact (N, > 0 repulsive), from the normal law this step.
    pub normal_force: f64,
    /// Overlap δ (m): negative past touching for an adhesive contact that still holds.
    pub delta: f64,
    /// Effective radius R_eff = R_i R_j / (R_i + R_j) (m; R_i against a flat wall).
    pub radius: f64,
    /// What the contact's normal law reports (its contact radius a, m; cap force, N; damping,
    /// N·s/m): the normal law's own for a law that declares `READS_CONTEXT`, else the default
    /// [`NormalContext::hertzian`] of this contact's `radius`, `delta` and `normal_force`.
    pub context: NormalContext,
    /// The time step (s) over which the history advances.
    pub dt: f64,
}

/// Every contact of one material pair for a heat law, structure of arrays.
#[derive(Debug)]
pub struct HeatBatch<'a> {
    /// Time step (s).
    pub dt: f64,
    /// Temperatures `[T_i, T_j]` (K): the particle's, then its partner's.
    pub temperature: &'a [[f64; 2]],
    /// Normal forces (N, > 0 repulsive).
    pub normal_force: &'a [f64],
    /// Overlaps (m).
    pub delta: &'a [f64],
    /// Effective radii (m).
    pub radius: &'a [f64],
    /// The normal law's contexts, one per contact, or none (empty): then each contact's
    /// `context` is the default built from its own `radius`, `delta` and `normal_force`
    /// ([`NormalContext::hertzian`]).
    pub context: &'a [NormalContext],
    /// History slots per contact.
    pub slots: usize,
    /// Per-contact history (`n × slots`), read and updated in place.
    pub history: &'a mut [f64],
    /// Output: each contact's heat flow into particle i (W) and conductance (W/K).
    pub flow: &'a mut [HeatFlow],
}

impl HeatBatch<'_> {
    /// The lengths of the batch's arrays, as the ABI checks them.
    pub(crate) fn lengths(&self) -> crate::lengths::BatchLengths<4> {
        crate::lengths::BatchLengths {
            call: "heat_batch",
            inputs: "temperature, normal_force, delta, radius",
            lens: [
                self.temperature.len(),
                self.normal_force.len(),
                self.delta.len(),
                self.radius.len(),
            ],
            output: "flow",
            n: self.flow.len(),
            slots: self.slots,
            history: self.history.len(),
            context: self.context.len(),
        }
    }

    /// Contact `i` of the batch.
    #[inline(always)]
    pub fn contact(&self, i: usize) -> HeatContact {
        let [t, tj] = self.temperature[i];
        HeatContact {
            temperature: t,
            partner_temperature: tj,
            normal_force: self.normal_force[i],
            delta: self.delta[i],
            radius: self.radius[i],
            context: match self.context.get(i) {
                Some(c) => *c,
                None => NormalContext::hertzian(self.radius[i], self.delta[i], self.normal_force[i]),
            },
            dt: self.dt,
        }
    }

    /// `flow[i] = f(contact i, its history)` for every contact: the loop of a batch call.
    #[inline(always)]
    pub fn each(self, mut f: impl FnMut(&HeatContact, &mut [f64]) -> HeatFlow) {
        let (slots, n) = (self.slots, self.flow.len());
        if slots == 0 && self.context.len() == n {
            // the common case (no history, the normal law's contexts): one pass over slices
            // of the same length, no per-contact branch nor bounds check
            let inputs = self.temperature[..n]
                .iter()
                .zip(&self.normal_force[..n])
                .zip(&self.delta[..n])
                .zip(&self.radius[..n])
                .zip(&self.context[..n]);
            for (o, ((((&[t, tj], &fz), &d), &r), &x)) in self.flow.iter_mut().zip(inputs) {
                let c = HeatContact {
                    temperature: t,
                    partner_temperature: tj,
                    normal_force: fz,
                    delta: d,
                    radius: r,
                    context: x,
                    dt: self.dt,
                };
                *o = f(&c, &mut []);
            }
            return;
        }
        for i in 0..n {
            let c = self.contact(i);
            self.flow[i] = f(&c, history_mut(self.history, slots, i));
        }
    }
}

/// A heat-conduction law bound to a material pair.
pub trait BoundHeat: Send + Sync + 'static {
    /// The heat flow into particle i (W) and the conductance (W/K) of contact `c`, updating
    /// `history` in place.
    fn heat(&self, c: &HeatContact, history: &mut [f64]) -> HeatFlow;

    /// [`Self::heat`] for every contact of the batch. Override only if a hand-vectorised form
    /// is faster than this loop.
    #[inline(always)]
    fn heat_batch(&self, b: HeatBatch<'_>) {
        b.each(|c, h| self.heat(c, h));
    }

    /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
    fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        Vec::new()
    }
}

history_law!(
    /// A configurable heat-conduction law (sdk 0.4). Declare its parameters with
    /// [`law_params!`](crate::law_params), implement this, then export with
    /// [`export_laws!`](crate::export_laws) under `heat: [...]`. A law written in the contact
    /// radius declares `READS_CONTEXT = true` to receive the normal law's own (JKR's, positive
    /// past touching until rupture).
    HeatLaw: BoundHeat, LawKind::Heat
);
