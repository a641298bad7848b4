//! The two-body collision driver: integrate a head-on collision under any contact law and
//! report what experimentalists measure (restitution, contact time, maximum overlap); sweeps,
//! calibration, contact laws as restitution laws, and Antypov & Elliott's figures.

pub mod calibrate;
pub mod cli;
pub mod extrap;
pub mod figures;
pub mod grid;
pub mod rk;
pub mod tabulate;
pub mod two_body;

pub use tabulate::TabulatedRestitution;
pub use two_body::{collide, CollideError, Collision, ContactForce, Options, Sample, Static};
