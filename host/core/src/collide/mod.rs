//! The two-body collision driver: integrate a head-on collision under any contact law (with or
//! without per-contact history) and report what experimentalists measure (restitution, contact
//! time, maximum overlap); numerical calibration.

pub mod adhesive;
pub mod calibrate;
mod calibrate_error;
pub mod extrap;
pub mod fit_curve;
pub mod heat;
pub mod lanes;
pub mod oblique;
pub mod outcome;
pub mod pair_law;
pub mod rk;
pub mod rolling;
pub mod two_body;

pub use heat::{impact_heat, HeatExchange, HeatImpact};
pub use lanes::collide_many;
pub use oblique::{oblique, Body, Impact, ObliqueCollision, ObliqueError, Target};
pub use two_body::{collide, collide_named, CollideError, Collision, ContactForce, Options, PairLaw, Sample};

/// Checks an input of the driver that must be finite and > 0: the message naming `name`, its
/// value `v` and its `unit` when it is not.
fn finite_positive(name: &str, unit: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{name} = {v} {unit} is out of range: it must be finite and > 0"
        ))
    }
}
