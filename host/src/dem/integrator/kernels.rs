//! The per-chunk kernels of a step: the kicks and the drift, the gather of a chunk's contacts
//! and the scatter of their forces, over ranges of particles that threads take in turn.

use super::heat::HeatView;
use crate::dem::cells::{Domain, Neighbours};
use crate::dem::contacts::{gather_pair_classes, gather_wall_classes, ClassMap, ContactSet, Rotating, View};
use crate::dem::species::{LawSet, SpeciesLaws};
use crate::dem::state::{from3, set_spin, spin, spin_len, Vec3, VecD};
use crate::dem::walls::WallState;
use crate::dem::DemError;

/// The first half-kick and the drift of one particle, with its acceleration `a` (m/s²) and
/// angular acceleration `al` (rad/s²); `vp` gets the second-order predicted velocity at the end
/// of the step, `ao` keeps `a` for the next prediction.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn kick_drift_one<const D: usize>(
    a: VecD<D>,
    al: Vec3,
    h: f64,
    dt: f64,
    x: &mut VecD<D>,
    v: &mut VecD<D>,
    w: &mut Vec3,
    vp: &mut VecD<D>,
    ao: &mut VecD<D>,
) {
    *v += a * h;
    *x += *v * dt;
    *w += al * h;
    *vp = *v + (a * 2.0 - *ao) * h;
    *ao = a;
}

/// The second half-kick of one particle (acceleration `a`, angular acceleration `al`), its end
/// state added to the running sums `sx` (position and velocity) and `sw` (spin), whose
/// finiteness is the state check.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn end_kick<const D: usize>(
    a: VecD<D>,
    al: Vec3,
    h: f64,
    x: &VecD<D>,
    v: &mut VecD<D>,
    w: &mut Vec3,
    sx: &mut VecD<D>,
    sw: &mut Vec3,
) {
    *v += a * h;
    *w += al * h;
    *sx += x + *v;
    *sw += *w;
}

/// One chunk's task in [`Engine::forces`]: chunk index, (previous, next) pair contact sets,
/// (previous, next) wall contact sets (one per class each), the chunk's forces and torques, its overflow.
pub(super) type ChunkTask<'a, const D: usize> = (
    usize,
    (
        (
            (
                (&'a [ContactSet], &'a mut [ContactSet]),
                (&'a [ContactSet], &'a mut [ContactSet]),
            ),
            (&'a mut [VecD<D>], &'a mut [f64]),
        ),
        &'a mut Overflow<D>,
    ),
);

/// Sums the forces and torques of one chunk's pair contacts `pairs` and wall contacts `walls`
/// (their classes' sets, in class order) into the chunk's `own` particles (`f`, `tq`:
/// particles from the chunk's first on, torques as [`Particles::torque`]), zeroed first;
/// `radius` holds the radii from the chunk's first particle on (to its farthest partner). A
/// pair partner beyond the chunk but within `f` (the later chunks of a range that sums each
/// particle's shares nearest chunk first, see `Engine::nearest_first`) gets its force and
/// torque there; one beyond `f` through `overflow` (force on i, torque on j; chunks of `chunk`
/// particles). The classes' sets are summed one after the other, pair sets then wall sets.
#[allow(clippy::too_many_arguments)]
pub(super) fn scatter_chunk<const D: usize>(
    pairs: &[ContactSet],
    walls: &[ContactSet],
    radius: &[f64],
    f: &mut [VecD<D>],
    tq: &mut [f64],
    own: usize,
    chunk: usize,
    overflow: &mut Overflow<D>,
) {
    f[..own].iter_mut().for_each(|v| *v = VecD::<D>::zeros());
    tq[..own * spin_len(D)].iter_mut().for_each(|v| *v = 0.0);
    overflow.clear();
    for set in pairs {
        scatter_pairs(set, radius, f, tq, chunk, overflow);
    }
    for set in walls {
        scatter_walls(set, radius, f, tq);
    }
    // (the rolling and twisting torques after the forces: every pair set's, then every wall
    // set's)
    for set in pairs.iter().filter(|s| s.rotational()) {
        scatter_rotation(Some(set), None, tq, chunk, overflow);
    }
    for set in walls.iter().filter(|s| s.rotational()) {
        scatter_rotation(None, Some(set), tq, chunk, overflow);
    }
}

/// The pair contacts' forces and torques of one class's set (see [`scatter_chunk`]).
#[inline(always)]
fn scatter_pairs<const D: usize>(
    pairs: &ContactSet,
    radius: &[f64],
    f: &mut [VecD<D>],
    tq: &mut [f64],
    chunk: usize,
    overflow: &mut Overflow<D>,
) {
    let (first, len) = (pairs.first, f.len());
    let signed = !pairs.sign.is_empty();
    for m in 0..pairs.len() {
        let (i, j) = (pairs.i[m] as usize - first, pairs.j[m] as usize);
        let nv = Vec3::from(pairs.normal[m]);
        let ft = Vec3::from(pairs.ftan[m]);
        // (a contact seen from j: the force is j's, i takes its opposite; the torques of the
        // tangential force have the same form on either side)
        let mut fi = from3::<D>(&(nv * pairs.fnorm[m] + ft));
        if signed {
            fi *= pairs.sign[m];
        }
        let nxf = nv.cross(&ft);
        f[i] += fi;
        add_spin::<D>(tq, i, &-(nxf * radius[i]));
        let jl = j - first;
        let tj = -(nxf * radius[jl]);
        if jl < len {
            f[jl] -= fi;
            add_spin::<D>(tq, jl, &tj);
        } else {
            overflow.push(later(jl, chunk), (j as u32, fi, tj));
        }
    }
}

/// The wall contacts' forces and torques of one class's set (see [`scatter_chunk`]).
#[inline(always)]
fn scatter_walls<const D: usize>(walls: &ContactSet, radius: &[f64], f: &mut [VecD<D>], tq: &mut [f64]) {
    let first = walls.first;
    for m in 0..walls.len() {
        let i = walls.i[m] as usize - first;
        let nv = Vec3::from(walls.normal[m]);
        let ft = Vec3::from(walls.ftan[m]);
        f[i] += from3::<D>(&(nv * walls.fnorm[m] + ft));
        add_spin::<D>(tq, i, &-(nv.cross(&ft) * radius[i]));
    }
}

/// The chunk of the particle `jl` after a chunk's first, as the index into
/// [`Overflow`]'s lists (the next chunk is 0): mostly the next one, without a division.
#[inline(always)]
fn later(jl: usize, chunk: usize) -> usize {
    if jl < 2 * chunk {
        0
    } else {
        jl / chunk - 1
    }
}

/// The rolling and twisting torques of one chunk's contacts (see [`scatter_chunk`]): on i,
/// R_eff n̂ × F_roll + M_twist n̂; on a pair's j, the opposite (through `overflow` beyond the
/// chunk, with no force).
#[cold]
fn scatter_rotation<const D: usize>(
    pairs: Option<&ContactSet>,
    walls: Option<&ContactSet>,
    tq: &mut [f64],
    chunk: usize,
    overflow: &mut Overflow<D>,
) {
    let len = tq.len() / spin_len(D);
    let torque = |s: &ContactSet, m: usize| {
        let nv = Vec3::from(s.normal[m]);
        let mut t = Vec3::zeros();
        if s.slots_r.is_some() {
            t += nv.cross(&Vec3::from(s.froll[m])) * s.radius[m];
        }
        if s.slots_w.is_some() {
            t += nv * s.mtwist[m];
        }
        t
    };
    if let Some(pairs) = pairs {
        let first = pairs.first;
        for m in 0..pairs.len() {
            let t = torque(pairs, m) * pairs.sign.get(m).copied().unwrap_or(1.0);
            let (i, j) = (pairs.i[m] as usize - first, pairs.j[m] as usize);
            add_spin::<D>(tq, i, &t);
            let jl = j - first;
            if jl < len {
                add_spin::<D>(tq, jl, &-t);
            } else {
                overflow.push(later(jl, chunk), (j as u32, VecD::<D>::zeros(), -t));
            }
        }
    }
    if let Some(walls) = walls {
        let first = walls.first;
        for m in 0..walls.len() {
            let t = torque(walls, m);
            add_spin::<D>(tq, walls.i[m] as usize - first, &t);
        }
    }
}

/// Adds `v` to spin `i` of the flat array `w` (a − b is a + (−b) in floating point: adding the
/// negation is subtracting).
#[inline(always)]
pub(super) fn add_spin<const D: usize>(w: &mut [f64], i: usize, v: &Vec3) {
    let s = spin::<D>(w, i) + v;
    set_spin::<D>(w, i, &s);
}

/// A pair contact's force (N) on i and torque (N·m) on its partner j (particle number).
pub(super) type Share<const D: usize> = (u32, VecD<D>, Vec3);

/// The forces and torques one chunk's pair contacts put on partners in later chunks (the chunk
/// itself holds those of its own particles), by the partners' chunk: `by[d]` for the chunk
/// d + 1 after this one, each in the order the contacts gave them. Each partner's shares are
/// added after the chunk's own, chunk by chunk in order ([`add_shares`]).
#[derive(Debug, Clone, Default)]
pub(super) struct Overflow<const D: usize> {
    by: Vec<Vec<Share<D>>>,
}

impl<const D: usize> Overflow<D> {
    /// Empties every list (keeping their room).
    pub(super) fn clear(&mut self) {
        self.by.iter_mut().for_each(Vec::clear);
    }

    /// A share for the chunk `d + 1` after this one.
    #[inline]
    pub(super) fn push(&mut self, d: usize, s: Share<D>) {
        if d >= self.by.len() {
            self.by.resize_with(d + 1, Vec::new);
        }
        self.by[d].push(s);
    }

    /// The shares for the chunk `d + 1` after this one.
    #[inline]
    pub(super) fn to(&self, d: usize) -> &[Share<D>] {
        self.by.get(d).map_or(&[], |v| &v[..])
    }

    /// Every list, nearest chunk first.
    pub(super) fn lists(&self) -> &[Vec<Share<D>>] {
        &self.by
    }
}

/// Adds `shares` to the forces `f` and torques `tq` of particles `base..` (the partner's force
/// is the opposite of the share's, its torque the share's).
#[inline]
pub(super) fn add_shares<const D: usize>(
    shares: &[Share<D>],
    base: usize,
    f: &mut [VecD<D>],
    tq: &mut [f64],
) {
    for &(j, fi, t) in shares {
        let jl = j as usize - base;
        f[jl] -= fi;
        add_spin::<D>(tq, jl, &t);
    }
}

/// What every chunk's force evaluation shares: the box, the neighbour list, the walls' states,
/// the laws and how contacts are sorted into their classes, the step (s) and whether contacts'
/// first and last steps take mean forces.
pub(super) struct ChunkContext<'a, const D: usize> {
    pub(super) dom: &'a Domain<D>,
    pub(super) nb: &'a Neighbours<D>,
    pub(super) walls: &'a [WallState<D>],
    pub(super) laws: &'a SpeciesLaws,
    pub(super) map: ClassMap<'a>,
    pub(super) dt: f64,
    pub(super) edges: bool,
    /// The temperatures the heat laws read, in a run with temperatures (see `heat.rs`).
    pub(super) heat: Option<HeatView<'a>>,
}

/// The forces of the chunk of particles `range`: its pair and wall contacts gathered from
/// `view` into their classes' sets (history from the chunk's previous sets `pairs.0` and
/// `walls.0` into the new ones `pairs.1` and `walls.1`, one set per class each), each class's
/// laws called on its own, and the forces and torques summed into `f` and `tq` from the
/// chunk's first particle (see [`scatter_chunk`], which fills `overflow`; chunks of `chunk`
/// particles).
#[allow(clippy::too_many_arguments)]
pub(super) fn chunk_forces<const D: usize>(
    ctx: &ChunkContext<'_, D>,
    range: std::ops::Range<usize>,
    view: &View<'_, D>,
    pairs: (&[ContactSet], &mut [ContactSet]),
    walls: (&[ContactSet], &mut [ContactSet]),
    f: &mut [VecD<D>],
    tq: &mut [f64],
    chunk: usize,
    overflow: &mut Overflow<D>,
) -> Result<(), DemError> {
    let ((pp, np), (pw, nw)) = (pairs, walls);
    gather_pair_classes(np, pp, range.clone(), ctx.dom, ctx.nb, view, &ctx.map)?;
    let near = ctx.nb.wall_candidates(range.clone(), ctx.walls);
    gather_wall_classes(nw, pw, range.clone(), ctx.walls, near, view, &ctx.map)?;
    for (set, laws) in np.iter_mut().zip(&ctx.laws.pair) {
        evaluate(set, laws, ctx, false)?;
    }
    for (set, laws) in nw.iter_mut().zip(&ctx.laws.wall) {
        evaluate(set, laws, ctx, true)?;
    }
    let radius = &view.radius[range.start - view.base..];
    scatter_chunk(np, nw, radius, f, tq, range.len(), chunk, overflow);
    Ok(())
}

/// One class's contacts `set` (against walls: `wall`) through its laws `laws`; its heat law
/// too in a run with temperatures, while the set is in cache.
#[inline]
fn evaluate<const D: usize>(
    set: &mut ContactSet,
    laws: &LawSet,
    ctx: &ChunkContext<'_, D>,
    wall: bool,
) -> Result<(), DemError> {
    let heat = laws.heat.as_deref().zip(ctx.heat.as_ref());
    let rot = Rotating {
        rolling: laws.rolling.as_deref(),
        twisting: laws.twisting.as_deref(),
        context: heat.is_some_and(|(h, _)| h.reads_context()),
    };
    set.evaluate(&*laws.normal, laws.tangential.as_deref(), rot, ctx.dt, ctx.edges)?;
    match heat {
        Some((law, view)) => view.conduct(set, law, wall, ctx.dt),
        None => Ok(()),
    }
}

/// The arrays the kick loops read, whole or one chunk's part.
pub(super) struct Shared<'a, const D: usize> {
    pub(super) force: &'a [VecD<D>],
    /// Torques, [`spin_len`]`(D)` per particle.
    pub(super) torque: &'a [f64],
    pub(super) im: &'a [f64],
    pub(super) ii: &'a [f64],
    /// The positions at the neighbour list's build, or empty (no valid list).
    pub(super) anchor: &'a [VecD<D>],
}

impl<'a, const D: usize> Shared<'a, D> {
    /// Forces, torques, inverse masses and moments of inertia, no anchors (no staleness test).
    pub(super) fn without_anchors(
        force: &'a [VecD<D>],
        torque: &'a [f64],
        im: &'a [f64],
        ii: &'a [f64],
    ) -> Shared<'a, D> {
        Shared {
            force,
            torque,
            im,
            ii,
            anchor: &[],
        }
    }

    /// The part of particles `a..a + len`.
    pub(super) fn chunk(&self, a: usize, len: usize) -> Shared<'a, D> {
        let b = a + len;
        Shared {
            force: &self.force[a..b],
            torque: &self.torque[a * spin_len(D)..b * spin_len(D)],
            im: &self.im[a..b],
            ii: &self.ii[a..b],
            anchor: if self.anchor.is_empty() {
                &[]
            } else {
                &self.anchor[a..b]
            },
        }
    }
}

/// One chunk's item in the kick–drift loop: chunk index, positions, velocities, spins,
/// predicted velocities, previous accelerations.
pub(super) type KickDriftChunk<'a, const D: usize> = (
    usize,
    (
        (
            ((&'a mut [VecD<D>], &'a mut [VecD<D>]), &'a mut [f64]),
            &'a mut [VecD<D>],
        ),
        &'a mut [VecD<D>],
    ),
);

/// The unit roundoff of f64 (2⁻⁵³).
pub(super) const ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// The first half-kick and the drift of one chunk of particles (gravity `g`, half step `h`,
/// step `dt`), preceded by the last step's second half-kick when `pending` (the same force
/// and the same two additions as the separate loops, so the same bits, in one pass over the
/// particles instead of two). Returns whether a particle has moved by more than half the
/// list's `skin` (m) since the anchors (the list is stale; never without anchors) and, when
/// `pending`, the sum of every coordinate of the last step's end state (finite unless one of
/// them is not; else 0).
///
/// `moved` (m) bounds the displacement of the chunk's particles since the anchors: the chunk's
/// largest speed × `dt` is added each step (with the roundoff of the drift's sums), and the
/// displacements themselves are read only once the bound nears half the skin (then `moved`
/// becomes their largest). So the anchors are read in a few steps of a list's life, not in
/// every one, and the test says stale exactly when a displacement exceeds half the skin.
/// Positions are wrapped only when the list is built, so the plain difference is the
/// displacement. A NaN displacement is never stale: the state check reports it.
#[allow(clippy::too_many_arguments)]
pub(super) fn kick_drift_chunk<const D: usize>(
    s: &Shared<'_, D>,
    pending: bool,
    g: VecD<D>,
    h: f64,
    dt: f64,
    pos: &mut [VecD<D>],
    vel: &mut [VecD<D>],
    omega: &mut [f64],
    vpred: &mut [VecD<D>],
    aold: &mut [VecD<D>],
    moved: &mut f64,
    skin: f64,
) -> (bool, f64) {
    let n = pos.len();
    let ns = n * spin_len(D);
    let (force, torque, im, ii) = (&s.force[..n], &s.torque[..ns], &s.im[..n], &s.ii[..n]);
    let (vel, omega, vpred, aold) = (&mut vel[..n], &mut omega[..ns], &mut vpred[..n], &mut aold[..n]);
    let (mut sx, mut sw) = (VecD::<D>::zeros(), Vec3::zeros());
    // the largest squared speed of the drift and squared distance from the origin after it
    let (mut v2max, mut x2max) = (0.0f64, 0.0f64);
    // (`pending` is the same for the whole loop: the compiler makes two loops of it)
    for i in 0..n {
        let (a, al) = (force[i] * im[i] + g, spin::<D>(torque, i) * ii[i]);
        let mut w = spin::<D>(omega, i);
        if pending {
            end_kick(a, al, h, &pos[i], &mut vel[i], &mut w, &mut sx, &mut sw);
        }
        kick_drift_one(
            a,
            al,
            h,
            dt,
            &mut pos[i],
            &mut vel[i],
            &mut w,
            &mut vpred[i],
            &mut aold[i],
        );
        set_spin::<D>(omega, i, &w);
        let (v2, x2) = (vel[i].norm_squared(), pos[i].norm_squared());
        v2max = if v2 > v2max { v2 } else { v2max };
        x2max = if x2 > x2max { x2 } else { x2max };
    }
    let sum = sx.sum() + sw.sum();
    if s.anchor.len() != n {
        return (false, sum);
    }
    // |fl(x + fl(v dt)) − (x + v dt)| ≤ u (|x + v dt| + |v dt|), each component
    *moved += v2max.sqrt() * dt * (1.0 + 4.0 * ROUNDOFF) + 2.0 * ROUNDOFF * x2max.sqrt();
    // (the displacements' own rounding is far below the margin of 0.49 against 0.5)
    if *moved <= 0.49 * skin {
        return (false, sum);
    }
    let anchor = &s.anchor[..n];
    let mut worst = 0.0f64;
    for i in 0..n {
        let d2 = (pos[i] - anchor[i]).norm_squared();
        worst = if d2 > worst { d2 } else { worst };
    }
    *moved = worst.sqrt();
    (worst > 0.25 * skin * skin, sum)
}

/// The second half-kick of one chunk of particles at positions `pos`; returns the sum of every
/// position, velocity and spin coordinate, finite unless one of them is not.
pub(super) fn kick_chunk<const D: usize>(
    s: &Shared<'_, D>,
    pos: &[VecD<D>],
    g: VecD<D>,
    h: f64,
    vel: &mut [VecD<D>],
    omega: &mut [f64],
) -> f64 {
    let n = vel.len();
    let ns = n * spin_len(D);
    let (force, torque, im, ii) = (&s.force[..n], &s.torque[..ns], &s.im[..n], &s.ii[..n]);
    let (pos, omega) = (&pos[..n], &mut omega[..ns]);
    // component-wise running sums: no horizontal add per particle
    let (mut sx, mut sw) = (VecD::<D>::zeros(), Vec3::zeros());
    for i in 0..n {
        let (a, al) = (force[i] * im[i] + g, spin::<D>(torque, i) * ii[i]);
        let mut w = spin::<D>(omega, i);
        end_kick(a, al, h, &pos[i], &mut vel[i], &mut w, &mut sx, &mut sw);
        set_spin::<D>(omega, i, &w);
    }
    sx.sum() + sw.sum()
}
