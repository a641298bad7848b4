//! The kinds of law the C ABI offers: their opaque handles, and each kind's `new`, `free`,
//! binding and history-width functions generated from the shapes of `handle.rs` (the header
//! declares them with the matching `DASHPOT_*_FUNCTIONS` macros).

use crate::error::{CError, DashpotStatus::*};
use crate::handle::{law_functions, model_functions, pair_functions, BindMaterials, BindPair, Model, NewLaw};
use dashpot_sdk::abi::{
    BoundRestitutionHandle, ContactLawHandle, ContactModelHandle, Heat, LawHandle, ModelHandle,
    RestitutionLawHandle, Rolling, TangentialLawHandle, TangentialModelHandle, Twisting,
};
use dashpot_sdk::{MaterialPair, Pair, ParamValue};

/// A configured contact (normal-force) law (opaque).
pub struct DashpotContactLaw {
    pub(crate) law: ContactLawHandle,
    /// The parameters it was created with (named in refusals).
    pub(crate) params: Vec<ParamValue>,
}

/// A contact law bound to a pair of materials (opaque): the hot path of a polydisperse DEM code.
pub struct DashpotContactModel {
    pub(crate) model: ContactModelHandle,
}

/// A contact law bound to one pair (opaque): the sdk 0.1 hot path.
pub struct DashpotBoundContact {
    pub(crate) model: ContactModelHandle,
    pub(crate) mass: f64,
    pub(crate) radius: f64,
}

/// A configured tangential (friction) law (opaque).
pub struct DashpotTangentialLaw {
    pub(crate) law: TangentialLawHandle,
}

/// A tangential law bound to a pair of materials (opaque).
pub struct DashpotTangentialModel {
    pub(crate) model: TangentialModelHandle,
}

/// A configured rolling-resistance law (opaque).
pub struct DashpotRollingLaw {
    pub(crate) law: LawHandle<Rolling>,
}

/// A rolling-resistance law bound to a pair of materials (opaque).
pub struct DashpotRollingModel {
    pub(crate) model: ModelHandle<Rolling>,
}

/// A configured twisting-resistance law (opaque).
pub struct DashpotTwistingLaw {
    pub(crate) law: LawHandle<Twisting>,
}

/// A twisting-resistance law bound to a pair of materials (opaque).
pub struct DashpotTwistingModel {
    pub(crate) model: ModelHandle<Twisting>,
}

/// A configured heat-conduction law (opaque; sdk 0.4).
pub struct DashpotHeatLaw {
    pub(crate) law: LawHandle<Heat>,
}

/// A heat-conduction law bound to a pair of materials (opaque; sdk 0.4).
pub struct DashpotHeatModel {
    pub(crate) model: ModelHandle<Heat>,
}

/// A configured restitution law r(v) (opaque).
pub struct DashpotRestitutionLaw {
    pub(crate) law: RestitutionLawHandle,
}

/// A restitution law bound to a pair (opaque).
pub struct DashpotBoundRestitution {
    pub(crate) bound: BoundRestitutionHandle,
}

/// A kind made by `Registry::$make`, whose handle binds to materials into a model handle (and,
/// given `params`, that keeps the parameters it was made with).
macro_rules! material_kind {
    ($($law:ident = $make:ident => $model:ident $(, $keep:ident)?;)*) => {$(
        impl NewLaw for $law {
            fn make(reg: &dashpot_core::Registry, name: &str, p: &[ParamValue]) -> Result<Self, CError> {
                Ok($law {
                    law: reg.$make(name, p)?,
                    $($keep: p.to_vec(),)?
                })
            }
        }

        impl BindMaterials for $law {
            type Model = $model;
            fn bind_materials(&self, m: &MaterialPair) -> Result<$model, CError> {
                Ok($model { model: self.law.bind(m)? })
            }
        }

        impl Model for $model {
            fn slots(&self) -> usize {
                self.model.history_slots()
            }
            fn law_name(&self) -> &str {
                self.model.name()
            }
            fn reads_context(&self) -> bool {
                self.model.reads_context()
            }
        }
    )*};
}

material_kind! {
    DashpotContactLaw = contact => DashpotContactModel, params;
    DashpotTangentialLaw = tangential => DashpotTangentialModel;
    DashpotRollingLaw = rolling => DashpotRollingModel;
    DashpotTwistingLaw = twisting => DashpotTwistingModel;
    DashpotHeatLaw = heat => DashpotHeatModel;
}

impl NewLaw for DashpotRestitutionLaw {
    fn make(reg: &dashpot_core::Registry, name: &str, p: &[ParamValue]) -> Result<Self, CError> {
        Ok(DashpotRestitutionLaw {
            law: reg.restitution(name, p)?,
        })
    }
}

impl BindPair for DashpotRestitutionLaw {
    type Bound = DashpotBoundRestitution;
    fn bind_pair(&self, pair: &Pair) -> Result<DashpotBoundRestitution, CError> {
        Ok(DashpotBoundRestitution {
            bound: self.law.bind(pair)?,
        })
    }
}

/// The pair carries no shear modulus: the binding takes the one of two bodies of Poisson's
/// ratio 0.3 (no normal law of the project uses it). A law with per-contact history has nowhere
/// to keep it in a pair binding and is refused.
impl BindPair for DashpotContactLaw {
    type Bound = DashpotBoundContact;
    fn bind_pair(&self, pair: &Pair) -> Result<DashpotBoundContact, CError> {
        let info = self.law.info();
        if !info.history.is_empty() {
            return Err(CError::new(
                DASHPOT_ERR_INVALID_PARAMETER,
                format!(
                    "contact law '{}' keeps per-contact history ({} slots), which a pair-bound law has nowhere \
                     to store: bind it to materials and pass the history with each batch",
                    info.name,
                    info.history.len()
                ),
            ));
        }
        let model = self.law.bind(&pair.materials(0.3)?)?;
        // a law whose arithmetic overflows for this pair is refused here, not as inf coefficients
        let coeffs = model.coefficients(pair.mass, pair.radius)?;
        dashpot_core::checks::finite_coefficients(
            &info.name,
            &self.params,
            &info.params,
            pair.mass,
            pair.radius,
            &coeffs,
            None,
        )?;
        Ok(DashpotBoundContact {
            model,
            mass: pair.mass,
            radius: pair.radius,
        })
    }
}

law_functions! {
    DashpotContactLaw: dashpot_contact_new, dashpot_contact_free;
    DashpotTangentialLaw: dashpot_tangential_new, dashpot_tangential_free;
    DashpotRestitutionLaw: dashpot_restitution_new, dashpot_restitution_free;
    DashpotRollingLaw: dashpot_rolling_new, dashpot_rolling_free;
    DashpotTwistingLaw: dashpot_twisting_new, dashpot_twisting_free;
    DashpotHeatLaw: dashpot_heat_new, dashpot_heat_free;
}

model_functions! {
    DashpotContactLaw => DashpotContactModel:
        dashpot_contact_bind_materials, dashpot_contact_model_free, dashpot_contact_model_history_slots,
        dashpot_contact_model_reads_context;
    DashpotTangentialLaw => DashpotTangentialModel:
        dashpot_tangential_bind_materials, dashpot_tangential_model_free, dashpot_tangential_model_history_slots,
        dashpot_tangential_model_reads_context;
    DashpotRollingLaw => DashpotRollingModel:
        dashpot_rolling_bind_materials, dashpot_rolling_model_free, dashpot_rolling_model_history_slots,
        dashpot_rolling_model_reads_context;
    DashpotTwistingLaw => DashpotTwistingModel:
        dashpot_twisting_bind_materials, dashpot_twisting_model_free, dashpot_twisting_model_history_slots,
        dashpot_twisting_model_reads_context;
    DashpotHeatLaw => DashpotHeatModel:
        dashpot_heat_bind_materials, dashpot_heat_model_free, dashpot_heat_model_history_slots,
        dashpot_heat_model_reads_context;
}

pair_functions! {
    DashpotContactLaw => DashpotBoundContact: dashpot_contact_bind, dashpot_bound_contact_free;
    DashpotRestitutionLaw => DashpotBoundRestitution: dashpot_restitution_bind, dashpot_bound_restitution_free;
}
