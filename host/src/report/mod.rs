//! Figures, plots and reports: what `figures` and `reproduce` write.

pub mod bed;
pub mod collide;
pub mod collide_families;
pub mod plot;
pub mod reproduce;
pub mod snapshot;
