//! # LAMMPS's granular sub-models as dashpot plugins (`gran-*`)
//!
//! The normal, damping, tangential, rolling and twisting sub-models of LAMMPS's `pair_style
//! granular` (and the friction of its classic `gran/*` styles) with exactly LAMMPS's physics:
//! the same forces and torques to rounding, step by step, as the LAMMPS this project pins
//! (22 Jul 2025, update 4), when the host passes LAMMPS's geometry.
//!
//! - Kernels ([`normal`], [`tangential`], [`rotation`]): pure functions of explicit inputs in
//!   LAMMPS's order of operations.
//! - Laws: damping is part of the normal law (LAMMPS's damping prefactors read the normal
//!   model's stiffness, elastic force and contact radius), so each normal × damping pair LAMMPS
//!   accepts is one contact law `gran-NORMAL-DAMPING` ([`normal_laws`]); the tangential
//!   ([`tangential_laws`]), rolling and twisting ([`rotation_laws`]) laws read the normal law's
//!   context (contact radius, LAMMPS's `Fncrit` and `damp_prefactor`).
//!
//! docs/laws.md lists the laws, the LAMMPS keyword each mirrors, and what the host computes.

#![warn(missing_docs)]

pub mod calibrate;
pub mod cbrt;
mod docs;
pub mod normal;
#[cfg(target_arch = "x86_64")]
mod normal_avx2;
pub mod normal_laws;
pub mod rotation;
#[cfg(target_arch = "x86_64")]
mod rotation_avx2;
pub mod rotation_laws;
pub mod spring;
pub mod tangential;
#[cfg(target_arch = "x86_64")]
mod tangential_avx2;
pub mod tangential_laws;

use normal_laws::*;
use rotation_laws::{GranRollingSds, GranTwistingMarshall, GranTwistingSds};
use tangential_laws::*;

// No comma between the contact and tangential groups: the sdk 0.3 macro's optional commas
// around the skipped restitution group would otherwise parse two ways.
dashpot_sdk::export_laws!(
    contact: [
        GranHookeVelocity,
        GranHookeMassVelocity,
        GranHookeViscoelastic,
        GranHookeTsuji,
        GranHookeCoeffRestitution,
        GranHertzVelocity,
        GranHertzMassVelocity,
        GranHertzViscoelastic,
        GranHertzTsuji,
        GranHertzCoeffRestitution,
        GranHertzMaterialVelocity,
        GranHertzMaterialMassVelocity,
        GranHertzMaterialViscoelastic,
        GranHertzMaterialTsuji,
        GranHertzMaterialCoeffRestitution,
        GranDmtVelocity,
        GranDmtMassVelocity,
        GranDmtViscoelastic,
        GranJkrVelocity,
        GranJkrMassVelocity,
        GranJkrViscoelastic,
    ]
    tangential: [
        GranLinearNoHistory,
        GranLinearHistory,
        GranMindlin,
        GranMindlinRescale,
        GranMindlinForce,
        GranMindlinRescaleForce,
        GranLinearHistoryClassic,
        GranMindlinClassic,
        GranWallHistoryClassic,
    ],
    rolling: [GranRollingSds],
    twisting: [GranTwistingSds, GranTwistingMarshall],
);
