//! What a law reports about the energy of its contacts (sdk 0.3): per contact, and per batch.

/// What a law reports about the energy of one contact after a step (sdk 0.3).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    /// Power dissipated by the contact at this step's state (W, ≥ 0): damping force × rate,
    /// plus the rate of plastic or frictional work.
    pub power: f64,
    /// Elastic energy stored in the contact (J): the work the law's conservative part would
    /// give back on unloading from this state.
    pub elastic: f64,
}

/// The per-contact energy outputs of a batch call (sdk 0.3), each as long as the batch.
#[derive(Debug)]
pub struct EnergyBatch<'a> {
    /// Output: the power each contact dissipated over the step (W).
    pub power: &'a mut [f64],
    /// Output: the elastic energy each contact stores at the end of the step (J).
    pub elastic: &'a mut [f64],
}

impl EnergyBatch<'_> {
    /// Writes the powers `power` (W) and elastic energies `elastic` (J, as many) of the contacts
    /// from `lo` on.
    #[inline(always)]
    pub fn put(&mut self, lo: usize, power: &[f64], elastic: &[f64]) {
        self.power[lo..lo + power.len()].copy_from_slice(power);
        self.elastic[lo..lo + elastic.len()].copy_from_slice(elastic);
    }

    /// Writes contact `i`'s energy `e`; false when there is none (the law does not account for
    /// energy), leaving the outputs as they were.
    #[inline(always)]
    pub fn set(&mut self, i: usize, e: Option<Energy>) -> bool {
        match e {
            Some(e) => {
                self.power[i] = e.power;
                self.elastic[i] = e.elastic;
                true
            }
            None => false,
        }
    }
}
