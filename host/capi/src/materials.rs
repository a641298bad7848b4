//! Materials (sdk 0.2): what a contact or tangential law is bound to once per pair of materials.
//! Each contact's own effective mass and radius travel with the batch call, so a polydisperse
//! packing needs one binding per pair of materials, not one per pair of sizes.
//!
//! Conventions: 1/E_eff = (1 − ν1²)/E1 + (1 − ν2²)/E2; Mindlin's shear modulus
//! 1/G_eff = (2 − ν1)/G1 + (2 − ν2)/G2 with G = E/(2(1 + ν)). A flat wall is rigid:
//! E_eff = E1/(1 − ν1²), G_eff = G1/(2 − ν1).

use crate::error::{output, DashpotStatus};
use dashpot_sdk::{LawError, MaterialPair};

/// The effective moduli of a pair of materials (SI).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DashpotMaterials {
    /// Effective Young's modulus E_eff (Pa).
    pub young_eff: f64,
    /// Effective (Mindlin) shear modulus G_eff (Pa).
    pub shear_eff: f64,
}

impl From<MaterialPair> for DashpotMaterials {
    fn from(m: MaterialPair) -> Self {
        DashpotMaterials {
            young_eff: m.young,
            shear_eff: m.shear,
        }
    }
}

impl DashpotMaterials {
    /// The sdk's material pair, validated (both moduli finite and > 0).
    pub fn to_materials(&self) -> Result<MaterialPair, LawError> {
        MaterialPair::new(self.young_eff, self.shear_eff)
    }
}

/// The materials of two spheres of Young's moduli `young1`, `young2` (Pa) and Poisson's ratios
/// `poisson1`, `poisson2`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (`out_materials`), `DASHPOT_ERR_INVALID_PAIR` (a modulus
/// not finite and > 0, or a ratio outside (−1, 0.5); the message names it). Thread-safe.
///
/// # Safety
/// `out_materials` must be null or valid for writing.
#[no_mangle]
pub unsafe extern "C" fn dashpot_materials_spheres(
    young1: f64,
    poisson1: f64,
    young2: f64,
    poisson2: f64,
    out_materials: *mut DashpotMaterials,
) -> DashpotStatus {
    output!(=> out_materials = MaterialPair::of_moduli(young1, poisson1, Some((young2, poisson2)))?.into())
}

/// The materials of a sphere (Young's modulus `young` in Pa, Poisson's ratio `poisson`) against a
/// flat rigid wall.
///
/// Errors and thread safety as [`dashpot_materials_spheres`].
///
/// # Safety
/// `out_materials` must be null or valid for writing.
#[no_mangle]
pub unsafe extern "C" fn dashpot_materials_wall(
    young: f64,
    poisson: f64,
    out_materials: *mut DashpotMaterials,
) -> DashpotStatus {
    output!(=> out_materials = MaterialPair::of_moduli(young, poisson, None)?.into())
}
