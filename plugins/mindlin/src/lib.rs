//! Mindlin–Deresiewicz tangential spring with Coulomb friction (no-slip stiffness of Mindlin
//! 1949, incremental as Mindlin & Deresiewicz 1953; the order of LAMMPS `pair_style granular`
//! `tangential mindlin` and Luding 2008, with a passive spring reset).
//!
//! # Formula
//! Per contact of overlap δ (m), effective radius r (m), effective mass m (kg), with G the
//! Mindlin effective shear modulus of the bound [`MaterialPair`]
//! (1/G = (2 − ν1)/G1 + (2 − ν2)/G2, Gi = Ei/(2(1 + νi)); a rigid wall's term drops):
//!
//! - stiffness k_t = 8 G a (N/m), contact radius a = √(r δ);
//! - dashpot η_t = 2 ζ_t √(m k_t) (N·s/m), ζ_t the parameter `damping` (relative to the
//!   contact's effective mass m, not to the tangential effective mass 2m/7 of a rolling sphere);
//! - history: the spring displacement ξ (m, 3 slots `xi_x`, `xi_y`, `xi_z`), zero at first
//!   touch.
//!
//! # Conventions
//! `normal` n̂ is the unit normal from the partner j to the particle i the force acts on;
//! `velocity` v is the velocity of i's contact point relative to j's, ω × r terms included
//! (for a sphere of radius R on a wall: v + ω × (−R n̂)); the result is the tangential force on
//! i (the partner receives its opposite). `normal_force` F_n is this step's normal force
//! (N, > 0 repulsive). To make ξ the tangential displacement of the contact points accumulated
//! over the step, pass the velocity over the step (in velocity Verlet the half-step velocity,
//! (x_{n+1} − x_n)/dt), and the normal force at the end of the step.
//!
//! # Order of one call (time step dt)
//! 1. δ ≤ 0: no contact; the force is 0 and ξ is reset to 0 (what it stored is dissipated).
//! 2. Rotate: ξ ← ξ − (ξ·n̂) n̂, rescaled to its previous length (the contact frame turned).
//! 3. Stiffness: k_t changed since the last call acts incrementally (Mindlin & Deresiewicz):
//!    as k_t grows the spring keeps its force, ξ ← (k_t,before / k_t) ξ (the new rim of the
//!    contact area carries no traction yet); as it falls the spring keeps its length (the force
//!    falls with it).
//! 4. Tangential relative velocity v_t = v − (v·n̂) n̂; advance ξ_t = ξ + v_t dt; trial force
//!    F_t = −k_t ξ_t − η_t v_t.
//! 5. Coulomb: if |F_t| > μ max(F_n, 0), F_t is scaled to length μ max(F_n, 0), and the spring
//!    is the one that force leaves in a spring ∥ dashpot element in series with the slider:
//!    ξ = ((η_t/dt) ξ_before − F_t)/(k_t + η_t/dt), the rest of v_t dt being slip
//!    ([`dashpot_sdk::physics::Slider`]); with η_t = 0 this is ξ = −F_t/k_t.
//!
//! Capping after advancing makes a sliding contact carry exactly μ F_n from its first step, and
//! leaves the spring holding the sliding force's spring share when the slip stops. With this
//! order a sphere launched sliding without spin on a plane ends rolling at 5/7 of its launch
//! speed and an oblique impact in gross sliding changes the tangential velocity by μ (1 + e) v_n
//! (both tested). There is no friction in tension (F_n ≤ 0).
//!
//! The law never does positive work on the motion it resists: neither a growing stiffness
//! (step 3) nor the dashpot (step 5: it acts on the spring's own rate, never on the slip) puts
//! energy into the spring that the motion did not. LAMMPS's `tangential mindlin` differs in both
//! (its spring keeps its length as k_t grows, and its reset ξ = −(F_t + η_t v_t)/k_t stores the
//! dashpot's share, which can turn the force along the slip: a spinning sphere hitting a wall
//! with damping can leave with more tangential and rotational energy than it came with); the
//! LAMMPS-compatible `gran-mindlin` keeps that bookkeeping.
//!
//! # Parameters
//! - `mu` (1, ≥ 0, default 0.5): Coulomb friction coefficient μ;
//! - `damping` (1, ≥ 0, default 0): tangential damping ratio ζ_t.
//!
//! References: R. D. Mindlin, J. Appl. Mech. 16, 259 (1949); Mindlin & Deresiewicz, J. Appl. Mech.
//! 20, 327 (1953); S. Luding, Granular Matter 10, 235 (2008); C. Thornton, S. J. Cummins &
//! P. W. Cleary, Powder Technol. 233, 30 (2013); LAMMPS `pair_style granular`.

#![warn(missing_docs)]

use dashpot_sdk::physics::{slider_friction, Slider};
use dashpot_sdk::{
    BoundTangential, Energy, EnergyBatch, History, LawError, MaterialPair, Range, TangentialBatch,
    TangentialContact, TangentialLaw,
};

dashpot_sdk::law_params! {
    /// The configured law: friction coefficient `mu` and damping ratio `damping`.
    #[derive(Debug, Clone)]
    pub struct Mindlin {
        /// Coulomb friction coefficient μ
        mu: f64 { unit: "1", default: 0.5, range: Range::non_negative() },
        /// tangential damping ratio ζ_t: η_t = 2 ζ_t √(m k_t)
        damping: f64 { unit: "1", default: 0.0, range: Range::non_negative() },
    }
}

impl Mindlin {
    /// The law with friction coefficient `mu` ≥ 0 and damping ratio `damping` ≥ 0.
    pub fn with(mu: f64, damping: f64) -> Mindlin {
        Mindlin { mu, damping }
    }
}

/// Mindlin's law bound to a pair of materials.
#[derive(Debug, Clone)]
pub struct MindlinBound {
    /// 8 G_eff (Pa): k_t = 8 G_eff √(r δ).
    pub eight_g: f64,
    /// Coulomb friction coefficient μ.
    pub mu: f64,
    /// Damping ratio ζ_t: η_t = 2 ζ_t √(m k_t).
    pub damping: f64,
}

impl MindlinBound {
    /// The no-slip stiffness k_t = 8 G_eff √(r δ) (N/m) at overlap `delta` (m) and effective
    /// radius `radius` (m); 0 for δ ≤ 0.
    #[inline(always)]
    pub fn stiffness(&self, radius: f64, delta: f64) -> f64 {
        self.eight_g * dashpot_sdk::physics::contact_radius(radius, delta)
    }
}

impl TangentialLaw for Mindlin {
    type Bound = MindlinBound;
    const NAME: &'static str = "mindlin";
    const SUMMARY: &'static str =
        "Mindlin–Deresiewicz tangential spring k_t = 8 G a with history, Coulomb cap μ F_n, optional damping";
    const DOC: &'static str = "Mindlin–Deresiewicz no-slip tangential spring with Coulomb friction \
        (Mindlin 1949; Mindlin & Deresiewicz 1953; Luding 2008; the order of LAMMPS pair granular \
        'tangential mindlin'). k_t = 8 G_eff a, a = √(r_eff δ), 1/G_eff = (2 − ν1)/G1 + (2 − ν2)/G2; \
        dashpot η_t = 2 ζ_t √(m k_t), m the effective mass. History: the spring displacement ξ (m; \
        slots xi_x, xi_y, xi_z), 0 at first touch, the stiffness k_t of the last call (N/m; slot \
        kt) and the dashpot's share of the last force (N; fd_x, fd_y, fd_z), which the energy books \
        read. Conventions: normal n from the partner to the particle; velocity = relative velocity \
        of the particle's contact point w.r.t. the partner's (ω × r included; pass the velocity over \
        the step, e.g. the half-step velocity of velocity Verlet); the result is the tangential \
        force on the particle. Each call: if δ ≤ 0 the force is 0 and ξ = 0; otherwise (1) rotate \
        ξ into the tangent plane keeping its length, (2) if k_t grew since the last call scale ξ by \
        k_t,before/k_t (the force is kept; incremental stiffness), (3) v_t = v − (v·n) n, \
        ξ_t = ξ + v_t dt, F_t = −k_t ξ_t − η_t v_t, (4) if |F_t| > μ max(F_n, 0) scale F_t to \
        μ max(F_n, 0) and set ξ = ((η_t/dt) ξ − F_t)/(k_t + η_t/dt) (a spring ∥ dashpot in series \
        with the slider: the dashpot acts on the spring's rate, not on the slip), else ξ = ξ_t. \
        No friction in tension. The law never does positive work on the motion it resists \
        (LAMMPS's reset ξ = −(F + η v)/k can; see gran-mindlin for LAMMPS's bookkeeping). \
        Parameters: mu (≥ 0, default 0.5), damping ζ_t (≥ 0, default 0). A sphere launched \
        sliding on a plane ends rolling at 5/7 of its launch speed; an oblique impact in gross \
        sliding changes the tangential velocity by μ (1 + e) v_n.";
    const HISTORY: &'static [History] = &{
        let [x, y, z] = History::TANGENTIAL_SPRING;
        let [fx, fy, fz] = History::DASHPOT_FORCE;
        [
            x,
            y,
            z,
            History::new(
                "kt",
                "N/m",
                "the spring's stiffness k_t at the last call (its energy's)",
            ),
            fx,
            fy,
            fz,
        ]
    };

    fn bind(&self, materials: &MaterialPair) -> Result<MindlinBound, LawError> {
        Ok(MindlinBound {
            eight_g: 8.0 * materials.shear,
            mu: self.mu,
            damping: self.damping,
        })
    }
}

impl MindlinBound {
    /// The slider of contact `c`: k_t now, `k_before` from the history, η_t, the cap μ F_n.
    #[inline(always)]
    fn slider(&self, c: &TangentialContact, k_before: f64) -> Slider {
        let kt = self.stiffness(c.radius, c.delta);
        // (as the lanes compute it: no dashpot to compute when ζ_t = 0)
        let eta = if self.damping != 0.0 {
            2.0 * self.damping * (c.mass * kt).sqrt()
        } else {
            0.0
        };
        Slider::new(kt, k_before, eta, self.mu * c.normal_force.max(0.0), c.dt)
    }

    /// One call on contact `c` (see the crate's doc), with the step's energy when `ENERGY`.
    #[inline(always)]
    fn step<const ENERGY: bool>(&self, c: &TangentialContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let sl = self.slider(c, h[3]);
        h[3] = sl.k;
        let (xi, fd) = h.split_at_mut(4);
        slider_friction::<ENERGY>(&sl, c, xi, fd)
    }
}

impl BoundTangential for MindlinBound {
    #[inline]
    fn force(&self, c: &TangentialContact, history: &mut [f64]) -> [f64; 3] {
        self.step::<false>(c, history).0
    }

    /// The same arithmetic as [`BoundTangential::force`], contact for contact, on x86-64 CPUs
    /// with AVX2 four contacts at a time in explicit lanes (`avx2.rs`; every branch a select),
    /// else one at a time. A test checks the bits of both against the per-contact form.
    #[inline(always)]
    fn force_batch(&self, b: TangentialBatch<'_>) {
        self.batch::<false>(b, None)
    }

    /// The force with the step's energy: elastic k_t |ξ|²/2 (J); power (W) as
    /// [`dashpot_sdk::physics::Slider::energy`] books it: the work of the force of the last call
    /// and this one over the step's velocity, less the change of the stored energy (the
    /// velocity Verlet balance, exactly).
    #[inline]
    fn force_energy(&self, c: &TangentialContact, history: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        self.step::<true>(c, history)
    }

    /// [`BoundTangential::force_energy`] over the batch in the lanes of
    /// [`BoundTangential::force_batch`], the same bits contact for contact (a test checks).
    #[inline(always)]
    fn force_batch_energy(&self, b: TangentialBatch<'_>, out: EnergyBatch<'_>) -> bool {
        self.batch::<true>(b, Some(out));
        true
    }
}

impl MindlinBound {
    /// The batch with (`ENERGY`) or without its energy outputs, in AVX2 lanes where the CPU has
    /// them ([`dashpot_sdk::simd::available`]), else contact by contact.
    #[inline(always)]
    fn batch<const ENERGY: bool>(&self, b: TangentialBatch<'_>, out: Option<EnergyBatch<'_>>) {
        // the host checks every batch against the law's declared slots (seven: ξ, k_t, the
        // dashpot's share); a caller that does not is told so through the trampoline's panic
        // catch
        assert_eq!(b.slots, SLOTS, "mindlin keeps 7 history slots per contact");
        #[cfg(target_arch = "x86_64")]
        if dashpot_sdk::simd::available() {
            // SAFETY: the CPU has AVX2 (checked just above); the slots were checked.
            return unsafe {
                if self.damping != 0.0 {
                    avx2::lanes::<true, ENERGY>(self, b, out)
                } else {
                    avx2::lanes::<false, ENERGY>(self, b, out)
                }
            };
        }
        let mut out = out.filter(|_| ENERGY);
        b.each_from(
            0,
            out.as_mut(),
            |c, h| self.force(c, h),
            |c, h| self.force_energy(c, h),
        );
    }
}

/// History slots per contact: ξ (3), k_t, the dashpot's share of the force (3).
const SLOTS: usize = 7;

#[cfg(target_arch = "x86_64")]
mod avx2;

dashpot_sdk::export_laws!(tangential: [Mindlin]);

#[cfg(test)]
mod tests;
