//! The force evaluation on its own (after a list build, or with no list): every chunk's contacts
//! gathered and their laws called in parallel, then the serial end of a step's evaluation.

use super::{add_shares, chunk_forces, ChunkContext, ChunkTask, Engine, Overflow};
use crate::dem::contacts::ClassMap;
use crate::dem::contacts::View;
use crate::dem::state::{from3, spin_len, Vec3};
use crate::dem::DemError;
use rayon::prelude::*;

impl<const D: usize> Engine<D> {
    /// Gathers the contacts at the current positions and predicted velocities, calls the laws,
    /// and sums forces and torques into the particles.
    ///
    /// The particles are cut into chunks ([`gather_chunk`]); each chunk is one task, run in
    /// parallel: it gathers its particles' pair and wall contacts (history from the same chunk
    /// of the last step), calls the laws on them, and sums the forces into its own particles'
    /// slice of the force and torque arrays ([`chunk_forces`]). A pair partner j beyond the
    /// chunk gets its share afterwards, chunk by chunk in an order fixed by the chunks
    /// ([`Engine::finish_forces`]; see `pipeline.rs`).
    /// The sums therefore run in one fixed order whatever the number of threads, and a run is
    /// bit for bit the same on one core or many. (The steps themselves do this work chunk by
    /// chunk right after each chunk's drift: [`Engine::drift_and_forces`].)
    pub(super) fn forces(&mut self) -> Result<(), DemError> {
        let ws = self.wall_states();
        if let Some(th) = self.heat.as_deref_mut() {
            th.prepare(self.t, &self.surface_wall);
        }
        let n = self.p.len();
        let c = self.chunk;
        let chunks = n.div_ceil(c);
        self.overflow.resize_with(chunks, Overflow::default);
        let (pc, wc) = (self.pairs.classes(), self.wall_contacts.classes());
        let (prev_p, next_p) = self.pairs.buffers(chunks);
        let (prev_w, next_w) = self.wall_contacts.buffers(chunks);
        let p = &mut self.p;
        let view = View {
            base: 0,
            pos: &p.pos,
            vpred: &self.vpred,
            vel: &p.vel,
            omega: &p.omega,
            radius: &p.radius,
            mass: &p.mass,
            uid: (!self.order.uid.is_empty()).then_some(&self.order.uid[..]),
            species: &self.species,
        };
        let ctx = ChunkContext {
            dom: &self.cfg.domain,
            nb: &self.nb,
            walls: &ws,
            laws: &self.laws,
            map: ClassMap {
                species: self.laws.species.len(),
                walls: ws.len(),
                pair: &self.laws.pair_class,
                wall: &self.surface_class,
            },
            dt: self.dt,
            edges: self.cfg.edge_means,
            heat: self.heat.as_deref().map(|th| th.view()),
        };
        let work = |(k, ((((pp, np), (pw, nw)), (f, tq)), ov)): ChunkTask<'_, D>| {
            let range = k * c..(k * c + f.len());
            chunk_forces(&ctx, range, &view, (pp, np), (pw, nw), f, tq, c, ov)
        };
        let force = &mut p.force;
        let torque = &mut p.torque;
        let overflow = &mut self.overflow;
        // the first error in chunk order, whatever the threads did
        // the same chain of zips, by std's iterators or rayon's (method names given)
        macro_rules! tasks {
            ($chunks:ident, $chunks_mut:ident, $iter_mut:ident) => {
                prev_p
                    .$chunks(pc)
                    .zip(next_p.$chunks_mut(pc))
                    .zip(prev_w.$chunks(wc).zip(next_w.$chunks_mut(wc)))
                    .zip(
                        force
                            .$chunks_mut(c)
                            .zip(torque.$chunks_mut(c * spin_len(D))),
                    )
                    .zip(overflow.$iter_mut())
                    .enumerate()
                    .map(work)
                    .collect()
            };
        }
        let results: Vec<Result<(), DemError>> = if !self.parallel {
            tasks!(chunks, chunks_mut, iter_mut)
        } else {
            tasks!(par_chunks, par_chunks_mut, par_iter_mut)
        };
        self.finish_forces(results.into_iter().collect(), false)
    }

    /// The serial end of a force evaluation whose chunks gave `results` (the first error in
    /// chunk order): a contact test that met a NaN reports the particle whose state is not
    /// finite; else the new contacts become the current ones, the partners beyond each chunk
    /// get their forces (chunk by chunk, in order; unless `shared`: the pipelined pass has
    /// added them), and the walls' impulses and episodes and the pair episodes are counted.
    pub(super) fn finish_forces(
        &mut self,
        results: Result<(), DemError>,
        shared: bool,
    ) -> Result<(), DemError> {
        results.map_err(|e| match self.check(true) {
            Err(nf @ DemError::NonFinite { .. }) => nf,
            _ => e,
        })?;
        self.pairs.swap();
        self.wall_contacts.swap();
        let p = &mut self.p;
        if !shared {
            // (each partner's shares come from one list of each earlier chunk, nearest chunk
            // first or farthest first: see `pipeline.rs`)
            let mut add = |ov: &Overflow<D>| {
                for list in ov.lists() {
                    add_shares::<D>(list, 0, &mut p.force, &mut p.torque);
                }
            };
            if self.nearest_first {
                self.overflow.iter().rev().for_each(&mut add);
            } else {
                self.overflow.iter().for_each(&mut add);
            }
        }
        for w in &self.wall_contacts.chunks {
            for m in 0..w.len() {
                let nv = Vec3::from(w.normal[m]);
                let fi = nv * w.fnorm[m] + Vec3::from(w.ftan[m]);
                let k = self.surface_wall[w.j[m] as usize];
                self.wall_impulse[k] -= from3::<D>(&fi) * self.dt;
                if w.fresh[m] {
                    self.wall_episodes[k] += 1;
                }
            }
        }
        if self.cfg.energy && self.walls_move {
            self.account_wall_work();
        }
        self.pair_episodes += self.pairs.formed() as u64;
        if self.cfg.energy {
            self.account_energy();
        }
        Ok(())
    }

    /// Adds the work of the moving walls over the step to [`Engine::wall_work`]: each wall
    /// contact's force on its particle (normal and tangential) · the wall's velocity at the
    /// contact point (the velocity its laws saw), and its rolling and twisting torques on the
    /// particle · the wall's angular velocity (those laws resist the spin relative to the
    /// wall's: what they do not dissipate of the wall's turn goes into the particle), × dt,
    /// chunk by chunk in order.
    fn account_wall_work(&mut self) {
        let ws = self.surfaces_at(self.t);
        let p = &self.p;
        let mut work = 0.0;
        for w in &self.wall_contacts.chunks {
            for m in 0..w.len() {
                let s = &ws[w.j[m] as usize];
                let i = w.i[m] as usize;
                let nv = Vec3::from(w.normal[m]);
                let n = from3::<D>(&nv);
                let (_, vw) = s.contact(&p.pos[i], p.radius[i], w.delta[m]);
                let f = n * w.fnorm[m] + from3::<D>(&Vec3::from(w.ftan[m]));
                work += f.dot(&vw);
                if w.rotational() && s.omega != Vec3::zeros() {
                    let mut t = Vec3::zeros();
                    if w.slots_r.is_some() {
                        t += nv.cross(&Vec3::from(w.froll[m])) * w.radius[m];
                    }
                    if w.slots_w.is_some() {
                        t += nv * w.mtwist[m];
                    }
                    work += t.dot(&s.omega);
                }
            }
        }
        self.wall_work += work * self.dt;
    }

    /// Adds the step's dissipation (each contact's power × dt, and the springs of the contacts
    /// that ended) to [`Engine::dissipated`], chunk by chunk in order.
    fn account_energy(&mut self) {
        for set in self.pairs.chunks.iter().chain(&self.wall_contacts.chunks) {
            for (k, p) in set.power_sum.iter().enumerate() {
                self.dissipated[k] += p * self.dt + set.dropped[k];
                self.unreported[k] |= set.unreported[k];
            }
        }
    }
}
