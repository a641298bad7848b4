//! Spring–dashpot–slider rolling resistance with the parameters and order of LAMMPS `rolling
//! sds`, its spring reset passive ([`dashpot_sdk::physics::Slider`]).

use dashpot_sdk::physics::{dot, Slider};
use dashpot_sdk::{
    BoundRolling, Energy, EnergyBatch, History, LawError, MaterialPair, Range, RollingBatch, RollingContact,
    RollingLaw,
};

dashpot_sdk::law_params! {
    /// The configured law.
    #[derive(Debug, Clone)]
    pub struct RollingSds {
        /// rolling stiffness k_roll
        k: f64 { unit: "N/m", default: 1e3, range: Range::positive() },
        /// rolling damping γ_roll
        gamma: f64 { unit: "N·s/m", default: 0.0, range: Range::non_negative() },
        /// rolling friction coefficient μ_roll
        mu: f64 { unit: "1", default: 0.1, range: Range::non_negative() },
    }
}

/// Relative threshold below which ξ is not rotated into the tangent plane (LAMMPS's EPSILON).
const FRAME_EPS: f64 = 1e-10;

impl RollingLaw for RollingSds {
    type Bound = RollingSds;
    const NAME: &'static str = "rolling-sds";
    const SUMMARY: &'static str =
        "Rolling spring–dashpot–slider (LAMMPS `rolling sds k gamma mu`): F_r = −k ξ − γ v_roll, |F_r| ≤ μ |F_n|";
    const DOC: &'static str = "Spring–dashpot–slider rolling resistance with the parameters and order of \
        LAMMPS `pair_style granular ... rolling sds k_roll gamma_roll mu_roll` (Luding 2008; Wang et al. \
        2015, Particuology 23, 49). Inputs: unit normal n̂ (from the partner to the particle), rolling \
        velocity v_roll = R_eff (ω_i − ω_j) × n̂ (m/s), the normal force F_n (N), the step dt (s). History: \
        the rolling displacement ξ (m; slots xi_x, xi_y, xi_z), 0 at first touch, and the dashpot's share of \
        the last force (N; fd_x, fd_y, fd_z), which the energy books read. Each call: (1) if \
        |ξ·n̂| k > 10⁻¹⁰ μ|F_n|, ξ is projected into the tangent plane and rescaled to its former length; \
        (2) ξ_t = ξ + v_roll dt, F_r = −k ξ_t − γ v_roll (N); (3) if |F_r| > μ|F_n|, F_r is scaled to \
        length μ|F_n| and ξ = ((γ/dt) ξ − F_r)/(k + γ/dt) (a spring ∥ dashpot in series with the slider: \
        the dashpot acts on the spring's rate, not on the slip), else ξ = ξ_t. The torque on the particle \
        is R_eff n̂ × F_r (N·m), on the partner its opposite; F_r itself is not applied to the centres. \
        Unlike LAMMPS's reset ξ = −(μ|F_n| F̂_r + γ v_roll)/k, the spring never holds the dashpot's share, \
        so the law never does positive work on the rolling it resists and leaves no energy in a spring \
        whose contact ends while it slides (gran-rolling-sds keeps LAMMPS's reset). Parameters: k (N/m), \
        gamma (N·s/m), mu (dimensionless). Energy: elastic = k|ξ|²/2 (J); power (W) = γ|v_roll|² while \
        the spring holds, the slip's work and the change of the stored energy while it slides.";
    const HISTORY: &'static [History] = &{
        let [fx, fy, fz] = History::DASHPOT_FORCE;
        [
            History::new("xi_x", "m", "rolling displacement ξ, x component"),
            History::new("xi_y", "m", "rolling displacement ξ, y component"),
            History::new("xi_z", "m", "rolling displacement ξ, z component"),
            fx,
            fy,
            fz,
        ]
    };

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl RollingSds {
    /// The slider of contact `c`: k, γ, the cap μ |F_n|.
    #[inline(always)]
    fn slider(&self, c: &RollingContact) -> Slider {
        Slider::new(self.k, self.k, self.gamma, self.mu * c.normal_force.abs(), c.dt)
    }

    /// The spring `xi` turned into the tangent plane of `n` keeping its length, if its normal
    /// part is worth it against the cap `fcrit` (LAMMPS's rule).
    #[inline(always)]
    fn turn(&self, mut xi: [f64; 3], n: [f64; 3], fcrit: f64) -> [f64; 3] {
        let xn = dot(xi, n);
        if xn.abs() * self.k > FRAME_EPS * fcrit {
            let len = dot(xi, xi).sqrt();
            for (x, nk) in xi.iter_mut().zip(n) {
                *x -= xn * nk;
            }
            let prj = dot(xi, xi).sqrt();
            let s = if prj > 0.0 { len / prj } else { 0.0 };
            for x in &mut xi {
                *x *= s;
            }
        }
        xi
    }

    /// One call on contact `c` (see [`RollingSds::DOC`]), with the step's energy when `ENERGY`.
    #[inline(always)]
    fn step<const ENERGY: bool>(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let sl = self.slider(c);
        let (read, fd) = ([h[0], h[1], h[2]], [h[3], h[4], h[5]]);
        let s = sl.advance(self.turn(read, c.normal, sl.cap), c.velocity);
        h[..3].copy_from_slice(&s.spring);
        h[3..6].copy_from_slice(&s.dashpot);
        (s.force, ENERGY.then(|| sl.energy(read, fd, &s, c.velocity)))
    }
}

impl BoundRolling for RollingSds {
    #[inline]
    fn force(&self, c: &RollingContact, h: &mut [f64]) -> [f64; 3] {
        self.step::<false>(c, h).0
    }

    /// The same arithmetic as [`BoundRolling::force`], contact for contact, on x86-64 CPUs with
    /// AVX2 four contacts at a time in explicit lanes (`avx2.rs`; every branch a select), else
    /// one at a time. A test checks the bits of both against the per-contact form.
    #[inline(always)]
    fn force_batch(&self, b: RollingBatch<'_>) {
        self.batch::<false>(b, None)
    }

    /// The force with the step's energy: elastic k |ξ|²/2 (J); power (W) as
    /// [`Slider::energy`] books it: the work of the force of the last call and this one over
    /// the step's rolling velocity less the change of the stored energy.
    #[inline]
    fn force_energy(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        self.step::<true>(c, h)
    }

    /// [`BoundRolling::force_energy`] over the batch in the lanes of
    /// [`BoundRolling::force_batch`], the same bits contact for contact (a test checks).
    #[inline(always)]
    fn force_batch_energy(&self, b: RollingBatch<'_>, out: EnergyBatch<'_>) -> bool {
        self.batch::<true>(b, Some(out));
        true
    }
}

impl RollingSds {
    /// The batch with (`ENERGY`) or without its energy outputs, in AVX2 lanes where the CPU has
    /// them ([`dashpot_sdk::simd::available`]), else contact by contact.
    #[inline(always)]
    fn batch<const ENERGY: bool>(&self, b: RollingBatch<'_>, out: Option<EnergyBatch<'_>>) {
        // the host checks every batch against the law's declared slots (six: ξ, the dashpot's
        // share)
        assert_eq!(b.slots, SLOTS, "rolling-sds keeps 6 history slots per contact");
        #[cfg(target_arch = "x86_64")]
        if dashpot_sdk::simd::available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::lanes::<ENERGY>(self, b, out) };
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

/// History slots per contact: ξ (3), the dashpot's share of the force (3).
const SLOTS: usize = 6;

#[cfg(target_arch = "x86_64")]
mod avx2;

dashpot_sdk::export_laws!(rolling: [RollingSds]);

#[cfg(test)]
mod tests {
    use super::*;

    /// The batch gives the per-contact form's bits on every path (a fresh spring, one to rotate
    /// into the tangent plane, one held, one capped, one whose trial force overflows |F_r|²), on
    /// every batch length (whole and partial lane groups and blocks, a remainder through the
    /// per-contact form), through the dispatch (AVX2 where the CPU has it); with its energy
    /// outputs too.
    #[test]
    fn the_batch_gives_the_per_contact_bits() {
        let law = RollingSds {
            k: 1.3e3,
            gamma: 0.07,
            mu: 0.2,
        };
        for n in [1, 3, 4, 11, 37, 70] {
            let mut normal = Vec::new();
            let mut velocity = Vec::new();
            let mut fnorm = Vec::new();
            let mut hist = Vec::new();
            for i in 0..n {
                let t = i as f64;
                let (a, b) = (0.3 * t, 0.7 + 0.2 * t);
                normal.push([a.cos() * b.sin(), a.sin() * b.sin(), b.cos()]);
                velocity.push([
                    if i % 9 == 4 { 1e170 } else { 0.01 * (t - 5.0) },
                    0.02 * t.sin(),
                    if i % 4 == 0 { 3.0 } else { 0.001 },
                ]);
                fnorm.push(if i % 11 == 7 { -0.5 } else { 0.4 + 0.1 * (t % 13.0) });
                let x = if i % 3 == 0 {
                    [0.0; 3]
                } else {
                    [1e-4 * (t % 9.0), -2e-4, 3e-5 * (t % 7.0)]
                };
                hist.extend_from_slice(&x);
                // the dashpot's share of the last force
                hist.extend_from_slice(&if i % 3 == 0 {
                    [0.0; 3]
                } else {
                    [1e-3, -2e-4 * (t % 5.0), 0.0]
                });
            }
            let contacts: Vec<RollingContact> = (0..n)
                .map(|i| RollingContact {
                    normal: normal[i],
                    velocity: velocity[i],
                    normal_force: fnorm[i],
                    delta: 1e-5,
                    mass: 1e-3,
                    radius: 2e-3,
                    context: Default::default(),
                    dt: 1e-4,
                })
                .collect();
            let what = format!("rolling-sds, {n} contacts");
            let f1 = dashpot_testkit::batch_is_per_contact(
                &contacts,
                &hist,
                6,
                |c, h| law.force(c, h),
                |b| law.force_batch(b),
                &what,
            );
            dashpot_testkit::batch_energy_is_per_contact(
                &contacts,
                &hist,
                6,
                |c, h| law.force_energy(c, h),
                |b, e| law.force_batch_energy(b, e),
                &format!("{what} with energy"),
            );
            if n >= 11 {
                let capped = (0..n)
                    .filter(|&i| {
                        (f1[i].iter().map(|x| x * x).sum::<f64>().sqrt() - law.mu * fnorm[i].abs()).abs()
                            < 1e-12
                    })
                    .count();
                assert!(
                    capped >= 2,
                    "the cases must include capped contacts ({capped} of {n})"
                );
            }
        }
    }

    /// The law never gives back more energy than the rolling put into it, and its books close
    /// ([`dashpot_sdk::testkit`]: random materials, random paths).
    #[test]
    fn never_gives_back_more_than_it_was_given() {
        for (k, gamma, mu) in [
            (1e3, 0.0, 0.1),
            (1e3, 0.05, 0.1),
            (10.0, 1.0, 0.01),
            (1e6, 0.3, 1.0),
        ] {
            dashpot_sdk::testkit::assert_dissipative_rolling(&RollingSds { k, gamma, mu });
        }
    }
}
