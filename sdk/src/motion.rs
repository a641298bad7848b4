//! The motion kinds (tangential, rolling, twisting): laws that see a contact's normal, one
//! relative motion, the normal force, overlap, effective mass and radius and the time step, and
//! keep per-contact history. Their contact and batch types come from one macro
//! (`motion_kind!`), their bound laws' methods from another (`motion_law_methods!`); the two
//! vector kinds (tangential, rolling) share [`VectorContact`] and [`VectorBatch`]
//! (`vector_law!`). The tangential kind is declared here, rolling and twisting in the
//! `rotation` module.

use crate::energy::{Energy, EnergyBatch};
use crate::law::{history_law, history_mut, law_info, law_trait, History, LawInfo, LawKind};
use crate::pair::MaterialPair;
use crate::params::{LawParams, ParamValue};
use crate::LawError;

/// Declares the contact and batch types of a kind whose law sees a contact's normal, one
/// relative motion (`$motion`), the normal force, overlap, effective mass and radius and the
/// time step, and writes one output per contact (`$out`), with `history` slots per contact; and
/// the batch's `contact(i)`.
macro_rules! motion_kind {
    (
        $(#[$cdoc:meta])* $contact:ident, $(#[$bdoc:meta])* $batch:ident,
        $(#[$mdoc:meta])* $motion:ident: $mty:ty, $(#[$odoc:meta])* $out:ident: $oty:ty
    ) => {
        $(#[$cdoc])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $contact {
            /// Unit contact normal n̂, from partner j to particle i.
            pub normal: [f64; 3],
            $(#[$mdoc])*
            pub $motion: $mty,
            /// The normal force on the contact (N, > 0 repulsive), from the normal law this step:
            /// what caps friction, rolling and twisting resistance.
            pub normal_force: f64,
            /// Overlap δ (m).
            pub delta: f64,
            /// Effective mass (kg).
            pub mass: f64,
            /// Effective radius R_eff (m).
            pub radius: f64,
            /// What the contact's normal law reports (sdk 0.4): its contact radius a (m), the
            /// force the caps scale with (N) and its damping coefficient (N·s/m). The normal
            /// law's own for a law that declares `READS_CONTEXT`; else the default
            /// [`NormalContext::hertzian`](crate::NormalContext::hertzian) of this contact's
            /// `radius`, `delta` and `normal_force`.
            pub context: crate::NormalContext,
            /// The time step (s) over which the history advances.
            pub dt: f64,
        }

        $(#[$bdoc])*
        #[derive(Debug)]
        pub struct $batch<'a> {
            /// Time step (s) over which the history advances.
            pub dt: f64,
            /// Unit normals n̂ (from partner to particle).
            pub normal: &'a [[f64; 3]],
            $(#[$mdoc])*
            pub $motion: &'a [$mty],
            /// Normal forces (N, > 0 repulsive).
            pub normal_force: &'a [f64],
            /// Overlaps (m).
            pub delta: &'a [f64],
            /// Effective masses (kg).
            pub mass: &'a [f64],
            /// Effective radii (m).
            pub radius: &'a [f64],
            /// The normal law's contexts (sdk 0.4), one per contact, or none (empty): then each
            /// contact's `context` is the default built from its own `radius`, `delta` and
            /// `normal_force` ([`NormalContext::hertzian`](crate::NormalContext::hertzian)).
            pub context: &'a [crate::NormalContext],
            /// History slots per contact.
            pub slots: usize,
            /// Per-contact history, read and updated in place.
            pub history: &'a mut [f64],
            $(#[$odoc])*
            pub $out: &'a mut [$oty],
        }

        impl $batch<'_> {
            /// The lengths of the batch's arrays, as the ABI checks them.
            pub(crate) fn lengths(&self) -> crate::lengths::BatchLengths<6> {
                crate::lengths::BatchLengths {
                    call: concat!(stringify!($out), "_batch"),
                    inputs: concat!("normal, ", stringify!($motion), ", normal_force, delta, mass, radius"),
                    lens: [
                        self.normal.len(),
                        self.$motion.len(),
                        self.normal_force.len(),
                        self.delta.len(),
                        self.mass.len(),
                        self.radius.len(),
                    ],
                    output: stringify!($out),
                    n: self.$out.len(),
                    slots: self.slots,
                    history: self.history.len(),
                    context: self.context.len(),
                }
            }

            /// Contact `i` of the batch.
            #[inline(always)]
            pub fn contact(&self, i: usize) -> $contact {
                $contact {
                    normal: self.normal[i],
                    $motion: self.$motion[i],
                    normal_force: self.normal_force[i],
                    delta: self.delta[i],
                    mass: self.mass[i],
                    radius: self.radius[i],
                    context: match self.context.get(i) {
                        Some(c) => *c,
                        None => crate::NormalContext::hertzian(self.radius[i], self.delta[i], self.normal_force[i]),
                    },
                    dt: self.dt,
                }
            }

            #[doc = concat!("`", stringify!($out), "[i] = f(contact i, its history)` for every contact: the loop of a batch call.")]
            #[inline(always)]
            pub fn each(self, mut f: impl FnMut(&$contact, &mut [f64]) -> $oty) {
                let slots = self.slots;
                for i in 0..self.$out.len() {
                    let c = self.contact(i);
                    self.$out[i] = f(&c, history_mut(self.history, slots, i));
                }
            }

            #[doc = concat!("`", stringify!($out), "[i]` and contact i's energy from `f(contact i, its history)` for every contact: the loop of a batch call with energy outputs; whether every contact reported one.")]
            #[inline(always)]
            pub fn each_energy(
                self,
                mut out: $crate::law::EnergyBatch<'_>,
                mut f: impl FnMut(&$contact, &mut [f64]) -> ($oty, Option<$crate::law::Energy>),
            ) -> bool {
                let slots = self.slots;
                let mut all = true;
                for i in 0..self.$out.len() {
                    let c = self.contact(i);
                    let (o, e) = f(&c, history_mut(self.history, slots, i));
                    self.$out[i] = o;
                    all &= out.set(i, e);
                }
                all
            }

            #[doc = concat!("Contacts `from..` through the per-contact forms: `", stringify!($out), "[i] = force(contact i, its history)`, or `force_energy` with contact i's energy written to `out` when there is one (the last contacts of a batch whose first ones went through lanes).")]
            #[inline]
            pub fn each_from(
                self,
                from: usize,
                mut out: Option<&mut $crate::law::EnergyBatch<'_>>,
                mut force: impl FnMut(&$contact, &mut [f64]) -> $oty,
                mut force_energy: impl FnMut(&$contact, &mut [f64]) -> ($oty, Option<$crate::law::Energy>),
            ) {
                let slots = self.slots;
                for i in from..self.$out.len() {
                    let c = self.contact(i);
                    let h = history_mut(self.history, slots, i);
                    match out.as_mut() {
                        Some(o) => {
                            let (f, e) = force_energy(&c, h);
                            self.$out[i] = f;
                            o.set(i, e);
                        }
                        None => self.$out[i] = force(&c, h),
                    }
                }
            }
        }
    };
}
pub(crate) use motion_kind;

/// The methods of a bound law of a motion kind (tangential, rolling, twisting), in its trait's
/// body: `$call` returns the `$what` of one contact (`$out`) and advances its history,
/// `$batch_call` does so for a batch (`$batch`), `energy` reports a contact's energy after a
/// call, `$energy_call` and `$batch_energy_call` return the output with the step's energy.
macro_rules! motion_law_methods {
    ($what:literal, $contact:ty, $batch:ty, $out:ty,
     $call:ident, $batch_call:ident, $energy_call:ident, $batch_energy_call:ident) => {
        #[doc = concat!("The ", $what, " on contact `c`, updating `history` in place.")]
        fn $call(&self, c: &$contact, history: &mut [f64]) -> $out;

        #[doc = concat!("[`Self::", stringify!($call), "`] for every contact of the batch. Override only if a hand-vectorised form is faster than this loop.")]
        #[inline(always)]
        fn $batch_call(&self, b: $batch) {
            b.each(|c, h| self.$call(c, h));
        }

        #[doc = concat!("The energy of contact `c` after a call that returned `output` (the ", $what, ") and left `history` (sdk 0.3): the elastic energy stored (J) and the power dissipated (W); `None` (the default) when the law does not account for it. A spring law that needs its history before the step overrides [`Self::", stringify!($energy_call), "`] instead.")]
        fn energy(&self, _c: &$contact, _history: &[f64], _output: $out) -> Option<Energy> {
            None
        }

        #[doc = concat!("The ", $what, " on contact `c`, `history` updated as by [`Self::", stringify!($call), "`], with the contact's energy over the step (sdk 0.3), the history before the step in view (what exact accounting of a sliding spring needs). The default is [`Self::", stringify!($call), "`] then [`Self::energy`].")]
        #[inline(always)]
        fn $energy_call(&self, c: &$contact, history: &mut [f64]) -> ($out, Option<Energy>) {
            let o = self.$call(c, history);
            (o, self.energy(c, history, o))
        }

        #[doc = concat!("[`Self::", stringify!($batch_call), "`] with each contact's energy written to `out` (sdk 0.3); whether every contact reported one. The default loops over [`Self::", stringify!($energy_call), "`]: a law that overrides `", stringify!($batch_call), "` for speed overrides this too.")]
        #[inline(always)]
        fn $batch_energy_call(&self, b: $batch, out: EnergyBatch<'_>) -> bool {
            b.each_energy(out, |c, h| self.$energy_call(c, h))
        }
    };
}
pub(crate) use motion_law_methods;

motion_kind!(
    /// The state of one contact as a tangential or rolling law sees it. Vectors are 3D (a 2D
    /// caller sets the third components to 0).
    VectorContact,
    /// Every contact of one material pair for a tangential or rolling law, structure of arrays.
    /// Vectors are `[x, y, z]` triples; `history` is `n × slots` as in [`NormalBatch`](crate::NormalBatch).
    VectorBatch,
    /// Relative velocity (m/s): for a tangential law, of i's contact point with respect to j's
    /// (ω × r terms included; the law uses its part in the tangent plane); for a rolling law,
    /// the rolling velocity v_roll = R_eff (ω_i − ω_j) × n̂.
    velocity: [f64; 3],
    /// Output: the force on particle i (N): tangential, in the tangent plane; or the
    /// rolling-resistance force F_r, whose torque on i is R_eff n̂ × F_r.
    force: [f64; 3]
);

/// Declares a vector kind (tangential, rolling): its names of [`VectorContact`] and
/// [`VectorBatch`], and its bound-law trait, whose output is the force `$what` on each contact
/// (`motion_law_methods!`), with the further items `$($more)*`.
macro_rules! vector_law {
    (
        $(#[$cdoc:meta])* $contact:ident, $(#[$bdoc:meta])* $batch:ident,
        $(#[$tdoc:meta])* $bound:ident: $what:literal { $($more:tt)* }
    ) => {
        $(#[$cdoc])*
        pub type $contact = $crate::motion::VectorContact;

        $(#[$bdoc])*
        pub type $batch<'a> = $crate::motion::VectorBatch<'a>;

        $(#[$tdoc])*
        pub trait $bound: Send + Sync + 'static {
            $crate::motion::motion_law_methods!(
                $what,
                $contact,
                $batch<'_>,
                [f64; 3],
                force,
                force_batch,
                force_energy,
                force_batch_energy
            );

            $($more)*
        }
    };
}
pub(crate) use vector_law;

vector_law!(
    /// The state of one contact as a tangential law sees it (see [`VectorContact`]).
    TangentialContact,
    /// Every contact of one material pair for a tangential law (see [`VectorBatch`]).
    TangentialBatch,
    /// A tangential (friction) law bound to a material pair.
    ///
    /// It returns the tangential force on particle i, capped by Coulomb's μ|F_n|, and advances
    /// the history (for a spring: its displacement, rotated into the current tangent plane) by
    /// `dt`.
    BoundTangential: "tangential force (N)" {}
);

history_law!(
    /// A configurable tangential (friction) law, composable at run time with any contact law.
    /// Declare its parameters with [`law_params!`](crate::law_params), implement this, then
    /// export with [`export_laws!`](crate::export_laws) under `tangential: [...]`.
    TangentialLaw: BoundTangential, LawKind::Tangential
);
