//! Particles and pairs: the effective mass, radius and modulus a law is bound to.
//!
//! Conventions (the project's, Antypov & Elliott 2011): m = m1 m2/(m1 + m2),
//! r = r1 r2/(r1 + r2), 1/E = (1 − ν1²)/E1 + (1 − ν2²)/E2. A flat wall is a rigid partner of
//! infinite mass and radius: m = m1, r = r1, E = E1/(1 − ν1²).

use crate::error::{output, CError, DashpotStatus};
use dashpot_sdk::{LawError, Pair, Particle};

/// One sphere, in SI units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DashpotParticle {
    /// Diameter (m), > 0.
    pub diameter: f64,
    /// Density (kg/m³), > 0.
    pub density: f64,
    /// Young's modulus (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio, in (−1, 0.5).
    pub poisson: f64,
}

/// The effective properties of a contacting pair: all a law sees of the two bodies.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DashpotPair {
    /// Effective mass (kg).
    pub mass: f64,
    /// Effective radius (m).
    pub radius: f64,
    /// Effective Young's modulus (Pa).
    pub young: f64,
}

impl From<Pair> for DashpotPair {
    fn from(p: Pair) -> Self {
        DashpotPair {
            mass: p.mass,
            radius: p.radius,
            young: p.young,
        }
    }
}

impl DashpotPair {
    /// The sdk's pair, validated (all three finite and > 0).
    pub fn to_pair(&self) -> Result<Pair, LawError> {
        Pair::new(self.mass, self.radius, self.young)
    }
}

impl From<&DashpotParticle> for Particle {
    fn from(p: &DashpotParticle) -> Particle {
        Particle {
            diameter: p.diameter,
            density: p.density,
            young: p.young,
            poisson: p.poisson,
        }
    }
}

/// A body given by its diameter (m), mass (kg), Young's modulus (Pa) and Poisson's ratio, each
/// checked (named with `which`: "1", "2" or "" for the one body of a wall pair): its radius,
/// mass and plane-strain modulus E/(1 − ν²).
fn body_of_mass(diameter: f64, mass: f64, young: f64, poisson: f64, which: &str) -> Result<[f64; 3], CError> {
    let positive = |v: f64, what: &str, unit: &str| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(LawError::invalid_pair(format!(
                "{what}{which} ({unit}) = {v} is out of range: it must be finite and > 0"
            )))
        }
    };
    positive(diameter, "diameter", "m")?;
    positive(mass, "mass", "kg")?;
    // The same checks as dashpot_sdk::Particle::validate, for a particle given by its mass.
    let p = Particle {
        diameter,
        density: 1.0,
        young,
        poisson,
    };
    let particle = format!("particle {which}");
    p.validate()
        .map_err(|e| LawError::invalid_pair(format!("{}: {}", particle.trim_end(), e.message)))?;
    Ok([0.5 * diameter, mass, p.plane_strain_modulus()])
}

/// The pair of two spheres `a` and `b`, each given by diameter, density, E and ν.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_PAIR` (a property out of range; the
/// message names it). Ownership: reads `*a`, `*b`, writes `*out`; nothing to free.
/// Thread-safe.
///
/// # Safety
/// Non-null pointers must be valid for the access described.
#[no_mangle]
pub unsafe extern "C" fn dashpot_pair_spheres(
    a: *const DashpotParticle,
    b: *const DashpotParticle,
    out_pair: *mut DashpotPair,
) -> DashpotStatus {
    output!(arg a, arg b => out_pair = Pair::spheres(&a.into(), &b.into())?.into())
}

/// The pair of sphere `a` and a flat rigid wall of infinite mass.
///
/// Errors, ownership and thread safety as [`dashpot_pair_spheres`].
///
/// # Safety
/// Non-null pointers must be valid for the access described.
#[no_mangle]
pub unsafe extern "C" fn dashpot_pair_wall(
    a: *const DashpotParticle,
    out_pair: *mut DashpotPair,
) -> DashpotStatus {
    output!(arg a => out_pair = Pair::wall(&a.into())?.into())
}

/// The pair of two spheres given by diameter (m), mass (kg), E (Pa) and ν each, as DEM codes
/// store them (LAMMPS's `radius` and `rmass`).
///
/// Errors, ownership and thread safety as [`dashpot_pair_spheres`].
///
/// # Safety
/// `out_pair` must be null or valid for writing.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_pair_from_masses(
    diameter1: f64,
    mass1: f64,
    young1: f64,
    poisson1: f64,
    diameter2: f64,
    mass2: f64,
    young2: f64,
    poisson2: f64,
    out_pair: *mut DashpotPair,
) -> DashpotStatus {
    output!(=> out_pair = {
        let [r1, m1, e1] = body_of_mass(diameter1, mass1, young1, poisson1, "1")?;
        let [r2, m2, e2] = body_of_mass(diameter2, mass2, young2, poisson2, "2")?;
        Pair::new(m1 * m2 / (m1 + m2), r1 * r2 / (r1 + r2), 1.0 / (1.0 / e1 + 1.0 / e2))?.into()
    })
}

/// The pair of a sphere given by diameter (m), mass (kg), E (Pa) and ν and a flat rigid wall.
///
/// Errors, ownership and thread safety as [`dashpot_pair_spheres`].
///
/// # Safety
/// `out_pair` must be null or valid for writing.
#[no_mangle]
pub unsafe extern "C" fn dashpot_pair_wall_from_mass(
    diameter: f64,
    mass: f64,
    young: f64,
    poisson: f64,
    out_pair: *mut DashpotPair,
) -> DashpotStatus {
    output!(=> out_pair = {
        let [r, m, e] = body_of_mass(diameter, mass, young, poisson, "")?;
        Pair::new(m, r, e)?.into()
    })
}
