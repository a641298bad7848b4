//! A sphere rolling on a flat wall under gravity until rolling resistance stops it: the normal,
//! tangential and rolling laws composed at one contact (sdk 0.3).
//!
//! The sphere (mass m, radius r, moment of inertia I) rests on the wall at the overlap where the
//! normal law carries its weight, and is launched along x̂ rolling without slip: v = v0 x̂,
//! ω = (v0/r) ŷ. The tangential law keeps the contact point from slipping, the rolling law
//! resists the rolling velocity v_roll = r ω × n̂ with a torque r n̂ × F_r. While the rolling law
//! slides at its cap |F_r| = μ_r F_n = μ_r m g, rolling without slip gives the deceleration
//! a = μ_r m g r² / (I + m r²), (5/7) μ_r g for a solid sphere, so the sphere stops after
//! t = v0/a and x = v0²/(2a) (7 v0²/(10 μ_r g) for a solid sphere).
//!
//! Integrated by velocity Verlet (the scheme of [`super::oblique`](mod@super::oblique)) with a step of 1/`steps` of
//! the period of the normal contact's oscillation about its resting overlap; the stop is the
//! first instant the centre's speed along x̂ reaches 0, located by linear interpolation within
//! the step.

use crate::laws::{EnergyOut, NormalLaw, RollingResistance, TangentialForce};
use dashpot_sdk::{LawError, NormalBatch, NormalContext, RollingBatch, TangentialBatch};
use nalgebra::Vector3;

/// The rolling sphere and its launch.
#[derive(Debug, Clone, Copy)]
pub struct RollingSpec {
    /// Mass m (kg).
    pub mass: f64,
    /// Radius r (m).
    pub radius: f64,
    /// Moment of inertia I about the centre (kg·m²); (2/5) m r² for a solid sphere.
    pub inertia: f64,
    /// Launch speed v0 (m/s), rolling without slip.
    pub v0: f64,
    /// Gravity g (m/s², > 0), pressing the sphere on the wall.
    pub gravity: f64,
    /// Time steps per period of the normal contact's oscillation (≥ 20).
    pub steps: usize,
}

/// Where and when the sphere stopped.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RollingStop {
    /// Time to the stop (s).
    pub stop_time: f64,
    /// Distance rolled (m).
    pub stop_distance: f64,
    /// The mean deceleration v0 / stop_time (m/s²).
    pub deceleration: f64,
    /// The resting overlap (m) and normal force (N) the run started from.
    pub rest_overlap: f64,
    /// The normal force at rest (N): m g.
    pub rest_force: f64,
    /// The largest slip speed of the contact point seen (m/s): ≪ v0 while rolling without slip.
    pub max_slip: f64,
    /// The time step (s) and the number of steps.
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// (t, x, v, ω) samples, one every `sample_every` steps (s, m, m/s, rad/s).
    #[serde(skip)]
    pub samples: Vec<[f64; 4]>,
}

/// Why a rolling run could not be done.
#[derive(Debug, thiserror::Error)]
pub enum RollingError {
    /// A bad input, named.
    #[error("{0}")]
    Bad(String),
    /// A law failed.
    #[error(transparent)]
    Law(#[from] LawError),
    /// The sphere did not stop.
    #[error(
        "the sphere did not stop within {t:.3e} s ({steps} steps; v = {v:e} m/s): the rolling law \
         does not resist rolling enough, or there is no friction to make the sphere roll"
    )]
    NoStop {
        /// Time reached (s).
        t: f64,
        /// Steps taken.
        steps: usize,
        /// Speed left (m/s).
        v: f64,
    },
}

/// The most steps a run takes before it gives up.
pub const MAX_STEPS: usize = 20_000_000;

/// The normal force at overlap `delta` at rest.
fn rest_force<N: NormalLaw + ?Sized>(law: &N, m: f64, r: f64, delta: f64) -> Result<f64, LawError> {
    let mut h = vec![0.0; law.history_slots()];
    law.force(
        dashpot_sdk::Contact {
            delta,
            rate: 0.0,
            mass: m,
            radius: r,
        },
        &mut h,
    )
}

/// Rolls the sphere of `spec` on a wall with `normal`, `tangential` and `rolling` laws (each
/// bound to the sphere–wall materials) until it stops; `sample_every` > 0 keeps every that many
/// steps' state.
pub fn roll<N, T, R>(
    normal: &N,
    tangential: &T,
    rolling: &R,
    spec: &RollingSpec,
    sample_every: usize,
) -> Result<RollingStop, RollingError>
where
    N: NormalLaw + ?Sized,
    T: TangentialForce + ?Sized,
    R: RollingResistance + ?Sized,
{
    let RollingSpec {
        mass: m,
        radius: r,
        inertia,
        v0,
        gravity: g,
        steps,
    } = *spec;
    let positive =
        |name: &str, x: f64, unit: &str| super::finite_positive(name, unit, x).map_err(RollingError::Bad);
    positive("mass", m, "kg")?;
    positive("radius", r, "m")?;
    positive("inertia", inertia, "kg m^2")?;
    positive("v0", v0, "m/s")?;
    positive("gravity", g, "m/s^2")?;
    if steps < 20 {
        return Err(RollingError::Bad(format!(
            "steps = {steps} per oscillation period is out of range: it must be at least 20"
        )));
    }
    // the resting overlap: F(δ) = m g, by bisection on a log scale
    let weight = m * g;
    let (mut lo, mut hi) = (0.0f64, r * 1e-12);
    while rest_force(normal, m, r, hi)? < weight {
        lo = hi;
        hi *= 2.0;
        if hi > 0.5 * r {
            return Err(RollingError::Bad(format!(
                "the normal law cannot carry the sphere's weight {weight:e} N at an overlap below half its radius"
            )));
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if rest_force(normal, m, r, mid)? < weight {
            lo = mid
        } else {
            hi = mid
        }
    }
    let d_rest = 0.5 * (lo + hi);
    // the step: the normal spring's period about rest, k = dF/dδ there
    let h = 1e-6 * d_rest;
    let k = (rest_force(normal, m, r, d_rest + h)? - rest_force(normal, m, r, d_rest - h)?) / (2.0 * h);
    let period = 2.0 * std::f64::consts::PI * (m / k.max(f64::MIN_POSITIVE)).sqrt();
    let dt = period / steps as f64;
    let max_steps = MAX_STEPS;

    let n = Vector3::new(0.0, 0.0, 1.0);
    let mut x = Vector3::new(0.0, 0.0, r - d_rest);
    let mut v = Vector3::new(v0, 0.0, 0.0);
    let mut w = Vector3::new(0.0, v0 / r, 0.0);
    let (sn, st, sr) = (
        normal.history_slots(),
        tangential.history_slots(),
        rolling.history_slots(),
    );
    let (mut hn, mut ht, mut hr) = (vec![0.0; sn], vec![0.0; st], vec![0.0; sr]);
    // at rest the normal force carries the weight
    let mut f = Vector3::new(0.0, 0.0, weight);
    let mut tq = Vector3::zeros();
    let mut t = 0.0;
    let mut samples = Vec::new();
    let mut max_slip = 0.0f64;
    let gvec = Vector3::new(0.0, 0.0, -g);
    // the normal law's context only when the tangential or rolling law reads it
    let reads = tangential.reads_context() || rolling.reads_context();
    for step in 1..=max_steps {
        let vh = v + (f / m + gvec) * (0.5 * dt);
        let wh = w + tq * (0.5 * dt / inertia);
        x += vh * dt;
        t += dt;
        let delta = r - x.z;
        let rate = -vh.z;
        let (mut fnv, mut context) = ([0.0], [NormalContext::default()]);
        let nb = NormalBatch {
            delta: &[delta],
            rate: &[rate],
            mass: &[m],
            radius: &[r],
            slots: sn,
            history: &mut hn,
            force: &mut fnv,
        };
        if reads {
            normal.force_batch_context(nb, None, &mut context, EnergyOut::none())?;
        } else {
            normal.force_batch(nb)?;
        }
        let c = -r * n;
        let slip = vh + wh.cross(&c);
        max_slip = max_slip.max(slip.norm());
        let mut ft = [[0.0; 3]];
        let tb = TangentialBatch {
            dt,
            normal: &[[n.x, n.y, n.z]],
            velocity: &[[slip.x, slip.y, slip.z]],
            normal_force: &[fnv[0]],
            delta: &[delta],
            mass: &[m],
            radius: &[r],
            context: if reads { &context } else { &[] },
            slots: st,
            history: &mut ht,
            force: &mut ft,
        };
        let vroll = r * wh.cross(&n);
        let mut fr = [[0.0; 3]];
        // the rolling law sees the contact the tangential law sees, at the rolling velocity
        let rb = RollingBatch {
            velocity: &[[vroll.x, vroll.y, vroll.z]],
            slots: sr,
            history: &mut hr,
            force: &mut fr,
            ..tb
        };
        tangential.force_batch(tb)?;
        rolling.force_batch(rb, EnergyOut::none())?;
        let ftv = Vector3::new(ft[0][0], ft[0][1], ft[0][2]);
        let frv = Vector3::new(fr[0][0], fr[0][1], fr[0][2]);
        f = fnv[0] * n + ftv;
        tq = c.cross(&ftv) + r * n.cross(&frv);
        let v_old = v.x;
        v = vh + (f / m + gvec) * (0.5 * dt);
        w = wh + tq * (0.5 * dt / inertia);
        if sample_every > 0 && step % sample_every == 0 {
            samples.push([t, x.x, v.x, w.y]);
        }
        if v.x <= 0.0 {
            // the stop inside the step, by linear interpolation of v
            let s = v_old / (v_old - v.x);
            let t_stop = t - dt + s * dt;
            let x_stop = x.x - (1.0 - s) * dt * vh.x;
            samples.push([t_stop, x_stop, 0.0, w.y]);
            return Ok(RollingStop {
                stop_time: t_stop,
                stop_distance: x_stop,
                deceleration: v0 / t_stop,
                rest_overlap: d_rest,
                rest_force: weight,
                max_slip,
                dt,
                steps: step,
                samples,
            });
        }
    }
    Err(RollingError::NoStop {
        t,
        steps: max_steps,
        v: v.x,
    })
}
