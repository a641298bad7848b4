//! The engine's temperatures (see [`crate::dem::heat`]): what a run with heat keeps, the
//! heat laws' calls inside the force pass, the explicit update after it, the books.
//!
//! The heat laws are called in the force pass itself, class set by class set right after the
//! set's other laws ([`HeatView::conduct`], from `kernels.rs`), while the set's forces,
//! overlaps, radii and contexts are in cache: each contact's flow is kept in the set
//! ([`ContactSet::flow`]). The pass writes no temperature: every law reads those of the
//! step's start. After the pass, [`Engine::conduct`] sums the flows per particle (chunk by
//! chunk, class by class, contact by contact: one order whatever the threads, so the same
//! bits on one thread or many) and steps the temperatures. A run without temperatures does
//! none of it: no array, no work per contact.

use super::Engine;
use crate::dem::contacts::ContactSet;
use crate::dem::heat::{HeatBooks, HeatSetup, HeatState, WallTemperature};
use crate::dem::DemError;
use crate::laws::HeatConduction;
use dashpot_sdk::{HeatBatch, HeatFlow};

/// Which walls conduct (have a temperature).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Conducting {
    /// No wall: wall contacts are not given to the heat laws.
    #[default]
    None,
    /// Some walls: the flows of the others' contacts are zeroed.
    Some,
    /// Every wall.
    All,
}

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
    /// Each particle's heat rate (W) and summed conductance (W/K) of the step being summed;
    /// zero between steps (the update zeroes what it has read).
    sums: Vec<[f64; 2]>,
    /// Each wall's temperature, if it conducts.
    walls: Vec<Option<WallTemperature>>,
    /// Which walls conduct.
    conducting: Conducting,
    /// Scratch: each wall surface's temperature at the end of the step being evaluated (K;
    /// NaN: its wall does not conduct).
    surface: Vec<f64>,
    /// Σ C T at the start (J).
    initial: f64,
    /// The heat the walls gave since the start (J).
    wall_heat: f64,
    /// The smallest C/ΣH met (s).
    limit: f64,
}

impl Thermal {
    /// The walls' surfaces' temperatures at time `t` (s), surface `s` of wall
    /// `surface_wall[s]`.
    pub(super) fn prepare(&mut self, t: f64, surface_wall: &[usize]) {
        if self.conducting == Conducting::None {
            return;
        }
        self.surface.clear();
        self.surface.extend(
            surface_wall
                .iter()
                .map(|&w| self.walls[w].map_or(f64::NAN, |w| w.at(t))),
        );
    }

    /// What the force pass's heat laws read (after [`Thermal::prepare`]).
    pub(super) fn view(&self) -> HeatView<'_> {
        HeatView {
            temperature: &self.temperature,
            surface: &self.surface,
            conducting: self.conducting,
        }
    }
}

/// What the heat laws read in the force pass: the temperatures at the step's start (K, the
/// engine's order) and the wall surfaces' at its end.
#[derive(Debug, Clone, Copy)]
pub(super) struct HeatView<'a> {
    temperature: &'a [f64],
    surface: &'a [f64],
    conducting: Conducting,
}

impl HeatView<'_> {
    /// The heat law `law` on the contacts of `set` (particle pairs, or against walls with
    /// `wall`), just evaluated: each contact's flow and conductance into [`ContactSet::flow`].
    /// A pair is presented to the law from the partner the user numbered first (as its other
    /// laws see it), so its flow is that partner's (× [`ContactSet::sign`] it is i's, which
    /// [`Engine::conduct`] takes); a contact with a wall that does not conduct gets no flow
    /// (its wall set none at all when no wall conducts). The temperatures the law reads are
    /// gathered into the set's scratch.
    pub(super) fn conduct(
        &self,
        set: &mut ContactSet,
        law: &dyn HeatConduction,
        wall: bool,
        dt: f64,
    ) -> Result<(), DemError> {
        let n = set.len();
        if n == 0 || (wall && self.conducting == Conducting::None) {
            set.flow.clear();
            return Ok(());
        }
        let temperature = self.temperature;
        set.pair_t.clear();
        if wall {
            // (a wall that does not conduct: its contacts see their own temperature twice,
            // and their flows are zeroed below)
            set.pair_t.extend(set.i.iter().zip(&set.j).map(|(&i, &j)| {
                let ti = temperature[i as usize];
                let tw = self.surface[j as usize];
                [ti, if tw.is_nan() { ti } else { tw }]
            }));
        } else if set.sign.is_empty() {
            set.pair_t.extend(
                set.i
                    .iter()
                    .zip(&set.j)
                    .map(|(&i, &j)| [temperature[i as usize], temperature[j as usize]]),
            );
        } else {
            // (the partner the laws see the contact from first: its index chosen, then loaded)
            set.pair_t
                .extend(set.i.iter().zip(&set.j).zip(&set.sign).map(|((&i, &j), &s)| {
                    let (a, b) = if s < 0.0 { (j, i) } else { (i, j) };
                    [temperature[a as usize], temperature[b as usize]]
                }));
        }
        set.flow.resize(n, HeatFlow::default());
        law.heat_batch(HeatBatch {
            dt,
            temperature: &set.pair_t,
            normal_force: &set.fnorm,
            delta: &set.delta,
            radius: &set.radius,
            context: if set.context.len() == n { &set.context } else { &[] },
            slots: 0,
            history: &mut [],
            flow: &mut set.flow,
        })?;
        if wall && self.conducting == Conducting::Some {
            for (f, &j) in set.flow.iter_mut().zip(&set.j) {
                if self.surface[j as usize].is_nan() {
                    *f = HeatFlow::default();
                }
            }
        }
        Ok(())
    }
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
        let conducting = match setup.walls.iter().filter(|w| w.is_some()).count() {
            0 => Conducting::None,
            k if k == setup.walls.len() => Conducting::All,
            _ => Conducting::Some,
        };
        self.heat = Some(Box::new(Thermal {
            temperature: setup.temperature,
            capacity,
            sums: vec![[0.0; 2]; n],
            walls: setup.walls,
            conducting,
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

    /// The conduction of the step just evaluated: the flows the force pass kept in the
    /// contact sets ([`HeatView::conduct`]: the heat laws on the step's end contacts, with the
    /// temperatures of its start), turned to i's, summed per particle, chunk by chunk, class by class, contact
    /// by contact (the same bits on any number of threads; a pair's partner gets −Q exactly),
    /// then T += dt Q / C (explicit Euler, as LAMMPS's `fix heat/flow`), the stability limit
    /// min C/ΣH kept, the sums zeroed for the next step in the same loop.
    pub(super) fn conduct(&mut self) {
        let Some(th) = self.heat.as_deref_mut() else {
            return;
        };
        let dt = self.dt;
        let sums = &mut th.sums[..];
        let mut wall_power = 0.0;
        for (contacts, laws, pair) in [
            (&self.pairs, &self.laws.pair, true),
            (&self.wall_contacts, &self.laws.wall, false),
        ] {
            let nc = contacts.classes();
            for (k, set) in contacts.chunks.iter().enumerate() {
                // (no heat law, no contact, or walls that do not conduct: no flow)
                if laws[k % nc].heat.is_none() || set.flow.is_empty() {
                    continue;
                }
                let flow = &set.flow[..set.len()];
                if pair && !set.sign.is_empty() {
                    // (the flow of a contact seen from j turned to i's: × −1 is the negation)
                    let signed = set.i.iter().zip(&set.j).zip(&set.sign).zip(flow);
                    for (((&i, &j), &s), f) in signed {
                        let q = f.heat * s;
                        let (a, b) = (sums[i as usize], sums[j as usize]);
                        sums[i as usize] = [a[0] + q, a[1] + f.conductance];
                        sums[j as usize] = [b[0] - q, b[1] + f.conductance];
                    }
                } else if pair {
                    for ((&i, &j), f) in set.i.iter().zip(&set.j).zip(flow) {
                        let (a, b) = (sums[i as usize], sums[j as usize]);
                        sums[i as usize] = [a[0] + f.heat, a[1] + f.conductance];
                        sums[j as usize] = [b[0] - f.heat, b[1] + f.conductance];
                    }
                } else {
                    // (a wall that does not conduct gave +0: adding it changes no sum)
                    for (&i, f) in set.i.iter().zip(flow) {
                        let s = &mut sums[i as usize];
                        s[0] += f.heat;
                        s[1] += f.conductance;
                        wall_power += f.heat;
                    }
                }
            }
        }
        let mut limit = th.limit;
        for ((t, &c), s) in th.temperature.iter_mut().zip(&th.capacity).zip(sums.iter_mut()) {
            let [q, g] = *s;
            // (C/H is divided only where it may lower the limit: the same minimum)
            if g > 0.0 && c <= g * limit * (1.0 + 1e-9) {
                limit = limit.min(c / g);
            }
            *t += dt * q / c;
            *s = [0.0; 2];
        }
        th.limit = limit;
        th.wall_heat += dt * wall_power;
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
