//! The integrator's options and what a collision returns: its outcome, samples and errors.

use crate::collide::rk::{RhsError, Step, System};
use crate::collide::{extrap, rk};
use dashpot_sdk::{EndCriterion, LawError};

/// The one-step method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Dormand–Prince 5(4): robust, for loose tolerances.
    DormandPrince5,
    /// Gragg–Bulirsch–Stoer extrapolation with this many columns (order twice that): several
    /// times fewer force evaluations than Dormand–Prince at tight tolerances.
    Extrapolation(usize),
    /// The default: extrapolation with its columns chosen from the tolerance
    /// ([`Method::resolve`]).
    Auto,
}

/// The extrapolation's columns at tolerances from this one up ([`Method::Auto`]); 5 below.
pub const FOUR_COLUMNS_FROM_RTOL: f64 = 1e-8;

impl Method {
    /// The method [`Method::Auto`] stands for at relative tolerance `rtol`: extrapolation with 4
    /// columns (order 8) for rtol ≥ 1e-8, 5 (order 10) below. Measured over 3,000 HSD and as
    /// many linear spring-dashpot collisions (ε in [0.01, 0.99], v0 in [10⁻³, 10] m/s): at every
    /// rtol from 1e-4 to 1e-8, 4 columns make 2–35 % fewer force evaluations than 5 and a worst
    /// restitution error as small or smaller (HSD at 1e-7: 9.1e-9 against 5.7e-7); at 1e-9 and
    /// below, 5 columns make fewer.
    pub fn resolve(self, rtol: f64) -> Method {
        match self {
            Method::Auto if rtol >= FOUR_COLUMNS_FROM_RTOL => Method::Extrapolation(4),
            Method::Auto => Method::Extrapolation(5),
            m => m,
        }
    }

    #[inline]
    pub(crate) fn step<S: System<2>>(
        self,
        sys: &mut S,
        x: f64,
        y: &[f64; 2],
        f: &[f64; 2],
        h: f64,
    ) -> Result<Step<2>, RhsError> {
        match self {
            Method::DormandPrince5 => rk::step(sys, x, y, f, h),
            Method::Extrapolation(k) => match sys.lockstep_step(x, y, f, h, k) {
                Some(s) => s,
                None => extrap::step(sys, x, y, f, h, k),
            },
            // resolved by `collide` before any step; 5 columns if not
            Method::Auto => Method::Extrapolation(5).step(sys, x, y, f, h),
        }
    }

    #[inline]
    pub(crate) fn factor(self, e: f64) -> f64 {
        match self {
            Method::DormandPrince5 => rk::step_factor(e),
            Method::Extrapolation(k) => extrap::step_factor(e, k),
            Method::Auto => extrap::step_factor(e, 5),
        }
    }
}

/// Integration settings.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Relative tolerance of each step (the realized restitution is accurate to about 10× this).
    pub rtol: f64,
    /// The one-step method.
    pub method: Method,
    /// Record the trajectory (every accepted step and event).
    pub record: bool,
    /// Largest time step as a fraction of the contact-time scale (smaller: smoother trajectories).
    pub max_step_fraction: f64,
    /// First step of each phase as a fraction of its natural scale.
    pub h0_fraction: f64,
    /// Give up after this many steps in one phase.
    pub max_steps: usize,
    /// Give up when the contact lasts longer than this many contact-time scales.
    pub max_time_factor: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            rtol: 1e-11,
            method: Method::Auto,
            record: false,
            max_step_fraction: 1.0,
            h0_fraction: 0.05,
            max_steps: 200_000,
            max_time_factor: 1.0e4,
        }
    }
}

/// One point of the phase trajectory.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sample {
    /// Time since first contact (s).
    pub t: f64,
    /// Overlap δ (m).
    pub delta: f64,
    /// Overlap rate δ̇ (m/s).
    pub rate: f64,
    /// Normal force (N).
    pub force: f64,
}

/// The observables of one collision.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Collision {
    /// Impact speed v0 (m/s).
    pub v0: f64,
    /// Realized restitution −δ̇(τ)/v0.
    pub restitution: f64,
    /// Contact time τ (s).
    pub contact_time: f64,
    /// Maximum overlap (m).
    pub max_overlap: f64,
    /// Time of the maximum overlap (s).
    pub max_overlap_time: f64,
    /// The criterion that ended the contact.
    pub end: EndCriterion,
    /// Accepted steps (all phases).
    pub steps: usize,
    /// Force evaluations.
    pub force_evals: usize,
    /// An adhesive contact that never ended: the particles stuck (restitution 0; the contact
    /// time is then that of the turn back that decided it).
    pub stuck: bool,
    /// The most tensile force met at an accepted state (N, negative), for a law that pulled.
    pub tensile_peak: Option<f64>,
    /// The phase trajectory (if recorded).
    #[serde(skip)]
    pub trajectory: Vec<Sample>,
}

/// Why a collision could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum CollideError {
    /// v0 is not a positive finite number.
    #[error("impact speed v0 = {0} m/s is out of range: it must be finite and > 0")]
    BadSpeed(f64),
    /// The effective mass is not a positive finite number.
    #[error("effective mass {0} kg is out of range: it must be finite and > 0")]
    BadMass(f64),
    /// The law failed (error, panic, NaN).
    #[error(transparent)]
    Law(#[from] LawError),
    /// The law's force is too weak to stop the particles within a 1 m overlap.
    #[error(
        "the contact law cannot stop the particles: at v0 = {v0} m/s its force stays below the \
         kinetic-energy scale m v0²/δ for every overlap up to 1 m (F at the last overlap probed, \
         with δ̇ = v0: {f_at_1m} N)"
    )]
    NoStop {
        /// Impact speed (m/s).
        v0: f64,
        /// F(δ, δ̇ = v0) (N) at the largest overlap probed (between 0.5 m and 1 m).
        f_at_1m: f64,
    },
    /// The law failed while its overlap scale was sought, at an overlap the collision comes near.
    #[error(
        "the contact law failed at overlap δ = {delta:e} m, where it was asked for the collision's \
         overlap scale at v0 = {v0} m/s (the overlap grows from 1e-40 m until F·δ reaches the \
         kinetic-energy scale m v0²; it had not reached it below {delta:e} m, so the collision \
         itself comes near this overlap): {source}"
    )]
    Probe {
        /// The overlap probed (m).
        delta: f64,
        /// Impact speed (m/s).
        v0: f64,
        /// The law's error.
        source: LawError,
    },
    /// The particles did not separate within the limits.
    #[error(
        "the contact law did not return the particles: after {steps} steps, at t = {t:e} s \
         ({factor:.0} contact-time scales) the overlap is δ = {delta:e} m and δ̇ = {rate:e} m/s; \
         stopped by the integration limit ({why})"
    )]
    NoReturn {
        /// Time reached (s).
        t: f64,
        /// Overlap there (m).
        delta: f64,
        /// Rate there (m/s).
        rate: f64,
        /// Steps taken.
        steps: usize,
        /// t over the contact-time scale.
        factor: f64,
        /// Which limit.
        why: &'static str,
    },
}

impl From<RhsError> for CollideError {
    fn from(e: RhsError) -> Self {
        match e {
            RhsError::Law(l) => CollideError::Law(l),
            RhsError::OutOfDomain => CollideError::Law(LawError::new(
                dashpot_sdk::ErrorKind::Other,
                "event location left the domain of the integrator",
            )),
        }
    }
}

/// Why a phase of an adaptive integration stops before its end: after `max_steps` steps (`why`
/// [0]) or past the time `t_limit` (`why` [1]); `None` while it may go on.
pub(crate) fn overrun(
    n: usize,
    max_steps: usize,
    t: f64,
    t_limit: f64,
    why: [&'static str; 2],
) -> Option<&'static str> {
    if n > max_steps {
        Some(why[0])
    } else if t > t_limit {
        Some(why[1])
    } else {
        None
    }
}

/// A trial step's result for the adaptive loops: `Ok(None)` when the step left the
/// formulation's domain (the caller retries a quarter of it), other errors passed on.
#[inline]
pub(crate) fn in_domain(r: Result<Step<2>, RhsError>) -> Result<Option<Step<2>>, RhsError> {
    match r {
        Ok(s) => Ok(Some(s)),
        Err(RhsError::OutOfDomain) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The error of a collision that does not end: at time `t` (s), overlap `delta` (m) and rate
/// `rate` (m/s) after `steps` steps, `t` being `t / tstar` collision time scales, and why.
pub(crate) fn no_return(tstar: f64) -> impl Fn(f64, f64, f64, usize, &'static str) -> CollideError {
    move |t, delta, rate, steps, why| CollideError::NoReturn {
        t,
        delta,
        rate,
        steps,
        factor: t / tstar,
        why,
    }
}
