//! Contacts from a checkpoint: the sets of the last evaluation put back, after a check that
//! each is what this run's classes would have written (so a set read from a file is never
//! half-used: it is refused whole, or taken whole).

use super::{ContactSet, Contacts};

impl Contacts {
    /// The sets of the last evaluation as a checkpoint keeps them: [`Contacts::chunks`].
    pub fn saved(&self) -> &[ContactSet] {
        &self.chunks
    }

    /// Whether `chunks` (from [`Contacts::saved`] of a run of the same scene) can stand as the
    /// sets of the last evaluation: each set of this run's class at its place, sized
    /// consistently, its contacts between particles `< particles` (pair contacts, `i < j`) or
    /// particles and surfaces `< surfaces` (wall contacts), in key order. The message names what
    /// is wrong.
    pub fn check_saved(
        &self,
        chunks: &[ContactSet],
        particles: usize,
        surfaces: Option<usize>,
    ) -> Result<(), String> {
        let nc = self.classes();
        if chunks.len() % nc != 0 {
            return Err(format!(
                "{} sets of contacts, not a multiple of the {nc} classes",
                chunks.len()
            ));
        }
        for (k, set) in chunks.iter().enumerate() {
            let s = self.slots[k % nc];
            let same = (set.slots_n, set.slots_t, set.slots_r, set.slots_w) == (s.n, s.t, s.r, s.w)
                && set.energy == self.energy
                && set.reach_bound.to_bits() == self.reach_bound.to_bits();
            if !same {
                return Err(format!(
                    "set {k}: its history slots or accounting differ from the laws of its class"
                ));
            }
            set.check_saved(particles, surfaces)
                .map_err(|m| format!("set {k}: {m}"))?;
        }
        Ok(())
    }

    /// Puts back the sets of the last evaluation (checked by [`Contacts::check_saved`]).
    pub fn restore(&mut self, chunks: Vec<ContactSet>) {
        self.chunks = chunks;
        self.spare.clear();
    }
}

impl ContactSet {
    /// See [`Contacts::check_saved`].
    fn check_saved(&self, particles: usize, surfaces: Option<usize>) -> Result<(), String> {
        let n = self.len();
        let rot = self.rotational();
        let (sr, sw) = (self.slots_r.unwrap_or(0), self.slots_w.unwrap_or(0));
        let lens = [
            ("j", self.j.len(), n),
            ("delta", self.delta.len(), n),
            ("rate", self.rate.len(), n),
            ("mass", self.mass.len(), n),
            ("radius", self.radius.len(), n),
            ("normal", self.normal.len(), n),
            ("vrel", self.vrel.len(), n),
            ("hist_n", self.hist_n.len(), n * self.slots_n),
            ("hist_t", self.hist_t.len(), n * self.slots_t),
            ("fnorm", self.fnorm.len(), n),
            ("ftan", self.ftan.len(), n),
            ("fresh", self.fresh.len(), n),
            ("last", self.last.len(), n),
            ("hist_r", self.hist_r.len(), if rot { n * sr } else { 0 }),
            ("hist_w", self.hist_w.len(), if rot { n * sw } else { 0 }),
            ("vroll", self.vroll.len(), if rot { n } else { 0 }),
            ("twist", self.twist.len(), if rot { n } else { 0 }),
            ("froll", self.froll.len(), if rot { n } else { 0 }),
            ("mtwist", self.mtwist.len(), if rot { n } else { 0 }),
            (
                "reach",
                self.reach.len(),
                if self.reach_bound > 0.0 { n } else { 0 },
            ),
        ];
        for (name, len, want) in lens {
            if len != want {
                return Err(format!(
                    "{name} holds {len} values for {n} contacts (want {want})"
                ));
            }
        }
        if !(self.sign.is_empty() || self.sign.len() == n) {
            return Err(format!("sign holds {} values for {n} contacts", self.sign.len()));
        }
        for (k, v) in self.power.iter().chain(&self.elastic).enumerate() {
            if v.len() != if self.energy { n } else { 0 } {
                return Err(format!(
                    "energy output {k} holds {} values for {n} contacts",
                    v.len()
                ));
            }
        }
        let mut prev = None;
        for (&i, &j) in self.i.iter().zip(&self.j) {
            let ok = (i as usize) < particles
                && match surfaces {
                    None => i < j && (j as usize) < particles,
                    Some(s) => (j as usize) < s,
                };
            if !ok || prev.is_some_and(|p| p >= (i, j)) {
                return Err(format!("contact ({i}, {j}) is out of range or out of order"));
            }
            prev = Some((i, j));
        }
        Ok(())
    }
}
