//! The frozen types of sdk 0.2 that sdk 0.3 changed, through which a 0.3 host still talks to
//! plugins built against sdk 0.2. sdk 0.3 added law kinds (rolling, twisting) to [`LawKind`],
//! which changes the layout of every type that reaches it; a 0.2 plugin's law list is therefore
//! read through these copies. Every other type a 0.2 plugin's root module reaches (the contact,
//! tangential and restitution vtables and batches) is unchanged in 0.3 and shared. Their layout
//! must never change: abi_stable compares it, field by field, with the one recorded in every
//! 0.2 plugin.

use super::{FfiContactLaw, FfiRestitutionLaw, FfiTangentialLaw};
use crate::error::FfiError;
use crate::law::{CalibrationTarget, EndCriterion, HistorySlot};
use crate::pair::Pair;
use crate::params::{ParamSpec, ParamValue};
use abi_stable::{
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};

/// Which kind of law (sdk 0.2).
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LawKind {
    /// A normal contact force F(δ, δ̇) (N), possibly with per-contact history.
    Contact = 1,
    /// A restitution coefficient r(v).
    Restitution = 2,
    /// A tangential (friction) force (N), with per-contact history.
    Tangential = 3,
}

/// A law's description (sdk 0.2).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, PartialEq)]
pub struct LawInfo {
    /// Name.
    pub name: RString,
    /// Kind.
    pub kind: LawKind,
    /// One line.
    pub summary: RString,
    /// Documentation.
    pub doc: RString,
    /// Parameter schema.
    pub params: RVec<ParamSpec>,
    /// End criterion of a contact law.
    pub end_criterion: ROption<EndCriterion>,
    /// Per-contact history slots.
    pub history: RVec<HistorySlot>,
}

/// The root module of an sdk 0.2 plugin, exactly as 0.2 declared it (with its law list in the
/// 0.2 description).
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = PluginModuleRef)))]
#[sabi(missing_field(panic))]
pub struct PluginModule {
    /// The plugin crate's name.
    pub name: RStr<'static>,
    /// The plugin crate's version.
    pub version: RStr<'static>,
    /// The dashpot-sdk version it was built against.
    pub sdk_version: RStr<'static>,
    /// sdk 0.1's law list.
    pub laws: extern "C" fn() -> RResult<RVec<super::v1::LawInfo>, FfiError>,
    /// sdk 0.1's contact-law constructor (an error in a 0.2 plugin).
    pub new_contact: extern "C" fn(
        name: RStr<'_>,
        params: RSlice<'_, ParamValue>,
    ) -> RResult<super::v1::FfiContactLaw, FfiError>,
    /// Creates a restitution law.
    pub new_restitution:
        extern "C" fn(name: RStr<'_>, params: RSlice<'_, ParamValue>) -> RResult<FfiRestitutionLaw, FfiError>,
    /// Closed-form calibration.
    #[sabi(last_prefix_field)]
    pub calibrate: extern "C" fn(
        name: RStr<'_>,
        target: &CalibrationTarget,
        pair: &Pair,
        fixed: RSlice<'_, ParamValue>,
    ) -> RResult<ROption<RVec<ParamValue>>, FfiError>,
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
}

impl LawInfo {
    /// The 0.3 description of a 0.2 law.
    pub fn upgrade(self) -> crate::law::LawInfo {
        crate::law::LawInfo {
            name: self.name,
            kind: match self.kind {
                LawKind::Contact => crate::law::LawKind::Contact,
                LawKind::Restitution => crate::law::LawKind::Restitution,
                LawKind::Tangential => crate::law::LawKind::Tangential,
            },
            summary: self.summary,
            doc: self.doc,
            params: self.params,
            end_criterion: self.end_criterion,
            history: self.history,
        }
    }

    /// The 0.2 description of a 0.3 law, `None` for a kind 0.2 did not have.
    pub fn downgrade(i: crate::law::LawInfo) -> Option<LawInfo> {
        let kind = match i.kind {
            crate::law::LawKind::Contact => LawKind::Contact,
            crate::law::LawKind::Restitution => LawKind::Restitution,
            crate::law::LawKind::Tangential => LawKind::Tangential,
            _ => return None,
        };
        Some(LawInfo {
            name: i.name,
            kind,
            summary: i.summary,
            doc: i.doc,
            params: i.params,
            end_criterion: i.end_criterion,
            history: i.history,
        })
    }
}
