//! Mindlin–Deresiewicz tangential spring with Coulomb friction (no-slip stiffness of Mindlin
//! 1949, bookkeeping of LAMMPS `pair_style granular` `tangential mindlin` and Luding 2008).
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
//! 1. δ ≤ 0: no contact; the force is 0 and ξ is reset to 0.
//! 2. Rotate: ξ ← ξ − (ξ·n̂) n̂, rescaled to its previous length (the contact frame turned).
//! 3. Tangential relative velocity: v_t = v − (v·n̂) n̂.
//! 4. Advance: ξ ← ξ + v_t dt.
//! 5. Trial force: F_t = −k_t ξ − η_t v_t.
//! 6. Coulomb: if |F_t| > μ max(F_n, 0), F_t is scaled to length μ max(F_n, 0) and the spring is
//!    reset to match it, ξ = −(F_t + η_t v_t)/k_t (ξ = 0 if k_t = 0).
//!
//! Capping after advancing makes a sliding contact carry exactly μ F_n from its first step, and
//! leaves the spring holding exactly the sliding force when the slip stops, so stick starts
//! without a jump. With this order a sphere launched sliding without spin on a plane ends rolling
//! at 5/7 of its launch speed and an oblique impact in gross sliding changes the tangential
//! velocity by μ (1 + e) v_n (both tested here). There is no friction in tension (F_n ≤ 0).
//!
//! Caveat, with damping: the reset stores the dashpot's share in the spring. When
//! η_t |v_t| > μ F_n the spring then holds a force along the slip that the dashpot balances, and
//! if k_t grows faster than η_t at the next step (loading: k_t ∝ √δ, η_t ∝ δ^{1/4}) the trial
//! force can point along the slip for a few steps. This belongs to the LAMMPS/Luding
//! bookkeeping; in the tested oblique impact (ζ_t = 0.3, tan θ = 3) it costs 0.4 % of the
//! tangential impulse, and it vanishes with ζ_t = 0.
//!
//! # Parameters
//! - `mu` (1, ≥ 0, default 0.5): Coulomb friction coefficient μ;
//! - `damping` (1, ≥ 0, default 0): tangential damping ratio ζ_t.
//!
//! References: R. D. Mindlin, J. Appl. Mech. 16, 259 (1949); Mindlin & Deresiewicz, J. Appl. Mech.
//! 20, 327 (1953); S. Luding, Granular Matter 10, 235 (2008); LAMMPS `pair_style granular`.

#![warn(missing_docs)]

use dashpot_sdk::physics::{dot, spring_friction, spring_friction_energy, SliderStep};
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
        (Mindlin 1949; Luding 2008; LAMMPS pair granular 'tangential mindlin'). k_t = 8 G_eff a, \
        a = √(r_eff δ), 1/G_eff = (2 − ν1)/G1 + (2 − ν2)/G2; dashpot η_t = 2 ζ_t √(m k_t), m the \
        effective mass. History: the spring displacement ξ (m; slots xi_x, xi_y, xi_z), 0 at first \
        touch, and the stiffness k_t of the last call (N/m; slot kt, which the energy accounting reads). Conventions: normal n from the partner to the particle; velocity = relative velocity \
        of the particle's contact point w.r.t. the partner's (ω × r included; pass the velocity over \
        the step, e.g. the half-step velocity of velocity Verlet); the result is the tangential \
        force on the particle. Each call: if δ ≤ 0 the force is 0 and ξ = 0; otherwise (1) rotate \
        ξ into the tangent plane keeping its length, (2) v_t = v − (v·n) n, (3) ξ += v_t dt, \
        (4) F_t = −k_t ξ − η_t v_t, (5) if |F_t| > μ max(F_n, 0) scale F_t to μ max(F_n, 0) and \
        reset ξ = −(F_t + η_t v_t)/k_t. No friction in tension. With damping, the reset spring \
        holds the dashpot's share, and while k_t grows on loading a trial force can briefly point \
        along the slip when η_t |v_t| > μ F_n (LAMMPS's bookkeeping; ζ_t = 0 avoids it). Parameters: mu (≥ 0, default 0.5), \
        damping ζ_t (≥ 0, default 0). A sphere launched sliding on a plane ends rolling at 5/7 of \
        its launch speed; an oblique impact in gross sliding changes the tangential velocity by \
        μ (1 + e) v_n.";
    const HISTORY: &'static [History] = &{
        let [x, y, z] = History::TANGENTIAL_SPRING;
        [
            x,
            y,
            z,
            History::new(
                "kt",
                "N/m",
                "the spring's stiffness k_t at the last call (its energy's)",
            ),
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

impl BoundTangential for MindlinBound {
    #[inline]
    fn force(&self, c: &TangentialContact, history: &mut [f64]) -> [f64; 3] {
        let kt = self.stiffness(c.radius, c.delta);
        let eta = 2.0 * self.damping * (c.mass * kt).sqrt();
        let f = spring_friction(kt, eta, self.mu, c, history);
        history[3] = kt;
        f
    }

    /// The same arithmetic as [`BoundTangential::force`], contact for contact, rearranged for
    /// SIMD: lanes of `LANES` contacts are transposed into component arrays, every branch of
    /// steps 1–6 becomes a select (both sides computed, the unused one discarded), and the
    /// results are transposed back; on x86-64 CPUs with AVX2, four contacts at a time in
    /// explicit lanes (`avx2.rs`). A test checks the bits of both against the per-contact form.
    #[inline(always)]
    fn force_batch(&self, b: TangentialBatch<'_>) {
        self.batch::<false>(b, None)
    }

    /// The force with the step's energy: elastic k_t |ξ|²/2 (J); power (W): the dashpot's
    /// η_t |v_t|² while the spring holds, the slip's −F_t·v_t plus the change of the stored
    /// energy while it slides or is dropped out of contact, less the energy the growing
    /// stiffness puts into the spring at fixed ξ (k_t of the last call from the history; see
    /// [`dashpot_sdk::physics::SliderStep`]).
    #[inline]
    fn force_energy(&self, c: &TangentialContact, history: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let kt = self.stiffness(c.radius, c.delta);
        let eta = 2.0 * self.damping * (c.mass * kt).sqrt();
        let (f, e) = spring_friction_energy([history[3], kt], eta, self.mu, c, history);
        history[3] = kt;
        (f, Some(e))
    }

    /// [`BoundTangential::force_energy`] over the batch in the SIMD lanes of
    /// [`BoundTangential::force_batch`], the same bits contact for contact (a test checks).
    #[inline(always)]
    fn force_batch_energy(&self, b: TangentialBatch<'_>, out: EnergyBatch<'_>) -> bool {
        self.batch::<true>(b, Some(out));
        true
    }
}

impl MindlinBound {
    /// The batch with (`ENERGY`) or without its energy outputs, in AVX2 lanes where the CPU has
    /// them ([`dashpot_sdk::simd::available`]), else in the portable lanes.
    #[inline(always)]
    fn batch<const ENERGY: bool>(&self, b: TangentialBatch<'_>, out: Option<EnergyBatch<'_>>) {
        // the host checks every batch against the law's declared slots (four: ξ, k_t); a caller
        // that does not is told so through the trampoline's panic catch
        assert_eq!(b.slots, SLOTS, "mindlin keeps 4 history slots per contact");
        let damped = self.damping != 0.0;
        #[cfg(target_arch = "x86_64")]
        if dashpot_sdk::simd::available() {
            // SAFETY: the CPU has AVX2 (checked just above); the slots were checked.
            return unsafe {
                if damped {
                    avx2::lanes::<true, ENERGY>(self, b, out)
                } else {
                    avx2::lanes::<false, ENERGY>(self, b, out)
                }
            };
        }
        if damped {
            lanes::<true, ENERGY>(self, b, out)
        } else {
            lanes::<false, ENERGY>(self, b, out)
        }
    }
}

/// Contacts per SIMD lane group.
const LANES: usize = 8;

/// History slots per contact: ξ (3), k_t.
const SLOTS: usize = 4;

/// [`spring_friction`] over a batch, `LANES` contacts at a time, branch-free (`DAMPED`: whether
/// η_t ≠ 0 needs computing; `ENERGY`: whether to write each contact's energy to `out`, as
/// [`spring_friction_energy`] computes it).
#[inline(always)]
fn lanes<const DAMPED: bool, const ENERGY: bool>(
    law: &MindlinBound,
    b: TangentialBatch<'_>,
    mut out: Option<EnergyBatch<'_>>,
) {
    let n = b.force.len();
    let (mu, two_zeta, dt) = (law.mu, 2.0 * law.damping, b.dt);
    let mut lo = 0;
    while lo < n {
        let m = LANES.min(n - lo);
        // transpose in (idle lanes: a harmless contact out of touch)
        let mut nv = [[0.0f64; LANES]; 3];
        let mut kprev = [0.0f64; LANES];
        let mut know = [0.0f64; LANES];
        let mut v = [[0.0f64; LANES]; 3];
        let mut h = [[0.0f64; LANES]; 3];
        let (mut d, mut r, mut ms, mut fnorm) = ([0.0; LANES], [1.0; LANES], [1.0; LANES], [0.0; LANES]);
        for l in 0..m {
            let i = lo + l;
            for k in 0..3 {
                nv[k][l] = b.normal[i][k];
                v[k][l] = b.velocity[i][k];
                h[k][l] = b.history[SLOTS * i + k];
            }
            if ENERGY {
                kprev[l] = b.history[SLOTS * i + 3];
            }
            d[l] = b.delta[i];
            r[l] = b.radius[i];
            ms[l] = b.mass[i];
            fnorm[l] = b.normal_force[i];
        }
        let mut f = [[0.0f64; LANES]; 3];
        let (mut power, mut elastic) = ([0.0f64; LANES], [0.0f64; LANES]);
        for l in 0..LANES {
            let kt = law.stiffness(r[l], d[l]);
            know[l] = kt;
            let eta = if DAMPED {
                two_zeta * (ms[l] * kt).sqrt()
            } else {
                0.0
            };
            let n3 = [nv[0][l], nv[1][l], nv[2][l]];
            let x0 = [h[0][l], h[1][l], h[2][l]];
            // 1. rotate into the tangent plane, keeping the length
            let xn = dot(x0, n3);
            let len2 = dot(x0, x0);
            let p = [x0[0] - xn * n3[0], x0[1] - xn * n3[1], x0[2] - xn * n3[2]];
            let plen2 = dot(p, p);
            let s = if plen2 > 0.0 { (len2 / plen2).sqrt() } else { 0.0 };
            let rot = xn != 0.0;
            let mut xi = [0.0; 3];
            for k in 0..3 {
                xi[k] = if rot { p[k] * s } else { x0[k] };
            }
            let turned = xi;
            // 2.–4. tangential velocity, advance, trial force
            let v3 = [v[0][l], v[1][l], v[2][l]];
            let vn = dot(v3, n3);
            let mut vt = [0.0; 3];
            let mut ft = [0.0; 3];
            for k in 0..3 {
                vt[k] = v3[k] - vn * n3[k];
                xi[k] += vt[k] * dt;
                ft[k] = -kt * xi[k] - eta * vt[k];
            }
            // 5. Coulomb cap, the spring reset to the capped force
            let cap = mu * fnorm[l].max(0.0);
            let f2 = dot(ft, ft);
            let slide = f2 > cap * cap;
            let sc = cap / f2.sqrt();
            let touching = d[l] > 0.0;
            for k in 0..3 {
                let fs = ft[k] * sc;
                let xs = if kt > 0.0 { -(fs + eta * vt[k]) / kt } else { 0.0 };
                let (fk, xk) = if slide { (fs, xs) } else { (ft[k], xi[k]) };
                // 6. out of touch: no force, the spring dropped
                f[k][l] = if touching { fk } else { 0.0 };
                h[k][l] = if touching { xk } else { 0.0 };
            }
            if ENERGY {
                // spring_friction_energy's SliderStep, from the spring the step started from
                let step = SliderStep {
                    k: kt,
                    k_before: kprev[l],
                    eta,
                    eta_held: eta,
                    xi_before: if touching { turned } else { x0 },
                    dt,
                };
                let (f3, x3) = ([f[0][l], f[1][l], f[2][l]], [h[0][l], h[1][l], h[2][l]]);
                let e = step.energy(slide || !touching, x3, vt, f3);
                (power[l], elastic[l]) = (e.power, e.elastic);
            }
        }
        // transpose out
        for l in 0..m {
            let i = lo + l;
            for k in 0..3 {
                b.force[i][k] = f[k][l];
                b.history[SLOTS * i + k] = h[k][l];
            }
            b.history[SLOTS * i + 3] = know[l];
        }
        if let (true, Some(o)) = (ENERGY, out.as_mut()) {
            o.put(lo, &power[..m], &elastic[..m]);
        }
        lo += m;
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2;

dashpot_sdk::export_laws!(tangential: [Mindlin]);

#[cfg(test)]
mod tests;
