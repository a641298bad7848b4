//! The vibrated bed's commands: `dashpot bed`, `dashpot scaling` and `dashpot figures bed`
//! (delegated to from [`crate::cli`]).

mod args;
pub mod check;
mod run;
mod sweeps;

pub use args::*;
pub use run::*;
pub use sweeps::*;
