//! Checks a law's author runs in the law's unit tests (feature `testkit`): the law never gives
//! back more energy than the motion put into it, and, when it reports its energy, its books
//! close.
//!
//! ```toml
//! [dev-dependencies]
//! dashpot-sdk = { version = "…", features = ["testkit"] }
//! ```
//!
//! ```
//! # use dashpot_sdk::*;
//! # law_params! {
//! #     /// F = k δ.
//! #     #[derive(Clone)]
//! #     pub struct Hooke { k: f64 { unit: "N/m", default: 1e5, range: Range::positive() } }
//! # }
//! # impl ContactLaw for Hooke {
//! #     type Bound = Self;
//! #     const NAME: &'static str = "hooke";
//! #     const SUMMARY: &'static str = "Hooke";
//! #     const DOC: &'static str = "F = k δ.";
//! #     const END_CRITERION: EndCriterion = EndCriterion::Overlap;
//! #     fn bind(&self, _m: &MaterialPair) -> Result<Self, LawError> { Ok(self.clone()) }
//! # }
//! # impl BoundContact for Hooke {
//! #     fn force(&self, c: Contact, _h: &mut [f64]) -> f64 { self.k * c.delta.max(0.0) }
//! # }
//! // in a #[test]: random materials, random loading paths, every parameter set you give
//! dashpot_sdk::testkit::assert_dissipative_contact(&Hooke::from_values(&[]).unwrap());
//! ```
//!
//! Each check drives the bound law along random paths of the contact's motion, sampled
//! densely (a few thousand steps), with the inputs a host passes (the half-step velocity, the
//! overlap's rate over the step): for a contact law a loading–unloading cycle of the overlap with
//! partial unloadings; for a tangential or rolling law a relative velocity that turns, stops
//! and reverses, under a normal force and overlap that breathe (and a normal that turns), ending
//! out of contact; for a twisting law a twisting rate likewise. Along a path it sums the work
//! the motion did on the contact, W = Σ ½ (F_{k−1} + F_k)·Δx_k (what velocity Verlet hands the
//! law, to a boundary term), and
//! - **passive**: a law that reports its elastic energy E never has W − (E − E_0) < 0 beyond
//!   10⁻⁴ of Σ|F·Δx| (it never gives back more than it was given; the trapezoid's own error
//!   for a slider whose cap changes is of order 1/steps of Σ|F·Δx|, the energy a law creates
//!   of order 1); a law that reports none, or an adhesive one (whose surface energy E leaves
//!   out), ends each complete cycle with W ≥ 0 to the same tolerance;
//! - **books**: a law that reports its energy has Σ power dt = W − (E − E_0) at the end, to
//!   10⁻² of what it dissipated. A law that keeps the force of its last call books the work
//!   exactly (dashpot's spring laws do, [`crate::physics::Slider`]: to rounding); one that books
//!   a dashpot's or a plastic power at the step's end is right to first order in the step (some
//!   10⁻³ on these paths); a missing term (energy left in a spring that is dropped, a power with
//!   the wrong sign) is of order 1.
//!
//! The drivers take a closure, so that a host can run them on laws it loaded
//! ([`drive_normal`], [`drive_vector`], [`drive_twisting`]); [`random_values`] samples a law's
//! parameters across their valid ranges.

use crate::{
    BoundContact, BoundRolling, BoundTangential, BoundTwisting, Contact, ContactLaw, Energy, LawInfo,
    MaterialPair, NormalContext, ParamValue, Range, RollingLaw, TangentialLaw, TwistingContact, TwistingLaw,
    VectorContact,
};
use std::f64::consts::PI;

/// Uniform random numbers from a xorshift64* generator started at a seed: the same sequence on
/// every machine, so that a failing path can be replayed from its seed.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// The generator started at `seed` (any value; 0 is moved off the generator's fixed point).
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9e37_79b9_7f4a_7c15)
    }

    /// A number in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in [lo, hi).
    pub fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// A number in [lo, hi) uniform in its logarithm (lo, hi > 0).
    pub fn log_between(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.uniform()).exp()
    }

    /// A unit 3-vector, uniform on the sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = self.between(-1.0, 1.0);
        let (s, phi) = ((1.0 - z * z).sqrt(), self.between(0.0, 2.0 * PI));
        [s * phi.cos(), s * phi.sin(), z]
    }
}

/// A value of a parameter of range `r` and default `default` (`None`: derived), for a random
/// check: within a bounded range anywhere (its ends included when valid, now and then); within
/// an unbounded one, log-uniform over four decades about the default (or about 1), and its
/// lower end when valid one time in five (an undamped law, a frictionless one). `None` leaves
/// a derived parameter to the law one time in three.
pub fn random_value(rng: &mut Rng, r: &Range, default: Option<f64>) -> Option<f64> {
    let u = rng.uniform();
    if default.is_none() && u < 1.0 / 3.0 {
        return None;
    }
    if r.min.is_finite() && r.max.is_finite() {
        // a bounded range: its ends now and then, else anywhere inside
        if r.min_inclusive && u < 0.1 {
            return Some(r.min);
        }
        if r.max_inclusive && u > 0.9 {
            return Some(r.max);
        }
        let x = rng.between(r.min, r.max);
        return Some(if r.contains(x) { x } else { 0.5 * (r.min + r.max) });
    }
    if r.min_inclusive && r.min.is_finite() && u < 0.2 {
        return Some(r.min);
    }
    let centre = default
        .filter(|d| *d != 0.0 && d.is_finite())
        .map_or(1.0, f64::abs);
    let mut x = centre * rng.log_between(1e-2, 1e2);
    if r.max.is_finite() && r.max <= 0.0 {
        x = -x;
    }
    if r.min.is_finite() && r.min > 0.0 {
        x += r.min;
    }
    Some(if r.contains(x) { x } else { centre })
}

/// Random values of every parameter of `info` across its valid range ([`random_value`]).
pub fn random_values(rng: &mut Rng, info: &LawInfo) -> Vec<ParamValue> {
    info.params
        .iter()
        .filter_map(|p| random_value(rng, &p.range, p.default).map(|v| ParamValue::new(&p.name, v)))
        .collect()
}

/// The scales of a random contact: effective mass (kg) and radius (m), Young's modulus (Pa),
/// typical overlap (m), the Hertz normal force at that overlap (N), the contact's time scale
/// √(m/k_n) (s), the path's duration (s) and step count.
#[derive(Debug, Clone, Copy)]
pub struct Scales {
    /// Effective mass (kg).
    pub mass: f64,
    /// Effective radius (m).
    pub radius: f64,
    /// The effective Young's modulus E* of the pair (Pa).
    pub young: f64,
    /// A typical overlap δ0 (m).
    pub overlap: f64,
    /// The Hertz force (4/3) E* √R δ0^{3/2} (N).
    pub force: f64,
    /// The contact's time scale √(m/k_n), k_n = E* √(R δ0) (s).
    pub time: f64,
    /// The path's duration (s).
    pub duration: f64,
    /// Steps along the path.
    pub steps: usize,
}

impl Scales {
    /// Random scales for materials of effective Young's modulus `young` (Pa): a radius of
    /// 0.1 mm to 10 cm, a density of 1000 to 8000 kg/m³, an overlap of 10⁻⁶ to 10⁻² of the
    /// radius, a path of 0.3 to 30 contact time scales in `steps` steps.
    pub fn random(rng: &mut Rng, young: f64, steps: usize) -> Scales {
        let radius = rng.log_between(1e-4, 1e-1);
        let mass = rng.between(1000.0, 8000.0) * 4.0 / 3.0 * PI * radius.powi(3);
        let overlap = radius * rng.log_between(1e-6, 1e-2);
        let kn = young * (radius * overlap).sqrt();
        let time = (mass / kn).sqrt();
        Scales {
            mass,
            radius,
            young,
            overlap,
            force: 4.0 / 3.0 * young * radius.sqrt() * overlap.powf(1.5),
            time,
            duration: time * rng.log_between(0.3, 30.0),
            steps,
        }
    }

    /// The time step (s).
    pub fn dt(&self) -> f64 {
        self.duration / self.steps as f64
    }
}

/// What driving a law along one path gave (J).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Books {
    /// The work the motion did on the contact over the path (J).
    pub work: f64,
    /// Σ |F·Δx| over the path (J): the scale of rounding.
    pub scale: f64,
    /// The least over the path of W − (E − E_0) (J), E the elastic energy the law reported (0
    /// when it reports none): what the law holds of the work done on it; < 0 when it gave
    /// back more than it was given.
    pub least: f64,
    /// Σ power dt (J), when the law reported its energy at every step.
    pub dissipated: Option<f64>,
    /// E − E_0 at the end (J), when the law reported its energy.
    pub stored: Option<f64>,
    /// Whether the law's force was ever tensile (an adhesive contact law).
    pub adhesive: bool,
    /// Whether the path ended with the law's force at 0 (the contact over).
    pub ended: bool,
}

impl Books {
    /// Err naming the deficit when the law gave back more energy than the motion put in:
    /// W − (E − E_0) < −10⁻⁴ Σ|F·Δx| at some step for a non-adhesive law that reports E, or
    /// W < −10⁻⁴ Σ|F·Δx| at the end of a complete cycle.
    pub fn check_passive(&self) -> Result<(), String> {
        let tol = 1e-4 * self.scale;
        if self.stored.is_some() && !self.adhesive && self.least < -tol {
            return Err(format!(
                "it gave back {:.3e} J more than the motion put into it (of {:.3e} J of work done either way)",
                -self.least, self.scale
            ));
        }
        if self.ended && self.work < -tol {
            return Err(format!(
                "over a complete cycle the motion gained {:.3e} J from it (of {:.3e} J of work done either way)",
                -self.work, self.scale
            ));
        }
        Ok(())
    }

    /// Err naming the residual when the law's reported energy does not close: |W − Σ power dt −
    /// (E − E_0)| > 10⁻² Σ power dt + 10⁻⁶ Σ|F·Δx| (Ok when it reports none).
    pub fn check_closed(&self) -> Result<(), String> {
        let (Some(d), Some(e)) = (self.dissipated, self.stored) else {
            return Ok(());
        };
        let residual = self.work - d - e;
        if residual.abs() > 1e-2 * d.abs() + 1e-6 * self.scale {
            return Err(format!(
                "its books do not close: work {:.6e} J − dissipated {:.6e} J − stored {:.6e} J = {:.3e} J",
                self.work, d, e, residual
            ));
        }
        Ok(())
    }
}

/// The running sums of a path.
struct Tally {
    work: f64,
    scale: f64,
    least: f64,
    dissipated: f64,
    reported: bool,
    e0: Option<f64>,
    stored: f64,
    adhesive: bool,
}

impl Tally {
    fn new() -> Tally {
        Tally {
            work: 0.0,
            scale: 0.0,
            least: 0.0,
            dissipated: 0.0,
            reported: true,
            e0: None,
            stored: 0.0,
            adhesive: false,
        }
    }

    /// One step: the work `dw` the motion did on the contact (J), its absolute size `size`, the
    /// law's energy report and the step `dt`.
    fn step(&mut self, dw: f64, size: f64, e: Option<Energy>, dt: f64) {
        self.work += dw;
        self.scale += size;
        match e {
            Some(e) => {
                let e0 = *self.e0.get_or_insert(0.0);
                self.dissipated += e.power * dt;
                self.stored = e.elastic - e0;
            }
            None => self.reported = false,
        }
        let held = if self.reported {
            self.work - self.stored
        } else {
            self.work
        };
        self.least = self.least.min(held);
    }

    fn books(&self, ended: bool) -> Books {
        Books {
            work: self.work,
            scale: self.scale,
            least: self.least,
            dissipated: self.reported.then_some(self.dissipated),
            stored: self.reported.then_some(self.stored),
            adhesive: self.adhesive,
            ended,
        }
    }
}

/// A smooth random signal on u ∈ [0, 1]: a constant and two sinusoids of random frequency and
/// phase, each of random weight.
#[derive(Clone, Copy)]
struct Wave([f64; 7]);

impl Wave {
    fn random(rng: &mut Rng) -> Wave {
        Wave([
            rng.between(-1.0, 1.0),
            rng.between(-1.0, 1.0),
            rng.between(0.5, 3.0),
            rng.between(0.0, 2.0 * PI),
            rng.between(-1.0, 1.0),
            rng.between(3.0, 15.0),
            rng.between(0.0, 2.0 * PI),
        ])
    }

    fn at(&self, u: f64) -> f64 {
        let w = &self.0;
        w[0] + w[1] * (2.0 * PI * w[2] * u + w[3]).sin() + w[4] * (2.0 * PI * w[5] * u + w[6]).sin()
    }
}

/// Drives a contact law's step `step` (the force, N, and its energy, from the contact and its
/// history of `slots` values) along one random loading–unloading cycle of the overlap (with
/// partial unloadings) at scales `s`: from touching, δ = 0, up and down (δ ∝ sin⁴ of the path's
/// time, each wiggle a partial unloading) and back to touching by 80 % of the steps, then apart
/// to −(0.1…3) δ_max. The path touches and leaves δ = 0 flat (as the fourth power of the time),
/// so that a force that jumps there (an adhesive law's) costs the work sums nothing. The rate it
/// passes is the overlap's at the step's end (a second-order difference), as a DEM host predicts
/// it for its dashpots; a contact that ends (its force and energy back to 0 after a force) is
/// booked as a host books it, its elastic energy dissipated.
pub fn drive_normal(
    rng: &mut Rng,
    s: &Scales,
    slots: usize,
    mut step: impl FnMut(&Contact, &mut [f64]) -> (f64, Option<Energy>),
) -> Books {
    let dmax = s.overlap * rng.between(0.3, 3.0);
    let (wiggle, bumps) = (rng.between(0.0, 0.9), rng.between(2.0, 8.0).round());
    let apart = rng.between(0.1, 3.0);
    let n = s.steps;
    let dt = s.dt();
    let delta = |k: usize| {
        let u = k as f64 / n as f64;
        if u <= 0.8 {
            let v = u / 0.8;
            let hump = (PI * v).sin().powi(4);
            dmax * hump * (1.0 + wiggle * (2.0 * PI * bumps * v).sin())
        } else {
            let v = (u - 0.8) / 0.2;
            -apart * dmax * v.powi(4)
        }
    };
    let mut h = vec![0.0; slots];
    let mut t = Tally::new();
    let (mut f_prev, mut d_prev) = (0.0, delta(0));
    let (mut last, mut elastic) = (0.0, 0.0);
    for k in 1..=n {
        let d = delta(k);
        // the overlap's rate at the step's end (a host predicts it so, for its dashpots)
        let c = Contact {
            delta: d,
            rate: (3.0 * d - 4.0 * d_prev + delta(k.saturating_sub(2))) / (2.0 * dt),
            mass: s.mass,
            radius: s.radius,
        };
        let (f, e) = step(&c, &mut h);
        t.adhesive |= f < 0.0;
        let dw = 0.5 * (f_prev + f) * (d - d_prev);
        // a contact that ends (no force, nothing stored) drops what it held, as a host does
        let e = e.map(|e| match (f, e.elastic) {
            (0.0, 0.0) if f_prev != 0.0 => Energy {
                power: e.power + elastic / dt,
                elastic: 0.0,
            },
            _ => e,
        });
        elastic = e.map_or(0.0, |e| e.elastic);
        t.step(dw, dw.abs(), e, dt);
        (f_prev, d_prev, last) = (f, d, f);
    }
    t.books(last == 0.0)
}

/// The motion of a tangential or rolling contact along a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// A tangential law: the velocity of the contact points (its normal part ignored by the
    /// law), the work −F·v_t.
    Tangential,
    /// A rolling law: the rolling velocity R (ω_i − ω_j) × n̂ in the tangent plane, the work
    /// −F·v_roll.
    Rolling,
}

/// The normal, overlap and normal force of a motion path at u ∈ [0, 1], and whether the
/// contact is over (the last 5 % of the path).
struct Stage {
    axis: [f64; 3],
    n0: [f64; 3],
    turn: f64,
    breathe: f64,
    f1: f64,
    load: Wave,
    tension: f64,
}

impl Stage {
    fn random(rng: &mut Rng) -> Stage {
        Stage {
            axis: rng.direction(),
            n0: rng.direction(),
            turn: rng.between(0.0, 0.6),
            breathe: rng.between(0.0, 0.6),
            f1: rng.between(0.5, 4.0),
            load: Wave::random(rng),
            // sometimes the normal force dips into tension
            tension: if rng.uniform() < 0.25 { 1.5 } else { 0.5 },
        }
    }

    /// (n̂, δ, F_n) at u, for scales `s`.
    fn at(&self, u: f64, s: &Scales) -> ([f64; 3], f64, f64) {
        // n̂ turned about `axis` by turn·u (Rodrigues)
        let (a, n) = (self.axis, self.n0);
        let th = self.turn * u;
        let (c, sn) = (th.cos(), th.sin());
        let axn = [
            a[1] * n[2] - a[2] * n[1],
            a[2] * n[0] - a[0] * n[2],
            a[0] * n[1] - a[1] * n[0],
        ];
        let ad = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
        let mut nv = [0.0; 3];
        for i in 0..3 {
            nv[i] = n[i] * c + axn[i] * sn + a[i] * ad * (1.0 - c);
        }
        let norm = (nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]).sqrt();
        nv = nv.map(|x| x / norm);
        if u > 0.95 {
            return (nv, -0.01 * s.overlap, 0.0);
        }
        let d = s.overlap * (1.0 + self.breathe * (2.0 * PI * self.f1 * u).sin());
        let hertz = s.force * (d / s.overlap).powf(1.5);
        let fnorm = hertz * (1.0 + self.tension * self.load.at(u).clamp(-1.0, 1.0));
        (nv, d, fnorm)
    }
}

/// A relative velocity (or rate) profile: a smooth wave in each component of amplitude `amp`,
/// brought smoothly to a stop over some stretches.
struct Drive {
    waves: [Wave; 3],
    amp: f64,
    stops: [(f64, f64); 2],
}

impl Drive {
    fn random(rng: &mut Rng, amp: f64) -> Drive {
        let mut stop = || {
            let a = rng.between(0.0, 0.9);
            (a, a + rng.between(0.0, 0.1))
        };
        let stops = [stop(), stop()];
        Drive {
            waves: [Wave::random(rng), Wave::random(rng), Wave::random(rng)],
            amp,
            stops,
        }
    }

    fn at(&self, u: f64) -> [f64; 3] {
        // dead within a stop, easing in and out of it over 5 % of the path (smoothly, as a
        // host's integrator changes a velocity: a jump in it would cost the work sums a
        // dashpot's force × the jump × dt that no law can know of)
        let mut ease = 1.0f64;
        for &(a, b) in &self.stops {
            let d = if u < a {
                a - u
            } else if u > b {
                u - b
            } else {
                0.0
            };
            let x = (d / 0.05).min(1.0);
            ease = ease.min(x * x * (3.0 - 2.0 * x));
        }
        self.waves.map(|w| ease * self.amp * w.at(u))
    }
}

/// Drives a tangential or rolling law's step `step` (the force, N, and its energy, from the
/// contact and its history of `slots` values) along one random path at scales `s`: a relative
/// velocity of random size (10⁻² to 10³ overlaps per path) that turns, stops and reverses, a
/// normal that turns, an overlap and a normal force that breathe (now and then into tension),
/// and the contact over (δ < 0, F_n = 0) for the last 5 % of the steps.
pub fn drive_vector(
    rng: &mut Rng,
    s: &Scales,
    slots: usize,
    motion: Motion,
    mut step: impl FnMut(&VectorContact, &mut [f64]) -> ([f64; 3], Option<Energy>),
) -> Books {
    let stage = Stage::random(rng);
    let amp = s.overlap / s.duration * rng.log_between(1e-2, 1e3);
    let drive = Drive::random(rng, amp);
    let (n, dt) = (s.steps, s.dt());
    let mut h = vec![0.0; slots];
    let mut t = Tally::new();
    let mut f_prev = [0.0; 3];
    let mut last = [0.0; 3];
    for k in 1..=n {
        let u = (k as f64 - 0.5) / n as f64;
        let (nv, delta, fnorm) = stage.at(k as f64 / n as f64, s);
        let mut v = drive.at(u);
        if motion == Motion::Rolling {
            // in the tangent plane
            let vn = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2];
            v = [v[0] - vn * nv[0], v[1] - vn * nv[1], v[2] - vn * nv[2]];
        }
        let c = VectorContact {
            normal: nv,
            velocity: v,
            normal_force: fnorm,
            delta,
            mass: s.mass,
            radius: s.radius,
            dt,
            context: NormalContext::hertzian(s.radius, delta, fnorm),
        };
        let (f, e) = step(&c, &mut h);
        let dw =
            -0.5 * dt * ((f_prev[0] + f[0]) * v[0] + (f_prev[1] + f[1]) * v[1] + (f_prev[2] + f[2]) * v[2]);
        t.step(dw, dw.abs(), e, dt);
        (f_prev, last) = (f, f);
    }
    t.books(last == [0.0; 3])
}

/// Drives a twisting law's step `step` (the torque, N·m, and its energy) along one random
/// path at scales `s`: a twisting rate of random size (10⁻⁴ to 10 rad per path) that stops and
/// reverses, under the normal force and overlap of [`drive_vector`].
pub fn drive_twisting(
    rng: &mut Rng,
    s: &Scales,
    slots: usize,
    mut step: impl FnMut(&TwistingContact, &mut [f64]) -> (f64, Option<Energy>),
) -> Books {
    let stage = Stage::random(rng);
    let amp = rng.log_between(1e-4, 10.0) / s.duration;
    let drive = Drive::random(rng, amp);
    let (n, dt) = (s.steps, s.dt());
    let mut h = vec![0.0; slots];
    let mut t = Tally::new();
    let (mut m_prev, mut last) = (0.0, 0.0);
    for k in 1..=n {
        let (nv, delta, fnorm) = stage.at(k as f64 / n as f64, s);
        let w = drive.at((k as f64 - 0.5) / n as f64)[0];
        let c = TwistingContact {
            normal: nv,
            rate: w,
            normal_force: fnorm,
            delta,
            mass: s.mass,
            radius: s.radius,
            dt,
            context: NormalContext::hertzian(s.radius, delta, fnorm),
        };
        let (m, e) = step(&c, &mut h);
        let dw = -0.5 * dt * (m_prev + m) * w;
        t.step(dw, dw.abs(), e, dt);
        (m_prev, last) = (m, m);
    }
    t.books(last == 0.0)
}

/// Paths per material of a check, materials per check, steps per path.
const PATHS: usize = 60;
const MATERIALS: usize = 4;
const STEPS: usize = 3000;

/// Runs `drive` on `PATHS` random paths for each of `MATERIALS` random materials (E from 1 MPa
/// to 200 GPa, ν from 0 to 0.45), panicking with the law's name, the seed and the failure.
fn check_all(name: &str, mut drive: impl FnMut(&mut Rng, &MaterialPair, &Scales) -> Result<Books, String>) {
    for m in 0..MATERIALS {
        let mut rng = Rng::new(0x5eed_0000 + m as u64);
        let (young, nu) = (rng.log_between(1e6, 2e11), rng.between(0.0, 0.45));
        let materials = MaterialPair::of_moduli(young, nu, None).expect("valid moduli");
        for p in 0..PATHS {
            let seed = (m * PATHS + p) as u64;
            let mut rng = Rng::new(seed);
            let s = Scales::random(&mut rng, materials.young, STEPS);
            let books = drive(&mut rng, &materials, &s);
            let fail = books.and_then(|b| b.check_passive().and(b.check_closed()));
            if let Err(e) = fail {
                panic!("law '{name}', path {seed} (E = {young:e} Pa, ν = {nu}; {s:?}): {e}");
            }
        }
    }
}

/// Panics unless the contact law `law`, bound to random materials, is passive along random
/// loading–unloading cycles and its reported energy closes ([`drive_normal`], [`Books`]).
pub fn assert_dissipative_contact<L: ContactLaw>(law: &L) {
    check_all(L::NAME, |rng, m, s| {
        let b = law.bind(m).map_err(|e| e.to_string())?;
        Ok(drive_normal(rng, s, L::HISTORY.len(), |c, h| {
            b.force_energy(*c, h)
        }))
    });
}

/// Panics unless the tangential law `law`, bound to random materials, is passive along random
/// paths of the contact points' slip and its reported energy closes ([`drive_vector`]).
pub fn assert_dissipative_tangential<L: TangentialLaw>(law: &L) {
    check_all(L::NAME, |rng, m, s| {
        let b = law.bind(m).map_err(|e| e.to_string())?;
        Ok(drive_vector(
            rng,
            s,
            L::HISTORY.len(),
            Motion::Tangential,
            |c, h| b.force_energy(c, h),
        ))
    });
}

/// Panics unless the rolling law `law`, bound to random materials, is passive along random
/// paths of the rolling velocity and its reported energy closes ([`drive_vector`]).
pub fn assert_dissipative_rolling<L: RollingLaw>(law: &L) {
    check_all(L::NAME, |rng, m, s| {
        let b = law.bind(m).map_err(|e| e.to_string())?;
        Ok(drive_vector(rng, s, L::HISTORY.len(), Motion::Rolling, |c, h| {
            b.force_energy(c, h)
        }))
    });
}

/// Panics unless the twisting law `law`, bound to random materials, is passive along random
/// paths of the twisting rate and its reported energy closes ([`drive_twisting`]).
pub fn assert_dissipative_twisting<L: TwistingLaw>(law: &L) {
    check_all(L::NAME, |rng, m, s| {
        let b = law.bind(m).map_err(|e| e.to_string())?;
        Ok(drive_twisting(rng, s, L::HISTORY.len(), |c, h| {
            b.torque_energy(c, h)
        }))
    });
}
