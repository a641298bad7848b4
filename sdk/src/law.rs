//! The kinds of law and what a law author implements: plain Rust types only (the stable ABI's
//! mirrors of them live behind the export macro, in [`abi`](crate::abi)).
//!
//! Every kind has two stages, as in every DEM code: *configure* (from parameters validated
//! against the law's schema: the law is its [`LawParams`] struct) and *bind* (once, to what does
//! not change from contact to contact: a [`MaterialPair`] for contact, tangential, rolling and
//! twisting laws, a [`Pair`] for restitution laws), so that the hot path is a pure function of
//! the contact state with every constant precomputed.

use crate::context::NormalContext;
pub use crate::energy::{Energy, EnergyBatch};
use crate::error::LawError;
use crate::pair::{MaterialPair, Pair};
use crate::params::{LawParams, ParamSpec, ParamValue, Params};
use abi_stable::StableAbi;

/// Which kind of law.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// A normal contact force F(δ, δ̇) (N), possibly with per-contact history.
    Contact = 1,
    /// A restitution coefficient r(v) at normal impact speed v.
    Restitution = 2,
    /// A tangential (friction) force at the contact point (N), with per-contact history (sdk 0.2).
    Tangential = 3,
    /// A rolling-resistance force (N) at the contact, with per-contact history (sdk 0.3).
    Rolling = 4,
    /// A twisting torque (N·m) about the contact normal, with per-contact history (sdk 0.3).
    Twisting = 5,
    /// A heat flow (W) through the contact between two temperatures, with per-contact history
    /// (sdk 0.4).
    Heat = 6,
}

impl LawKind {
    /// `"contact"`, `"restitution"`, `"tangential"`, `"rolling"`, `"twisting"` or `"heat"` (its
    /// name in JSON too).
    pub const fn as_str(self) -> &'static str {
        match self {
            LawKind::Contact => "contact",
            LawKind::Restitution => "restitution",
            LawKind::Tangential => "tangential",
            LawKind::Rolling => "rolling",
            LawKind::Twisting => "twisting",
            LawKind::Heat => "heat",
        }
    }
}

/// When a two-body contact is over. Realized restitution and contact time depend on it, so every
/// number the project reports says which criterion produced it.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EndCriterion {
    /// Contact ends when the overlap δ returns to 0 (Antypov & Elliott's convention). A damped
    /// law then pulls the particles together at the very end (a fictitious attraction).
    Overlap = 1,
    /// Contact ends when the total normal force returns to 0 on rebound (no attraction).
    Force = 2,
}

impl EndCriterion {
    /// `"overlap"` or `"force"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            EndCriterion::Overlap => "overlap",
            EndCriterion::Force => "force",
        }
    }
}

/// Everything a host needs to know about a law without creating it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LawInfo {
    /// The name a user selects the law by (`--law NAME`); unique within a host.
    pub name: String,
    /// Which kind of law.
    pub kind: LawKind,
    /// One line: what the law is.
    pub summary: String,
    /// Longer documentation: the formula, the parameters' meaning, conventions, references.
    pub doc: String,
    /// The parameter schema.
    pub params: Vec<ParamSpec>,
    /// For a contact law: the end-of-contact criterion its closed-form calibration assumes.
    pub end_criterion: Option<EndCriterion>,
    /// The per-contact history slots the law keeps (f64 each; empty for a memoryless law).
    pub history: Vec<HistorySlot>,
    /// For a tangential, rolling, twisting or heat law: whether it reads the normal law's
    /// [`NormalContext`] (sdk 0.4), which a host then computes and passes; false for every law
    /// of an older sdk.
    pub reads_context: bool,
}

/// One per-contact history slot, as published by a law (the caller stores the value).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HistorySlot {
    /// Short name, e.g. `"delta_max"` or `"xi_x"`.
    pub name: String,
    /// SI unit of the stored value.
    pub unit: String,
    /// One line: what the slot holds.
    pub doc: String,
}

/// A history slot as a law author declares it (`const HISTORY: &[History] = &[...]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct History {
    /// Short name.
    pub name: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// One line.
    pub doc: &'static str,
}

impl History {
    /// A slot declaration.
    pub const fn new(name: &'static str, unit: &'static str, doc: &'static str) -> History {
        History { name, unit, doc }
    }

    /// The three slots of a tangential spring's displacement ξ (m): `xi_x`, `xi_y`, `xi_z`, the
    /// history of a Cundall–Strack friction law (`const HISTORY: &[History] =
    /// &History::TANGENTIAL_SPRING;`; Mindlin's adds its stiffness of the last call).
    pub const TANGENTIAL_SPRING: [History; 3] = [
        History::new("xi_x", "m", "tangential spring displacement ξ, x component"),
        History::new("xi_y", "m", "tangential spring displacement ξ, y component"),
        History::new("xi_z", "m", "tangential spring displacement ξ, z component"),
    ];

    /// The three slots of the dashpot's share of the force a spring–dashpot–slider law returned
    /// last (N): `fd_x`, `fd_y`, `fd_z`, which [`crate::physics::Slider::energy`] reads to book
    /// the step's work exactly (the vector laws of [`crate::physics::Slider`] keep them after
    /// their spring).
    pub const DASHPOT_FORCE: [History; 3] = [
        History::new(
            "fd_x",
            "N",
            "the dashpot's share of the last force, x (its energy's)",
        ),
        History::new("fd_y", "N", "the dashpot's share of the last force, y"),
        History::new("fd_z", "N", "the dashpot's share of the last force, z"),
    ];
}

/// A derived constant of a bound law (for example a damping coefficient), for display and tests.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Coefficient {
    /// Symbol, e.g. `"gamma"`.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// Value in `unit`.
    pub value: f64,
    /// One line: what it is, with the equation it comes from.
    pub doc: String,
}

impl Coefficient {
    /// A coefficient.
    pub fn new(name: &str, unit: &str, value: f64, doc: &str) -> Coefficient {
        Coefficient {
            name: name.into(),
            unit: unit.into(),
            value,
            doc: doc.into(),
        }
    }
}

/// What a calibration must reproduce: a measured restitution and, optionally, a contact time.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CalibrationTarget {
    /// Measured coefficient of restitution, in (0, 1].
    pub restitution: f64,
    /// Measured contact time (s), if any.
    pub contact_time: Option<f64>,
    /// Normal impact speed (m/s) of the measurement, if known. Needed by laws whose restitution
    /// or contact time depends on it.
    pub impact_speed: Option<f64>,
    /// The end-of-contact criterion under which restitution and contact time were defined.
    pub end: EndCriterion,
}

/// The state of one contact as a normal law sees it: overlap, its rate and the contact's own
/// effective geometry. All SI.
///
/// Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while approaching).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Overlap δ (m); δ < 0 means no contact (a law returns 0 there).
    pub delta: f64,
    /// Overlap rate δ̇ (m/s), positive while the particles approach.
    pub rate: f64,
    /// Effective mass m1 m2/(m1 + m2) of this contact (kg); the particle's mass against a wall.
    pub mass: f64,
    /// Effective radius r1 r2/(r1 + r2) of this contact (m); the particle's radius against a
    /// flat wall.
    pub radius: f64,
}

/// Every contact of one kind of material pair, structure of arrays: what one batch call
/// evaluates. All slices have length `n = force.len()`, except `history` (`n × slots`, contact
/// `i` owning `history[i*slots .. (i+1)*slots]`).
///
/// History: zero at a contact's first touch; the law reads it and writes the updated value in
/// place. The caller owns the storage, keeps what the law wrote when it accepts the step (a DEM
/// step), or hands a scratch copy for a trial evaluation (an integrator's stage), and drops it
/// when the contact ends.
#[derive(Debug)]
pub struct NormalBatch<'a> {
    /// Overlaps δ (m).
    pub delta: &'a [f64],
    /// Overlap rates δ̇ (m/s), > 0 approaching.
    pub rate: &'a [f64],
    /// Effective masses (kg), per contact.
    pub mass: &'a [f64],
    /// Effective radii (m), per contact.
    pub radius: &'a [f64],
    /// History slots per contact (the law's `HISTORY.len()`).
    pub slots: usize,
    /// Per-contact history, `n × slots`, read and updated in place.
    pub history: &'a mut [f64],
    /// Output: the normal force on each contact (N), positive when repulsive.
    pub force: &'a mut [f64],
}

impl Contact {
    /// The force (N) a batch call `batch` gives this one contact, its `history` (the law's
    /// slots) updated in place: what a single-contact call of a batch-only interface is.
    pub fn force_through<E>(
        self,
        history: &mut [f64],
        batch: impl FnOnce(NormalBatch<'_>) -> Result<(), E>,
    ) -> Result<f64, E> {
        let mut out = [0.0];
        batch(NormalBatch {
            delta: &[self.delta],
            rate: &[self.rate],
            mass: &[self.mass],
            radius: &[self.radius],
            slots: history.len(),
            history,
            force: &mut out,
        })?;
        Ok(out[0])
    }
}

impl NormalBatch<'_> {
    /// `force[i]` and contact i's energy from `f(contact i, its history)` for every contact:
    /// the loop of a batch call with energy outputs; whether every contact reported one.
    #[inline(always)]
    pub fn each_energy(
        self,
        mut out: EnergyBatch<'_>,
        mut f: impl FnMut(Contact, &mut [f64]) -> (f64, Option<Energy>),
    ) -> bool {
        let slots = self.slots;
        let mut all = true;
        for i in 0..self.force.len() {
            let (o, e) = f(self.contact(i), history_mut(self.history, slots, i));
            self.force[i] = o;
            all &= out.set(i, e);
        }
        all
    }

    /// The lengths of the batch's arrays, as the ABI checks them.
    pub(crate) fn lengths(&self) -> crate::lengths::BatchLengths<4> {
        crate::lengths::BatchLengths {
            call: "force_batch",
            inputs: "delta, rate, mass, radius",
            lens: [
                self.delta.len(),
                self.rate.len(),
                self.mass.len(),
                self.radius.len(),
            ],
            output: "force",
            n: self.force.len(),
            slots: self.slots,
            history: self.history.len(),
            context: 0,
        }
    }

    /// Contact `i` of the batch.
    #[inline(always)]
    pub fn contact(&self, i: usize) -> Contact {
        Contact {
            delta: self.delta[i],
            rate: self.rate[i],
            mass: self.mass[i],
            radius: self.radius[i],
        }
    }
}

impl NormalContext {
    /// The default context ([`NormalContext::hertzian`]) of normal contact `c`, on which the
    /// law's force is `force` (N).
    #[inline(always)]
    pub fn default_for(c: &Contact, force: f64) -> NormalContext {
        NormalContext::hertzian(c.radius, c.delta, force)
    }
}

/// A contact law bound to a material pair: the normal force on the hot path.
///
/// Everything that depends only on the materials and the parameters is computed at
/// [`ContactLaw::bind`]; the contact's own effective mass and radius arrive with each call, so a
/// polydisperse packing needs one binding per pair of materials, not per pair of sizes.
///
/// Sign convention: δ ≥ 0 is the overlap (m), δ̇ its rate (m/s, > 0 while approaching), and the
/// returned force (N) is positive when repulsive. For δ < 0 (no contact) a law returns 0.
pub trait BoundContact: Send + Sync + 'static {
    /// The normal force (N) on contact `c`. `history` has the law's `HISTORY.len()` slots
    /// (empty for a memoryless law): read it, and write the updated value back.
    fn force(&self, c: Contact, history: &mut [f64]) -> f64;

    /// Whether [`force`](BoundContact::force) (and the energy methods) are straight-line
    /// arithmetic, with no branch on the contact's values (`max` and `min` are not branches), in
    /// a law without history (sdk 0.3). The sdk then evaluates the law eight contacts at a time,
    /// interleaved with the checks of the next contacts: straight-line code vectorises over so
    /// few contacts, and HSD's batch is ~1.5× faster than in blocks of 64. A law with branches
    /// vectorises only in a long loop and keeps the blocks of 64 (the default, `false`).
    const STRAIGHT_LINE: bool = false;

    /// `b.force[i]` for every contact of the batch (see [`NormalBatch`]; the caller guarantees
    /// the lengths). Override only if a hand-vectorised form is faster than this loop.
    #[inline(always)]
    fn force_batch(&self, b: NormalBatch<'_>) {
        let n = b.force.len();
        if b.slots == 0 {
            for i in 0..n {
                let c = Contact {
                    delta: b.delta[i],
                    rate: b.rate[i],
                    mass: b.mass[i],
                    radius: b.radius[i],
                };
                b.force[i] = self.force(c, &mut []);
            }
        } else {
            for (i, h) in b.history.chunks_exact_mut(b.slots).take(n).enumerate() {
                let c = Contact {
                    delta: b.delta[i],
                    rate: b.rate[i],
                    mass: b.mass[i],
                    radius: b.radius[i],
                };
                b.force[i] = self.force(c, h);
            }
        }
    }

    /// Derived constants of the law bound to a contact of effective `mass` (kg) and `radius`
    /// (m): stiffness, damping coefficient, ...
    fn coefficients(&self, _mass: f64, _radius: f64) -> Vec<Coefficient> {
        Vec::new()
    }

    /// How far beyond touching (m, ≥ 0) the contact `c` still acts, given its `history` as the
    /// last force call left it (sdk 0.3): the contact ends once δ < −reach, and a caller keeps
    /// it (and its history) until then. An adhesive law returns its pull-off separation, which
    /// may depend on history (JKR: 0 before the first touch); the default, 0, ends the contact
    /// when the overlap does.
    fn reach(&self, _c: &Contact, _history: &[f64]) -> f64 {
        0.0
    }

    /// [`BoundContact::reach`] for every contact of a batch just evaluated (its histories as
    /// the force call left them), into `out` (one per contact, m). Override only if a
    /// hand-vectorised form is faster, with the same bits.
    #[inline(always)]
    fn reach_batch(&self, b: &NormalBatch<'_>, out: &mut [f64]) {
        for (i, x) in out.iter_mut().enumerate() {
            *x = self.reach(&b.contact(i), history_of(b.history, b.slots, i));
        }
    }

    /// What the law tells the contact's other laws (tangential, rolling, twisting, heat) about
    /// contact `c` after a force call that returned `force` (N) and left `history` (sdk 0.4):
    /// its contact radius (m), the force their caps scale with (N) and its normal damping
    /// coefficient (N·s/m), each finite and ≥ 0 ([`NormalContext`]). The default,
    /// [`NormalContext::default_for`], is the Hertzian radius √(R max(δ, 0)), max(F, 0) and no
    /// damping: a law whose contact disc, cap or damping differ (an adhesive law, a plastic
    /// law, a law with a viscous dashpot) overrides it. Hosts ask for it only when one of the
    /// contact's other laws reads it.
    fn context(&self, c: &Contact, _history: &[f64], force: f64) -> NormalContext {
        NormalContext::default_for(c, force)
    }

    /// Whether a host's call that asks for contexts (and no energy) evaluates each contact's
    /// force and context together through [`BoundContact::force_context`] (sdk 0.4), instead of
    /// the force batch and then [`BoundContact::context_batch`]: for a law whose context repeats
    /// the work of its force (a contact radius from a cube root, a damping prefactor). The
    /// results must be those of the two calls, bit for bit. Default `false`.
    const CONTEXT_WITH_FORCE: bool = false;

    /// The normal force (N) on contact `c`, `history` updated as by [`BoundContact::force`],
    /// and the contact's context after it, as [`BoundContact::context`] gives it (sdk 0.4). The
    /// default is those two calls; a law that sets [`BoundContact::CONTEXT_WITH_FORCE`]
    /// overrides it to share their work.
    #[inline(always)]
    fn force_context(&self, c: Contact, history: &mut [f64]) -> (f64, NormalContext) {
        let f = self.force(c, history);
        (f, self.context(&c, history, f))
    }

    /// [`BoundContact::force_context`] for every contact of batch `b`: its forces and
    /// histories written, each contact's context into `out` (one per contact). What a host's
    /// call asking for contexts (and no energy) runs for a law that sets
    /// [`BoundContact::CONTEXT_WITH_FORCE`]; the default loops over `force_context`. Override
    /// only if a hand-vectorised form is faster, with the same bits.
    #[inline(always)]
    fn force_context_batch(&self, b: &mut NormalBatch<'_>, out: &mut [NormalContext]) {
        let slots = b.slots;
        for (i, x) in out.iter_mut().enumerate() {
            let c = b.contact(i);
            (b.force[i], *x) = self.force_context(c, history_mut(b.history, slots, i));
        }
    }

    /// [`BoundContact::context`] for every contact of a batch just evaluated (its forces and
    /// histories as the force call left them), into `out` (one per contact). Override only if a
    /// hand-vectorised form is faster than this loop.
    fn context_batch(&self, b: &NormalBatch<'_>, out: &mut [NormalContext]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.context(&b.contact(i), history_of(b.history, b.slots, i), b.force[i]);
        }
    }

    /// The energy of contact `c` after a force call that returned `force` (N) and left
    /// `history` (sdk 0.3); `None` (the default) when the law does not account for it.
    fn energy(&self, _c: &Contact, _history: &[f64], _force: f64) -> Option<Energy> {
        None
    }

    /// The normal force (N) on contact `c`, `history` updated as by [`BoundContact::force`],
    /// with the contact's energy over the step (sdk 0.3): what a law that sees its history both
    /// before and after the step can account exactly. The default is [`BoundContact::force`]
    /// then [`BoundContact::energy`].
    #[inline(always)]
    fn force_energy(&self, c: Contact, history: &mut [f64]) -> (f64, Option<Energy>) {
        let f = self.force(c, history);
        (f, self.energy(&c, history, f))
    }

    /// [`BoundContact::force_batch`] with each contact's energy written to `out` (sdk 0.3);
    /// returns whether every contact reported one. The default loops over
    /// [`BoundContact::force_energy`]: a law that overrides `force_batch` for speed overrides
    /// this too.
    #[inline(always)]
    fn force_batch_energy(&self, b: NormalBatch<'_>, out: EnergyBatch<'_>) -> bool {
        b.each_energy(out, |c, h| self.force_energy(c, h))
    }
}

/// A restitution law bound to a pair.
pub trait BoundRestitution: Send + Sync + 'static {
    /// The coefficient of restitution r(v) (dimensionless) at normal impact speed `speed` ≥ 0 (m/s).
    fn restitution(&self, speed: f64) -> f64;

    /// `out[i] = restitution(speed[i])`; slices of equal length.
    #[inline]
    fn restitution_batch(&self, speed: &[f64], out: &mut [f64]) {
        for (o, &v) in out.iter_mut().zip(speed) {
            *o = self.restitution(v);
        }
    }
}

/// Contact `i`'s history slots of `h` (`slots` per contact; empty when there are none).
#[inline(always)]
pub(crate) fn history_mut(h: &mut [f64], slots: usize, i: usize) -> &mut [f64] {
    if slots == 0 {
        &mut []
    } else {
        &mut h[i * slots..(i + 1) * slots]
    }
}

/// Contact `i`'s history slots of `h` (`slots` per contact; empty when there are none), read
/// only.
#[inline(always)]
pub(crate) fn history_of(h: &[f64], slots: usize, i: usize) -> &[f64] {
    if slots == 0 {
        &[]
    } else {
        &h[i * slots..(i + 1) * slots]
    }
}

/// The description of a law of `kind` from its trait's constants and parameter struct
/// (`reads_context`: whether it reads the normal law's context).
pub(crate) fn law_info<P: LawParams>(
    kind: LawKind,
    [name, summary, doc]: [&str; 3],
    end_criterion: Option<EndCriterion>,
    history: &[History],
    reads_context: bool,
) -> LawInfo {
    LawInfo {
        name: name.into(),
        kind,
        summary: summary.into(),
        doc: doc.into(),
        params: P::schema(),
        end_criterion,
        history: history
            .iter()
            .map(|h| HistorySlot {
                name: h.name.into(),
                unit: h.unit.into(),
                doc: h.doc.into(),
            })
            .collect(),
        reads_context,
    }
}

/// Declares a configurable law kind: the law is its parameters ([`LawParams`]), has a name, a
/// summary and a doc, optionally checks its parameters together, and binds to what `$bind_ty`
/// describes.
macro_rules! law_trait {
    (
        $(#[$doc:meta])*
        $trait:ident: $bound:ident, $kind:expr, bind($arg:ident: $bind_ty:ty),
        end: $end:expr, history: $history:expr, reads_context: $reads:expr,
        { $($items:tt)* }
    ) => {
        $(#[$doc])*
        pub trait $trait: LawParams + Send + Sync + 'static {
            /// The law bound (may be `Self`).
            type Bound: $bound;
            /// The name users select it by.
            const NAME: &'static str;
            /// One line.
            const SUMMARY: &'static str;
            /// The formula, conventions, units and references.
            const DOC: &'static str;

            $($items)*

            /// Checks the parameters together, once each is known to lie in its range (for
            /// example that one stiffness is not below another); the default accepts them.
            fn check(&self) -> Result<(), LawError> {
                Ok(())
            }

            /// Binds the law (its parameters already checked) to what does not change from
            /// contact to contact (already validated): precompute everything that depends only
            /// on it and the parameters.
            fn bind(&self, $arg: &$bind_ty) -> Result<Self::Bound, LawError>;

            /// The law from named values, as a plugin creates it: validated against its schema,
            /// read as its struct, then checked together ([`Self::check`]).
            fn from_values(given: &[ParamValue]) -> Result<Self, LawError> {
                crate::params::configure::<Self>(Self::NAME, given, Self::check)
            }

            /// The law's description, for registries.
            fn info() -> LawInfo {
                law_info::<Self>($kind, [Self::NAME, Self::SUMMARY, Self::DOC], $end, $history, $reads)
            }
        }
    };
}
pub(crate) use law_trait;

/// Declares a law kind bound to a material pair that keeps per-contact history (none by
/// default) and may read the normal law's context: tangential, rolling, twisting and heat
/// laws.
macro_rules! history_law {
    ($(#[$doc:meta])* $trait:ident: $bound:ident, $kind:expr) => {
        law_trait!(
            $(#[$doc])*
            $trait: $bound, $kind, bind(materials: MaterialPair),
            end: None, history: Self::HISTORY, reads_context: Self::READS_CONTEXT,
            {
                /// The per-contact history the law keeps (a spring: its three displacement
                /// components; none by default).
                const HISTORY: &'static [History] = &[];

                /// Whether the law reads its contacts' `context`, what the normal law reports
                /// ([`NormalContext`](crate::NormalContext): contact radius, cap force, normal
                /// damping; sdk 0.4). Hosts compute the normal law's contexts and pass them only
                /// for a law that declares it; a law that does not (the default) sees the
                /// default context of its contact ([`NormalContext::hertzian`](crate::NormalContext::hertzian)).
                const READS_CONTEXT: bool = false;
            }
        );
    };
}
pub(crate) use history_law;

law_trait!(
    /// A configurable contact law. Declare its parameters with
    /// [`law_params!`](crate::law_params), implement this, then export with
    /// [`export_laws!`](crate::export_laws).
    ContactLaw: BoundContact, LawKind::Contact, bind(materials: MaterialPair),
    end: Some(Self::END_CRITERION), history: Self::HISTORY, reads_context: false,
    {
        /// The end-of-contact criterion the law's calibration (its `eps`, say) refers to.
        const END_CRITERION: EndCriterion;
        /// The per-contact history the law keeps (none by default).
        const HISTORY: &'static [History] = &[];

        /// Parameters that reproduce `target` for `pair` in closed form, or `Ok(None)` if the
        /// law has no closed form for it (hosts then fit numerically). `fixed` are values the
        /// user set.
        fn calibrate(
            _target: &CalibrationTarget,
            _pair: &Pair,
            _fixed: &Params,
        ) -> Result<Option<Vec<ParamValue>>, LawError> {
            Ok(None)
        }
    }
);

law_trait!(
    /// A configurable restitution law. Declare its parameters with
    /// [`law_params!`](crate::law_params), implement this, then export with
    /// [`export_laws!`](crate::export_laws) under `restitution: [...]`.
    RestitutionLaw: BoundRestitution, LawKind::Restitution, bind(pair: Pair),
    end: None, history: &[], reads_context: false,
    {}
);
