//! # dashpot host
//!
//! The `dashpot` CLI ([`cli`]), reports and figures ([`report`]), the experiments (the vibrated
//! bed, [`bed`], run by either engine), the two engines (the event-driven engine in
//! [`bed::engine`], the soft-sphere DEM engine in [`dem`]) and what they share (the [`piston`],
//! contact laws as restitution laws in [`tabulate`]). The registry, the law-facing traits and
//! the two-body collision driver live in `dashpot-core` and are re-exported here.
//!
//! Dependency rule: `cli` → `report` → experiments (`bed`, `collide`) → engines (`bed::engine`,
//! `dem`) → `laws` → sdk. Nothing outside `cli` imports it, the engines import neither `cli`,
//! `report` nor each other, and only `laws` names the sdk's ABI handles
//! (`host/tests/architecture.rs` checks it).

pub mod ae_statements;
pub mod bed;
pub mod budget;
pub mod cli;
pub mod config;
pub mod dem;
pub mod output;
pub mod piston;
pub mod progress;
pub mod report;
pub mod tabulate;

pub use dashpot_core::{checks, laws, registry};
pub use registry::{Registry, SearchPath};
pub use report::{plot, reproduce};

/// The two-body collision driver (from `dashpot-core`) and contact laws as restitution laws.
pub mod collide {
    pub use crate::tabulate::TabulatedRestitution;
    pub use dashpot_core::collide::*;
}
