//! Why a calibration failed ([`super::calibrate::calibrate`]): each refusal names the law, the
//! parameter, the target and what the law reached.

use super::two_body::CollideError;
use dashpot_sdk::LawError;

/// Why a calibration failed.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// Bad target values.
    #[error("{0}")]
    BadTarget(String),
    /// The law or the integrator failed.
    #[error(transparent)]
    Collide(#[from] CollideError),
    /// The law failed.
    #[error(transparent)]
    Law(#[from] LawError),
    /// Which parameter to fit is ambiguous.
    #[error(
        "say which parameter of '{law}' to fit to the restitution with --fit NAME (one of: \
         {candidates}); the default is `eps`, else `damp`, else the only parameter other than \
         `k`, and '{law}' has none of these"
    )]
    Ambiguous {
        /// The law.
        law: String,
        /// Its parameters.
        candidates: String,
    },
    /// The fit ended on parameters that do not reproduce its target.
    #[error(
        "the fit of '{law}' missed its target: {what} {target} wanted, {reached} reached \
         (residual {residual:+.3e}, tolerance {tolerance:e}) with {param}: {why}"
    )]
    Missed {
        /// The law.
        law: String,
        /// "restitution" or "contact time (s)".
        what: &'static str,
        /// The fitted parameter(s) and their values, as `name = value`.
        param: String,
        /// The target.
        target: f64,
        /// The value the fitted parameters realize.
        reached: f64,
        /// reached − target.
        residual: f64,
        /// The acceptance bound ([`fit_tolerance`]; relative for a contact time).
        tolerance: f64,
        /// Why, as far as the fit can tell.
        why: String,
    },
    /// The target lies in a jump of the law's response to the parameter.
    #[error(
        "no value of '{param}' reproduces {what} {target}: it jumps from {f_hi} to {f_lo} \
         between {param} = {hi:e} and {lo:e} (the law changes regime there, as an adhesive law \
         that captures the particle does); the closest value reached, {reached}, misses it by \
         {residual:+.3e}"
    )]
    Jump {
        /// The fitted parameter.
        param: String,
        /// "restitution" or "contact time".
        what: &'static str,
        /// The target.
        target: f64,
        /// The parameter value on the side below the target.
        lo: f64,
        /// The parameter value on the side above the target.
        hi: f64,
        /// The law's value at `lo` (below the target).
        f_lo: f64,
        /// The law's value at `hi` (above the target).
        f_hi: f64,
        /// The value closest to the target that was reached.
        reached: f64,
        /// reached − target.
        residual: f64,
    },
    /// No parameter value in range gives the target.
    #[error(
        "no value of '{param}' reproduces {what} = {target}: over {lo:e} … {hi:e} the law gives \
         {f_lo} … {f_hi}"
    )]
    Unreachable {
        /// The fitted parameter.
        param: String,
        /// "restitution" or "contact time".
        what: &'static str,
        /// The target.
        target: f64,
        /// Searched interval.
        lo: f64,
        /// Searched interval.
        hi: f64,
        /// Values at its ends.
        f_lo: f64,
        /// Values at its ends.
        f_hi: f64,
    },
}

impl From<super::rk::RhsError> for CalibrateError {
    fn from(e: super::rk::RhsError) -> Self {
        CalibrateError::Collide(e.into())
    }
}
