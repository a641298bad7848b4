//! # dashpot host
//!
//! Loads law plugins by name ([`registry`]) and runs the drivers; the `dashpot` CLI ([`cli`]).

pub mod ae_statements;
pub mod bed;
pub mod cli;
pub mod collide;
pub mod config;
pub mod output;
pub mod plot;
pub mod registry;
pub mod reproduce;

pub use registry::{Registry, SearchPath};
