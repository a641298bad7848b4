//! # Soft-sphere DEM: many particles, every contact through the laws' batch calls
#![warn(missing_docs)]
//!
//! Disks (2D) or spheres (3D), generic over the dimension `D` with nalgebra's fixed-size
//! vectors: translation and rotation, polydisperse sizes, gravity, periodic axes, flat walls
//! fixed or moving (a piston), all contacts (particle pairs and particle–wall) evaluated each
//! step by a normal [`NormalLaw`] and an optional [`TangentialForce`], one batch call per chunk
//! of contacts, in parallel.
//!
//! - [`state`]: the particles (structure of arrays), the 2D mass convention ([`DiskMass`]);
//! - [`cells`]: the domain (periodic axes) and the neighbour list (cells + skin);
//! - [`contacts`]: contacts gathered into arrays, history carried over by key;
//! - [`walls`]: walls and their motion;
//! - [`checkpoint`]: checkpoint files (the whole state, to resume a run bit for bit);
//! - [`integrator`]: the engine and its step (velocity Verlet with a predicted velocity for the
//!   rate-dependent forces), the choice of the time step;
//! - [`heat`]: temperatures and the heat the contacts conduct (sdk 0.4);
//! - [`observables`]: energies, contacts, wall impulses;
//! - [`scene`]: the TOML scene format and the packing generator; [`xyz`]: trajectories;
//! - [`bed`]: McNamara & Falcon's vibrated bed on this engine.

pub mod cells;
pub mod checkpoint;
pub mod contacts;
pub mod footprint;
pub mod heat;
pub mod integrator;
pub mod observables;
pub mod scene;
pub mod species;
pub mod state;
pub mod walls;
pub mod xyz;

pub use cells::Domain;
pub use integrator::{Engine, EngineConfig};
pub use species::{LawSet, SpeciesInfo, SpeciesLaws};
pub use state::{Body, DiskMass, Material, Vec3, VecD};
pub use walls::{Motion, Wall};

use crate::laws::{HeatConduction, NormalLaw, RollingResistance, TangentialForce, TwistingResistance};
use dashpot_sdk::LawError;

/// The laws of a run, each bound twice: to the particle pair (`MaterialPair::spheres`) and to
/// the particle–wall pair (`MaterialPair::wall`).
pub struct Laws {
    /// Normal law between particles.
    pub pair: Box<dyn NormalLaw>,
    /// Normal law against walls.
    pub wall: Box<dyn NormalLaw>,
    /// Tangential law between particles (none: frictionless).
    pub pair_tangential: Option<Box<dyn TangentialForce>>,
    /// Tangential law against walls.
    pub wall_tangential: Option<Box<dyn TangentialForce>>,
    /// Rolling and twisting resistance (sdk 0.3), if any.
    pub rotation: Rotation,
}

/// The rolling and twisting laws of a run (sdk 0.3) and its heat conduction (sdk 0.4), each
/// bound to particle pairs and to particle–wall pairs; none by default.
#[derive(Default)]
pub struct Rotation {
    /// Rolling resistance between particles.
    pub pair_rolling: Option<Box<dyn RollingResistance>>,
    /// Rolling resistance against walls.
    pub wall_rolling: Option<Box<dyn RollingResistance>>,
    /// Twisting resistance between particles.
    pub pair_twisting: Option<Box<dyn TwistingResistance>>,
    /// Twisting resistance against walls.
    pub wall_twisting: Option<Box<dyn TwistingResistance>>,
    /// Heat conduction between particles (see [`Engine::with_heat`]).
    pub pair_heat: Option<Box<dyn HeatConduction>>,
    /// Heat conduction against walls.
    pub wall_heat: Option<Box<dyn HeatConduction>>,
}

impl Rotation {
    /// Whether any rolling or twisting law is set.
    pub fn any(&self) -> bool {
        self.pair_rolling.is_some() || self.pair_twisting.is_some()
    }
}

impl Laws {
    /// Loads `normal` (and `tangential`) from the registry, bound to `mat` for particle pairs and
    /// particle–wall pairs.
    pub fn from_registry(
        reg: &crate::Registry,
        normal: (&str, &[dashpot_sdk::ParamValue]),
        tangential: Option<(&str, &[dashpot_sdk::ParamValue])>,
        mat: &Material,
    ) -> Result<Laws, LawError> {
        let (pp, pw) = material_pairs(mat)?;
        let n = reg.contact(normal.0, normal.1)?;
        let (pair_tangential, wall_tangential): (OptTangential, OptTangential) = match tangential {
            Some((name, params)) => {
                let t = reg.tangential(name, params)?;
                (Some(Box::new(t.bind(&pp)?)), Some(Box::new(t.bind(&pw)?)))
            }
            None => (None, None),
        };
        Ok(Laws {
            pair: Box::new(n.bind(&pp)?),
            wall: Box::new(n.bind(&pw)?),
            pair_tangential,
            wall_tangential,
            rotation: Rotation::default(),
        })
    }

    /// Adds the rolling law `rolling` and the twisting law `twisting` (name and parameters, each
    /// optional) from the registry, bound to `mat` for particle pairs and particle–wall pairs.
    pub fn with_rotation(
        mut self,
        reg: &crate::Registry,
        rolling: Option<(&str, &[dashpot_sdk::ParamValue])>,
        twisting: Option<(&str, &[dashpot_sdk::ParamValue])>,
        mat: &Material,
    ) -> Result<Laws, LawError> {
        let (pp, pw) = material_pairs(mat)?;
        if let Some((name, params)) = rolling {
            let l = reg.rolling(name, params)?;
            self.rotation.pair_rolling = Some(Box::new(l.bind(&pp)?));
            self.rotation.wall_rolling = Some(Box::new(l.bind(&pw)?));
        }
        if let Some((name, params)) = twisting {
            let l = reg.twisting(name, params)?;
            self.rotation.pair_twisting = Some(Box::new(l.bind(&pp)?));
            self.rotation.wall_twisting = Some(Box::new(l.bind(&pw)?));
        }
        Ok(self)
    }

    /// Adds the heat law `heat` (name and parameters) from the registry, bound to `mat` for
    /// particle pairs and particle–wall pairs (it acts once the engine has temperatures:
    /// [`Engine::with_heat`]).
    pub fn with_heat(
        mut self,
        reg: &crate::Registry,
        heat: (&str, &[dashpot_sdk::ParamValue]),
        mat: &Material,
    ) -> Result<Laws, LawError> {
        let (pp, pw) = material_pairs(mat)?;
        let l = reg.heat(heat.0, heat.1)?;
        self.rotation.pair_heat = Some(Box::new(l.bind(&pp)?));
        self.rotation.wall_heat = Some(Box::new(l.bind(&pw)?));
        Ok(self)
    }
}

/// The particle–particle and particle–wall material pairs of `mat` (what each law binds to).
fn material_pairs(
    mat: &Material,
) -> Result<(dashpot_sdk::MaterialPair, dashpot_sdk::MaterialPair), LawError> {
    let p = mat.particle(1.0);
    Ok((
        dashpot_sdk::MaterialPair::spheres(&p, &p)?,
        dashpot_sdk::MaterialPair::wall(&p)?,
    ))
}

/// A tangential law, if any.
type OptTangential = Option<Box<dyn TangentialForce>>;

/// Why a DEM run stopped.
#[derive(Debug, thiserror::Error)]
pub enum DemError {
    /// A law failed (error, panic, non-finite force).
    #[error(transparent)]
    Law(#[from] LawError),
    /// The two-body integrator could not find the collision time used to choose the step.
    #[error("choosing the time step: {0}")]
    Timestep(String),
    /// Bad input: the message names the value and the valid range.
    #[error("{0}")]
    Invalid(String),
    /// An overlap beyond the sane bound: the step is too large or the material too soft.
    #[error(
        "particle {i} overlaps {partner} by {delta:.4e} m, more than {frac} of the radius {radius:.4e} m: \
         the time step is too large for the impact speeds, or the material too soft (set a smaller dt or a larger young)",
        frac = contacts::MAX_OVERLAP
    )]
    Overlap {
        /// The particle.
        i: usize,
        /// The other particle or the wall.
        partner: String,
        /// The overlap (m).
        delta: f64,
        /// The smaller radius (m).
        radius: f64,
    },
    /// A particle's state is not finite.
    #[error(
        "particle {i} has a non-finite state at t = {t} s (position {pos}, velocity {vel}, angular velocity {spin})"
    )]
    NonFinite {
        /// The particle.
        i: usize,
        /// Time (s).
        t: f64,
        /// Position, formatted.
        pos: String,
        /// Velocity, formatted.
        vel: String,
        /// Angular velocity, formatted.
        spin: String,
    },
    /// One run of a grid failed: which one, and why (the error kind kept).
    #[error("{point}: {error}")]
    InRun {
        /// The run, e.g. "n = 2, f = 20 Hz".
        point: String,
        /// What went wrong.
        error: Box<DemError>,
    },
    /// A particle left the bounded domain.
    #[error(
        "particle {i} left the domain at t = {t} s: position {pos} outside [{lo}, {hi}] along axis {axis}"
    )]
    Lost {
        /// The particle.
        i: usize,
        /// Time (s).
        t: f64,
        /// Position, formatted.
        pos: String,
        /// Axis.
        axis: usize,
        /// Lower bound (m).
        lo: f64,
        /// Upper bound (m).
        hi: f64,
    },
}
