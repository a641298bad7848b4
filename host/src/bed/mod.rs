//! # The vibrated bed: an event-driven engine for 2D inelastic hard disks
#![warn(missing_docs)]
//!
//! McNamara & Falcon (PRE 71, 031302, 2005), Sec. II: `N = n L/d` disks of diameter `d` and mass
//! `m` in a box of width `L`, periodic horizontally, between a fixed lid and a piston driven by
//! two joined parabolas ([`piston`]), under gravity `g` (or none). Every collision is
//! instantaneous and binary; the normal restitution comes from a [`Restitution`] law evaluated at
//! the normal relative impact speed; the lid and the piston are partners of infinite mass.
//!
//! Geometry: heights y in m, with the piston oscillating in z ∈ [−A/2, A/2]. As in the paper,
//! the box height h is measured from the piston at its highest position: the lid is at
//! `A/2 + h0 + (h − h0)` with `h0 = n·d`, the height of `n` layers of disks of diameter `d`
//! stacked square. The paper does not define `h0` beyond "the height of the bed at rest"; `n·d`
//! is our reading (a 2D random packing of `n` layers is somewhat lower, about 0.9 `n d`).
//!
//! The engine ([`engine::Bed`]) is generic over [`Restitution`], implemented for a plugin's
//! [`PluginRestitution`] and, through [`Compiled`], for any law compiled into the program;
//! another kind of law (a contact law integrated into a restitution, say) needs only one more
//! implementation of that trait.

pub mod cells;
pub mod engine;
pub mod events;

pub mod observables;
pub mod on_dem;
pub mod scaling;
pub mod spec;
pub mod statements;

pub use engine::{Bed, BedConfig, BedReport, EventRecord, Kind};

pub use dashpot_core::laws::{Compiled, PluginRestitution, Restitution};
use dashpot_sdk::{LawError, Pair, Particle};
pub use spec::LawChoice;

/// The restitution of the two kinds of pair in the bed: two disks, and a disk against a wall
/// (the lid or the piston, of infinite mass).
#[derive(Debug, Clone, Copy)]
pub struct Laws<R> {
    /// Disk against disk.
    pub disk: R,
    /// Disk against the lid or the piston.
    pub wall: R,
}

/// Young's modulus (Pa) given to the bed's disks when a law is bound to them: stainless steel.
/// Restitution laws of the paper do not use it.
pub const STEEL_YOUNG: f64 = 2.0e11;
/// Poisson's ratio given to the bed's disks: stainless steel.
pub const STEEL_POISSON: f64 = 0.3;

/// The particle a law is bound to: a sphere of diameter `d` (m) and mass `m` (kg) (the paper's
/// disks stand for 2 mm steel spheres), of steel's elastic moduli.
pub fn bed_particle(d: f64, m: f64) -> Particle {
    Particle {
        diameter: d,
        density: m / (std::f64::consts::PI / 6.0 * d * d * d),
        young: STEEL_YOUNG,
        poisson: STEEL_POISSON,
    }
}

/// The disk–disk and disk–wall pairs of the bed's particle.
pub fn bed_pairs(d: f64, m: f64) -> Result<(Pair, Pair), LawError> {
    particle_pairs(&bed_particle(d, m))
}

/// The disk–disk and disk–wall pairs of particle `p`.
fn particle_pairs(p: &Particle) -> Result<(Pair, Pair), LawError> {
    Ok((Pair::spheres(p, p)?, Pair::wall(p)?))
}

/// Restitution law `law` from the registry, bound to the pairs of the disks `p` (two disks, a
/// disk and a wall).
pub fn plugin_laws(
    reg: &crate::Registry,
    law: &LawChoice,
    p: &Particle,
) -> Result<Laws<PluginRestitution>, LawError> {
    let law = reg.restitution(&law.name, &law.params)?;
    let (pp, pw) = particle_pairs(p)?;
    Ok(Laws {
        disk: law.bind(&pp)?,
        wall: law.bind(&pw)?,
    })
}

/// Contact law `law`, turned into restitution laws for the disk–disk and disk–wall pairs of the
/// disks `p`: r(v) is the restitution the collision driver realizes at impact speed v, under
/// the end-of-contact criterion the law declares, tabulated on a log grid over [1e-4, 20] m/s
/// to within 1e-6 (power-law tails outside).
pub fn contact_laws(
    reg: &crate::Registry,
    law: &LawChoice,
    p: &Particle,
) -> Result<Laws<crate::collide::TabulatedRestitution>, LawError> {
    let (disk, wall) = crate::tabulate::contact_restitution(reg, &law.name, &law.params, p)?;
    Ok(Laws { disk, wall })
}

/// A restitution of any kind, chosen by name at run time.
pub type DynRestitution = Box<dyn Restitution + Send>;

impl<R> Laws<R> {
    /// Both laws as [`DynRestitution`]s, each as `wrap` makes it.
    fn boxed<W: Restitution + Send + 'static>(self, wrap: impl Fn(R) -> W) -> Laws<DynRestitution> {
        Laws {
            disk: Box::new(wrap(self.disk)),
            wall: Box::new(wrap(self.wall)),
        }
    }
}

/// The restitution `law`, bound to the pairs of the disks `p` (the bed's diameter and mass, and
/// a material: steel's by default ([`bed_particle`]), else what `--young` and `--poisson` give,
/// which a `from:LAW` table is computed for): what `dashpot bed`, `scaling` and `figures bed`
/// use. A name is a restitution-law plugin ([`plugin_laws`]), or `from:` a contact law
/// integrated over a collision ([`contact_laws`]).
pub fn resolve_for(
    reg: &crate::Registry,
    law: &LawChoice,
    p: &Particle,
) -> Result<Laws<DynRestitution>, LawError> {
    Ok(match law.name.strip_prefix(FROM_CONTACT) {
        Some(contact) => {
            let contact = LawChoice::new(contact, law.params.clone());
            contact_laws(reg, &contact, p)?.boxed(Compiled)
        }
        None => plugin_laws(reg, law, p)?.boxed(|law| law),
    })
}

/// The prefix that selects a contact law as a restitution law: `--restitution from:hsd`.
pub const FROM_CONTACT: &str = "from:";

/// What can go wrong in a bed run.
#[derive(Debug, thiserror::Error)]
pub enum BedError {
    /// A parameter out of its valid range.
    #[error("{0}")]
    Invalid(String),
    /// The law failed (or returned a coefficient outside [0, 1]).
    #[error("restitution law: {0}")]
    Law(#[from] LawError),
    /// The event rate exploded in simulated time (inelastic collapse, or disks crushed).
    #[error("{0}")]
    Collapse(String),
    /// Two disks, or a disk and a wall, overlap by more than the limit: a contact was missed.
    #[error("{0}")]
    Overlap(String),
    /// One run of several (a grid point, a seed) failed: which one, and why (the error kind
    /// kept).
    #[error("{point}: {error}")]
    InRun {
        /// The run, e.g. "n = 2, f = 20 Hz" or "seed 3".
        point: String,
        /// What went wrong.
        error: Box<BedError>,
    },
}
