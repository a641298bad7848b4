//! The heat two bodies exchange during an impact (sdk 0.4): a head-on impact of a sphere on a
//! wall or on another sphere, integrated as a DEM code integrates it (velocity Verlet with a
//! fixed step, `steps` per contact time, the contact time from the exact head-on driver), with
//! the normal law's context (its contact radius a) handed at every step to a heat law, and the
//! temperatures stepped as LAMMPS's `fix heat/flow` steps them: T₁ += dt Q/C₁, T₂ −= dt Q/C₂
//! (a wall is a reservoir at T₂). Heat does not act back on the motion.
//!
//! What it reports: the heat that went into the particle, ∫ Q dt (J), the temperatures after,
//! ∫ H dt (J/K: for a law linear in ΔT the exchange is ΔT_out = ΔT_in Π (1 − dt H_n (1/C₁ +
//! 1/C₂)), e^{−(1/C₁ + 1/C₂) ∫ H dt} as dt → 0), the largest conductance, and the motion's
//! contact time and restitution. C₁ ΔT₁ + C₂ ΔT₂ = 0 to rounding between spheres.

use super::oblique::{contact_over, Body, ObliqueError, Target};
use super::two_body::{collide, Options, PairLaw};
use crate::laws::{EnergyOut, HeatConduction, NormalLaw};
use dashpot_sdk::{EndCriterion, HeatBatch, HeatFlow, NormalBatch, NormalContext};

/// The impact and the bodies' thermal state.
#[derive(Debug, Clone, Copy)]
pub struct HeatImpact {
    /// Normal speed of approach at first contact (m/s), > 0.
    pub speed: f64,
    /// When contact ends.
    pub end: EndCriterion,
    /// Time steps per contact time (≥ 100).
    pub steps: usize,
    /// Temperatures before the impact (K): the particle's, then the partner's (a wall's own).
    pub temperature: [f64; 2],
    /// Heat capacities C = m c (J/K) of the particle and of the partner (ignored for a wall).
    pub capacity: [f64; 2],
}

/// What the impact exchanged.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HeatExchange {
    /// Temperatures after the impact (K): the particle's, then the partner's (a wall's stays).
    pub temperature: [f64; 2],
    /// The heat that went into the particle during the contact, ∫ Q dt (J); the partner
    /// received its opposite.
    pub heat: f64,
    /// ∫ H dt over the contact (J/K).
    pub conductance_time: f64,
    /// The largest conductance during the contact (W/K).
    pub max_conductance: f64,
    /// Contact time (s).
    pub contact_time: f64,
    /// Normal restitution of the motion (0 when the particles stuck).
    pub restitution: f64,
    /// Time step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
}

/// The heat exchanged by `particle` hitting `target` head-on under `normal` (the motion) and
/// `heat` (the conduction), both bound to the pair's materials.
pub fn impact_heat<N: NormalLaw, H: HeatConduction>(
    normal: &N,
    heat: &H,
    particle: &Body,
    target: &Target,
    imp: &HeatImpact,
) -> Result<HeatExchange, ObliqueError> {
    let input = |m: String| ObliqueError::Input(m);
    super::finite_positive("impact speed", "m/s", imp.speed).map_err(input)?;
    super::finite_positive("particle mass", "kg", particle.mass).map_err(input)?;
    super::finite_positive("particle radius", "m", particle.radius).map_err(input)?;
    if imp.steps < 100 {
        return Err(input(format!(
            "steps per contact = {} is out of range: it must be ≥ 100",
            imp.steps
        )));
    }
    let wall = matches!(target, Target::Wall);
    for (k, t) in imp.temperature.iter().enumerate() {
        if !(t.is_finite() && *t >= 0.0) {
            return Err(input(format!(
                "temperature {} = {t} K is out of range: it must be finite and >= 0",
                k + 1
            )));
        }
    }
    for (k, c) in imp.capacity.iter().enumerate().take(if wall { 1 } else { 2 }) {
        super::finite_positive(&format!("heat capacity {}", k + 1), "J/K", *c).map_err(input)?;
    }
    if heat.history_slots() > 0 {
        return Err(input(format!(
            "the heat law '{}' keeps history: the impact driver runs heat laws without history",
            heat.name()
        )));
    }
    let (m1, r1) = (particle.mass, particle.radius);
    let (m_eff, r_eff, inv_m2) = match target {
        Target::Wall => (m1, r1, 0.0),
        Target::Sphere(b) => {
            super::finite_positive("partner mass", "kg", b.mass).map_err(input)?;
            super::finite_positive("partner radius", "m", b.radius).map_err(input)?;
            (
                m1 * b.mass / (m1 + b.mass),
                r1 * b.radius / (r1 + b.radius),
                1.0 / b.mass,
            )
        }
    };
    let head_on = PairLaw::new(normal, m_eff, r_eff);
    let tau = collide(&head_on, m_eff, imp.speed, imp.end, &Options::default())?.contact_time;
    let dt = tau / imp.steps as f64;
    let inv_m1 = 1.0 / m1;
    // the relative normal coordinate: δ = −x, the particle's and the partner's velocities
    let (mut delta, mut v1, mut v2) = (0.0f64, -imp.speed, 0.0f64);
    let mut hn = vec![0.0; normal.history_slots()];
    let (mut f, mut t, mut steps) = (0.0f64, 0.0f64, 0usize);
    let [mut t1, mut t2] = imp.temperature;
    let (mut q_sum, mut h_sum, mut h_max) = (0.0f64, 0.0f64, 0.0f64);
    let mut unloading = false;
    let stuck: bool;
    let max_steps = 100 * imp.steps;
    loop {
        // kick, drift (the force pushes the particle up, the partner down)
        let v1h = v1 + 0.5 * dt * f * inv_m1;
        let v2h = v2 - 0.5 * dt * f * inv_m2;
        delta -= (v1h - v2h) * dt;
        t += dt;
        steps += 1;
        let rate = -(v1h - v2h);
        let (mut fv, mut reach, mut ctx) = ([0.0], [0.0], [NormalContext::default()]);
        normal.force_batch_context(
            NormalBatch {
                delta: &[delta],
                rate: &[rate],
                mass: &[m_eff],
                radius: &[r_eff],
                slots: hn.len(),
                history: &mut hn,
                force: &mut fv,
            },
            Some(&mut reach),
            &mut ctx,
            EnergyOut::none(),
        )?;
        f = fv[0];
        let mut flow = [HeatFlow::default()];
        heat.heat_batch(HeatBatch {
            dt,
            temperature: &[[t1, t2]],
            normal_force: &fv,
            delta: &[delta],
            radius: &[r_eff],
            context: &ctx,
            slots: 0,
            history: &mut [],
            flow: &mut flow,
        })?;
        let q = flow[0].heat;
        t1 += dt * q / imp.capacity[0];
        if !wall {
            t2 -= dt * q / imp.capacity[1];
        }
        q_sum += dt * q;
        h_sum += dt * flow[0].conductance;
        h_max = h_max.max(flow[0].conductance);
        v1 = v1h + 0.5 * dt * f * inv_m1;
        v2 = v2h - 0.5 * dt * f * inv_m2;
        let rate = -(v1 - v2);
        if rate < 0.0 {
            unloading = true;
        }
        if let Some(s) = contact_over(imp.end, unloading, delta, reach[0], f, rate) {
            stuck = s;
            break;
        }
        if steps > max_steps {
            return Err(ObliqueError::NoReturn {
                limit: 100.0,
                delta,
                rate,
            });
        }
    }
    Ok(HeatExchange {
        temperature: [t1, t2],
        heat: q_sum,
        conductance_time: h_sum,
        max_conductance: h_max,
        contact_time: t,
        restitution: if stuck { 0.0 } else { (v1 - v2) / imp.speed },
        dt,
        steps,
    })
}
