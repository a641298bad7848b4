//! What a run measures: energies, contacts, the state as JSON.

use super::state::VecD;
use super::Engine;

/// Energies (J).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Energy {
    /// Translational kinetic energy Σ ½ m v².
    pub translational: f64,
    /// Rotational kinetic energy Σ ½ I ω².
    pub rotational: f64,
    /// Potential energy in gravity, −Σ m g·x (positions as wrapped into the box).
    pub gravity: f64,
}

impl Energy {
    /// Kinetic plus gravitational (J); the elastic energy stored in the contacts is not included
    /// (a law does not publish its potential).
    pub fn total(&self) -> f64 {
        self.translational + self.rotational + self.gravity
    }
}

impl<const D: usize> Engine<D> {
    /// The energies now.
    pub fn energy(&self) -> Energy {
        let p = &self.p;
        let g: VecD<D> = self.config().gravity;
        let mut e = Energy {
            translational: 0.0,
            rotational: 0.0,
            gravity: 0.0,
        };
        for i in 0..p.len() {
            e.translational += 0.5 * p.mass[i] * p.vel[i].norm_squared();
            e.rotational += 0.5 * p.inertia[i] * p.angular_velocity(i).norm_squared();
            e.gravity -= p.mass[i] * g.dot(&p.pos[i]);
        }
        e
    }

    /// Granular temperature: the mean kinetic energy per particle (J), translational only.
    pub fn temperature(&self) -> f64 {
        self.energy().translational / self.p.len().max(1) as f64
    }

    /// Each particle's share of the power its contacts dissipated at the last step (W, every
    /// family; a spring its contact dropped at the step counts as dissipated then): half of
    /// each pair contact's, the whole of a wall contact's. `None` without
    /// [`EngineConfig::energy`], or when a family's law does not report its energy.
    pub fn particle_power(&self) -> Option<Vec<f64>> {
        if !self.config().energy || self.unreported.iter().any(|&u| u) {
            return None;
        }
        let mut out = vec![0.0; self.p.len()];
        for (sets, pair) in [(&self.pairs.chunks, true), (&self.wall_contacts.chunks, false)] {
            for set in sets {
                for m in 0..set.len() {
                    let w: f64 = set.power.iter().map(|f| f[m]).sum();
                    // (the contacts number particles in the engine's order)
                    let (i, j) = (self.user_index(set.i[m] as usize), set.j[m] as usize);
                    if pair {
                        out[i] += 0.5 * w;
                        out[self.user_index(j)] += 0.5 * w;
                    } else {
                        out[i] += w;
                    }
                }
                // the springs of the contacts that ended at this step, dissipated
                for &(i, j, e) in &set.ended {
                    let (i, w) = (self.user_index(i as usize), e / self.dt());
                    if pair {
                        out[i] += 0.5 * w;
                        out[self.user_index(j as usize)] += 0.5 * w;
                    } else {
                        out[i] += w;
                    }
                }
            }
        }
        Some(out)
    }

    /// The elastic energy stored in the contacts now (J), by family (with
    /// [`EngineConfig::energy`]; zeros without).
    pub fn elastic(&self) -> [f64; 4] {
        let mut e = [0.0; 4];
        for set in self.pairs.chunks.iter().chain(&self.wall_contacts.chunks) {
            for (k, v) in set.elastic.iter().enumerate() {
                e[k] += v[..set.len()].iter().sum::<f64>();
            }
        }
        e
    }

    /// Each particle's species (indices into the run's species), in the user's numbering.
    pub fn particle_species(&self) -> Vec<u8> {
        let mut out = vec![0u8; self.p.len()];
        for (k, &s) in self.species().iter().enumerate() {
            out[self.user_index(k)] = s;
        }
        out
    }

    /// Contacts now (particle pairs + particle–wall).
    pub fn contacts(&self) -> usize {
        self.pairs.len() + self.wall_contacts.len()
    }

    /// The final state, as `dashpot dem --json` prints it.
    pub fn state_json(&self) -> serde_json::Value {
        let p = &self.p;
        let parts: Vec<serde_json::Value> = (0..p.len())
            .map(|i| {
                let w = if D == 2 {
                    serde_json::json!(p.angular_velocity(i).z)
                } else {
                    serde_json::json!(p.angular_velocity(i).as_slice())
                };
                serde_json::json!({
                    "position": p.pos[i].as_slice(),
                    "velocity": p.vel[i].as_slice(),
                    "angular_velocity": w,
                    "diameter": 2.0 * p.radius[i],
                })
            })
            .collect();
        let e = self.energy();
        let mv = self.mean_velocity();
        let mut parts = parts;
        if let Some(t) = self.temperatures() {
            for (p, t) in parts.iter_mut().zip(t) {
                p["temperature"] = serde_json::json!(t);
            }
        }
        let mut v = serde_json::json!({
            "dimension": D,
            "particles": parts,
            "dt": self.dt(),
            "steps": self.steps(),
            "time": self.time(),
            "energy": e.total(),
            "energies": e,
            "contacts": self.contacts(),
            "pair_contacts": self.pairs.len(),
            "wall_contacts": self.wall_contacts.len(),
            "pair_episodes": self.pair_episodes,
            "neighbour_rebuilds": self.rebuilds(),
            "collision_time": self.step_choice.collision_time,
            "impact_speed": self.step_choice.impact_speed,
            "dt_given": self.step_choice.given,
            "mean_velocity": [mv.x, mv.y, mv.z],
        });
        // the thermal books (a run with heat): Σ C T, the walls' heat, their balance
        if let Some(b) = self.heat_books() {
            v["heat"] = b.json();
        }
        v
    }
}
