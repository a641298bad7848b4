//! Spring–dashpot–slider rolling resistance with the semantics of LAMMPS `rolling sds`.

use dashpot_sdk::physics::{dot, SliderStep};
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
    const DOC: &'static str = "Spring–dashpot–slider rolling resistance with the semantics of LAMMPS \
        `pair_style granular ... rolling sds k_roll gamma_roll mu_roll` (Luding 2008; Wang et al. 2015, \
        Particuology 23, 49). Inputs: unit normal n̂ (from the partner to the particle), rolling velocity \
        v_roll = R_eff (ω_i − ω_j) × n̂ (m/s), the normal force F_n (N), the step dt (s). History: the rolling \
        displacement ξ (m; slots xi_x, xi_y, xi_z), 0 at first touch. Each call: (1) if |ξ·n̂| k > 10⁻¹⁰ μ|F_n|, \
        ξ is projected into the tangent plane and rescaled to its former length; (2) ξ += v_roll dt; (3) \
        F_r = −k ξ − γ v_roll (N); (4) if |F_r| > μ|F_n|: when ξ ≠ 0, ξ = −(μ|F_n| F_r/|F_r| + γ v_roll)/k and \
        F_r is scaled to length μ|F_n|; when ξ = 0, F_r = 0. The torque on the particle is R_eff n̂ × F_r (N·m), \
        on the partner its opposite; F_r itself is not applied to the centres. Parameters: k (N/m), gamma \
        (N·s/m), mu (dimensionless). Energy: elastic = k|ξ|²/2 (J); power (W) = γ|v_roll|² while the spring holds, −F_r·v_roll plus the \
        change of the stored energy while it slides.";
    const HISTORY: &'static [History] = &[
        History::new("xi_x", "m", "rolling displacement ξ, x component"),
        History::new("xi_y", "m", "rolling displacement ξ, y component"),
        History::new("xi_z", "m", "rolling displacement ξ, z component"),
    ];

    fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> {
        Ok(self.clone())
    }
}

impl RollingSds {
    /// [`BoundRolling::force`], whether the force was capped (the spring slid), and the spring
    /// the step started from, turned into the tangent plane.
    #[inline]
    fn step(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], bool, [f64; 3]) {
        let n = c.normal;
        let fcrit = self.mu * c.normal_force.abs();
        let mut xi = [h[0], h[1], h[2]];
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
        let turned = xi;
        for (x, v) in xi.iter_mut().zip(c.velocity) {
            *x += v * c.dt;
        }
        let mut f = [0.0; 3];
        for k in 0..3 {
            f[k] = -self.k * xi[k] - self.gamma * c.velocity[k];
        }
        let mag = dot(f, f).sqrt();
        let capped = mag > fcrit;
        if capped {
            if dot(xi, xi) != 0.0 {
                for k in 0..3 {
                    xi[k] = -(fcrit * f[k] / mag + self.gamma * c.velocity[k]) / self.k;
                    f[k] *= fcrit / mag;
                }
            } else {
                f = [0.0; 3];
            }
        }
        h[..3].copy_from_slice(&xi);
        (f, capped, turned)
    }

    /// The step's energy ([`SliderStep::energy`]) from the spring it started from (turned into
    /// the tangent plane), the spring `xi` it left, the rolling velocity `v` and the force `f`.
    #[inline(always)]
    fn energy_of(
        &self,
        before: [f64; 3],
        capped: bool,
        xi: [f64; 3],
        v: [f64; 3],
        f: [f64; 3],
        dt: f64,
    ) -> Energy {
        let step = SliderStep {
            k: self.k,
            k_before: self.k,
            eta: self.gamma,
            eta_held: self.gamma,
            xi_before: before,
            dt,
        };
        step.energy(capped, xi, v, f)
    }
}

impl BoundRolling for RollingSds {
    #[inline]
    fn force(&self, c: &RollingContact, h: &mut [f64]) -> [f64; 3] {
        self.step(c, h).0
    }

    /// The same arithmetic as [`BoundRolling::force`], contact for contact, rearranged for SIMD:
    /// lanes of `LANES` contacts are transposed into component arrays, each branch becomes a
    /// select (both sides computed, the unused one discarded), and the results are transposed
    /// back; on x86-64 CPUs with AVX2, four contacts at a time in explicit lanes (`avx2.rs`).
    /// A test checks the bits of both against the per-contact form.
    #[inline(always)]
    fn force_batch(&self, b: RollingBatch<'_>) {
        self.batch::<false>(b, None)
    }

    /// The force with the step's energy: elastic k |ξ|²/2 (J); power (W): γ |v_roll|² while the
    /// spring holds, −F_r·v_roll plus the change of the stored energy while it slides (see
    /// [`SliderStep`]).
    #[inline]
    fn force_energy(&self, c: &RollingContact, h: &mut [f64]) -> ([f64; 3], Option<Energy>) {
        let (f, capped, before) = self.step(c, h);
        let e = self.energy_of(before, capped, [h[0], h[1], h[2]], c.velocity, f, c.dt);
        (f, Some(e))
    }

    /// [`BoundRolling::force_energy`] over the batch in the SIMD lanes of
    /// [`BoundRolling::force_batch`], the same bits contact for contact (a test checks).
    #[inline(always)]
    fn force_batch_energy(&self, b: RollingBatch<'_>, out: EnergyBatch<'_>) -> bool {
        self.batch::<true>(b, Some(out));
        true
    }
}

impl RollingSds {
    /// The batch with (`ENERGY`) or without its energy outputs, in AVX2 lanes where the CPU has
    /// them ([`dashpot_sdk::simd::available`]), else in the portable lanes.
    #[inline(always)]
    fn batch<const ENERGY: bool>(&self, b: RollingBatch<'_>, out: Option<EnergyBatch<'_>>) {
        // the host checks every batch against the law's declared slots (three: ξ)
        assert_eq!(b.slots, 3, "rolling-sds keeps 3 history slots per contact");
        #[cfg(target_arch = "x86_64")]
        if dashpot_sdk::simd::available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::lanes::<ENERGY>(self, b, out) };
        }
        lanes::<ENERGY>(self, b, out)
    }
}

/// Contacts per SIMD lane group.
const LANES: usize = 8;

/// Up to `LANES` vectors as three component arrays (idle lanes 0).
#[inline(always)]
fn columns<'a>(v: impl Iterator<Item = &'a [f64]>) -> [[f64; LANES]; 3] {
    let mut c = [[0.0; LANES]; 3];
    for (l, x) in v.enumerate() {
        for q in 0..3 {
            c[q][l] = x[q];
        }
    }
    c
}

/// [`BoundRolling::force`] over a batch, `LANES` contacts at a time, branch-free; with
/// `ENERGY`, each contact's energy to `out` as [`BoundRolling::force_energy`] computes it.
#[inline(always)]
fn lanes<const ENERGY: bool>(law: &RollingSds, b: RollingBatch<'_>, mut out: Option<EnergyBatch<'_>>) {
    let n = b.force.len();
    let (k, gamma, mu, dt) = (law.k, law.gamma, law.mu, b.dt);
    let mut lo = 0;
    while lo < n {
        let m = LANES.min(n - lo);
        // transpose in (idle lanes: a contact at rest with no normal force)
        let nv = columns(b.normal[lo..lo + m].iter().map(|x| &x[..]));
        let v = columns(b.velocity[lo..lo + m].iter().map(|x| &x[..]));
        let mut h = columns(b.history[3 * lo..3 * (lo + m)].chunks_exact(3));
        let mut fnorm = [0.0f64; LANES];
        fnorm[..m].copy_from_slice(&b.normal_force[lo..lo + m]);
        let mut f = [[0.0f64; LANES]; 3];
        let (mut power, mut elastic) = ([0.0f64; LANES], [0.0f64; LANES]);
        for l in 0..LANES {
            let n3 = [nv[0][l], nv[1][l], nv[2][l]];
            let v3 = [v[0][l], v[1][l], v[2][l]];
            let x0 = [h[0][l], h[1][l], h[2][l]];
            let fcrit = mu * fnorm[l].abs();
            // (1) the frame update: projected into the tangent plane, rescaled to its length
            let xn = dot(x0, n3);
            let rot = xn.abs() * k > FRAME_EPS * fcrit;
            let len = dot(x0, x0).sqrt();
            let p = [x0[0] - xn * n3[0], x0[1] - xn * n3[1], x0[2] - xn * n3[2]];
            let prj = dot(p, p).sqrt();
            let s = if prj > 0.0 { len / prj } else { 0.0 };
            // (2) advance, (3) trial force
            let mut xi = [0.0; 3];
            let mut ft = [0.0; 3];
            for q in 0..3 {
                xi[q] = if rot { p[q] * s } else { x0[q] };
            }
            let turned = xi;
            for q in 0..3 {
                xi[q] += v3[q] * dt;
                ft[q] = -k * xi[q] - gamma * v3[q];
            }
            // (4) the cap: the spring reset to the capped force, or no force from a zero spring
            let mag = dot(ft, ft).sqrt();
            let capped = mag > fcrit;
            let spring = dot(xi, xi) != 0.0;
            for q in 0..3 {
                let xs = -(fcrit * ft[q] / mag + gamma * v3[q]) / k;
                let fs = ft[q] * (fcrit / mag);
                let (fo, xo) = match (capped, spring) {
                    (true, true) => (fs, xs),
                    (true, false) => (0.0, xi[q]),
                    _ => (ft[q], xi[q]),
                };
                f[q][l] = fo;
                h[q][l] = xo;
            }
            if ENERGY {
                let (f3, x3) = ([f[0][l], f[1][l], f[2][l]], [h[0][l], h[1][l], h[2][l]]);
                let e = law.energy_of(turned, capped, x3, v3, f3, dt);
                (power[l], elastic[l]) = (e.power, e.elastic);
            }
        }
        // transpose out
        for l in 0..m {
            let i = lo + l;
            b.force[i] = [f[0][l], f[1][l], f[2][l]];
            b.history[3 * i..3 * i + 3].copy_from_slice(&[h[0][l], h[1][l], h[2][l]]);
        }
        if let (true, Some(o)) = (ENERGY, out.as_mut()) {
            o.put(lo, &power[..m], &elastic[..m]);
        }
        lo += m;
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2;

dashpot_sdk::export_laws!(rolling: [RollingSds]);

#[cfg(test)]
mod tests {
    use super::*;

    /// The batch gives the per-contact form's bits on every path (a fresh spring, one to rotate
    /// into the tangent plane, one held, one capped with and without a spring), on every batch
    /// length (whole and partial lane groups and blocks, a remainder through the per-contact
    /// form), through the dispatch (AVX2 where the CPU has it) and through the portable lanes;
    /// with its energy outputs too.
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
                    0.01 * (t - 5.0),
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
                3,
                |c, h| law.force(c, h),
                |b| law.force_batch(b),
                &what,
            );
            dashpot_testkit::batch_is_per_contact(
                &contacts,
                &hist,
                3,
                |c, h| law.force(c, h),
                |b| lanes::<false>(&law, b, None),
                &format!("{what} (portable lanes)"),
            );
            for portable in [false, true] {
                dashpot_testkit::batch_energy_is_per_contact(
                    &contacts,
                    &hist,
                    3,
                    |c, h| law.force_energy(c, h),
                    |b, e| {
                        if portable {
                            lanes::<true>(&law, b, Some(e));
                            true
                        } else {
                            law.force_batch_energy(b, e)
                        }
                    },
                    &format!("{what} with energy (portable lanes: {portable})"),
                );
            }
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
}
