//! Pass 2 of a pair gathering: each candidate pair's contact values (overlap, rate, effective
//! mass and radius, normal, slip) written into a set's arrays.

use super::gather::user;
use super::{View, MAX_OVERLAP};
use crate::dem::cells::Images;
use crate::dem::state::{spin, to3};
use crate::dem::DemError;

/// The arrays pass 2 of a pair gathering writes, one element per contact.
pub(super) struct PairsOut<'a> {
    pub(super) i: &'a mut [u32],
    pub(super) j: &'a mut [u32],
    pub(super) delta: &'a mut [f64],
    pub(super) rate: &'a mut [f64],
    pub(super) mass: &'a mut [f64],
    pub(super) radius: &'a mut [f64],
    pub(super) normal: &'a mut [[f64; 3]],
    pub(super) vrel: &'a mut [[f64; 3]],
    /// Each contact's side (see [`ContactSet::sign`]), written when `SORTED`.
    pub(super) sign: &'a mut [f64],
}

impl PairsOut<'_> {
    /// Writes contact `k`: the pair `i`, `j` and its values `c`; its side when `SORTED`.
    #[inline(always)]
    pub(super) fn put<const SORTED: bool>(&mut self, k: usize, i: u32, j: u32, c: &ContactValues) {
        if SORTED {
            self.sign[k] = c.sign;
        }
        self.i[k] = i;
        self.j[k] = j;
        self.delta[k] = c.delta;
        self.rate[k] = c.rate;
        self.mass[k] = c.mass;
        self.radius[k] = c.radius;
        self.normal[k] = c.normal;
        self.vrel[k] = c.vrel;
    }
}

/// A contact's gathered values (see [`super::ContactSet`]; `sign`: a pair's side, with
/// `SORTED`; 1 for a wall contact).
pub(super) struct ContactValues {
    pub(super) delta: f64,
    pub(super) rate: f64,
    pub(super) mass: f64,
    pub(super) radius: f64,
    pub(super) normal: [f64; 3],
    pub(super) vrel: [f64; 3],
    pub(super) sign: f64,
}

/// The contact of the candidate pair `(ig, jg)` of `view` (see [`pair_geometry`]); `us`: the
/// view's user numbers when `SORTED`.
#[inline(always)]
fn pair_contact<const D: usize, const SORTED: bool>(
    ig: usize,
    jg: usize,
    images: &Images<D>,
    view: &View<'_, D>,
    us: &[u32],
) -> Result<ContactValues, DemError> {
    let View {
        base,
        pos,
        vpred,
        vel,
        omega,
        radius,
        mass,
        uid,
        ..
    } = *view;
    // indices into the view
    let (i, ju) = (ig - base, jg - base);
    let d = images.delta(&pos[i], &pos[ju]);
    let sum = radius[i] + radius[ju];
    let dist = d.norm_squared().sqrt();
    let delta = sum - dist;
    let rmin = radius[i].min(radius[ju]);
    if delta.is_nan() || delta > MAX_OVERLAP * rmin {
        return Err(DemError::Overlap {
            i: user(uid, base, ig),
            partner: format!("particle {}", user(uid, base, jg)),
            delta,
            radius: rmin,
        });
    }
    let mut nv = to3(&(d / dist));
    let rate = -to3(&(vpred[i] - vpred[ju])).dot(&nv);
    let dv = to3(&(vel[i] - vel[ju]));
    let (wi, wj) = (spin::<D>(omega, i), spin::<D>(omega, ju));
    let mut v = dv - (wi * radius[i] + wj * radius[ju]).cross(&nv);
    let mut sign = 1.0;
    if SORTED {
        sign = if us[i] > us[ju] { -1.0 } else { 1.0 };
        nv *= sign;
        v *= sign;
    }
    let (mi, mj) = (mass[i], mass[ju]);
    Ok(ContactValues {
        delta,
        rate,
        mass: mi * mj / (mi + mj),
        radius: radius[i] * radius[ju] / sum,
        normal: [nv.x, nv.y, nv.z],
        vrel: [v.x, v.y, v.z],
        sign,
    })
}

/// Pass 2 of a pair gathering: each candidate pair's overlap (m), overlap rate (m/s, from the
/// predicted velocities), effective mass (kg) and radius (m), unit normal from j to i, and the
/// slip of i's contact point relative to j's (m/s, from the step's velocities and spins); an
/// overlap beyond [`MAX_OVERLAP`] (or NaN) is refused. `SORTED` (the engine's own order): a
/// pair whose j the user numbered first is seen from j, normal and slip negated (exactly:
/// the very numbers the laws get in the user's order).
pub(super) fn pair_geometry<const D: usize>(
    sorted: bool,
    cand: &[(u32, u32)],
    images: &Images<D>,
    view: &View<'_, D>,
    out: PairsOut<'_>,
) -> Result<(), DemError> {
    if sorted {
        pair_geometry_of::<D, true>(cand, images, view, out)
    } else {
        pair_geometry_of::<D, false>(cand, images, view, out)
    }
}

/// [`pair_geometry`] in the engine's own order (`SORTED`) or the user's.
#[inline(never)]
fn pair_geometry_of<const D: usize, const SORTED: bool>(
    cand: &[(u32, u32)],
    images: &Images<D>,
    view: &View<'_, D>,
    out: PairsOut<'_>,
) -> Result<(), DemError> {
    let n = cand.len();
    let mut out = PairsOut {
        i: &mut out.i[..n],
        j: &mut out.j[..n],
        delta: &mut out.delta[..n],
        rate: &mut out.rate[..n],
        mass: &mut out.mass[..n],
        radius: &mut out.radius[..n],
        normal: &mut out.normal[..n],
        vrel: &mut out.vrel[..n],
        sign: if SORTED {
            &mut out.sign[..n]
        } else {
            &mut out.sign[..0]
        },
    };
    let us = if SORTED { view.uid.unwrap_or(&[]) } else { &[][..] };
    for (k, &(i, j)) in cand.iter().enumerate() {
        let c = pair_contact::<D, SORTED>(i as usize, j as usize, images, view, us)?;
        out.put::<SORTED>(k, i, j, &c);
    }
    Ok(())
}
