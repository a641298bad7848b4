//! Cundall–Strack tangential spring with Coulomb friction: a constant stiffness k_t and a history
//! spring (Cundall & Strack, Géotechnique 29, 47, 1979; bookkeeping of LAMMPS `pair_style
//! granular` `tangential linear_history` and Luding 2008).
//!
//! # Formula
//! Per contact of overlap δ (m) and effective mass m (kg):
//!
//! - stiffness k_t (N/m), the parameter `kt`, the same for every contact;
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
//!    reset to match it, ξ = −(F_t + η_t v_t)/k_t.
//!
//! Capping after advancing makes a sliding contact carry exactly μ F_n from its first step, and
//! leaves the spring holding exactly the sliding force when the slip stops, so stick starts
//! without a jump. With this order a sphere launched sliding without spin on a plane ends rolling
//! at 5/7 of its launch speed and an oblique impact in gross sliding changes the tangential
//! velocity by μ (1 + e) v_n (both tested here). There is no friction in tension (F_n ≤ 0). With
//! damping the reset spring holds the dashpot's share −η_t v_t/k_t; with a constant k_t the next
//! trial force can only turn along the slip if the slip speed drops by more than μ F_n/η_t in
//! one step (not so with Mindlin's growing k_t, see the `mindlin` law).
//!
//! # Parameters
//! - `kt` (N/m, > 0, default 1e5, illustrative): tangential stiffness k_t;
//! - `mu` (1, ≥ 0, default 0.5): Coulomb friction coefficient μ;
//! - `damping` (1, ≥ 0, default 0): tangential damping ratio ζ_t.
//!
//! References: P. A. Cundall & O. D. L. Strack, Géotechnique 29, 47 (1979); S. Luding, Granular
//! Matter 10, 235 (2008); LAMMPS `pair_style granular`.

#![warn(missing_docs)]

use dashpot_sdk::physics::{spring_slider_energy, tangential_part};
use dashpot_sdk::{
    BoundTangential, Energy, History, LawError, MaterialPair, ParamSpec, Params, Range, TangentialContact,
    TangentialLaw,
};

/// The configured law: stiffness `kt` (N/m), friction coefficient `mu`, damping ratio `damping`.
#[derive(Debug, Clone)]
pub struct LinearHistory {
    kt: f64,
    mu: f64,
    damping: f64,
}

impl LinearHistory {
    /// The law with stiffness `kt` > 0 (N/m), friction coefficient `mu` ≥ 0 and damping ratio
    /// `damping` ≥ 0.
    pub fn with(kt: f64, mu: f64, damping: f64) -> LinearHistory {
        LinearHistory { kt, mu, damping }
    }
}

/// The law bound to a pair of materials (which it does not use).
#[derive(Debug, Clone)]
pub struct LinearHistoryBound {
    /// Tangential stiffness k_t (N/m).
    pub kt: f64,
    /// Coulomb friction coefficient μ.
    pub mu: f64,
    /// Damping ratio ζ_t: η_t = 2 ζ_t √(m k_t).
    pub damping: f64,
}

impl TangentialLaw for LinearHistory {
    type Bound = LinearHistoryBound;
    const NAME: &'static str = "linear-history";
    const SUMMARY: &'static str =
        "Cundall–Strack tangential spring of constant k_t with history, Coulomb cap μ F_n, optional damping";
    const DOC: &'static str = "Cundall–Strack tangential spring with Coulomb friction (Cundall & Strack \
        1979; Luding 2008; LAMMPS pair granular 'tangential linear_history'). Constant stiffness \
        k_t; dashpot η_t = 2 ζ_t √(m k_t), m the effective mass. History: the spring displacement ξ \
        (m; slots xi_x, xi_y, xi_z), 0 at first touch. Conventions: normal n from the partner to \
        the particle; velocity = relative velocity of the particle's contact point w.r.t. the \
        partner's (ω × r included; pass the velocity over the step, e.g. the half-step velocity of \
        velocity Verlet); the result is the tangential force on the particle. Each call: if δ ≤ 0 \
        the force is 0 and ξ = 0; otherwise (1) rotate ξ into the tangent plane keeping its length, \
        (2) v_t = v − (v·n) n, (3) ξ += v_t dt, (4) F_t = −k_t ξ − η_t v_t, (5) if \
        |F_t| > μ max(F_n, 0) scale F_t to μ max(F_n, 0) and reset ξ = −(F_t + η_t v_t)/k_t. No \
        friction in tension. Parameters: kt (N/m, > 0, default 1e5, illustrative), mu (≥ 0, \
        default 0.5), damping ζ_t (≥ 0, default 0). A sphere launched sliding on a plane ends \
        rolling at 5/7 of its launch speed; an oblique impact in gross sliding changes the \
        tangential velocity by μ (1 + e) v_n.";
    const HISTORY: &'static [History] = &[
        History::new("xi_x", "m", "tangential spring displacement ξ, x component"),
        History::new("xi_y", "m", "tangential spring displacement ξ, y component"),
        History::new("xi_z", "m", "tangential spring displacement ξ, z component"),
    ];

    fn params() -> Vec<ParamSpec> {
        vec![
            ParamSpec::new(
                "kt",
                "N/m",
                1.0e5,
                Range::positive(),
                "tangential stiffness k_t; the default is illustrative, not a material value",
            ),
            ParamSpec::new(
                "mu",
                "1",
                0.5,
                Range::non_negative(),
                "Coulomb friction coefficient μ",
            ),
            ParamSpec::new(
                "damping",
                "1",
                0.0,
                Range::non_negative(),
                "tangential damping ratio ζ_t: η_t = 2 ζ_t √(m k_t)",
            ),
        ]
    }

    fn new(p: &Params) -> Result<Self, LawError> {
        Ok(LinearHistory {
            kt: p.get("kt")?,
            mu: p.get("mu")?,
            damping: p.get("damping")?,
        })
    }

    fn bind(&self, _materials: &MaterialPair) -> Result<LinearHistoryBound, LawError> {
        Ok(LinearHistoryBound {
            kt: self.kt,
            mu: self.mu,
            damping: self.damping,
        })
    }
}

impl BoundTangential for LinearHistoryBound {
    #[inline]
    fn force(&self, c: &TangentialContact, history: &mut [f64]) -> [f64; 3] {
        let eta = 2.0 * self.damping * (c.mass * self.kt).sqrt();
        spring_friction(self.kt, eta, self.mu, c, history)
    }

    /// Elastic ½ k_t |ξ|² (J); power: η_t |v_t|² while the spring holds, −F_t·v_t while it
    /// slides (W); 0 out of contact.
    fn energy(&self, c: &TangentialContact, history: &[f64], force: [f64; 3]) -> Option<Energy> {
        if c.delta <= 0.0 {
            return Some(Energy::default());
        }
        let eta = 2.0 * self.damping * (c.mass * self.kt).sqrt();
        Some(spring_slider_energy(
            self.kt,
            eta,
            self.mu * c.normal_force.max(0.0),
            [history[0], history[1], history[2]],
            tangential_part(c.velocity, c.normal),
            force,
        ))
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Steps 1–6 of the crate docs for a spring of stiffness `kt` (N/m) and dashpot `eta` (N·s/m).
#[inline(always)]
fn spring_friction(kt: f64, eta: f64, mu: f64, c: &TangentialContact, h: &mut [f64]) -> [f64; 3] {
    if c.delta <= 0.0 {
        h[..3].fill(0.0);
        return [0.0; 3];
    }
    let n = c.normal;
    let mut xi = [h[0], h[1], h[2]];
    // Rotate into the current tangent plane, keeping the length.
    let xn = dot(xi, n);
    if xn != 0.0 {
        let len2 = dot(xi, xi);
        let p = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
        let plen2 = dot(p, p);
        let s = if plen2 > 0.0 { (len2 / plen2).sqrt() } else { 0.0 };
        xi = [p[0] * s, p[1] * s, p[2] * s];
    }
    // Tangential relative velocity, advance, trial force.
    let vn = dot(c.velocity, n);
    let vt = [
        c.velocity[0] - vn * n[0],
        c.velocity[1] - vn * n[1],
        c.velocity[2] - vn * n[2],
    ];
    let mut f = [0.0; 3];
    for i in 0..3 {
        xi[i] += vt[i] * c.dt;
        f[i] = -kt * xi[i] - eta * vt[i];
    }
    // Coulomb cap, with the spring reset to the capped force.
    let cap = mu * c.normal_force.max(0.0);
    let f2 = dot(f, f);
    if f2 > cap * cap {
        let s = cap / f2.sqrt();
        for i in 0..3 {
            f[i] *= s;
            xi[i] = if kt > 0.0 { -(f[i] + eta * vt[i]) / kt } else { 0.0 };
        }
    }
    h[..3].copy_from_slice(&xi);
    f
}

dashpot_sdk::export_laws!(tangential: [LinearHistory]);

#[cfg(test)]
mod tests {
    use super::*;
    use dashpot_sdk::ParamValue;
    use std::f64::consts::PI;

    const G: f64 = 9.81;

    fn law(kt: f64, mu: f64, damping: f64) -> LinearHistoryBound {
        let p = Params::resolve(
            LinearHistory::NAME,
            &LinearHistory::params(),
            &[
                ParamValue::new("kt", kt),
                ParamValue::new("mu", mu),
                ParamValue::new("damping", damping),
            ],
        )
        .unwrap();
        LinearHistory::new(&p)
            .unwrap()
            .bind(&MaterialPair::of_moduli(1e9, 0.3, None).unwrap())
            .unwrap()
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn norm(a: [f64; 3]) -> f64 {
        dot(a, a).sqrt()
    }

    /// A solid sphere (mass m, radius R, I = 2/5 m R²) on the rigid plane z = 0.
    #[derive(Debug, Clone, Copy)]
    struct Sphere {
        m: f64,
        r: f64,
        x: [f64; 3],
        v: [f64; 3],
        w: [f64; 3],
    }

    /// What one accepted step produced.
    struct Step {
        t: f64,
        f_t: [f64; 3],
        f_n: f64,
        /// Velocity of the contact point the law saw (half step).
        slip: [f64; 3],
    }

    /// Translational and rotational velocity Verlet, gravity `g` along −z, normal force
    /// `normal(δ)` (δ = R − z), the tangential law called once per step with the half-step
    /// velocities of the contact point and the end-of-step normal force; history kept.
    /// `each` sees every step and returns false to stop.
    fn run(
        law: &impl BoundTangential,
        mut s: Sphere,
        g: f64,
        dt: f64,
        normal: &mut dyn FnMut(f64) -> f64,
        each: &mut dyn FnMut(&Sphere, &Step) -> bool,
    ) -> Sphere {
        let n = [0.0, 0.0, 1.0];
        let arm = [0.0, 0.0, -s.r]; // centre → contact point, −R n̂
        let inertia = 0.4 * s.m * s.r * s.r;
        let mut h = [0.0; 3];
        let mut a = [0.0, 0.0, normal(s.r - s.x[2]) / s.m - g];
        let mut alpha = [0.0; 3];
        for i in 1.. {
            let mut vh = [0.0; 3];
            let mut wh = [0.0; 3];
            for k in 0..3 {
                vh[k] = s.v[k] + 0.5 * dt * a[k];
                wh[k] = s.w[k] + 0.5 * dt * alpha[k];
                s.x[k] += dt * vh[k];
            }
            let delta = s.r - s.x[2];
            let f_n = normal(delta);
            let wxr = cross(wh, arm);
            let c = TangentialContact {
                normal: n,
                velocity: [vh[0] + wxr[0], vh[1] + wxr[1], vh[2] + wxr[2]],
                normal_force: f_n,
                delta,
                mass: s.m,
                radius: s.r,
                dt,
            };
            let f_t = law.force(&c, &mut h);
            let torque = cross(arm, f_t);
            for k in 0..3 {
                a[k] = (f_n * n[k] + f_t[k]) / s.m;
                alpha[k] = torque[k] / inertia;
            }
            a[2] -= g;
            for k in 0..3 {
                s.v[k] = vh[k] + 0.5 * dt * a[k];
                s.w[k] = wh[k] + 0.5 * dt * alpha[k];
            }
            let step = Step {
                t: i as f64 * dt,
                f_t,
                f_n,
                slip: c.velocity,
            };
            if !each(&s, &step) {
                break;
            }
        }
        s
    }

    /// A glass-like sphere, R = 1 cm, ρ = 2500 kg/m³.
    fn sphere(v: [f64; 3], z: f64) -> Sphere {
        let r: f64 = 0.01;
        Sphere {
            m: 4.0 / 3.0 * PI * r.powi(3) * 2500.0,
            r,
            x: [0.0, 0.0, z],
            v,
            w: [0.0; 3],
        }
    }

    /// Launches the sphere sliding at 1 m/s, 30° from x, pressed on the plane by a constant
    /// normal force m g (overlap fixed at 1 µm); returns (final speed / launch speed, time-averaged speed over the
    /// last 20 ms / launch speed, final slip / launch speed, and the time the Coulomb cap first
    /// released (the end of the sliding phase) over its prediction 2v0/(7μg) − η_t/k_t: the
    /// slip falls at (7/2) μ g until the dashpot's −η_t Δv_t per step outweighs the spring's
    /// k_t v_t dt, i.e. at v_t = η_t (7/2) μ g / k_t).
    fn slide(kt: f64, mu: f64, damping: f64) -> (f64, f64, f64, f64) {
        let b = law(kt, mu, damping);
        let s0 = sphere([0.0; 3], 0.0);
        let (weight, delta0) = (s0.m * G, 1e-6);
        let v0 = 1.0;
        let dir = [(PI / 6.0).cos(), (PI / 6.0).sin(), 0.0];
        let s0 = sphere([v0 * dir[0], v0 * dir[1], 0.0], s0.r - delta0);
        let t_slide = 2.0 * v0 / (7.0 * mu * G);
        let t_end = t_slide + 0.06;
        let dt = 1e-5;
        let kt = b.kt;
        let t_release = t_slide - 2.0 * damping * (s0.m * kt).sqrt() / kt;
        let (mut t_slide_end, mut sum, mut count) = (f64::NAN, 0.0, 0);
        let s = run(&b, s0, G, dt, &mut |_| weight, &mut |s, st| {
            let cap = mu * st.f_n.max(0.0);
            assert!(
                norm(st.f_t) <= cap * (1.0 + 1e-12),
                "Coulomb cap broken at t = {}",
                st.t
            );
            // The velocity stays along the launch direction, friction against it.
            assert!(norm(cross(s.v, dir)) < 1e-12 * v0);
            let (f, u) = (norm(st.f_t), norm(st.slip));
            if t_slide_end.is_nan() && f >= cap * (1.0 - 1e-9) {
                // Sliding: friction at the cap, exactly against the slip of the contact point.
                assert!(dot(st.f_t, st.slip) <= -(1.0 - 1e-9) * f * u, "t = {}", st.t);
            }
            if t_slide_end.is_nan() && st.t > 0.1 * t_slide && norm(st.f_t) < cap * (1.0 - 1e-9) {
                t_slide_end = st.t;
            }
            if st.t > t_end - 0.02 {
                sum += norm(s.v);
                count += 1;
            }
            st.t < t_end
        });
        let wxr = cross(s.w, [0.0, 0.0, -s.r]);
        let slip = norm([s.v[0] + wxr[0], s.v[1] + wxr[1], 0.0]);
        (
            norm(s.v) / v0,
            sum / count as f64 / v0,
            slip / v0,
            t_slide_end / t_release,
        )
    }

    #[test]
    fn sliding_sphere_ends_rolling_at_five_sevenths() {
        for (kt, mu, damping) in [(1e5, 0.3, 0.5), (1e5, 0.1, 0.5), (1e6, 0.6, 0.3), (3e3, 0.3, 1.0)] {
            let (v, _, slip, t) = slide(kt, mu, damping);
            println!(
                "k_t = {kt:.0e} N/m, μ = {mu}, ζ_t = {damping}: v/v0 − 5/7 = {:.1e}, slip/v0 = {slip:.1e}, \
                 sliding ends at {t:.5} × prediction",
                v - 5.0 / 7.0
            );
            assert!((v - 5.0 / 7.0).abs() < 1e-3, "v/v0 = {v}");
            assert!(slip < 1e-3, "still slipping: {slip}");
            assert!((t - 1.0).abs() < 1e-3, "sliding ends at {t} × prediction");
        }
    }

    #[test]
    fn undamped_sliding_sphere_rolls_at_five_sevenths_on_average() {
        // No dashpot: the stuck spring keeps oscillating; the mean speed is 5/7.
        let (v, mean, _, t) = slide(1e5, 0.3, 0.0);
        println!(
            "ζ_t = 0: final v/v0 − 5/7 = {:.1e}, mean over the last 20 ms − 5/7 = {:.1e}, sliding ends at {t:.5} × prediction",
            v - 5.0 / 7.0,
            mean - 5.0 / 7.0
        );
        assert!((mean - 5.0 / 7.0).abs() < 1e-3, "mean v/v0 = {mean}");
        assert!((t - 1.0).abs() < 1e-3, "sliding ends at {t} × prediction");
    }

    /// A sphere hits the plane at normal speed `vn` and tangential speed `vt`, without spin or
    /// gravity, on a bilinear normal spring (loading k1, unloading k2 ≥ k1: e = √(k1/k2), never
    /// attractive). Returns (Δv_t, ω_y, e) measured when the sphere leaves the plane.
    fn oblique(b: &LinearHistoryBound, k1: f64, k2: f64, vn: f64, vt: f64, strict: bool) -> (f64, f64, f64) {
        let s0 = sphere([vt, 0.0, -vn], 0.01);
        let mut dmax = 0.0f64;
        let dt = 1e-3 * (s0.m / k2).sqrt();
        let s = run(
            b,
            s0,
            0.0,
            dt,
            &mut |d| {
                dmax = dmax.max(d);
                if d <= 0.0 {
                    0.0
                } else {
                    (k1 * dmax - k2 * (dmax - d)).max(0.0)
                }
            },
            &mut |s, st| {
                assert!(norm(st.f_t) <= b.mu * st.f_n.max(0.0) * (1.0 + 1e-12));
                if strict && st.f_n > 0.0 {
                    // Gross sliding: the cap is reached at every step in contact, against the slip.
                    assert!(
                        (norm(st.f_t) / (b.mu * st.f_n) - 1.0).abs() < 1e-12,
                        "sticking at {}",
                        st.t
                    );
                    assert!(st.f_t[0] < 0.0 && st.f_t[1] == 0.0);
                }
                s.x[2] < s.r || s.v[2] < 0.0
            },
        );
        (vt - s.v[0], s.w[1], s.v[2] / vn)
    }

    #[test]
    fn oblique_impact_in_gross_sliding_matches_the_closed_form() {
        let mu = 0.2;
        // tan θ = 3 > (7/2) μ (1 + e) = 1.4: gross sliding throughout.
        let (vn, vt) = (1.0, 3.0);
        // Gross sliding from the first step needs k_t v_t > μ k_n v_n (the spring's first
        // stretch against the normal spring's first compression).
        for (damping, k1, k2) in [(0.0, 1e6, 1e6), (0.0, 1e6, 4e6), (0.3, 1e6, 4e6)] {
            let b = law(1e6, mu, damping);
            let (dvt, w, e) = oblique(&b, k1, k2, vn, vt, true);
            let want = mu * (1.0 + e) * vn;
            let r = 0.01;
            println!(
                "ζ_t = {damping}, k2/k1 = {}: e = {e:.8}, Δv_t = {dvt:.8} vs μ(1+e)v_n = {want:.8}, \
                 ω = {w:.6} vs {:.6} rad/s",
                k2 / k1,
                2.5 * want / r
            );
            assert!(((e - (k1 / k2).sqrt()) / e).abs() < 1e-4, "e = {e}");
            let tol = 1e-6;
            assert!((dvt / want - 1.0).abs() < tol, "Δv_t = {dvt}, want {want}");
            assert!((w / (2.5 * want / r) - 1.0).abs() < tol, "ω = {w}");
        }
    }

    fn contact(normal: [f64; 3], velocity: [f64; 3], delta: f64, dt: f64) -> TangentialContact {
        TangentialContact {
            normal,
            velocity,
            normal_force: 1e3,
            delta,
            mass: 0.01,
            radius: 0.01,
            dt,
        }
    }

    #[test]
    fn spring_rotation_preserves_its_length() {
        let b = law(1e5, 0.5, 0.0);
        let xi0 = [2e-6, -1e-6, 0.0];
        for theta in [0.01f64, 0.3, 1.2] {
            let n = [theta.sin() * 0.6, theta.sin() * 0.8, theta.cos()];
            let mut h = xi0;
            // dt = 0 and no velocity: the call only rotates the spring.
            let f = b.force(&contact(n, [0.3, 0.1, 0.2], 1e-6, 0.0), &mut h);
            assert!(
                (norm(h) / norm(xi0) - 1.0).abs() < 1e-14,
                "|ξ| changed: {}",
                norm(h)
            );
            assert!(dot(h, n).abs() < 1e-15 * norm(xi0), "ξ·n = {}", dot(h, n));
            let kt = b.kt;
            for k in 0..3 {
                assert!((f[k] + kt * h[k]).abs() < 1e-12 * kt * norm(xi0));
            }
        }
    }

    #[test]
    fn spring_and_dashpot_oppose_the_slip_and_no_friction_in_tension() {
        let (b0, b1) = (law(1e5, 0.5, 0.0), law(1e5, 0.5, 0.7));
        let n = [0.0, 0.0, 1.0];
        let (delta, dt) = (1e-6, 1e-6);
        let kt = b0.kt;
        // The normal part of the velocity is ignored; the first step stretches ξ by v_t dt.
        let v = [0.2, 0.0, -5.0];
        let mut h = [0.0; 3];
        let f = b0.force(&contact(n, v, delta, dt), &mut h);
        assert_eq!(h, [0.2 * dt, 0.0, 0.0]);
        assert!((f[0] + kt * 0.2 * dt).abs() < 1e-15 && f[1] == 0.0 && f[2] == 0.0);
        let mut h = [0.0; 3];
        let f = b1.force(&contact(n, v, delta, dt), &mut h);
        let eta = 2.0 * 0.7 * (0.01 * kt).sqrt();
        assert!((f[0] + kt * 0.2 * dt + eta * 0.2).abs() < 1e-12 * f[0].abs());
        // Tension: no friction, the spring keeps only the dashpot's share (zero without one).
        let mut c = contact(n, v, delta, dt);
        c.normal_force = -1.0;
        let mut h = [1e-6, 0.0, 0.0];
        assert_eq!(b0.force(&c, &mut h), [0.0; 3]);
        assert_eq!(h, [0.0; 3]);
        // Sliding: the spring is reset so that −k_t ξ − η v_t is the capped force.
        let mut c = contact(n, [1.0, 0.0, 0.0], delta, 1e-3);
        c.normal_force = 1e-3;
        let mut h = [0.0; 3];
        let f = b1.force(&c, &mut h);
        assert!((norm(f) - 0.5e-3).abs() < 1e-15 && f[0] < 0.0);
        assert!((-kt * h[0] - eta * 1.0 - f[0]).abs() < 1e-12 * eta);
    }

    #[test]
    fn history_resets_out_of_contact() {
        let b = law(1e5, 0.5, 0.2);
        for delta in [0.0, -1e-9] {
            let mut h = [1e-6, 2e-6, -3e-7];
            assert_eq!(
                b.force(&contact([0.0, 0.0, 1.0], [1.0, 2.0, 0.0], delta, 1e-6), &mut h),
                [0.0; 3]
            );
            assert_eq!(h, [0.0; 3]);
        }
    }

    #[test]
    fn schema_and_history_slots() {
        let info = LinearHistory::info();
        assert_eq!(info.history.len(), 3);
        assert!(info.history.iter().all(|h| h.unit == "m"));
        let schema = LinearHistory::params();
        let p = Params::resolve(LinearHistory::NAME, &schema, &[]).unwrap();
        assert_eq!(
            (
                p.get("kt").unwrap(),
                p.get("mu").unwrap(),
                p.get("damping").unwrap()
            ),
            (1e5, 0.5, 0.0)
        );
        for bad in [("kt", 0.0), ("mu", -0.1), ("damping", -1.0)] {
            assert!(Params::resolve(LinearHistory::NAME, &schema, &[ParamValue::new(bad.0, bad.1)]).is_err());
        }
    }
}
