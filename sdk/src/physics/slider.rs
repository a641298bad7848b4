//! dashpot's own spring–dashpot–slider: the step its spring laws take, and its energy.

use super::{tangential_part, turn_into_plane};

/// dashpot's own spring–dashpot–slider, the one its `mindlin`, `linear-history`, `rolling-sds`,
/// `twisting-sds` and `twisting-marshall` laws take a step of: a spring k in parallel with a
/// dashpot η (a Kelvin–Voigt element) in series with a Coulomb slider of strength `cap`. Units:
/// N/m, N·s/m, N and m for a force spring (tangential, rolling); N·m/rad, N·m·s/rad, N·m and
/// rad for a twist (one component).
///
/// One step from the spring ξ_s the last step left (turned into the current tangent plane by
/// the law) with relative velocity v over a step dt:
/// 1. a stiffness that changed since the last step (Mindlin's k_t ∝ √δ) acts incrementally
///    (Mindlin & Deresiewicz): as k grows the spring keeps its force, ξ_0 = (k_before/k) ξ_s
///    (the new rim of the contact carries no traction yet); as k falls it keeps its length,
///    ξ_0 = ξ_s (the force falls with the stiffness). Either way the stored energy k |ξ_0|²/2 is
///    at most the energy the last step reported: a changing stiffness never stores energy no
///    force paid for;
/// 2. trial: ξ_t = ξ_0 + v dt, F_t = −k ξ_t − η v;
/// 3. Coulomb: if |F_t| > cap, the force is F = cap F_t/|F_t| (the trial force's direction) and
///    the element moves by the return that gives it: the spring ξ' solves
///    F = −k ξ' − (η/dt)(ξ' − ξ_0), ξ' = ((η/dt) ξ_0 − F)/(k + η/dt), the rest of v dt being the
///    slip (along −F). The dashpot acts on the spring's own rate, never on the slip, so the
///    spring holds no share of the dashpot's force (LAMMPS's reset ξ = −(F + η v)/k does: see
///    [`super::spring_friction`]). With η = 0 it is the Cundall–Strack reset ξ' = −F/k, bit for
///    bit.
///
/// The element is passive: the dashpot dissipates η |ξ'−ξ_0|²/dt, the slider cap × |slip|, and
/// the spring gives back no more than it was given. A sliding contact carries exactly `cap`
/// from its first step and the spring holds the sliding force's spring share when the slip
/// stops, so a sphere launched sliding on a plane still ends rolling at 5/7 of its launch speed.
///
/// Besides its spring, a law keeps the dashpot's share of the force it returned, F + k ξ'
/// ([`Slid::dashpot`]), so that [`Slider::energy`] books each step exactly as the bodies'
/// integrator works it: velocity Verlet applies the force of the step before and this step's
/// over the step's (half-step) velocity, −(F_before + F)·v dt/2 = the work the bodies did on the
/// contact; the power is that work less the change of the stored energy k |ξ|²/2 from what the
/// last step reported, over dt. The balance of a run then closes to the integrator's own
/// rounding, damped or not (a law that knew only its spring would have to guess the dashpot's
/// force of the step before, an error first order in the velocity's change over a step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slider {
    /// Stiffness k of this step (N/m; N·m/rad), ≥ 0.
    pub k: f64,
    /// Stiffness of the last step (N/m; N·m/rad): `k` for a constant one, 0 at first touch.
    pub k_before: f64,
    /// Dashpot η (N·s/m; N·m·s/rad), ≥ 0.
    pub eta: f64,
    /// The slider's strength: the largest force (N; N·m for a twist), ≥ 0.
    pub cap: f64,
    /// 1/dt (1/s) for the step dt > 0, 0 for a step of no length ([`Slider::rate`]).
    pub rate: f64,
    /// Time step dt (s).
    pub dt: f64,
}

/// What one step of a [`Slider`] left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slid<const N: usize> {
    /// The force on the particle (N; N·m for a twist).
    pub force: [f64; N],
    /// The spring after the step (m; rad), what the law keeps.
    pub spring: [f64; N],
    /// The dashpot's share of the force, F + k ξ' (N; N·m), what the law keeps for the next
    /// step's energy.
    pub dashpot: [f64; N],
    /// Whether the force was capped (the slider slid).
    pub sliding: bool,
}

/// a · b for vectors of any length, summed left to right (for three components, [`dot`]'s
/// order).
#[inline(always)]
fn dot_n<const N: usize>(a: [f64; N], b: [f64; N]) -> f64 {
    let mut s = a[0] * b[0];
    for i in 1..N {
        s += a[i] * b[i];
    }
    s
}

/// |f| without overflow or underflow in the squares (for a force whose |f|² is not finite).
#[cold]
fn norm_scaled<const N: usize>(f: [f64; N]) -> f64 {
    let m = f.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * f.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

impl Slider {
    /// The slider of stiffness `k` (N/m; N·m/rad) whose last step had `k_before` (`k` for a
    /// constant stiffness, 0 at first touch), dashpot `eta` (N·s/m; N·m·s/rad) and strength
    /// `cap` (N; N·m), over a step of `dt` (s).
    #[inline(always)]
    pub fn new(k: f64, k_before: f64, eta: f64, cap: f64, dt: f64) -> Slider {
        Slider {
            k,
            k_before,
            eta,
            cap,
            rate: Slider::rate(dt),
            dt,
        }
    }

    /// 1/dt (1/s), or 0 for a step of no length (dt ≤ 0 or NaN).
    #[inline(always)]
    pub fn rate(dt: f64) -> f64 {
        if dt > 0.0 {
            1.0 / dt
        } else {
            0.0
        }
    }

    /// The step from the spring `xi` the last step left (turned into the current tangent plane;
    /// a twist as `[θ]`) with relative velocity `v` (m/s, in the tangent plane; rad/s): see the
    /// type's doc.
    #[inline(always)]
    pub fn advance<const N: usize>(&self, xi: [f64; N], v: [f64; N]) -> Slid<N> {
        let (k, eta, dt) = (self.k, self.eta, self.dt);
        // 1. the incremental stiffness
        let g = if k > self.k_before { self.k_before / k } else { 1.0 };
        let mut start = [0.0; N];
        let mut spring = [0.0; N];
        let mut force = [0.0; N];
        for i in 0..N {
            start[i] = xi[i] * g;
            // 2. the trial
            spring[i] = start[i] + v[i] * dt;
            force[i] = -k * spring[i] - eta * v[i];
        }
        // 3. Coulomb, with the return of the Kelvin–Voigt element
        let f2 = dot_n(force, force);
        let (sliding, mag) = if f2.is_finite() {
            (f2 > self.cap * self.cap, f2.sqrt())
        } else {
            let m = norm_scaled(force);
            (m > self.cap, m)
        };
        if sliding {
            let s = self.cap / mag;
            let c = eta * self.rate;
            let kc = k + c;
            for i in 0..N {
                force[i] *= s;
                spring[i] = if kc > 0.0 {
                    (c * start[i] - force[i]) / kc
                } else {
                    0.0
                };
            }
        }
        let mut dashpot = [0.0; N];
        for i in 0..N {
            dashpot[i] = force[i] + k * spring[i];
        }
        Slid {
            force,
            spring,
            dashpot,
            sliding,
        }
    }

    /// The energy of step `s` from the spring `xi` and the dashpot's share `fd` the last step
    /// left (as kept, before any turning: the force F_before = −k_before ξ + f_d is what the
    /// bodies felt), the forces working against the relative velocity `w` (m/s, the contact's
    /// whole velocity over the step; rad/s): the elastic energy E = k |ξ'|²/2 (J) and the power
    /// (W), −(F_before + F)·w/2 + (E_before − E)/dt with E_before = k_before |ξ|²/2 what the last
    /// step reported. A step of no length dissipates nothing.
    #[inline(always)]
    pub fn energy<const N: usize>(
        &self,
        xi: [f64; N],
        fd: [f64; N],
        s: &Slid<N>,
        w: [f64; N],
    ) -> crate::Energy {
        let (k, kb) = (self.k, self.k_before);
        let elastic = 0.5 * k * dot_n(s.spring, s.spring);
        let before = 0.5 * kb * dot_n(xi, xi);
        let mut sum = [0.0; N];
        for i in 0..N {
            sum[i] = fd[i] - kb * xi[i] + s.force[i];
        }
        let power = (before - elastic) * self.rate - 0.5 * dot_n(sum, w);
        crate::Energy {
            power: if self.rate > 0.0 { power } else { 0.0 },
            elastic,
        }
    }

    /// The step of a contact that ended, its spring `xi` and dashpot's share `fd` (as kept)
    /// dropped: no force, nothing kept, what the spring stored dissipated ([`Slider::energy`]
    /// of a step to rest).
    #[inline(always)]
    pub fn dropped<const N: usize>(&self, xi: [f64; N], fd: [f64; N], w: [f64; N]) -> crate::Energy {
        let s = Slid {
            force: [0.0; N],
            spring: [0.0; N],
            dashpot: [0.0; N],
            sliding: true,
        };
        self.energy(xi, fd, &s, w)
    }
}

/// One call of a tangential spring law on a [`Slider`] `sl` (its stiffness, dashpot and cap for
/// contact `c`), the spring ξ in `h[..3]` (m) and the dashpot's share of the last force in
/// `fd` (N, three values the law keeps): if δ ≤ 0 the force is 0, the spring and the dashpot's
/// share dropped ([`Slider::dropped`]); otherwise ξ turned into the tangent plane
/// ([`turn_into_plane`]) takes the slider's step with the tangential velocity v − (v·n̂) n̂.
/// Returns the force (N), and the step's energy when `ENERGY` (the forces working against the
/// whole relative velocity: the force of the step before lay in that step's plane).
#[inline(always)]
pub fn slider_friction<const ENERGY: bool>(
    sl: &Slider,
    c: &crate::TangentialContact,
    h: &mut [f64],
    fd: &mut [f64],
) -> ([f64; 3], Option<crate::Energy>) {
    let (read, held) = ([h[0], h[1], h[2]], [fd[0], fd[1], fd[2]]);
    if c.delta <= 0.0 {
        h[..3].fill(0.0);
        fd[..3].fill(0.0);
        return ([0.0; 3], ENERGY.then(|| sl.dropped(read, held, c.velocity)));
    }
    let xi = turn_into_plane(read, c.normal);
    let s = sl.advance(xi, tangential_part(c.velocity, c.normal));
    h[..3].copy_from_slice(&s.spring);
    fd[..3].copy_from_slice(&s.dashpot);
    (s.force, ENERGY.then(|| sl.energy(read, held, &s, c.velocity)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The undamped slider resets as Cundall–Strack, and a stuck, damped one's dashpot share is
    /// −η v; a slider whose trial force overflows |F|² still caps it.
    #[test]
    fn resets_and_overflow() {
        let sl = Slider {
            k: 10.0,
            k_before: 10.0,
            eta: 0.0,
            cap: 1.0,
            rate: 1e3,
            dt: 1e-3,
        };
        let s = sl.advance([0.2, 0.0, 0.0], [1.0, 0.0, 0.0]);
        assert_eq!(s.force, [-1.0, 0.0, 0.0]);
        assert_eq!(s.spring, [0.1, 0.0, 0.0]);
        let damped = Slider { eta: 0.5, ..sl };
        let s = damped.advance([0.01, 0.0, 0.0], [1.0, 0.0, 0.0]);
        assert!(!s.sliding && (s.dashpot[0] + 0.5).abs() < 1e-15, "{s:?}");
        let stiff = Slider {
            k: 1e200,
            k_before: 1e200,
            ..sl
        };
        let s = stiff.advance([1e-8, 0.0, 0.0], [0.0; 3]);
        // (to rounding: |F| measured scaled, F × cap/|F|)
        let capped = (s.force[0] + 1.0).abs() <= 2.0 * f64::EPSILON && s.force[1] == 0.0 && s.force[2] == 0.0;
        assert!(s.sliding && capped, "{s:?}");
    }
}
