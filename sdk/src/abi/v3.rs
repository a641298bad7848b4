//! The frozen types of sdk 0.3, through which a 0.4 host still talks to plugins built against
//! sdk 0.3: its law list (sdk 0.4 added the heat kind to [`LawKind`] and `reads_context` to the
//! law description, which changes the layout of every type that reaches them), its root module,
//! and the raw batches of its kinds (the 0.4 batches embed them, adding the normal context). Its
//! vtables are the generic ones of [`kind`](super::kind), over these batches. Their layout must
//! never change: abi_stable compares it, field by field, with the one recorded in every 0.3
//! plugin.

use super::ffi::ParamValue;
use super::kind::FfiLaw;
use super::series::{frozen_law_info, root_module};
use super::v2;
use crate::error::FfiError;
use crate::law::EndCriterion;
use abi_stable::{
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};

frozen_law_info!(
    "0.3",
    [
        Contact = 1: "A normal contact force F(δ, δ̇) (N), possibly with per-contact history.",
        Restitution = 2: "A restitution coefficient r(v).",
        Tangential = 3: "A tangential (friction) force (N), with per-contact history.",
        Rolling = 4: "A rolling-resistance force (N), with per-contact history.",
        Twisting = 5: "A twisting torque (N·m) about the normal, with per-contact history."
    ],
    history
);

root_module!(
    /// The root module of an sdk 0.3 plugin, exactly as 0.3 declared it.
    {
        /// Every law the plugin exports, of every kind.
        pub laws: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
        /// Creates contact law `name` from parameters (validated against its schema).
        pub new_contact: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<FfiLaw<FfiNormalBatch3>, FfiError>,
        /// Creates tangential law `name`.
        pub new_tangential: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<FfiLaw<FfiVectorBatch>, FfiError>,
        /// Creates rolling law `name`.
        pub new_rolling: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<FfiLaw<FfiVectorBatch>, FfiError>,
        /// Creates twisting law `name`.
        pub new_twisting: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<FfiLaw<FfiTwistingBatch>, FfiError>,
    }
);

/// A raw 0.3 normal batch: 0.2's arrays, plus the optional outputs (null when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiNormalBatch3 {
    /// The 0.2 arrays.
    pub base: v2::FfiNormalBatch,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
    /// Output: reach per contact (m, ≥ 0; the contact ends at δ < −reach), or null.
    pub reach: *mut f64,
}

/// A raw 0.3 batch of a vector kind (tangential, rolling): 0.2's tangential arrays (vectors are `n`
/// `[x, y, z]` triples, `history` is `n × slots`), plus the optional energy outputs (null when
/// not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiVectorBatch {
    /// The 0.2 arrays.
    pub base: v2::FfiTangentialBatch,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
}

/// A raw 0.3 twisting batch: `normal` is `n` `[x, y, z]` triples, the rest `n` values, `history`
/// `n × slots`; `power` and `elastic` optional outputs (null when not wanted).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiTwistingBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Unit normals (3n values).
    pub normal: *const f64,
    /// Relative twisting rates (rad/s).
    pub rate: *const f64,
    /// Normal forces (N).
    pub normal_force: *const f64,
    /// Overlaps (m).
    pub delta: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history, updated in place.
    pub history: *mut f64,
    /// Output: twisting torques about n̂ (N·m).
    pub torque: *mut f64,
    /// Output: dissipated power per contact (W), or null.
    pub power: *mut f64,
    /// Output: elastic energy per contact (J), or null.
    pub elastic: *mut f64,
}
