//! The frozen types of sdk 0.2, through which a 0.3 host still talks to plugins built against
//! sdk 0.2: its law list (sdk 0.3 added law kinds to [`LawKind`], which changes the layout of
//! every type that reaches it), its root module, and its contact and tangential laws (vtables and
//! raw batches; the 0.3 normal batch embeds the 0.2 one). The restitution ABI is 0.1's, shared.
//! Their layout must never change: abi_stable compares it, field by field, with the one recorded
//! in every 0.2 plugin.

use super::fault::{BatchFault, BatchStatus};
use super::ffi::ParamValue;
use super::object::ffi_object;
use super::series::{frozen_law_info, root_module};
use crate::error::FfiError;
use crate::law::EndCriterion;
use crate::pair::MaterialPair;
use abi_stable::{
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};
use std::ffi::c_void;

frozen_law_info!(
    "0.2",
    [
        Contact = 1: "A normal contact force F(δ, δ̇) (N), possibly with per-contact history.",
        Restitution = 2: "A restitution coefficient r(v).",
        Tangential = 3: "A tangential (friction) force (N), with per-contact history."
    ],
    history
);

root_module!(
    /// The root module of an sdk 0.2 plugin, exactly as 0.2 declared it (with its law list in the
    /// 0.2 description).
    {
        /// sdk 0.1's law list.
        pub laws: extern "C" fn() -> RResult<RVec<super::v1::LawInfo>, FfiError>,
        /// sdk 0.1's contact-law constructor (an error in a 0.2 plugin).
        pub new_contact: extern "C" fn(
            name: RStr<'_>,
            params: RSlice<'_, ParamValue>,
        ) -> RResult<super::v1::FfiContactLaw, FfiError>,
    }
    /// The 0.2 law list.
    #[sabi(missing_field(option))]
    pub laws2: extern "C" fn() -> RResult<RVec<LawInfo>, FfiError>,
    /// Creates a contact law (bound later to a material pair).
    #[sabi(missing_field(option))]
    pub new_contact2:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiContactLaw, FfiError>,
    /// Creates a tangential law.
    #[sabi(missing_field(option))]
    pub new_tangential:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiTangentialLaw, FfiError>,
);

/// A batch of contacts for a normal law, as raw arrays (see [`NormalBatch`](crate::NormalBatch)).
/// All pointers refer to `n` values except `history` (`n × slots`); they may dangle when
/// `n == 0`.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiNormalBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Overlaps δ (m).
    pub delta: *const f64,
    /// Overlap rates δ̇ (m/s), > 0 approaching.
    pub rate: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history (`n × slots`), updated in place.
    pub history: *mut f64,
    /// Output: normal forces (N).
    pub force: *mut f64,
}

/// A batch of contacts for a tangential law, as raw arrays (see
/// [`TangentialBatch`](crate::TangentialBatch)); vectors are `n` `[x, y, z]` triples.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiTangentialBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Unit normals (3n values).
    pub normal: *const f64,
    /// Relative contact-point velocities (m/s, 3n values).
    pub velocity: *const f64,
    /// Normal forces (N).
    pub normal_force: *const f64,
    /// Overlaps (m).
    pub delta: *const f64,
    /// Effective masses (kg).
    pub mass: *const f64,
    /// Effective radii (m).
    pub radius: *const f64,
    /// Per-contact history (`n × slots`), updated in place.
    pub history: *mut f64,
    /// Output: tangential forces (N, 3n values).
    pub force: *mut f64,
}

ffi_object!(law
    /// The functions of a configured 0.2 contact law (not yet bound to materials).
    ContactLawVTable {
        /// Binds the law at `obj` to a pair of materials.
        pub bind: unsafe extern "C" fn(
            obj: *const c_void,
            materials: &MaterialPair,
        ) -> RResult<FfiContactModel, FfiError>,
    }
    /// A configured 0.2 contact law owned by the plugin that made it.
    FfiContactLaw
);

ffi_object!(model_with_coefficients
    /// The hot-path functions of a contact law bound to a pair of materials.
    ContactModelVTable {
        /// Evaluates a batch; checks inputs and outputs in blocks as it goes and stops at the first
        /// bad one, described in `*fault`.
        pub force_batch: unsafe extern "C" fn(
            obj: *const c_void,
            batch: &FfiNormalBatch,
            fault: &mut BatchFault,
        ) -> BatchStatus,
    }
    /// A contact law bound to a pair of materials, owned by the plugin that made it.
    FfiContactModel
);

ffi_object!(law
    /// The functions of a configured tangential law.
    TangentialLawVTable {
        /// Binds the law at `obj` to a pair of materials.
        pub bind: unsafe extern "C" fn(
            obj: *const c_void,
            materials: &MaterialPair,
        ) -> RResult<FfiTangentialModel, FfiError>,
    }
    /// A configured tangential law owned by the plugin that made it.
    FfiTangentialLaw
);

ffi_object!(model
    /// The hot-path functions of a tangential law bound to a pair of materials.
    TangentialModelVTable {
        /// Evaluates a batch, checked like [`ContactModelVTable::force_batch`].
        pub force_batch: unsafe extern "C" fn(
            obj: *const c_void,
            batch: &FfiTangentialBatch,
            fault: &mut BatchFault,
        ) -> BatchStatus,
    }
    /// A tangential law bound to a pair of materials, owned by the plugin that made it.
    FfiTangentialModel
);
