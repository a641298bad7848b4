//! The engine's whole state between two calls, as a checkpoint keeps it ([`EngineState`]):
//! everything a step reads that the scene does not give, so that an engine made from the same
//! scene and given this state steps on exactly as the engine it was taken from.
//!
//! Kept: the particles (positions, velocities, spins, the last forces and torques, in the
//! user's order), the engine's own order and its per-particle arrays in it (the predictor's
//! velocities and last accelerations, the species), the neighbour list as built (its anchors
//! decide when it is next rebuilt, and a rebuild wraps positions into a periodic box), each
//! chunk's displacement bound, every contact of the last evaluation with the history of each
//! of its laws and the flags of its first and last steps, the time, the step count and the
//! books (dissipated energy, the walls' work, impulses and episodes). Not kept: what the scene
//! gives (radii, masses, materials, the laws, the walls, the step, the configuration),
//! scratch, and the measured costs that only decide how the steps are shared between threads
//! (the same bits either way).

use super::Engine;
use crate::dem::cells::Neighbours;
use crate::dem::contacts::ContactSet;
use crate::dem::state::VecD;
use crate::dem::DemError;
use serde::{Deserialize, Serialize};

/// An engine's state between calls (see the module doc); [`Engine::save_state`] takes it,
/// [`Engine::restore_state`] puts it back into an engine of the same scene.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EngineState<const D: usize> {
    dt: f64,
    t: f64,
    steps: u64,
    pos: Vec<VecD<D>>,
    vel: Vec<VecD<D>>,
    omega: Vec<f64>,
    force: Vec<VecD<D>>,
    torque: Vec<f64>,
    vpred: Vec<VecD<D>>,
    aold: Vec<VecD<D>>,
    species: Vec<u8>,
    uid: Vec<u32>,
    due: bool,
    nb: Neighbours<D>,
    moved: Vec<f64>,
    pairs: Vec<ContactSet>,
    walls: Vec<ContactSet>,
    wall_impulse: Vec<VecD<D>>,
    wall_episodes: Vec<u64>,
    pair_episodes: u64,
    dissipated: [f64; 4],
    unreported: [bool; 4],
    wall_work: f64,
    /// The temperatures and thermal books (a run with heat), last: a checkpoint of format 1,
    /// which had none, reads as one of format 2 with `None` here (see
    /// [`crate::dem::checkpoint::decode`]).
    heat: Option<crate::dem::heat::HeatState>,
}

impl<const D: usize> EngineState<D> {
    /// Time (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }
}

impl<const D: usize> Engine<D> {
    /// The state between calls (see the module doc), to put back with
    /// [`Engine::restore_state`] into an engine of the same scene.
    pub fn save_state(&self) -> EngineState<D> {
        debug_assert!(!self.pending_kick && !self.order.inside);
        let p = &self.p;
        EngineState {
            dt: self.dt,
            t: self.t,
            steps: self.steps,
            pos: p.pos.clone(),
            vel: p.vel.clone(),
            omega: p.omega.clone(),
            force: p.force.clone(),
            torque: p.torque.clone(),
            vpred: self.vpred.clone(),
            aold: self.aold.clone(),
            species: self.species.clone(),
            uid: self.order.uid.clone(),
            due: self.order.due,
            nb: self.nb.clone(),
            moved: self.moved.clone(),
            pairs: self.pairs.saved().to_vec(),
            walls: self.wall_contacts.saved().to_vec(),
            wall_impulse: self.wall_impulse.clone(),
            wall_episodes: self.wall_episodes.clone(),
            pair_episodes: self.pair_episodes,
            dissipated: self.dissipated,
            unreported: self.unreported,
            wall_work: self.wall_work,
            heat: self.save_heat(),
        }
    }

    /// Puts back `s`, taken by [`Engine::save_state`] from an engine of the same scene: from
    /// here the engine steps on as that one did, bit for bit. Checked whole before anything is
    /// changed: a state that does not fit this engine (another particle count, step, species,
    /// walls or laws) is refused with a message naming what differs, and the engine is left
    /// as it was.
    pub fn restore_state(&mut self, s: EngineState<D>) -> Result<(), DemError> {
        self.check_state(&s)
            .map_err(|m| DemError::Invalid(format!("the saved state does not fit this scene: {m}")))?;
        let n = self.p.len();
        let p = &mut self.p;
        (p.pos, p.vel, p.omega, p.force, p.torque) = (s.pos, s.vel, s.omega, s.force, s.torque);
        (self.vpred, self.aold, self.species) = (s.vpred, s.aold, s.species);
        self.order.inside = false;
        self.order.due = s.due;
        self.order.uid = s.uid;
        // the fixed arrays in the engine's order (the user's stay in `p`), and their inverses
        let user = |k: usize| self.order.uid.get(k).map_or(k, |&u| u as usize);
        let perm = |v: &[f64]| (0..n).map(|k| v[user(k)]).collect::<Vec<f64>>();
        let (radius, mass, inertia) = (perm(&self.p.radius), perm(&self.p.mass), perm(&self.p.inertia));
        self.inv_mass = mass.iter().map(|m| 1.0 / m).collect();
        self.inv_inertia = inertia.iter().map(|i| 1.0 / i).collect();
        if !self.order.uid.is_empty() {
            self.order.fixed = [radius, mass, inertia];
        }
        self.nb = s.nb;
        self.moved = s.moved;
        self.nb.chunk_reach(self.chunk, &mut self.reach);
        self.back.clear();
        self.back.extend(0..self.reach.len());
        for (k, &far) in self.reach.iter().enumerate().rev() {
            for m in k + 1..=far {
                self.back[m] = k;
            }
        }
        self.pairs.restore(s.pairs);
        self.wall_contacts.restore(s.walls);
        (self.t, self.steps, self.pending_kick) = (s.t, s.steps, false);
        self.wall_impulse = s.wall_impulse;
        self.wall_episodes = s.wall_episodes;
        self.pair_episodes = s.pair_episodes;
        (self.dissipated, self.unreported, self.wall_work) = (s.dissipated, s.unreported, s.wall_work);
        self.restore_heat(s.heat);
        Ok(())
    }

    /// Why `s` cannot be put back into this engine, if it cannot.
    fn check_state(&self, s: &EngineState<D>) -> Result<(), String> {
        let n = self.p.len();
        let ns = n * crate::dem::state::spin_len(D);
        if s.dt.to_bits() != self.dt.to_bits() {
            return Err(format!("its step is {:e} s, this scene's {:e} s", s.dt, self.dt));
        }
        if !(s.t.is_finite() && s.t >= 0.0) {
            return Err(format!("its time {} s is not finite and >= 0", s.t));
        }
        let lens = [
            ("positions", s.pos.len(), n),
            ("velocities", s.vel.len(), n),
            ("spins", s.omega.len(), ns),
            ("forces", s.force.len(), n),
            ("torques", s.torque.len(), ns),
            ("predicted velocities", s.vpred.len(), n),
            ("accelerations", s.aold.len(), n),
            ("species", s.species.len(), self.species.len()),
            ("wall impulses", s.wall_impulse.len(), self.walls.len()),
            ("wall episodes", s.wall_episodes.len(), self.walls.len()),
        ];
        for (name, len, want) in lens {
            if len != want {
                return Err(format!("it holds {len} {name} where this scene has {want}"));
            }
        }
        let nspecies = self.laws.species.len();
        if let Some(b) = s.species.iter().find(|&&b| b as usize >= nspecies) {
            return Err(format!("species {b} of {nspecies}"));
        }
        let finite = |v: &[VecD<D>]| v.iter().all(|x| x.iter().all(|c| c.is_finite()));
        let ok = finite(&s.pos) && finite(&s.vel) && finite(&s.force) && finite(&s.vpred) && finite(&s.aold);
        if !(ok && s.omega.iter().chain(&s.torque).all(|x| x.is_finite())) {
            return Err("a particle's state is not finite".into());
        }
        if !s.uid.is_empty() {
            let mut seen = vec![false; n];
            for &u in &s.uid {
                let u = u as usize;
                if u >= n || std::mem::replace(&mut seen[u], true) {
                    return Err("its order is not a permutation of the particles".into());
                }
            }
            if s.uid.len() != n {
                return Err("its order is not a permutation of the particles".into());
            }
        }
        check_list(&s.nb, n).map_err(|m| format!("neighbour list: {m}"))?;
        let mut reach = Vec::new();
        s.nb.chunk_reach(self.chunk, &mut reach);
        if s.moved.len() != reach.len() || reach.iter().any(|&r| r >= reach.len()) {
            return Err(format!(
                "{} displacement bounds for {} chunks",
                s.moved.len(),
                reach.len()
            ));
        }
        self.check_heat(s.heat.as_ref())?;
        self.pairs
            .check_saved(&s.pairs, n, None)
            .map_err(|m| format!("pair contacts: {m}"))?;
        self.wall_contacts
            .check_saved(&s.walls, n, Some(self.surface_wall.len()))
            .map_err(|m| format!("wall contacts: {m}"))
    }
}

/// Why `nb` is not a neighbour list of `n` particles, if it is not.
fn check_list<const D: usize>(nb: &Neighbours<D>, n: usize) -> Result<(), String> {
    if nb.start.len() != n + 1 || nb.start.first() != Some(&0) {
        return Err(format!("{} row starts for {n} particles", nb.start.len()));
    }
    if nb.start.windows(2).any(|w| w[0] > w[1]) || nb.start[n] as usize != nb.js.len() {
        return Err("its rows are not in order".into());
    }
    if nb.js.iter().any(|&j| j as usize >= n) || nb.wall_cand.iter().any(|&i| i as usize >= n) {
        return Err("a partner is out of range".into());
    }
    if !(nb.cross.len() == n || nb.cross.is_empty()) || !(nb.anchor.len() == n || nb.anchor.is_empty()) {
        return Err("its flags or anchors are not one per particle".into());
    }
    Ok(())
}
