//! Oblique impacts: a solid sphere against a flat wall or another sphere, with a normal contact
//! law and a tangential (friction) law, both with per-contact history, and rotation.
//!
//! The head-on driver ([`super::two_body`]) integrates the normal motion alone with an
//! extrapolation method to near machine precision. An oblique impact couples the normal force to
//! a tangential spring that is integrated in time and capped by Coulomb's law (a non-smooth
//! stick–slip switch), so here both bodies are advanced the way a DEM code advances them:
//! velocity Verlet with a fixed step, `steps` per contact time, the laws called through the same
//! batch interface a DEM loop uses (one contact per call), the history kept per accepted step.
//! The contact normal stays the line of centres at first contact (the classical two-body impact;
//! see the comment in [`oblique`]). The contact time that sets the step comes from the head-on
//! driver at the impact's normal speed.
//!
//! Frame: the wall (or the partner's centre) at the origin, the normal ẑ pointing to the
//! particle, the incident tangential direction x̂; spins about ŷ, positive in the sense of
//! rolling along +x̂ (a sphere rolling on the wall with v_x = R ω_y).

use super::two_body::{collide, CollideError, Options, PairLaw};
use crate::laws::{EnergyOut, NormalLaw, TangentialForce};
use dashpot_sdk::{EndCriterion, LawError, NormalBatch, NormalContext, TangentialBatch};
use nalgebra::Vector3;

/// A solid body: mass (kg), radius (m) and moment of inertia about a diameter (kg·m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Mass (kg).
    pub mass: f64,
    /// Radius (m).
    pub radius: f64,
    /// Moment of inertia about a diameter (kg·m²); (2/5) m R² for a solid sphere.
    pub inertia: f64,
}

impl Body {
    /// A solid sphere of mass `mass` (kg) and radius `radius` (m): I = (2/5) m R².
    pub fn solid_sphere(mass: f64, radius: f64) -> Body {
        Body {
            mass,
            radius,
            inertia: 0.4 * mass * radius * radius,
        }
    }
}

/// What the particle hits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// A flat rigid wall of infinite mass.
    Wall,
    /// Another sphere, at rest and without spin before the impact.
    Sphere(Body),
}

/// The impact.
#[derive(Debug, Clone, Copy)]
pub struct Impact {
    /// Speed of approach at first contact (m/s), > 0.
    pub speed: f64,
    /// Angle of incidence from the normal (rad), in [0, π/2).
    pub angle: f64,
    /// Initial spin of the particle about ŷ (rad/s).
    pub spin: f64,
    /// When contact ends.
    pub end: EndCriterion,
    /// Time steps per contact time (≥ 100).
    pub steps: usize,
}

/// The observables of an oblique impact.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ObliqueCollision {
    /// Normal restitution −v_n,out / v_n,in of the relative centre velocity (0 when stuck).
    pub restitution: f64,
    /// An adhesive contact whose rebound turned back before its reach: the particles stuck
    /// (the other outputs are those of that instant).
    pub stuck: bool,
    /// Normal relative speed at impact (m/s).
    pub normal_velocity_in: f64,
    /// Tangential relative centre velocity at impact (m/s), along x̂.
    pub tangential_velocity_in: f64,
    /// The particle centre's tangential velocity after the impact, relative to the partner's
    /// centre, along the incident tangential direction x̂ (m/s).
    pub tangential_velocity_out: f64,
    /// The particle's spin after the impact about ŷ (rad/s), positive when rolling along x̂.
    pub angular_velocity_out: f64,
    /// The partner sphere's spin after the impact about ŷ (rad/s); 0 for a wall.
    pub partner_angular_velocity_out: f64,
    /// Rebound angle (degrees) of the relative centre velocity from the normal, positive on the
    /// side of the incident tangential direction.
    pub rebound_angle: f64,
    /// Tangential velocity of the contact point after the impact (m/s), along x̂.
    pub contact_point_velocity_out: f64,
    /// Contact time (s).
    pub contact_time: f64,
    /// Maximum overlap (m).
    pub max_overlap: f64,
    /// Time step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Share of the steps in contact during which the tangential force sat on the Coulomb cap
    /// (gross sliding).
    pub sliding_share: f64,
    /// The criterion that ended the contact.
    pub end: EndCriterion,
}

/// Why an oblique impact could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum ObliqueError {
    /// A bad input.
    #[error("{0}")]
    Input(String),
    /// The law failed (error, panic, NaN).
    #[error(transparent)]
    Law(#[from] LawError),
    /// The head-on collision that sets the time step failed.
    #[error(transparent)]
    HeadOn(#[from] CollideError),
    /// The particles did not separate.
    #[error(
        "the particles did not separate within {limit} contact times (overlap {delta:e} m, normal \
         speed {rate:e} m/s): the normal law may be overdamped or attractive; try --end force"
    )]
    NoReturn {
        /// Contact times waited.
        limit: f64,
        /// Overlap (m).
        delta: f64,
        /// Normal relative speed (m/s).
        rate: f64,
    },
}

fn finite_positive(what: &str, unit: &str, v: f64) -> Result<(), ObliqueError> {
    super::finite_positive(what, unit, v).map_err(ObliqueError::Input)
}

/// Integrates the oblique impact of `particle` on `target` under `normal` and, if given,
/// `tangential` (both bound to the pair's materials).
pub fn oblique<N: NormalLaw, T: TangentialForce>(
    normal: &N,
    tangential: Option<&T>,
    particle: &Body,
    target: &Target,
    impact: &Impact,
) -> Result<ObliqueCollision, ObliqueError> {
    finite_positive("impact speed", "m/s", impact.speed)?;
    finite_positive("particle mass", "kg", particle.mass)?;
    finite_positive("particle radius", "m", particle.radius)?;
    finite_positive("particle moment of inertia", "kg m²", particle.inertia)?;
    if let Target::Sphere(b) = target {
        finite_positive("partner mass", "kg", b.mass)?;
        finite_positive("partner radius", "m", b.radius)?;
        finite_positive("partner moment of inertia", "kg m²", b.inertia)?;
    }
    if !(impact.angle >= 0.0 && impact.angle < std::f64::consts::FRAC_PI_2) {
        return Err(ObliqueError::Input(format!(
            "angle of incidence = {}° is out of range: it must lie in [0, 90)",
            impact.angle.to_degrees()
        )));
    }
    if !impact.spin.is_finite() {
        return Err(ObliqueError::Input(format!(
            "initial spin = {} rad/s is not finite",
            impact.spin
        )));
    }
    if impact.steps < 100 {
        return Err(ObliqueError::Input(format!(
            "steps per contact = {} is out of range: it must be ≥ 100",
            impact.steps
        )));
    }
    let (m1, r1, i1) = (particle.mass, particle.radius, particle.inertia);
    let (m2, r2, i2, wall) = match target {
        Target::Wall => (f64::INFINITY, f64::INFINITY, f64::INFINITY, true),
        Target::Sphere(b) => (b.mass, b.radius, b.inertia, false),
    };
    let (m_eff, r_eff) = if wall {
        (m1, r1)
    } else {
        (m1 * m2 / (m1 + m2), r1 * r2 / (r1 + r2))
    };
    let vn = impact.speed * impact.angle.cos();
    let vt = impact.speed * impact.angle.sin();

    // the contact time at this normal speed, from the exact head-on driver
    let head_on = PairLaw::new(normal, m_eff, r_eff);
    let tau = collide(&head_on, m_eff, vn, impact.end, &Options::default())?.contact_time;
    let dt = tau / impact.steps as f64;

    let ex = Vector3::new(1.0, 0.0, 0.0);
    let ez = Vector3::new(0.0, 0.0, 1.0);
    // positions: the partner at the origin, the particle touching it
    let mut x1 = if wall {
        Vector3::new(0.0, 0.0, r1)
    } else {
        Vector3::new(0.0, 0.0, r1 + r2)
    };
    let mut x2 = Vector3::zeros();
    let mut v1 = vt * ex - vn * ez;
    let mut v2 = Vector3::zeros();
    let mut w1 = Vector3::new(0.0, impact.spin, 0.0);
    let mut w2 = Vector3::zeros();
    let (sn, st) = (
        normal.history_slots(),
        tangential.map_or(0, |t| t.history_slots()),
    );
    let mut hn = vec![0.0; sn];
    let mut ht = vec![0.0; st];
    let (mut f1, mut t1, mut t2) = (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
    let mut steps = 0usize;
    // |F_t| / F_n at every step in contact: the steps on the Coulomb line share the largest one
    let mut ratios: Vec<f64> = Vec::with_capacity(impact.steps + 16);
    let mut max_overlap = 0.0f64;
    let mut unloading = false;
    let stuck: bool;
    let limit = 100.0;
    let max_steps = (limit * impact.steps as f64) as usize;
    let (inv_m1, inv_m2) = (1.0 / m1, if wall { 0.0 } else { 1.0 / m2 });
    let (inv_i1, inv_i2) = (1.0 / i1, if wall { 0.0 } else { 1.0 / i2 });
    let mut t = 0.0;
    loop {
        // kick, drift
        let v1h = v1 + f1 * (0.5 * dt * inv_m1);
        let v2h = v2 - f1 * (0.5 * dt * inv_m2);
        let w1h = w1 + t1 * (0.5 * dt * inv_i1);
        let w2h = w2 + t2 * (0.5 * dt * inv_i2);
        x1 += v1h * dt;
        x2 += v2h * dt;
        t += dt;
        steps += 1;
        // the contact at the new positions
        // the normal stays ẑ, the line of centres at first contact: the classical two-body
        // impact (Maw, Barber & Fawcett; Thornton), exact against a wall; between spheres the
        // line of centres turns by about v_t τ/(R1 + R2) during contact (mrad), which this
        // driver leaves out so that its numbers are those of the theory it is checked against
        let (n, delta) = if wall {
            (ez, r1 - x1.z)
        } else {
            (ez, r1 + r2 - (x1 - x2).z)
        };
        let rate = -(v1h - v2h).dot(&n);
        let (mut fn_, mut reach, mut context) = ([0.0], [0.0], [NormalContext::default()]);
        let nb = NormalBatch {
            delta: &[delta],
            rate: &[rate],
            mass: &[m_eff],
            radius: &[r_eff],
            slots: sn,
            history: &mut hn,
            force: &mut fn_,
        };
        // the normal law's context only for a tangential law that reads it
        let reads = tangential.is_some_and(|t| t.reads_context());
        if reads {
            normal.force_batch_context(nb, Some(&mut reach), &mut context, EnergyOut::none())?;
        } else {
            normal.force_batch_with(nb, Some(&mut reach), EnergyOut::none())?;
        }
        let fnv = fn_[0];
        max_overlap = max_overlap.max(delta);
        if rate < 0.0 {
            unloading = true;
        }
        // contact points, relative to each centre
        let c1 = -r1 * n;
        let c2 = if wall { Vector3::zeros() } else { r2 * n };
        let mut ft = Vector3::zeros();
        if let Some(tl) = tangential {
            let vc = (v1h + w1h.cross(&c1)) - (v2h + w2h.cross(&c2));
            let mut out = [[0.0; 3]];
            tl.force_batch(TangentialBatch {
                dt,
                normal: &[[n.x, n.y, n.z]],
                velocity: &[[vc.x, vc.y, vc.z]],
                normal_force: &[fnv],
                delta: &[delta],
                mass: &[m_eff],
                radius: &[r_eff],
                context: if reads { &context } else { &[] },
                slots: st,
                history: &mut ht,
                force: &mut out,
            })?;
            ft = Vector3::new(out[0][0], out[0][1], out[0][2]);
        }
        if delta > 0.0 && fnv > 0.0 {
            ratios.push(ft.norm() / fnv);
        }
        f1 = fnv * n + ft;
        t1 = c1.cross(&ft);
        t2 = c2.cross(&(-ft));
        // kick
        v1 = v1h + f1 * (0.5 * dt * inv_m1);
        v2 = v2h - f1 * (0.5 * dt * inv_m2);
        w1 = w1h + t1 * (0.5 * dt * inv_i1);
        w2 = w2h + t2 * (0.5 * dt * inv_i2);
        // an adhesive contact lasts to its reach (δ < −reach), and sticks if the rebound turns
        // back before it gets there
        if let Some(s) = contact_over(impact.end, unloading, delta, reach[0], fnv, rate) {
            stuck = s;
            break;
        }
        if steps > max_steps {
            return Err(ObliqueError::NoReturn { limit, delta, rate });
        }
    }
    let vr = v1 - v2;
    let (vn_out, vt_out) = (vr.dot(&ez), vr.dot(&ex));
    let c1 = -r1 * ez;
    let c2 = if wall { Vector3::zeros() } else { r2 * ez };
    let vc = (v1 + w1.cross(&c1)) - (v2 + w2.cross(&c2));
    Ok(ObliqueCollision {
        restitution: if stuck { 0.0 } else { vn_out / vn },
        stuck,
        normal_velocity_in: vn,
        tangential_velocity_in: vt,
        tangential_velocity_out: vt_out,
        angular_velocity_out: w1.y,
        partner_angular_velocity_out: if wall { 0.0 } else { w2.y },
        rebound_angle: vt_out.atan2(vn_out).to_degrees(),
        contact_point_velocity_out: vc.dot(&ex),
        contact_time: t,
        max_overlap,
        dt,
        steps,
        sliding_share: sliding_share(&ratios),
        end: impact.end,
    })
}

/// The share of contact steps whose |F_t|/F_n equals the largest one seen (to 1e-6): the steps
/// on the Coulomb line, without knowing the tangential law's μ.
/// After a step of a contact with overlap `delta` (m), normal force `force` (N) and overlap
/// rate `rate` (m/s), `unloading` once the overlap has started to fall: `None` while it goes
/// on, `Some(false)` when it has ended by `end` (an adhesive contact at its reach, δ < −reach
/// (m)), `Some(true)` when the rebound turned back before then (the particles stuck).
pub(crate) fn contact_over(
    end: EndCriterion,
    unloading: bool,
    delta: f64,
    reach: f64,
    force: f64,
    rate: f64,
) -> Option<bool> {
    let over = match end {
        EndCriterion::Overlap => unloading && delta <= -reach,
        EndCriterion::Force => unloading && force <= 0.0,
    };
    if over {
        Some(false)
    } else if unloading && rate > 0.0 {
        Some(true)
    } else {
        None
    }
}

fn sliding_share(ratios: &[f64]) -> f64 {
    let top = ratios.iter().copied().fold(0.0, f64::max);
    if ratios.is_empty() || top == 0.0 {
        return 0.0;
    }
    ratios.iter().filter(|&&r| r >= top * (1.0 - 1e-6)).count() as f64 / ratios.len() as f64
}
