//! # dashpot-core
//!
//! What every dashpot front end shares, and all that the C ABI links:
//! - [`registry`]: plugin discovery and laws by name;
//! - [`laws`]: the law-facing traits every driver uses ([`laws::NormalLaw`],
//!   [`laws::TangentialForce`]), implemented for plugin handles and for laws compiled in; the
//!   only module that names ABI handles;
//! - [`checks`]: refusals every front end shares (overflowing laws, calibrations out of range);
//! - [`collide`]: the two-body collision driver (head-on, any contact law, with history).
//!
//! Dependency rule: `dashpot` (CLI, plots, bed, DEM) → `dashpot-core` → `dashpot-sdk`;
//! `dashpot-capi` → `dashpot-core`. No clap, plotters, rayon or indicatif here.

#![warn(missing_docs)]

pub mod checks;
pub mod collide;
pub mod laws;
pub mod registry;

pub use registry::{Registry, SearchPath};
