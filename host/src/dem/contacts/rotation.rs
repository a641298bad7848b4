//! The rolling and twisting part of a contact set (sdk 0.3): each contact's rolling velocity
//! and twisting rate, their laws' histories carried over, and the laws' calls.

use super::{contexts, family_out, motion_batch, ContactSet};
use crate::dem::DemError;
use crate::laws::{RollingResistance, TwistingResistance};
use dashpot_sdk::{RollingBatch, TwistingBatch};
use std::ops::Range;

/// The rolling and twisting laws of one kind of contacts, if any.
#[derive(Clone, Copy, Default)]
pub struct Rotating<'a> {
    /// Rolling resistance.
    pub rolling: Option<&'a dyn RollingResistance>,
    /// Twisting resistance.
    pub twisting: Option<&'a dyn TwistingResistance>,
    /// Whether another law of the contact (its heat law, sdk 0.4) reads the normal law's
    /// contexts: they are then kept ([`ContactSet::context`]).
    pub context: bool,
}

impl ContactSet {
    /// The rolling and twisting laws on contacts `r` (after the normal forces).
    pub(super) fn evaluate_rotation(
        &mut self,
        rot: &Rotating<'_>,
        r: Range<usize>,
        dt: f64,
    ) -> Result<(), DemError> {
        let (a, b) = (r.start, r.end);
        let energy = self.energy;
        // (each law gets the normal law's contexts only if it reads them: a law that does not
        // would only have them checked)
        if let (Some(law), Some(sr)) = (rot.rolling, self.slots_r) {
            let mut batch = motion_batch!(RollingBatch {
                self[a..b], dt, normal_force: &self.fnorm[a..b],
                velocity: vroll, hist_r / sr => force: froll
            });
            if !law.reads_context() {
                batch.context = &[];
            }
            let written = law.force_batch(
                batch,
                family_out(energy, &mut self.power, &mut self.elastic, 2, a..b),
            )?;
            self.unreported[2] |= energy && !written;
            self.add_power(2, r.clone());
        }
        if let (Some(law), Some(sw)) = (rot.twisting, self.slots_w) {
            let mut batch = motion_batch!(TwistingBatch {
                self[a..b], dt, normal_force: &self.fnorm[a..b],
                rate: twist, hist_w / sw => torque: mtwist
            });
            if !law.reads_context() {
                batch.context = &[];
            }
            let written = law.torque_batch(
                batch,
                family_out(energy, &mut self.power, &mut self.elastic, 3, a..b),
            )?;
            self.unreported[3] |= energy && !written;
            self.add_power(3, r);
        }
        Ok(())
    }
}
