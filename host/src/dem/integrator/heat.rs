//! The engine's temperatures (see [`crate::dem::heat`]): what a run with heat keeps, the
//! conduction pass after each step's forces, the explicit update, the books.

use super::Engine;
use crate::dem::heat::{HeatBooks, HeatSetup, HeatState, WallTemperature};
use crate::dem::DemError;
use dashpot_sdk::{HeatBatch, HeatFlow};

/// A run's temperatures and what their update needs. Per-particle arrays follow the
/// particles (the user's order between calls, the engine's inside a step).
#[derive(Debug, Clone, Default)]
pub(super) struct Thermal {
    /// Temperatures (K).
    pub(super) temperature: Vec<f64>,
    /// Heat capacities C = m c (J/K).
    pub(super) capacity: Vec<f64>,
    /// The other order's buffers of `temperature` and `capacity` (see `order.rs`).
    pub(super) spare: [Vec<f64>; 2],
    /// Each particle's heat rate at the last step (W).
    rate: Vec<f64>,
    /// Each particle's summed conductance at the last step (W/K).
    conductance: Vec<f64>,
    /// Each wall's temperature, if it conducts.
    walls: Vec<Option<WallTemperature>>,
    /// Scratch: each wall's temperature now (K; NaN: it does not conduct).
    wall_now: Vec<f64>,
    /// Scratch: a class's contacts' temperatures, and the flows its law returns.
    pair_t: Vec<[f64; 2]>,
    flow: Vec<HeatFlow>,
    /// Σ C T at the start (J).
    initial: f64,
    /// The heat the walls gave since the start (J).
    wall_heat: f64,
    /// The smallest C/ΣH met (s).
    limit: f64,
}

impl<const D: usize> Engine<D> {
    /// The run with temperatures: each particle's from `setup.temperature` (K, the user's
    /// numbering), heat capacity m c of its species' `setup.specific_heat` (J/(kg·K)), the
    /// walls' temperatures `setup.walls` (one per wall). The contacts conduct through their
    /// classes' heat laws ([`crate::dem::LawSet::heat`]); a class without one does not. A heat
    /// law keeping history is refused (the engine carries none for heat), as is any value out
    /// of range, naming it.
    pub fn with_heat(mut self, setup: HeatSetup) -> Result<Engine<D>, DemError> {
        let bad = |m: String| Err(DemError::Invalid(m));
        let n = self.p.len();
        if setup.temperature.len() != n {
            return bad(format!(
                "{} temperatures for {n} particles: give one per particle",
                setup.temperature.len()
            ));
        }
        if let Some((i, t)) = setup
            .temperature
            .iter()
            .enumerate()
            .find(|(_, t)| !(t.is_finite() && **t >= 0.0))
        {
            return bad(format!(
                "particle {i}: temperature = {t} K is out of range: it must be finite and >= 0"
            ));
        }
        let ns = self.laws.species.len();
        if setup.specific_heat.len() != ns {
            return bad(format!(
                "{} heat capacities for {ns} species: give one per species",
                setup.specific_heat.len()
            ));
        }
        if let Some((s, c)) = setup
            .specific_heat
            .iter()
            .enumerate()
            .find(|(_, c)| !(c.is_finite() && **c > 0.0))
        {
            return bad(format!(
                "species {s}: heat_capacity = {c} J/(kg·K) is out of range: it must be finite and > 0"
            ));
        }
        if setup.walls.len() != self.walls.len() {
            return bad(format!(
                "{} wall temperatures for {} walls: give one per wall (None: it does not conduct)",
                setup.walls.len(),
                self.walls.len()
            ));
        }
        for (k, w) in setup.walls.iter().enumerate() {
            if let Some(m) = w.and_then(|w| w.problem(&format!("wall[{k}].temperature"))) {
                return bad(m);
            }
        }
        for (what, set) in self
            .laws
            .pair
            .iter()
            .map(|l| ("particle", l))
            .chain(self.laws.wall.iter().map(|l| ("wall", l)))
        {
            if let Some(h) = set.heat.as_ref().filter(|h| h.history_slots() > 0) {
                return bad(format!(
                    "the heat law '{}' of {what} contacts keeps {} history values per contact: the DEM engine runs heat laws without history",
                    h.name(),
                    h.history_slots()
                ));
            }
        }
        let species = self.particle_species();
        let capacity: Vec<f64> = (0..n)
            .map(|i| self.p.mass[i] * setup.specific_heat[species[i] as usize])
            .collect();
        let initial = thermal_sum(&capacity, &setup.temperature);
        self.heat = Some(Box::new(Thermal {
            temperature: setup.temperature,
            capacity,
            rate: vec![0.0; n],
            conductance: vec![0.0; n],
            wall_now: vec![f64::NAN; setup.walls.len()],
            walls: setup.walls,
            initial,
            limit: f64::INFINITY,
            ..Thermal::default()
        }));
        Ok(self)
    }

    /// Whether the run has temperatures ([`Engine::with_heat`]).
    pub fn has_heat(&self) -> bool {
        self.heat.is_some()
    }

    /// Each particle's temperature (K), in the user's numbering (see [`Engine::user_index`]);
    /// `None` without [`Engine::with_heat`].
    pub fn temperatures(&self) -> Option<&[f64]> {
        self.heat.as_deref().map(|h| &h.temperature[..])
    }

    /// The temperatures to edit between calls (K).
    pub fn temperatures_mut(&mut self) -> Option<&mut [f64]> {
        self.heat.as_deref_mut().map(|h| &mut h.temperature[..])
    }

    /// Each particle's heat capacity m c (J/K), in the user's numbering.
    pub fn heat_capacities(&self) -> Option<&[f64]> {
        self.heat.as_deref().map(|h| &h.capacity[..])
    }

    /// Each wall's temperature (`None`: it does not conduct).
    pub fn wall_temperatures(&self) -> Option<&[Option<WallTemperature>]> {
        self.heat.as_deref().map(|h| &h.walls[..])
    }

    /// The thermal books now (`None` without temperatures).
    pub fn heat_books(&self) -> Option<HeatBooks> {
        let h = self.heat.as_deref()?;
        let thermal = thermal_sum(&h.capacity, &h.temperature);
        Some(HeatBooks {
            thermal,
            thermal_initial: h.initial,
            wall_heat: h.wall_heat,
            balance: thermal - h.initial - h.wall_heat,
            stability_limit: h.limit,
            dt: self.dt,
        })
    }

    /// The conduction of the step just evaluated: each contact's heat law on the contacts of
    /// the last evaluation (at the step's end, with the normal laws' contexts), the heat rates
    /// summed per particle (chunk by chunk, class by class, in order: the same bits on any
    /// number of threads), then T += dt Q / C.
    pub(super) fn conduct(&mut self) -> Result<(), DemError> {
        let Some(th) = self.heat.as_deref_mut() else {
            return Ok(());
        };
        let dt = self.dt;
        th.rate.iter_mut().for_each(|q| *q = 0.0);
        th.conductance.iter_mut().for_each(|g| *g = 0.0);
        for (now, w) in th.wall_now.iter_mut().zip(&th.walls) {
            *now = w.map_or(f64::NAN, |w| w.at(self.t));
        }
        let mut wall_power = 0.0;
        for (contacts, laws, pair) in [
            (&self.pairs, &self.laws.pair, true),
            (&self.wall_contacts, &self.laws.wall, false),
        ] {
            let nc = contacts.classes();
            for (k, set) in contacts.chunks.iter().enumerate() {
                let n = set.len();
                let Some(law) = laws[k % nc].heat.as_deref() else {
                    continue;
                };
                if n == 0 {
                    continue;
                }
                th.pair_t.clear();
                for m in 0..n {
                    let ti = th.temperature[set.i[m] as usize];
                    let tj = if pair {
                        th.temperature[set.j[m] as usize]
                    } else {
                        // (a wall that does not conduct: the contact's result is not used)
                        let tw = th.wall_now[self.surface_wall[set.j[m] as usize]];
                        if tw.is_nan() {
                            ti
                        } else {
                            tw
                        }
                    };
                    // (a pair is presented from the partner the user numbered first)
                    let flip = pair && set.sign.get(m).is_some_and(|&s| s < 0.0);
                    th.pair_t.push(if flip { [tj, ti] } else { [ti, tj] });
                }
                th.flow.resize(n, HeatFlow::default());
                law.heat_batch(HeatBatch {
                    dt,
                    temperature: &th.pair_t,
                    normal_force: &set.fnorm,
                    delta: &set.delta,
                    radius: &set.radius,
                    context: if set.context.len() == n { &set.context } else { &[] },
                    slots: 0,
                    history: &mut [],
                    flow: &mut th.flow[..n],
                })?;
                for (m, f) in th.flow[..n].iter().enumerate() {
                    let i = set.i[m] as usize;
                    if pair {
                        let j = set.j[m] as usize;
                        let q = if set.sign.get(m).is_some_and(|&s| s < 0.0) {
                            -f.heat
                        } else {
                            f.heat
                        };
                        th.rate[i] += q;
                        th.rate[j] -= q;
                        th.conductance[i] += f.conductance;
                        th.conductance[j] += f.conductance;
                    } else if !th.wall_now[self.surface_wall[set.j[m] as usize]].is_nan() {
                        th.rate[i] += f.heat;
                        th.conductance[i] += f.conductance;
                        wall_power += f.heat;
                    }
                }
            }
        }
        let mut limit = th.limit;
        for i in 0..th.temperature.len() {
            let (c, g) = (th.capacity[i], th.conductance[i]);
            if g > 0.0 {
                limit = limit.min(c / g);
            }
            th.temperature[i] += dt * th.rate[i] / c;
        }
        th.limit = limit;
        th.wall_heat += dt * wall_power;
        Ok(())
    }

    /// The temperatures into the engine's order (`into`) or out of it (see `order.rs`).
    pub(super) fn cross_heat(&mut self, into: bool) {
        if let Some(th) = self.heat.as_deref_mut() {
            let [st, sc] = &mut th.spare;
            super::order::permute_into(&th.temperature, st, &self.order.uid, 1, into);
            super::order::permute_into(&th.capacity, sc, &self.order.uid, 1, into);
            std::mem::swap(&mut th.temperature, st);
            std::mem::swap(&mut th.capacity, sc);
        }
    }

    /// The temperatures renumbered with the particles: the new particle k is the old `perm[k]`.
    pub(super) fn gather_heat(&mut self, perm: &[u32]) {
        if let Some(th) = self.heat.as_deref_mut() {
            super::order::gather(&mut th.temperature, perm, 1);
            super::order::gather(&mut th.capacity, perm, 1);
        }
    }

    /// What a checkpoint keeps of the temperatures (the user's order).
    pub(super) fn save_heat(&self) -> Option<HeatState> {
        self.heat.as_deref().map(|h| HeatState {
            temperature: h.temperature.clone(),
            thermal_initial: h.initial,
            wall_heat: h.wall_heat,
            limit: h.limit,
        })
    }

    /// Why `s` cannot be this run's temperatures, if it cannot.
    pub(super) fn check_heat(&self, s: Option<&HeatState>) -> Result<(), String> {
        match (self.heat.as_deref(), s) {
            (None, None) => Ok(()),
            (Some(_), None) => Err("it holds no temperatures where this scene conducts heat".into()),
            (None, Some(_)) => Err("it holds temperatures where this scene has no heat law".into()),
            (Some(h), Some(s)) => {
                if s.temperature.len() != h.temperature.len() {
                    return Err(format!(
                        "it holds {} temperatures where this scene has {}",
                        s.temperature.len(),
                        h.temperature.len()
                    ));
                }
                let ok = s.temperature.iter().all(|t| t.is_finite())
                    && s.thermal_initial.is_finite()
                    && s.wall_heat.is_finite()
                    && !s.limit.is_nan();
                ok.then_some(())
                    .ok_or_else(|| "its temperatures or thermal books are not finite".into())
            }
        }
    }

    /// Puts back the temperatures of a checkpoint (checked by [`Engine::check_heat`]); the
    /// particle arrays are in the user's order.
    pub(super) fn restore_heat(&mut self, s: Option<HeatState>) {
        if let (Some(h), Some(s)) = (self.heat.as_deref_mut(), s) {
            h.temperature = s.temperature;
            h.initial = s.thermal_initial;
            h.wall_heat = s.wall_heat;
            h.limit = s.limit;
            h.spare = Default::default();
        }
    }
}

/// Σ C_i T_i (J), in order.
fn thermal_sum(capacity: &[f64], temperature: &[f64]) -> f64 {
    capacity.iter().zip(temperature).map(|(c, t)| c * t).sum()
}
