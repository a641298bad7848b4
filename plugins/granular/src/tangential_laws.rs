//! The tangential laws `gran-*`: LAMMPS's `linear_nohistory`, `linear_history`, the four
//! `mindlin` variants and the classic history springs, reading the normal law's context.

use crate::spring::{through_context, Ctx, ReadsContext, SpringStep};
use crate::tangential::{classic, linear_history, linear_nohistory, mindlin, Motion, Spring};
use dashpot_sdk::{
    BoundTangential, History, LawError, MaterialPair, Range, TangentialBatch, TangentialContact,
    TangentialLaw,
};

/// A required parameter of a law declared with `law_params!`: its value, or an error naming it.
pub(crate) fn need(v: Option<f64>, law: &str, name: &str, what: &str) -> Result<f64, LawError> {
    v.ok_or_else(|| {
        LawError::invalid_parameter(format!(
            "law '{law}' needs '{name}' ({what}): LAMMPS has no default for it"
        ))
    })
}

/// The constants of a law with a spring, a dashpot ratio and a friction coefficient: `kt`
/// (`default` when absent; required when there is none), `xt` and `mu` (required).
pub(crate) fn spring_of(
    law: &str,
    kt: Option<f64>,
    default: Option<f64>,
    unit: &str,
    xt: Option<f64>,
    mu: Option<f64>,
) -> Result<Spring, LawError> {
    Ok(Spring {
        k: need(kt.or(default), law, "kt", unit)?,
        xt: need(xt, law, "xt", "1, >= 0")?,
        mu: need(mu, law, "mu", "1, >= 0")?,
    })
}

/// The motion of tangential contact `c`.
#[inline(always)]
fn motion(c: &TangentialContact) -> Motion {
    Motion {
        n: c.normal,
        v: c.velocity,
        dt: c.dt,
    }
}

/// Implements `BoundTangential` through [`ReadsContext`].
macro_rules! spring_bound {
    ($ty:ty) => {
        through_context!(
            BoundTangential,
            $ty,
            TangentialContact,
            [f64; 3],
            force,
            force_energy
        );
    };
}

/// The common end of the tangential laws' documentation.
macro_rules! tangential_common_doc {
    () => {
        " Inputs: n̂ the unit normal from the partner to the particle, the relative velocity of \
        the contact points (m/s; the law uses its part normal to n̂, LAMMPS's v_tr = v_t − \
        (R_i ω_i + R_j ω_j) × n̂), dt (s). The tangential dashpot is η_t = x_t η_n and the \
        Coulomb cap μ F_c, with η_n and F_c (LAMMPS's damp_prefactor and Fncrit) and the \
        contact radius a from the contact's normal law (the sdk 0.4 normal context: a gran-* \
        normal law reports LAMMPS's values; another law a = √(δR), F_c = max(F_n, 0), η_n = 0). \
        Output: the tangential force on the particle (N); its torque −(R_i − δ/2) n̂ × F_t (pairs) \
        or −R_i n̂ × F_t (walls, classic pair styles) is the host's. Energy: elastic spring energy \
        (J); power (W) the energy taken from the motion and the spring per second, negative on a \
        step where LAMMPS's bookkeeping stores energy no force paid for (a growing stiffness, \
        a reset spring holding the dashpot's share, a rescaling): the law keeps LAMMPS's \
        physics and reports it. Same forces as LAMMPS 22 Jul 2025 to rounding, step by step. \
        References: LAMMPS pair_style granular documentation; Luding, Granular Matter 10, 235 \
        (2008); Thornton et al., Powder Technol. 233, 30 (2013)."
    };
}

dashpot_sdk::law_params! {
    /// LAMMPS `tangential linear_nohistory x_t μ`.
    #[derive(Debug, Clone)]
    pub struct GranLinearNoHistory {
        /// x_t: the tangential dashpot over the normal damping prefactor (required)
        pub xt: Option<f64> { unit: "1", range: Range::non_negative() },
        /// Coulomb friction coefficient μ (required)
        pub mu: Option<f64> { unit: "1", range: Range::non_negative() },
    }
}

/// `gran-linear-nohistory` bound (no stiffness: k = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearNoHistoryBound(pub Spring);

impl TangentialLaw for GranLinearNoHistory {
    type Bound = LinearNoHistoryBound;
    const NAME: &'static str = "gran-linear-nohistory";
    const READS_CONTEXT: bool = true;
    const SUMMARY: &'static str =
        "LAMMPS tangential linear_nohistory (classic gran/hooke): F_t = −min(μ F_c, x_t η_n |v_t|) v̂_t";
    const DOC: &'static str = concat!(
        "LAMMPS `tangential linear_nohistory x_t μ` (the friction of classic `gran/hooke`, with \
        x_t = gammat/gamman): a dashpot capped by Coulomb, no memory: F_t = −min(μ F_c, η_t |v_t|) \
        v_t/|v_t| (0 for v_t = 0). Parameters: xt, mu. Energy: power η_t-or-cap |v_t| (W), no \
        elastic energy.",
        tangential_common_doc!()
    );

    fn check(&self) -> Result<(), LawError> {
        self.bind(&MaterialPair {
            young: 1.0,
            shear: 1.0,
        })
        .map(|_| ())
    }

    fn bind(&self, _m: &MaterialPair) -> Result<LinearNoHistoryBound, LawError> {
        spring_of(Self::NAME, None, Some(0.0), "", self.xt, self.mu).map(LinearNoHistoryBound)
    }
}

impl ReadsContext<TangentialContact> for LinearNoHistoryBound {
    type Out = [f64; 3];
    #[inline(always)]
    fn eval(&self, x: &Ctx, c: &TangentialContact, _h: &mut [f64]) -> ([f64; 3], SpringStep) {
        let step = linear_nohistory(&self.0, x, &motion(c));
        (step.force, step)
    }
}

spring_bound!(LinearNoHistoryBound);

/// A history spring law bound: its stiffness (N/m, or N/m² for the a-scaled ones), x_t and μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringBound<const KIND: u8>(pub Spring);

/// The kinds of [`SpringBound`].
pub mod kind {
    /// `linear_history`.
    pub const LINEAR: u8 = 0;
    /// `mindlin`.
    pub const MINDLIN: u8 = 1;
    /// `mindlin_rescale`.
    pub const MINDLIN_RESCALE: u8 = 2;
    /// `mindlin/force`.
    pub const MINDLIN_FORCE: u8 = 3;
    /// `mindlin_rescale/force`.
    pub const MINDLIN_RESCALE_FORCE: u8 = 4;
    /// classic `gran/hooke/history`.
    pub const CLASSIC_HOOKE: u8 = 5;
    /// classic `gran/hertz/history`.
    pub const CLASSIC_HERTZ: u8 = 6;
    /// LAMMPS 22 Jul 2025's granular `linear_history_classic`, `mindlin_classic` and
    /// `fix wall/gran hooke/history`, `hertz/history`.
    pub const CLASSIC_GRANULAR: u8 = 7;
}

impl<const KIND: u8> SpringBound<KIND> {
    /// One step of the law on contact `c` with history `h` under context `x`.
    #[inline(always)]
    fn step(&self, x: &Ctx, c: &TangentialContact, h: &mut [f64]) -> SpringStep {
        let s = self.0;
        let m = motion(c);
        match KIND {
            kind::LINEAR => linear_history(&s, x, &m, h),
            kind::MINDLIN => mindlin::<false, false>(&s, x, &m, h),
            kind::MINDLIN_RESCALE => mindlin::<false, true>(&s, x, &m, h),
            kind::MINDLIN_FORCE => mindlin::<true, false>(&s, x, &m, h),
            kind::MINDLIN_RESCALE_FORCE => mindlin::<true, true>(&s, x, &m, h),
            kind::CLASSIC_HOOKE => classic(&s, s.k, x, &m, h, s.k),
            _ => {
                // the a-scaled classic springs keep a in slot 3 for their energy
                let a = x.contact_radius;
                let k_before = s.k * h[3];
                let spring = Spring { k: s.k * a, ..s };
                let k_reset = if KIND == kind::CLASSIC_HERTZ {
                    spring.k
                } else {
                    s.k
                };
                let out = classic(&spring, k_reset, x, &m, h, k_before);
                h[3] = a;
                out
            }
        }
    }
}

impl<const KIND: u8> ReadsContext<TangentialContact> for SpringBound<KIND> {
    type Out = [f64; 3];
    #[inline(always)]
    fn eval(&self, x: &Ctx, c: &TangentialContact, h: &mut [f64]) -> ([f64; 3], SpringStep) {
        let s = self.step(x, c, h);
        (s.force, s)
    }
}

impl<const KIND: u8> SpringBound<KIND> {
    /// The batch's forces: with the normal law's contexts on an x86-64 CPU with AVX2, four
    /// contacts at a time in explicit lanes (`tangential_avx2`, the per-contact form's bits),
    /// the last `n % 4` (all of a batch of fewer than four) one at a time, as is every contact
    /// of a batch without contexts.
    #[inline(always)]
    fn batch(&self, mut b: TangentialBatch<'_>) {
        let mut from = 0;
        #[cfg(target_arch = "x86_64")]
        if !b.context.is_empty() && b.force.len() >= 4 && dashpot_sdk::simd::available() {
            let ctx = b.context;
            // SAFETY: the CPU has AVX2 (checked just above); the lanes check the lengths
            from = unsafe { crate::tangential_avx2::lanes::<KIND>(&self.0, &mut b, ctx) };
        }
        crate::spring::each_from!(b, from, force, |c, h| self.eval(&c.context, c, h).0);
    }
}

/// Implements `BoundTangential` for a history spring: through [`ReadsContext`], the batch in
/// lanes.
macro_rules! spring_batch_bound {
    ($($kind:path),*) => {$(
        through_context!(
            BoundTangential,
            SpringBound<{ $kind }>,
            TangentialContact,
            [f64; 3],
            force,
            force_energy,
            #[inline(always)]
            fn force_batch(&self, b: TangentialBatch<'_>) {
                self.batch(b)
            }
        );
    )*};
}

spring_batch_bound!(
    kind::LINEAR,
    kind::MINDLIN,
    kind::MINDLIN_RESCALE,
    kind::MINDLIN_FORCE,
    kind::MINDLIN_RESCALE_FORCE,
    kind::CLASSIC_HOOKE,
    kind::CLASSIC_HERTZ,
    kind::CLASSIC_GRANULAR
);

/// The slots of a displacement spring and of the a it was last scaled with.
const SPRING_A: [History; 4] = [
    History::TANGENTIAL_SPRING[0],
    History::TANGENTIAL_SPRING[1],
    History::TANGENTIAL_SPRING[2],
    History::new("a_last", "m", "the contact radius at the last step"),
];

/// The slots of a force-history Mindlin spring.
const FORCE_A: [History; 4] = [
    History::new("f_x", "N", "elastic tangential force, x component"),
    History::new("f_y", "N", "elastic tangential force, y component"),
    History::new("f_z", "N", "elastic tangential force, z component"),
    History::new("a_last", "m", "the contact radius at the last step"),
];

/// Declares a history spring law: its parameters (`kt` required, or derived from the materials
/// as 8 G_eff when `$derived`), name, summary, doc, history and kind.
macro_rules! spring_law {
    ($(#[$m:meta])* $ty:ident, $kind:path, $name:literal, $kunit:literal, $kdoc:literal,
     derived: $derived:literal, history: $history:expr, summary: $summary:literal, doc: $doc:expr) => {
        dashpot_sdk::law_params! {
            $(#[$m])*
            #[derive(Debug, Clone)]
            pub struct $ty {
                #[doc = $kdoc]
                pub kt: Option<f64> { unit: $kunit, range: Range::positive() },
                /// x_t: the tangential dashpot over the normal damping prefactor (required)
                pub xt: Option<f64> { unit: "1", range: Range::non_negative() },
                /// Coulomb friction coefficient μ (required)
                pub mu: Option<f64> { unit: "1", range: Range::non_negative() },
            }
        }

        impl TangentialLaw for $ty {
            type Bound = SpringBound<{ $kind }>;
            const NAME: &'static str = $name;
            const SUMMARY: &'static str = $summary;
            const DOC: &'static str = concat!($doc, tangential_common_doc!());
            const HISTORY: &'static [History] = &$history;
            const READS_CONTEXT: bool = true;

            fn check(&self) -> Result<(), LawError> {
                let derived = $derived.then_some(1.0);
                spring_of(Self::NAME, self.kt, derived, $kunit, self.xt, self.mu).map(|_| ())
            }

            fn bind(&self, m: &MaterialPair) -> Result<Self::Bound, LawError> {
                let derived = $derived.then_some(8.0 * m.shear);
                spring_of(Self::NAME, self.kt, derived, $kunit, self.xt, self.mu).map(SpringBound)
            }
        }
    };
}

spring_law!(
    /// LAMMPS `tangential linear_history k_t x_t μ`.
    GranLinearHistory, kind::LINEAR, "gran-linear-history", "N/m",
    "tangential stiffness k_t (required)", derived: false, history: History::TANGENTIAL_SPRING,
    summary: "LAMMPS tangential linear_history: spring k_t ξ + dashpot x_t η_n, Coulomb cap μ F_c",
    doc: "LAMMPS `tangential linear_history k_t x_t μ` (Luding 2008): history ξ (m). Each step: \
        ξ is turned into the tangent plane at its length when |ξ·n̂| k_t > 10⁻¹⁰ μ F_c; \
        ξ += v_t dt; F_t = −k_t ξ − η_t v_t; if |F_t| > μ F_c: with ξ ≠ 0, F_t is scaled to \
        μ F_c and ξ = −(F_t + η_t v_t)/k_t (the spring holds the dashpot's share), with ξ = 0, \
        F_t = 0. Parameters: kt (N/m), xt, mu."
);

spring_law!(
    /// LAMMPS `tangential mindlin k x_t μ`.
    GranMindlin, kind::MINDLIN, "gran-mindlin", "N/m^2",
    "stiffness per contact radius k (the spring is k a); absent: 8 G_eff (LAMMPS's NULL)",
    derived: true, history: SPRING_A,
    summary: "LAMMPS tangential mindlin: spring k a ξ + dashpot x_t η_n, Coulomb cap μ F_c",
    doc: "LAMMPS `tangential mindlin k|NULL x_t μ` (Mindlin & Deresiewicz 1953; Thornton et \
        al. 2013): as linear_history with the stiffness k a, a the contact radius (JKR's own a \
        with jkr); k (N/m²) the parameter `kt`, or 8 G_eff from the bound materials when absent \
        (LAMMPS's NULL: 1/G_eff = 2(2 − ν1)(1 + ν1)/E1 + 2(2 − ν2)(1 + ν2)/E2; a wall of the \
        particle's material G_eff = E/(4(2 − ν)(1 + ν))). History ξ (m) and a_last (m, the a \
        of the last step, for the energy only). Parameters: kt (N/m², optional), xt, mu."
);

spring_law!(
    /// LAMMPS `tangential mindlin_rescale k x_t μ`.
    GranMindlinRescale, kind::MINDLIN_RESCALE, "gran-mindlin-rescale", "N/m^2",
    "stiffness per contact radius k (the spring is k a); absent: 8 G_eff (LAMMPS's NULL)",
    derived: true, history: SPRING_A,
    summary: "LAMMPS tangential mindlin_rescale: gran-mindlin with ξ scaled by a/a_last on unloading",
    doc: "LAMMPS `tangential mindlin_rescale k|NULL x_t μ`: gran-mindlin, with ξ first scaled \
        by a/a_last when the contact radius shrinks (a < a_last, unloading), a_last the contact \
        radius of the last step (history slot 3, as LAMMPS keeps it)."
);

spring_law!(
    /// LAMMPS `tangential mindlin/force k x_t μ`.
    GranMindlinForce, kind::MINDLIN_FORCE, "gran-mindlin-force", "N/m^2",
    "stiffness per contact radius k (the spring is k a); absent: 8 G_eff (LAMMPS's NULL)",
    derived: true, history: FORCE_A,
    summary: "LAMMPS tangential mindlin/force: incremental elastic force F_el += −k a v_t dt, cap μ F_c",
    doc: "LAMMPS `tangential mindlin/force k|NULL x_t μ`: the history is the elastic force F_el \
        (N), advanced by F_el += −k a v_t dt (after turning into the tangent plane when \
        |F_el·n̂| > 10⁻¹⁰ μ F_c); F_t = F_el − η_t v_t; past the cap F_el = F_t + η_t v_t with F_t \
        scaled to μ F_c. History F_el (N) and a_last (m, for the energy)."
);

spring_law!(
    /// LAMMPS `tangential mindlin_rescale/force k x_t μ`.
    GranMindlinRescaleForce, kind::MINDLIN_RESCALE_FORCE, "gran-mindlin-rescale-force", "N/m^2",
    "stiffness per contact radius k (the spring is k a); absent: 8 G_eff (LAMMPS's NULL)",
    derived: true, history: FORCE_A,
    summary: "LAMMPS tangential mindlin_rescale/force: gran-mindlin-force with F_el scaled by a/a_last on unloading",
    doc: "LAMMPS `tangential mindlin_rescale/force k|NULL x_t μ`: gran-mindlin-force, with F_el \
        first scaled by a/a_last when the contact radius shrinks (slot 3, as LAMMPS keeps it)."
);

spring_law!(
    /// The friction of classic `pair_style gran/hooke/history`.
    GranLinearHistoryClassic, kind::CLASSIC_HOOKE, "gran-linear-history-classic", "N/m",
    "tangential stiffness k_t (required; classic kt, 2/7 kn for NULL)", derived: false,
    history: History::TANGENTIAL_SPRING,
    summary: "classic gran/hooke/history friction: ξ += v_t dt then projected, F = −k_t ξ − x_t η_n v_t",
    doc: "The friction of LAMMPS's classic `pair_style gran/hooke/history kn kt gamman gammat \
        xmu dampflag` (with gran-hooke-mass-velocity, k = kn, damp = gamman, xt = gammat/gamman \
        or 0 when dampflag = 0, mu = xmu): ξ += v_t dt; ξ projected onto the tangent plane (not \
        rescaled); F_t = −k_t ξ − η_t v_t; past μ F_c (with ξ ≠ 0 before the projection) \
        ξ = −(F_t + η_t v_t)/k_t with F_t scaled to μ F_c. History ξ (m). Parameters: kt (N/m), \
        xt, mu."
);

spring_law!(
    /// The friction of classic `pair_style gran/hertz/history`.
    GranMindlinClassic, kind::CLASSIC_HERTZ, "gran-mindlin-classic", "N/m^2",
    "tangential stiffness per contact radius k_t (required; the spring is k_t a)", derived: false,
    history: SPRING_A,
    summary: "classic gran/hertz/history friction: as gran-linear-history-classic with the spring k_t a",
    doc: "The friction of LAMMPS's classic `pair_style gran/hertz/history kn kt gamman gammat \
        xmu dampflag` (with gran-hertz-viscoelastic, k = kn, damp = gamman, xt = gammat/gamman \
        or 0, mu = xmu; kn and kt converted from pressure units by LAMMPS, /nktv2p): as \
        gran-linear-history-classic with the spring k_t a, a = √(δR), and the reset \
        ξ = −(F_t + η_t v_t)/(k_t a). History ξ (m) and a_last (m, for the energy)."
);

spring_law!(
    /// LAMMPS 22 Jul 2025's granular `linear_history_classic` and `mindlin_classic`.
    GranWallHistoryClassic, kind::CLASSIC_GRANULAR, "gran-wall-history-classic", "N/m",
    "tangential stiffness k_t (required)", derived: false, history: SPRING_A,
    summary: "fix wall/gran hooke/history and hertz/history friction of LAMMPS 22 Jul 2025: spring k_t a, reset by k_t",
    doc: "The classic history friction as LAMMPS 22 Jul 2025 computes it in `pair_style \
        granular` (`tangential linear_history_classic`, `mindlin_classic`) and hence in `fix \
        wall/gran hooke/history` and `hertz/history`: as gran-linear-history-classic, but the \
        spring is k_t a (a = √(δR), with hooke too) and the reset past the cap divides by k_t \
        alone, ξ = −(F_t + η_t v_t)/k_t (so a slid spring holds a times the force it should). \
        The classic pair styles do not do this (gran-linear-history-classic, \
        gran-mindlin-classic); later LAMMPS releases neither. History ξ (m) and a_last (m, for \
        the energy). Parameters: kt, xt, mu."
);
