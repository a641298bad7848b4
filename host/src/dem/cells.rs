//! The domain (periodic axes) and the neighbour list: a cell list rebuilt when a particle has
//! moved by more than half the skin since the last build (a Verlet list on top of cells).
//!
//! The list holds every pair (i, j), i < j, whose surfaces were closer than `skin` at the build,
//! sorted by i then j, as compressed rows (`start[i]..start[i+1]` into `js`). Until any particle
//! has moved by skin/2 no other pair can touch, so contacts are found by scanning the list only.

use super::state::VecD;
use super::walls::WallState;
use rayon::prelude::*;
use std::ops::Range;

/// The simulation box: periodic along some axes (positions wrapped into `[lo, hi)` there), open
/// along the others (particles may go anywhere; walls confine them).
#[derive(Debug, Clone, PartialEq)]
pub struct Domain<const D: usize> {
    /// Lower corner (m) (used along periodic axes, and to detect lost particles along the others
    /// when `bounded`).
    pub lo: VecD<D>,
    /// Upper corner (m).
    pub hi: VecD<D>,
    /// Periodic axes.
    pub periodic: [bool; D],
    /// A particle outside `[lo, hi]` along an open axis is lost (an error).
    pub bounded: bool,
}

impl<const D: usize> Domain<D> {
    /// Box length along axis `k` (m).
    #[inline]
    pub fn length(&self, k: usize) -> f64 {
        self.hi[k] - self.lo[k]
    }

    /// The minimum-image displacement `a − b` (m) (in loops over pairs, take
    /// [`Domain::images`] once and call [`Images::delta`]).
    #[inline]
    pub fn delta(&self, a: &VecD<D>, b: &VecD<D>) -> VecD<D> {
        self.images().delta(a, b)
    }

    /// The box's images, for the pair loops ([`Images::delta`] is [`Domain::delta`] with the
    /// lengths worked out once).
    pub fn images(&self) -> Images<D> {
        let mut im = Images {
            len: [0.0; D],
            half: [f64::INFINITY; D],
        };
        for k in 0..D {
            if self.periodic[k] {
                im.len[k] = self.length(k);
                im.half[k] = 0.5 * im.len[k];
            }
        }
        im
    }

    /// Wraps `x` into the box along periodic axes.
    #[inline]
    pub fn wrap(&self, x: &mut VecD<D>) {
        for k in 0..D {
            if self.periodic[k] {
                let l = self.length(k);
                let mut y = x[k] - self.lo[k];
                y -= l * (y / l).floor();
                if y >= l {
                    y -= l;
                }
                x[k] = self.lo[k] + y;
            }
        }
    }
}

/// The periodic lengths of a [`Domain`] (m), for loops over pairs.
#[derive(Debug, Clone, Copy)]
pub struct Images<const D: usize> {
    len: [f64; D],
    /// Half the length along periodic axes, infinite along open ones.
    half: [f64; D],
}

impl<const D: usize> Images<D> {
    /// The minimum-image displacement `a − b` (m).
    #[inline(always)]
    pub fn delta(&self, a: &VecD<D>, b: &VecD<D>) -> VecD<D> {
        let mut d = a - b;
        for k in 0..D {
            // only pairs across the boundary need the image (never along an open axis)
            if d[k].abs() > self.half[k] {
                let q = d[k] / self.len[k];
                // |q| ≥ 1/2 here (half is len/2 exactly), so below 3/2 round(q) is ±1: no call
                // to libm's `round` (baseline x86-64 has no rounding instruction), whose
                // clobbered registers cost every pair loop spills
                let r = if q.abs() < 1.5 { q.signum() } else { round_far(q) };
                d[k] -= self.len[k] * r;
            }
        }
        d
    }
}

impl<const D: usize> Images<D> {
    /// Whether `a − b` (m) is longer than half the box along some periodic axis (the minimum
    /// image is not the plain difference).
    #[inline(always)]
    pub fn crosses(&self, a: &VecD<D>, b: &VecD<D>) -> bool {
        let d = a - b;
        (0..D).any(|k| d[k].abs() > self.half[k])
    }
}

/// `q.round()`, out of line: an image more than one box length away (a particle far outside
/// the box, never a listed pair).
#[cold]
#[inline(never)]
fn round_far(q: f64) -> f64 {
    q.round()
}

/// The neighbour list (see the module doc).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Neighbours<const D: usize> {
    /// Row starts, `n + 1` entries.
    pub start: Vec<u32>,
    /// Partners j > i of each row i, sorted.
    pub js: Vec<u32>,
    /// Whether some partner of each row i lay across a periodic boundary at the build (its
    /// minimum image is not the plain difference of positions). A row without one keeps
    /// none for the list's life as far as contacts go: a listed pair is within the largest
    /// diameter plus the skin at the build and its partners move apart by less than the skin
    /// while the list is valid, less than half a periodic length (which exceeds twice the
    /// largest diameter plus the skin), so no image of it can touch.
    pub cross: Vec<bool>,
    /// Positions at the build (m).
    pub anchor: Vec<VecD<D>>,
    /// The skin (m).
    pub skin: f64,
    /// Builds so far.
    pub builds: u64,
    /// The particles that may touch a wall before the next build, sorted
    /// ([`Neighbours::find_wall_candidates`]).
    pub wall_cand: Vec<u32>,
    /// The walls' surfaces when they were found; empty until then.
    pub wall_then: Vec<WallState<D>>,
}

/// Particles per parallel task.
const CHUNK: usize = 2048;

impl<const D: usize> Neighbours<D> {
    /// Rebuilds the list for `pos` (wrapped first) and radii `radius`.
    pub fn build(&mut self, dom: &Domain<D>, pos: &mut [VecD<D>], radius: &[f64], skin: f64) {
        let n = pos.len();
        pos.par_iter_mut().for_each(|x| dom.wrap(x));
        self.skin = skin;
        self.builds += 1;
        self.wall_cand.clear();
        self.wall_then.clear();
        self.anchor.clear();
        self.anchor.extend_from_slice(pos);
        if n == 0 {
            self.start = vec![0];
            self.js.clear();
            self.cross.clear();
            return;
        }
        let rmax = radius.iter().cloned().fold(0.0, f64::max);
        // (a positive size even for particles too small to have one: 5e-324 m halves to 0)
        let mut size = (2.0 * rmax + skin).max(f64::MIN_POSITIVE);
        // grid bounds: the box along periodic axes, the particles' extent along the others
        let mut lo = VecD::<D>::zeros();
        let mut hi = VecD::<D>::zeros();
        for k in 0..D {
            if dom.periodic[k] {
                lo[k] = dom.lo[k];
                hi[k] = dom.hi[k];
            } else {
                let (a, b) = pos.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x[k]), b.max(x[k]))
                });
                lo[k] = a;
                hi[k] = b + 1e-12 * (1.0 + b.abs());
            }
        }
        // at most ~2 cells per particle (a far-flung particle must not blow up the grid)
        loop {
            let cells: f64 = (0..D)
                .map(|k| ((hi[k] - lo[k]) / size).floor().max(1.0))
                .product();
            // (NaN, from extents that are not finite, ends it too)
            if cells <= 2.0 * n as f64 + 64.0 || cells.is_nan() {
                break;
            }
            size *= 1.5;
        }
        let mut dims = [1usize; D];
        let mut csize = [size; D];
        for k in 0..D {
            dims[k] = ((hi[k] - lo[k]) / size).floor().max(1.0) as usize;
            csize[k] = (hi[k] - lo[k]) / dims[k] as f64;
            if csize[k].is_nan() || csize[k] <= 0.0 {
                csize[k] = size;
            }
        }
        let ncell: usize = dims.iter().product();
        let cell_of = |x: &VecD<D>| -> usize {
            let mut c = 0usize;
            for k in (0..D).rev() {
                let q = (((x[k] - lo[k]) / csize[k]).floor() as i64).clamp(0, dims[k] as i64 - 1);
                c = c * dims[k] + q as usize;
            }
            c
        };
        let cell: Vec<usize> = pos.par_iter().map(cell_of).collect();
        let mut cstart = vec![0u32; ncell + 1];
        for &c in &cell {
            cstart[c + 1] += 1;
        }
        for c in 0..ncell {
            cstart[c + 1] += cstart[c];
        }
        let mut fill = cstart.clone();
        let mut members = vec![0u32; n];
        for (i, &c) in cell.iter().enumerate() {
            members[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        // along each axis, the three neighbour layers of a cell's (−1, 0, +1), wrapped along a
        // periodic axis, absent past an open one's ends; repeated where a periodic axis has
        // fewer than three cells, so that the cells are then deduplicated
        let repeats = (0..D).any(|k| dom.periodic[k] && dims[k] < 3);
        let neighbour_cells = |c: usize, out: &mut Vec<usize>| {
            let mut idx = [0usize; D];
            let mut r = c;
            for k in 0..D {
                idx[k] = r % dims[k];
                r /= dims[k];
            }
            // the cells' indices along each axis (at most three)
            let mut along = [[0usize; 3]; D];
            let mut count = [0usize; D];
            for k in 0..D {
                for d in [-1i64, 0, 1] {
                    let q = idx[k] as i64 + d;
                    let q = if (0..dims[k] as i64).contains(&q) {
                        q
                    } else if dom.periodic[k] {
                        q.rem_euclid(dims[k] as i64)
                    } else {
                        continue;
                    };
                    along[k][count[k]] = q as usize;
                    count[k] += 1;
                }
            }
            out.clear();
            let total: usize = count.iter().product();
            for m in 0..total {
                let (mut mm, mut id, mut stride) = (m, 0usize, 1usize);
                for k in 0..D {
                    id += along[k][mm % count[k]] * stride;
                    mm /= count[k];
                    stride *= dims[k];
                }
                out.push(id);
            }
            if repeats {
                out.sort_unstable();
                out.dedup();
            }
        };
        let images = dom.images();
        type Rows = (Vec<u32>, Vec<u32>, Vec<bool>);
        let chunks: Vec<Rows> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|ch| {
                let (a, b) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
                let mut counts = Vec::with_capacity(b - a);
                let mut cross = Vec::with_capacity(b - a);
                let mut js = Vec::new();
                let mut last_cell = usize::MAX;
                let mut nb = Vec::with_capacity(27);
                for i in a..b {
                    if cell[i] != last_cell {
                        last_cell = cell[i];
                        neighbour_cells(last_cell, &mut nb);
                    }
                    let before = js.len();
                    let mut crosses = false;
                    for &c in &nb {
                        for &j in &members[cstart[c] as usize..cstart[c + 1] as usize] {
                            if (j as usize) <= i {
                                continue;
                            }
                            let cut = radius[i] + radius[j as usize] + skin;
                            if images.delta(&pos[i], &pos[j as usize]).norm_squared() < cut * cut {
                                js.push(j);
                                crosses |= images.crosses(&pos[i], &pos[j as usize]);
                            }
                        }
                    }
                    js[before..].sort_unstable();
                    counts.push((js.len() - before) as u32);
                    cross.push(crosses);
                }
                (counts, js, cross)
            })
            .collect();
        self.start.clear();
        self.start.reserve(n + 1);
        self.start.push(0);
        self.js.clear();
        self.cross.clear();
        let mut acc = 0u32;
        for (counts, js, cross) in chunks {
            for c in counts {
                acc += c;
                self.start.push(acc);
            }
            self.js.extend_from_slice(&js);
            self.cross.extend_from_slice(&cross);
        }
    }

    /// After a build: the particles that may touch one of `walls` (their surfaces now) before
    /// the next build, for laws acting up to `reach` (m) beyond touching. While the list is
    /// valid a particle moves by less than half the skin from its anchor, and [`Neighbours::
    /// wall_candidates`] allows a surface half the skin of motion: a particle whose gap
    /// to every wall is wider than the skin plus `reach` (with 1 % to spare, and a millionth
    /// of its radius for round-off) cannot come within `reach` of one before the next build.
    pub fn find_wall_candidates(&mut self, walls: &[WallState<D>], radius: &[f64], reach: f64) {
        let margin = 1.01 * (self.skin + reach);
        self.wall_cand.clear();
        self.wall_cand.extend(
            self.anchor
                .iter()
                .zip(radius)
                .enumerate()
                .filter(|(_, (x, &r))| {
                    walls.iter().any(|w| {
                        let d = w.overlap(x, r);
                        // (NaN kept: the gathering reports it)
                        d > -(margin + 1e-6 * r) || d.is_nan()
                    })
                })
                .map(|(i, _)| i as u32),
        );
        self.wall_then.clear();
        self.wall_then.extend_from_slice(walls);
    }

    /// The wall candidates among the particles `range` ([`Neighbours::find_wall_candidates`]),
    /// or `None` if there are none to go by: not found since the build, other walls, or a wall
    /// moved by more than half the skin since (a plane along its normal, a cylinder across its
    /// axis, a box by its centre; or a wall turned: see [`WallState::moved_since`]), when every
    /// particle is looked at, with the same result.
    pub fn wall_candidates(&self, range: Range<usize>, walls: &[WallState<D>]) -> Option<&[u32]> {
        if self.wall_then.len() != walls.len() || walls.is_empty() {
            return None;
        }
        let fixed = walls
            .iter()
            .zip(&self.wall_then)
            .all(|(w, then)| w.moved_since(then) <= 0.5 * self.skin);
        if !fixed {
            return None;
        }
        let c = &self.wall_cand;
        let a = c.partition_point(|&i| (i as usize) < range.start);
        let b = a + c[a..].partition_point(|&i| (i as usize) < range.end);
        Some(&c[a..b])
    }

    /// For each chunk of `chunk` particles, the last chunk holding a partner of one of its
    /// particles (the chunk itself if none lies beyond), written into `out`.
    pub fn chunk_reach(&self, chunk: usize, out: &mut Vec<usize>) {
        let n = self.start.len().saturating_sub(1);
        out.clear();
        out.extend((0..n.div_ceil(chunk)).map(|c| {
            let rows = c * chunk..((c + 1) * chunk).min(n);
            // each row's partners are sorted: its last is its farthest
            let far = rows
                .clone()
                .filter_map(|i| self.of(i).last().map(|&j| j as usize))
                .max()
                .unwrap_or(0);
            far.max(rows.start) / chunk
        }));
    }

    /// Partners of particle `i`.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.js[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::walls::Wall;

    /// Particles too small to have a size (a diameter of 5e-324 m halves to a radius of 0),
    /// with no skin, some far apart: the build ends, with a grid, and lists no pair.
    #[test]
    fn a_build_ends_for_particles_of_no_size() {
        let dom = Domain::<3> {
            lo: VecD::<3>::zeros(),
            hi: VecD::<3>::zeros(),
            periodic: [false; 3],
            bounded: false,
        };
        let mut pos = vec![
            VecD::<3>::new(0.0, 0.0, 0.0),
            VecD::<3>::new(1.0, 0.0, 0.0),
            VecD::<3>::new(1e300, -1e300, 0.0),
        ];
        let mut nb = Neighbours::<3>::default();
        nb.build(&dom, &mut pos, &[0.0; 3], 0.0);
        assert_eq!(nb.start, vec![0, 0, 0, 0]);
        nb.build(&dom, &mut pos, &[0.5 * 5e-324; 3], 0.0);
        assert_eq!(nb.start.len(), 4);
    }

    /// Every particle that comes within `reach` of a wall while the list is valid (moved by at
    /// most half the skin, the walls by at most half the skin along their normals) is among
    /// the candidates; a wall moved further gives no candidates (every particle is looked at).
    #[test]
    fn wall_candidates_hold_every_particle_that_can_reach_a_wall() {
        let dom = Domain::<3> {
            lo: VecD::<3>::new(0.0, 0.0, 0.0),
            hi: VecD::<3>::new(0.02, 0.02, 0.02),
            periodic: [true, true, false],
            bounded: false,
        };
        let walls = [
            Wall::fixed(VecD::<3>::new(0.0, 0.0, 0.0), VecD::<3>::new(0.0, 0.0, 1.0)),
            Wall::fixed(VecD::<3>::new(0.0, 0.0, 0.02), VecD::<3>::new(0.0, 0.0, -1.0)),
        ];
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (skin, reach) = (4e-4, 1e-4);
        let n = 2000;
        let radius: Vec<f64> = (0..n).map(|_| 5e-4 + 5e-4 * rnd()).collect();
        let mut pos: Vec<VecD<3>> = (0..n)
            .map(|_| VecD::<3>::new(0.02 * rnd(), 0.02 * rnd(), 0.02 * rnd()))
            .collect();
        let mut nb = Neighbours::<3>::default();
        nb.build(&dom, &mut pos, &radius, skin + reach);
        let now: Vec<WallState<3>> = walls.iter().map(|w| w.at(0.0)).collect();
        nb.find_wall_candidates(&now, &radius, reach);
        let all = nb.wall_candidates(0..n, &now).expect("candidates");
        assert!(!all.is_empty() && all.len() < n / 2, "{} candidates", all.len());
        for trial in 0..200 {
            // every particle moved by up to half the skin, the walls by up to half of it
            let s = 0.5 * nb.skin;
            let shift = [s * (2.0 * rnd() - 1.0), s * (2.0 * rnd() - 1.0)];
            let moved: Vec<WallState<3>> = now
                .iter()
                .zip(shift)
                .map(|(w, z)| WallState {
                    point: w.point + w.normal * z,
                    ..*w
                })
                .collect();
            let near = nb
                .wall_candidates(0..n, &moved)
                .expect("walls within half the skin");
            for (i, x0) in nb.anchor.iter().enumerate() {
                let dir = VecD::<3>::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
                let x = x0 + dir * (s * rnd());
                let d = moved
                    .iter()
                    .map(|w| w.overlap(&x, radius[i]))
                    .fold(f64::NEG_INFINITY, f64::max);
                if d > -reach {
                    assert!(near.contains(&(i as u32)), "trial {trial}: particle {i} at {d} m");
                }
            }
            // the candidates of a range of particles: those of all the candidates in the range
            let c = nb.wall_candidates(500..1000, &moved).expect("candidates");
            assert!(c.iter().all(|&i| (500..1000).contains(&(i as usize))));
            assert_eq!(
                c.len(),
                near.iter()
                    .filter(|&&i| (500..1000).contains(&(i as usize)))
                    .count()
            );
        }
        // the worst case: each wall half the skin into the pile, each particle half the skin
        // straight at it (just under: the wall's offset is compared after round-off)
        let s = 0.4999 * nb.skin;
        for (w, wall) in now.iter().enumerate() {
            let mut moved = now.clone();
            moved[w].point = wall.point + wall.normal * s;
            let near = nb
                .wall_candidates(0..n, &moved)
                .expect("walls within half the skin");
            for (i, x0) in nb.anchor.iter().enumerate() {
                let x = x0 - wall.normal * s;
                let d = radius[i] - (x - moved[w].point).dot(&wall.normal);
                if d > -reach {
                    assert!(near.contains(&(i as u32)), "wall {w}: particle {i} at {d} m");
                }
            }
        }
        let far = [
            WallState {
                point: now[0].point + now[0].normal * (0.51 * nb.skin),
                ..now[0]
            },
            now[1],
        ];
        assert!(nb.wall_candidates(0..n, &far).is_none());
    }
}
