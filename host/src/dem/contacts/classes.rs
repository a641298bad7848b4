//! A chunk's contacts gathered into the sets of their classes (see [`super::Contacts`]): the
//! candidates found once, sorted into the classes in key order, each set merged with its own
//! previous one.

use super::gather::{touching, wall_contact};
use super::pair_geometry::pair_geometry;
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
    let mut class = std::mem::take(&mut sets[0].class_of);
    let listed = nb.start[range.end] as usize - nb.start[range.start] as usize;
    if split.len() < listed {
        split.resize(listed, (0, 0));
    }
    let images = dom.images();
    let count = touching(range.clone(), nb, &images, view, sets[0].reach_bound, &mut split);
    let cand = &split[..count];
    // each candidate's class, and the contacts of each class
    let (base, n, nc) = (view.base, map.species, sets.len());
    let mut counts = [0usize; 256];
    // (every element written below: grown, never cleared)
    if class.len() < count {
        class.resize(count, 0);
    }
    for (c, &(i, j)) in class[..count].iter_mut().zip(cand) {
        let (a, b) = (view.species[i as usize - base], view.species[j as usize - base]);
        *c = map.pair[a as usize * n + b as usize];
        counts[*c as usize] += 1;
    }
    let sorted = view.uid.is_some();
    for (s, &k) in sets.iter_mut().zip(&counts) {
        s.first = range.start;
        s.start_pairs(k, sorted);
    }
    // the candidates sorted by class (a counting sort: each class's in key order)
    let mut start = [0usize; 257];
    for c in 0..nc {
        start[c + 1] = start[c] + counts[c];
    }
    let mut next = start;
    let mut by_class = std::mem::take(&mut sets[0].cand);
    by_class.resize(count.max(by_class.len()), (0, 0));
    for (&p, &c) in cand.iter().zip(&class[..count]) {
        let q = &mut next[c as usize];
        by_class[*q] = p;
        *q += 1;
    }
    // pass 2 by blocks of rows, each block class by class: the particles a block reads stay in
    // cache while its classes' contacts are written into their sets
    let mut at = [0usize; 256];
    let mut done = Ok(());
    'blocks: for b in (CLASS_BLOCK..count + CLASS_BLOCK).step_by(CLASS_BLOCK) {
        // the block: the rows before that of candidate b
        let end = cand.get(b).map_or(u32::MAX, |&(i, _)| i);
        for (c, s) in sets.iter_mut().enumerate() {
            let rest = &by_class[start[c] + at[c]..start[c + 1]];
            let m = rest.partition_point(|&(i, _)| i < end);
            if m == 0 {
                continue;
            }
            let out = s.pairs_out(at[c]..at[c] + m);
            done = pair_geometry(sorted, &rest[..m], &images, view, out);
            if done.is_err() {
                break 'blocks;
            }
            at[c] += m;
        }
    }
    sets[0].cand = by_class;
    sets[0].split = split;
    sets[0].class_of = class;
    done?;
    for (s, p) in sets.iter_mut().zip(prevs) {
        s.finish_pairs(p, view);
    }
    Ok(())
}

/// Candidates per block of a gathering into several classes' sets (see
/// [`gather_pair_classes`]).
const CLASS_BLOCK: usize = 128;

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
    // each class's room: its candidates' species against each wall (each set sized to hold
    // its class's contacts, not every class's)
    let nw = map.walls;
    let mut at = [0usize; 256];
    for &(ig, _) in &cand[..count] {
        let sp = view.species[ig as usize - view.base] as usize;
        for &cl in &map.wall[sp * nw..(sp + 1) * nw] {
            at[cl as usize] += 1;
        }
    }
    for (s, k) in sets.iter_mut().zip(&mut at) {
        s.first = range.start;
        s.size(*k);
        *k = 0;
    }
    let adhesive = sets[0].reach_bound > 0.0;
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
