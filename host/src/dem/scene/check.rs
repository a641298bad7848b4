//! The checks of a scene's start state, before the first step: particles overlapping each other
//! or a wall, and particles outside a bounded box. Each problem names the particles (or the
//! wall), where they are, and what to change; none of them is about the time step, which the
//! engine's own overlap bound (a run that has gone wrong) would otherwise blame.

use super::super::cells::{Domain, Neighbours};
use super::super::contacts::MAX_OVERLAP;
use super::super::state::{Body, VecD};
use super::super::walls::Wall;

/// Overlaps below this fraction of the smaller radius are touching, not overlapping (positions
/// written as touching come out of the decimal conversion a few ulps apart).
const TOUCHING: f64 = 1e-9;

/// A position as the scene writes it: `[x, y]` (m).
fn at<const D: usize>(x: &VecD<D>) -> String {
    format!("{:?}", x.as_slice())
}

/// Every problem of the start state, one message each (empty: the scene may start).
/// `allow_overlap`: the scene's `allow_initial_overlap` (a pre-compressed packing), which
/// accepts overlaps up to [`MAX_OVERLAP`] of the smaller radius.
pub fn start_problems<const D: usize>(
    bodies: &[Body<D>],
    walls: &[Wall<D>],
    domain: &Domain<D>,
    allow_overlap: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    out.extend(outside_box(bodies, domain));
    out.extend(pair_overlaps(bodies, domain, allow_overlap));
    out.extend(wall_overlaps(bodies, walls, allow_overlap));
    out
}

/// Particles whose centre lies outside a bounded box along an open (non-periodic) axis.
fn outside_box<const D: usize>(bodies: &[Body<D>], dom: &Domain<D>) -> Option<String> {
    if !dom.bounded {
        return None;
    }
    let out_along =
        |b: &Body<D>| (0..D).find(|&k| !dom.periodic[k] && !(dom.lo[k]..=dom.hi[k]).contains(&b.position[k]));
    let bad: Vec<(usize, usize)> = bodies
        .iter()
        .enumerate()
        .filter_map(|(i, b)| out_along(b).map(|k| (i, k)))
        .collect();
    let &(i, k) = bad.first()?;
    Some(format!(
        "{} particle(s) start outside the bounded box [box] lo = {} .. hi = {} m: the first, particle {i} at {} m, along axis {k} ({} m is outside [{}, {}] m); move the particles inside, enlarge the box, or set box.bounded = false",
        bad.len(),
        at(&dom.lo),
        at(&dom.hi),
        at(&bodies[i].position),
        bodies[i].position[k],
        dom.lo[k],
        dom.hi[k]
    ))
}

/// The advice of both overlap messages: `apart` says how to separate them.
fn overlap_advice(allow_overlap: bool, apart: &str) -> String {
    if allow_overlap {
        format!(
            "even with allow_initial_overlap = true an overlap is refused beyond {MAX_OVERLAP} of the smaller radius (the contact laws do not hold that deep); {apart}"
        )
    } else {
        format!(
            "{apart}, or, for a deliberately pre-compressed packing, set allow_initial_overlap = true at the top of the scene (overlaps up to {MAX_OVERLAP} of the smaller radius are then accepted)"
        )
    }
}

/// Whether an overlap `delta` (m) of particles of smaller radius `rmin` (m) is refused.
fn refused(delta: f64, rmin: f64, allow_overlap: bool) -> bool {
    if allow_overlap {
        delta > MAX_OVERLAP * rmin
    } else {
        delta > TOUCHING * rmin
    }
}

/// Pairs of particles that overlap at the start (periodic images included): how many, and the
/// deepest.
fn pair_overlaps<const D: usize>(bodies: &[Body<D>], dom: &Domain<D>, allow_overlap: bool) -> Option<String> {
    let radius: Vec<f64> = bodies.iter().map(|b| 0.5 * b.diameter).collect();
    let mut pos: Vec<VecD<D>> = bodies.iter().map(|b| b.position).collect();
    // every pair whose surfaces are closer than 0: overlapping
    let mut nb = Neighbours::<D>::default();
    nb.build(dom, &mut pos, &radius, 0.0);
    let images = dom.images();
    let mut count = 0usize;
    let mut worst: Option<(usize, usize, f64)> = None;
    for i in 0..bodies.len() {
        for &j in nb.of(i) {
            let j = j as usize;
            let delta = radius[i] + radius[j] - images.delta(&pos[i], &pos[j]).norm();
            if refused(delta, radius[i].min(radius[j]), allow_overlap) {
                count += 1;
                if worst.is_none_or(|(_, _, w)| delta > w) {
                    worst = Some((i, j, delta));
                }
            }
        }
    }
    let (i, j, delta) = worst?;
    let rmin = radius[i].min(radius[j]);
    Some(format!(
        "{count} pair(s) of particles overlap at the start, before the run: the largest overlap is {delta:.4e} m ({:.0} % of the smaller radius {rmin:.4e} m), particle {i} at {} m (diameter {} m) and particle {j} at {} m (diameter {} m); {}",
        100.0 * delta / rmin,
        at(&bodies[i].position),
        bodies[i].diameter,
        at(&bodies[j].position),
        bodies[j].diameter,
        overlap_advice(
            allow_overlap,
            "move them apart (centres at least the sum of the radii apart)"
        )
    ))
}

/// Particles that overlap a wall (or lie behind it) at the start: how many, and the deepest.
fn wall_overlaps<const D: usize>(
    bodies: &[Body<D>],
    walls: &[Wall<D>],
    allow_overlap: bool,
) -> Option<String> {
    let mut count = 0usize;
    let mut worst: Option<(usize, usize, f64)> = None;
    for (w, wall) in walls.iter().enumerate() {
        for s in wall.surfaces(0.0) {
            for (i, b) in bodies.iter().enumerate() {
                let r = 0.5 * b.diameter;
                let delta = s.overlap(&b.position, r);
                if refused(delta, r, allow_overlap) {
                    count += 1;
                    if worst.is_none_or(|(_, _, d)| delta > d) {
                        worst = Some((i, w, delta));
                    }
                }
            }
        }
    }
    let (i, w, delta) = worst?;
    let b = &bodies[i];
    let r = 0.5 * b.diameter;
    let behind = if delta > r {
        " (its centre is behind the wall, inside the solid side)"
    } else {
        ""
    };
    Some(format!(
        "{count} particle(s) overlap a wall at the start, before the run: the largest overlap is {delta:.4e} m ({:.0} % of the radius {r:.4e} m), particle {i} at {} m (diameter {} m) and wall {w} ({}){behind}; {}",
        100.0 * delta / r,
        at(&b.position),
        b.diameter,
        walls[w].describe(),
        overlap_advice(
            allow_overlap,
            "move the particle to the wall's open side (a plane's: where its normal points), its centre at least its radius from the wall"
        )
    ))
}
