//! The rolling and twisting laws `gran-rolling-sds`, `gran-twisting-sds` and
//! `gran-twisting-marshall`, reading the normal law's context.

use crate::rotation::{marshall_twist, rolling_sds, Sds, Twist};
use crate::spring::{through_context, Ctx, ReadsContext, SpringStep};
use crate::tangential::{Motion, Spring};
use crate::tangential_laws::{need, spring_of};
use dashpot_sdk::{
    BoundRolling, BoundTwisting, History, LawError, MaterialPair, Range, RollingBatch, RollingContact,
    RollingLaw, TwistingBatch, TwistingContact, TwistingLaw,
};

/// The common end of the rolling and twisting laws' documentation.
macro_rules! rotation_common_doc {
    () => {
        " The cap F_c (N, LAMMPS's Fncrit) and, for marshall, the contact radius a and the normal \
        damping prefactor η_n come from the contact's normal law (the sdk 0.4 normal context; \
        a law reporting none: F_c = max(F_n, 0), a = √(δR), η_n = 0). Energy: elastic spring \
        energy (J); power (W) the energy taken from the motion and the spring per second. Same \
        torques as LAMMPS 22 Jul 2025 to rounding, step by step. References: LAMMPS pair_style \
        granular documentation; Luding, Granular Matter 10, 235 (2008); Wang et al., \
        Particuology 23, 49 (2015); Marshall, J. Comput. Phys. 228, 1541 (2009)."
    };
}

/// `k`, `gamma`, `mu` of an sds law, each required (`units`: each one's unit and range).
fn sds(
    name: &str,
    k: Option<f64>,
    gamma: Option<f64>,
    mu: Option<f64>,
    units: [&str; 3],
) -> Result<Sds, LawError> {
    Ok(Sds {
        k: need(k, name, "k", units[0])?,
        gamma: need(gamma, name, "gamma", units[1])?,
        mu: need(mu, name, "mu", units[2])?,
    })
}

/// Declares a spring–dashpot–slider law of LAMMPS (`rolling sds`, `twisting sds`): its
/// parameters `k`, `gamma`, `mu` (each required, with its unit and doc), name, summary, doc,
/// history, and its bound type made from the [`Sds`] constants by `$make`.
macro_rules! sds_law {
    ($(#[$m:meta])* $ty:ident: $trait:ident, $name:literal,
     k: $ku:literal $kd:literal, gamma: $gu:literal $gd:literal, mu: $mu:literal $md:literal,
     bound: $bound:ty = $make:expr, history: $history:expr, summary: $summary:literal, doc: $doc:literal) => {
        dashpot_sdk::law_params! {
            $(#[$m])*
            #[derive(Debug, Clone)]
            pub struct $ty {
                #[doc = $kd]
                pub k: Option<f64> { unit: $ku, range: Range::positive() },
                #[doc = $gd]
                pub gamma: Option<f64> { unit: $gu, range: Range::non_negative() },
                #[doc = $md]
                pub mu: Option<f64> { unit: $mu, range: Range::non_negative() },
            }
        }

        impl $ty {
            fn sds(&self) -> Result<Sds, LawError> {
                let units = [concat!($ku, ", > 0"), concat!($gu, ", >= 0"), concat!($mu, ", >= 0")];
                sds(<Self as $trait>::NAME, self.k, self.gamma, self.mu, units)
            }
        }

        impl $trait for $ty {
            type Bound = $bound;
            const NAME: &'static str = $name;
            const SUMMARY: &'static str = $summary;
            const DOC: &'static str = concat!($doc, rotation_common_doc!());
            const HISTORY: &'static [History] = &$history;
            const READS_CONTEXT: bool = true;

            fn check(&self) -> Result<(), LawError> {
                self.sds().map(|_| ())
            }

            fn bind(&self, _m: &MaterialPair) -> Result<$bound, LawError> {
                self.sds().map($make)
            }
        }
    };
}

sds_law!(
    /// LAMMPS `rolling sds k γ μ`.
    GranRollingSds: RollingLaw, "gran-rolling-sds",
    k: "N/m" "rolling stiffness k_roll (required)",
    gamma: "N*s/m" "rolling damping γ_roll (required)",
    mu: "1" "rolling friction coefficient μ_roll (required)",
    bound: Sds = |s| s,
    history: [
        History::new("xi_x", "m", "rolling displacement ξ_r, x component"),
        History::new("xi_y", "m", "rolling displacement ξ_r, y component"),
        History::new("xi_z", "m", "rolling displacement ξ_r, z component"),
    ],
    summary: "LAMMPS rolling sds: F_r = −k ξ_r − γ v_roll, |F_r| ≤ μ F_c, torque R n̂ × F_r",
    doc: "LAMMPS `rolling sds k γ μ` (Luding 2008; Wang et al. 2015): the rolling velocity \
        v_roll = R (ω_i − ω_j) × n̂ (m/s) advances a spring ξ_r (m): ξ_r is turned into the \
        tangent plane at its length when |ξ_r·n̂| k > 10⁻¹⁰ μ F_c; ξ_r += v_roll dt; \
        F_r = −k ξ_r − γ v_roll; if |F_r| > μ F_c: with ξ_r ≠ 0, ξ_r = −(μ F_c F_r/|F_r| + \
        γ v_roll)/k and F_r scaled to μ F_c, with ξ_r = 0, F_r = 0. The torque on the particle \
        is R n̂ × F_r (N·m), on the partner its opposite; F_r is not applied to the centres. \
        Parameters: k (N/m), gamma (N·s/m), mu."
);

sds_law!(
    /// LAMMPS `twisting sds k γ μ`.
    GranTwistingSds: TwistingLaw, "gran-twisting-sds",
    k: "N*m/rad" "twisting stiffness k_twist (required)",
    gamma: "N*m*s/rad" "twisting damping γ_twist (required)",
    mu: "m" "twisting friction coefficient μ_twist (required): the critical torque is μ F_c",
    bound: TwistSdsBound = |s| TwistSdsBound(Twist { k: s.k, damp: s.gamma, mu: s.mu }),
    history: [History::new("theta", "rad", "twist angle θ")],
    summary: "LAMMPS twisting sds: M = −k θ − γ ω_t, |M| ≤ μ F_c",
    doc: "LAMMPS `twisting sds k γ μ` (Luding 2008): the twist rate ω_t = (ω_i − ω_j)·n̂ (rad/s) \
        advances an angle θ (rad): θ += ω_t dt; M = −k θ − γ ω_t (N·m, about n̂ on the particle); \
        if |M| > μ F_c: θ = (μ F_c sgn ω_t − γ ω_t)/k and M = −μ F_c sgn ω_t. History θ (rad). \
        Parameters: k (N·m/rad), gamma (N·m·s/rad), mu (m)."
);

/// `gran-twisting-sds` bound.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwistSdsBound(pub Twist);

impl ReadsContext<RollingContact> for Sds {
    type Out = [f64; 3];
    #[inline(always)]
    fn eval(&self, x: &Ctx, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], SpringStep) {
        let m = Motion {
            n: c.normal,
            v: c.velocity,
            dt: c.dt,
        };
        let s = rolling_sds(self, x.cap_force, &m, h);
        (s.force, s)
    }
}

through_context!(
    BoundRolling,
    Sds,
    RollingContact,
    [f64; 3],
    force,
    force_energy,
    /// With the normal law's contexts on an x86-64 CPU with AVX2, four contacts at a time in
    /// explicit lanes (`rotation_avx2`, the per-contact form's bits), the last `n % 4` one at a
    /// time; without them, every contact one at a time.
    #[inline(always)]
    fn force_batch(&self, mut b: RollingBatch<'_>) {
        let mut from = 0;
        #[cfg(target_arch = "x86_64")]
        if !b.context.is_empty() && b.force.len() >= 4 && dashpot_sdk::simd::available() {
            let ctx = b.context;
            // SAFETY: the CPU has AVX2 (checked just above); the lanes check the lengths
            from = unsafe { crate::rotation_avx2::rolling_sds(self, &mut b, ctx) };
        }
        crate::spring::each_from!(b, from, force, |c, h| self.eval(&c.context, c, h).0);
    }
);

impl ReadsContext<TwistingContact> for TwistSdsBound {
    type Out = f64;
    #[inline(always)]
    fn eval(&self, x: &Ctx, c: &TwistingContact, h: &mut [f64]) -> (f64, SpringStep) {
        self.0.step(x.cap_force, c.rate, c.dt, &mut h[0], self.0.k)
    }
}

through_context!(
    BoundTwisting,
    TwistSdsBound,
    TwistingContact,
    f64,
    torque,
    torque_energy
);

dashpot_sdk::law_params! {
    /// LAMMPS `twisting marshall`, with the tangential model's constants.
    #[derive(Debug, Clone)]
    pub struct GranTwistingMarshall {
        /// the tangential model's stiffness as LAMMPS keeps it (N/m for linear_history, N/m² for mindlin); absent: 8 G_eff (mindlin NULL)
        pub kt: Option<f64> { unit: "N/m or N/m^2", range: Range::positive() },
        /// the tangential model's x_t (required)
        pub xt: Option<f64> { unit: "1", range: Range::non_negative() },
        /// the tangential model's friction coefficient μ (required)
        pub mu: Option<f64> { unit: "1", range: Range::non_negative() },
    }
}

/// `gran-twisting-marshall` bound: the tangential model's k_t, x_t and μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarshallBound(pub Spring);

impl TwistingLaw for GranTwistingMarshall {
    type Bound = MarshallBound;
    const NAME: &'static str = "gran-twisting-marshall";
    const READS_CONTEXT: bool = true;
    const SUMMARY: &'static str =
        "LAMMPS twisting marshall: k = k_t a²/2, γ = x_t η_n a²/2, M_c = (2/3) μ a F_c from the tangential model";
    const DOC: &'static str = concat!(
        "LAMMPS `twisting marshall` (Marshall 2009, eqs. 30–34): a twisting spring–dashpot–slider \
        whose constants follow the tangential model and the contact radius a at each step: \
        k = k_t a²/2 (k_t as LAMMPS keeps it: N/m for linear_history, N/m² for the mindlin \
        variants, so that k is then k a²/2 of the per-radius stiffness, as in LAMMPS), \
        γ = x_t η_n a²/2, M_c = (2/3) μ a F_c; then as gran-twisting-sds: θ += ω_t dt, \
        M = −k θ − γ ω_t, past M_c θ = (M_c sgn ω_t − γ ω_t)/k and M = −M_c sgn ω_t. Parameters: \
        the tangential model's kt (absent: 8 G_eff, LAMMPS's mindlin NULL), xt and mu, which a \
        translation of LAMMPS's syntax copies. History θ (rad) and a_last (m, for the energy).",
        rotation_common_doc!()
    );
    const HISTORY: &'static [History] = &[
        History::new("theta", "rad", "twist angle θ"),
        History::new("a_last", "m", "the contact radius at the last step"),
    ];

    fn check(&self) -> Result<(), LawError> {
        spring_of(Self::NAME, self.kt, Some(1.0), "", self.xt, self.mu).map(|_| ())
    }

    fn bind(&self, m: &MaterialPair) -> Result<MarshallBound, LawError> {
        spring_of(Self::NAME, self.kt, Some(8.0 * m.shear), "", self.xt, self.mu).map(MarshallBound)
    }
}

impl ReadsContext<TwistingContact> for MarshallBound {
    type Out = f64;
    #[inline(always)]
    fn eval(&self, x: &Ctx, c: &TwistingContact, h: &mut [f64]) -> (f64, SpringStep) {
        let s = &self.0;
        let t = marshall_twist(s.k, s.xt, s.mu, x);
        let k_before = 0.5 * s.k * h[1] * h[1];
        let out = t.step(x.cap_force, c.rate, c.dt, &mut h[0], k_before);
        h[1] = x.contact_radius;
        out
    }
}

through_context!(
    BoundTwisting,
    MarshallBound,
    TwistingContact,
    f64,
    torque,
    torque_energy,
    /// With the normal law's contexts on an x86-64 CPU with AVX2, four contacts at a time in
    /// explicit lanes (`rotation_avx2`, the per-contact form's bits), the last `n % 4` one at a
    /// time; without them, every contact one at a time.
    #[inline(always)]
    fn torque_batch(&self, mut b: TwistingBatch<'_>) {
        let mut from = 0;
        #[cfg(target_arch = "x86_64")]
        if !b.context.is_empty() && b.torque.len() >= 4 && dashpot_sdk::simd::available() {
            let ctx = b.context;
            // SAFETY: the CPU has AVX2 (checked just above); the lanes check the lengths
            from = unsafe { crate::rotation_avx2::twisting_marshall(&self.0, &mut b, ctx) };
        }
        crate::spring::each_from!(b, from, torque, |c, h| self.eval(&c.context, c, h).0);
    }
);
