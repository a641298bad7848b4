//! # dashpot host
//!
//! The `dashpot` CLI ([`cli`]) and the drivers that need more than the core: the event-driven
//! vibrated bed ([`bed`]), contact laws as restitution laws ([`tabulate`]), figures and reports
//! ([`report`]). The registry, the law-facing traits and the two-body collision driver live in
//! `dashpot-core` and are re-exported here.
//!
//! Dependency rule: `cli` → `report` → drivers (`collide`, `bed`) → `laws` → sdk; nothing
//! imports `cli`.

pub mod ae_statements;
pub mod bed;
pub mod cli;
pub mod config;
pub mod dem;
pub mod output;
pub mod report;
pub mod tabulate;

pub use dashpot_core::{laws, registry};
pub use registry::{Registry, SearchPath};
pub use report::{plot, reproduce};

/// The two-body collision driver (from `dashpot-core`) and contact laws as restitution laws.
pub mod collide {
    pub use crate::tabulate::TabulatedRestitution;
    pub use dashpot_core::collide::*;
}
