//! A scene's pair plan made into the engine's laws: each class of contacts' laws created from
//! the registry and bound to that class's pair of materials.

use super::bad;
use super::pairs::{partners_materials, ClassPlan, PairPlan};
use super::SceneError;
use crate::dem::species::{LawSet, SpeciesLaws};

impl PairPlan {
    /// The engine's laws: each class's laws created from `reg` and bound to its materials.
    pub fn bind(&self, reg: &crate::Registry) -> Result<SpeciesLaws, SceneError> {
        let bind_class = |c: &ClassPlan| -> Result<LawSet, SceneError> {
            let mp = partners_materials(&self.species, c.partners)?;
            let ctx = |what: &str, e: dashpot_sdk::LawError| {
                let name = match what {
                    "tangential" => c.laws.tangential.as_ref(),
                    "rolling" => c.laws.rolling.as_ref(),
                    "twisting" => c.laws.twisting.as_ref(),
                    "heat" => c.laws.heat.as_ref(),
                    _ => Some(&c.laws.normal),
                }
                .map_or("", |t| t.name.as_str());
                bad(format!(
                    "the {what} law '{name}' of the {} contacts: {e}",
                    c.label
                ))
            };
            let t = &c.laws;
            let normal = reg
                .contact(&t.normal.name, &t.normal.param_values())
                .and_then(|l| l.bind(&mp))
                .map_err(|e| ctx("normal", e))?;
            let tangential = match &t.tangential {
                Some(x) => Some(Box::new(
                    reg.tangential(&x.name, &x.param_values())
                        .and_then(|l| l.bind(&mp))
                        .map_err(|e| ctx("tangential", e))?,
                ) as Box<dyn crate::laws::TangentialForce>),
                None => None,
            };
            let rolling = match &t.rolling {
                Some(x) => Some(Box::new(
                    reg.rolling(&x.name, &x.param_values())
                        .and_then(|l| l.bind(&mp))
                        .map_err(|e| ctx("rolling", e))?,
                ) as Box<dyn crate::laws::RollingResistance>),
                None => None,
            };
            let twisting = match &t.twisting {
                Some(x) => Some(Box::new(
                    reg.twisting(&x.name, &x.param_values())
                        .and_then(|l| l.bind(&mp))
                        .map_err(|e| ctx("twisting", e))?,
                ) as Box<dyn crate::laws::TwistingResistance>),
                None => None,
            };
            let heat = match &t.heat {
                Some(x) => Some(Box::new(
                    reg.heat(&x.name, &x.param_values())
                        .and_then(|l| l.bind(&mp))
                        .map_err(|e| ctx("heat", e))?,
                ) as Box<dyn crate::laws::HeatConduction>),
                None => None,
            };
            Ok(LawSet {
                normal: Box::new(normal),
                tangential,
                rolling,
                twisting,
                heat,
            })
        };
        Ok(SpeciesLaws {
            species: self.species.clone(),
            pair_class: self.pair_class.clone(),
            pair: self.pair.iter().map(bind_class).collect::<Result<_, _>>()?,
            pair_labels: self.pair.iter().map(|c| c.label.clone()).collect(),
            wall_class: self.wall_class.clone(),
            wall: self.wall.iter().map(bind_class).collect::<Result<_, _>>()?,
            wall_labels: self.wall.iter().map(|c| c.label.clone()).collect(),
        })
    }
}
