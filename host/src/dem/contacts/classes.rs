//! A chunk's contacts gathered into the sets of their classes (see [`super::Contacts`]): the
//! candidates found once, sorted into the classes in key order, each set merged with its own
//! previous one.

use super::gather::{touching, wall_contact};
use super::{ClassMap, ContactSet, View};
use crate::dem::cells::{Domain, Neighbours};
use crate::dem::walls::WallState;
use crate::dem::DemError;
use std::ops::Range;

/// The pair contacts of the particles of `range` sorted into their classes' sets `sets` (one
/// per class of `map`, in class order), each set's history carried over from the same class's
/// previous set in `prevs` (see [`ContactSet::gather_pairs`]). One class: that set gathers
/// alone. Several: the candidates are found once, then sorted into the classes (each class's
/// in key order), and each set takes its own.
pub fn gather_pair_classes<const D: usize>(
    sets: &mut [ContactSet],
    prevs: &[ContactSet],
    range: Range<usize>,
    dom: &Domain<D>,
    nb: &Neighbours<D>,
    view: &View<'_, D>,
    map: &ClassMap<'_>,
) -> Result<(), DemError> {
    if sets.len() == 1 {
        return sets[0].gather_pairs(&prevs[0], range, dom, nb, view);
    }
    let mut split = std::mem::take(&mut sets[0].split);
    let listed = nb.start[range.end] as usize - nb.start[range.start] as usize;
    if split.len() < listed {
        split.resize(listed, (0, 0));
    }
    let images = dom.images();
    let count = touching(range.clone(), nb, &images, view, sets[0].reach_bound, &mut split);
    for s in sets.iter_mut() {
        s.first = range.start;
        s.cand.clear();
    }
    let (base, n) = (view.base, map.species);
    for &(i, j) in &split[..count] {
        let (a, b) = (view.species[i as usize - base], view.species[j as usize - base]);
        sets[map.pair[a as usize * n + b as usize] as usize]
            .cand
            .push((i, j));
    }
    sets[0].split = split;
    for (s, p) in sets.iter_mut().zip(prevs) {
        let k = s.cand.len();
        s.pairs_from_candidates(p, k, &images, view)?;
    }
    Ok(())
}

/// The particle–wall contacts of the particles of `range` sorted into their classes' sets
/// `sets` (see [`gather_pair_classes`] and [`ContactSet::gather_walls`]).
pub fn gather_wall_classes<const D: usize>(
    sets: &mut [ContactSet],
    prevs: &[ContactSet],
    range: Range<usize>,
    walls: &[WallState<D>],
    near: Option<&[u32]>,
    view: &View<'_, D>,
    map: &ClassMap<'_>,
) -> Result<(), DemError> {
    if sets.len() == 1 {
        return sets[0].gather_walls(&prevs[0], range, walls, near, view);
    }
    let count = sets[0].wall_candidates(range.clone(), walls, near, view);
    let cand = std::mem::take(&mut sets[0].cand);
    for s in sets.iter_mut() {
        s.first = range.start;
        s.size(count * walls.len());
    }
    let adhesive = sets[0].reach_bound > 0.0;
    let mut at = [0usize; 256];
    let nw = map.walls;
    let mut refused = None;
    'all: for &(ig, _) in &cand[..count] {
        let sp = view.species[ig as usize - view.base] as usize;
        for (w, ws) in walls.iter().enumerate() {
            match wall_contact(ws, ig as usize, view, adhesive) {
                Ok(None) => {}
                Ok(Some(c)) => {
                    let cl = map.wall[sp * nw + w] as usize;
                    sets[cl].put_wall_contact(at[cl], ig, w, &c);
                    at[cl] += 1;
                }
                Err(e) => {
                    refused = Some(e.naming(w));
                    break 'all;
                }
            }
        }
    }
    sets[0].cand = cand;
    if let Some(e) = refused {
        return Err(e);
    }
    for ((cl, s), p) in sets.iter_mut().enumerate().zip(prevs) {
        s.size(at[cl]);
        s.carry(p, true);
    }
    Ok(())
}
