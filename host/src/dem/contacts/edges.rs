//! The first and last step of a contact: mean forces over the part of the step in contact
//! (see [`super::ContactSet::evaluate`]).

use super::*;

/// 5-point Gauss–Legendre nodes and weights on [0, 1].
const GAUSS5: [(f64, f64); 5] = [
    (0.046_910_077_030_668_02, 0.118_463_442_528_094_54),
    (0.230_765_344_947_158_45, 0.239_314_335_249_683_23),
    (0.5, 0.284_444_444_444_444_44),
    (0.769_234_655_052_841_6, 0.239_314_335_249_683_23),
    (0.953_089_922_969_332, 0.118_463_442_528_094_54),
];

/// The contacts of one chunk, as [`step_edge_means`] reads them.
pub(super) struct Edges<'a> {
    pub(super) delta: &'a [f64],
    pub(super) rate: &'a [f64],
    pub(super) mass: &'a [f64],
    pub(super) radius: &'a [f64],
    pub(super) fresh: &'a [bool],
}

/// The arrays of [`step_edge_means`]' extra batch, kept from call to call (no allocation once
/// grown): the contacts to correct (contact, upper overlap D of the mean, the time-to-overlap
/// factor |δ̇| dt) and the batch's inputs and forces, 5 per contact.
#[derive(Debug, Clone, Default)]
pub(super) struct EdgeScratch {
    jobs: Vec<(usize, f64, f64)>,
    delta: Vec<f64>,
    rate: Vec<f64>,
    mass: Vec<f64>,
    radius: Vec<f64>,
    force: Vec<f64>,
}

/// The first- and last-step means of [`ContactSet::evaluate`], for one chunk: `f` holds the
/// law's forces at the step end and is corrected in place; `last` is read (the previous step's
/// flag) and written; `scratch` holds the extra batch.
pub(super) fn step_edge_means(
    law: &dyn NormalLaw,
    c: Edges<'_>,
    last: &mut [bool],
    f: &mut [f64],
    dt: f64,
    scratch: &mut EdgeScratch,
) -> Result<(), DemError> {
    let h = 0.5 * dt;
    let EdgeScratch {
        jobs,
        delta: qd,
        rate: qr,
        mass: qm,
        radius: qa,
        force: qf,
    } = scratch;
    jobs.clear();
    for m in 0..f.len() {
        let (d, r) = (c.delta[m], c.rate[m]);
        let was_last = last[m];
        last[m] = false;
        // the first step of a contact, the step after its last, its last step: the three tests
        // without a branch each (in a settled pile the rate's sign is a coin toss), then one
        // branch, rarely taken (4.8 % of the 3D pile's step, same bits)
        let first = c.fresh[m] & (r > 0.0) & (d <= 1.5 * r * dt);
        let gone = was_last & (r < 0.0) & (d < -r * h);
        let ends = (r < 0.0) & (d + r * dt - f[m] / c.mass[m] * h * dt <= 0.0);
        if !(first | gone | ends) {
            continue;
        }
        if first {
            jobs.push((m, d + r * h, r * dt));
        } else if gone {
            f[m] = 0.0;
        } else {
            jobs.push((m, d - r * h, -r * dt));
            last[m] = true;
        }
    }
    if jobs.is_empty() {
        return Ok(());
    }
    let k = jobs.len() * GAUSS5.len();
    for v in [&mut *qd, &mut *qr, &mut *qm, &mut *qa] {
        v.clear();
    }
    for &(m, dd, _) in jobs.iter() {
        for (u, _) in GAUSS5 {
            qd.push(dd * u.powi(4));
            qr.push(c.rate[m]);
            qm.push(c.mass[m]);
            qa.push(c.radius[m]);
        }
    }
    qf.clear();
    qf.resize(k, 0.0);
    law.force_batch(NormalBatch {
        delta: qd,
        rate: qr,
        mass: qm,
        radius: qa,
        slots: 0,
        history: &mut [],
        force: qf,
    })?;
    for (q, &(m, dd, div)) in jobs.iter().enumerate() {
        // ∫_0^D F dδ = ∫_0^1 F(D u⁴) 4 D u³ du
        let integral: f64 = GAUSS5
            .iter()
            .enumerate()
            .map(|(g, (u, w))| w * qf[q * GAUSS5.len() + g] * 4.0 * dd * u.powi(3))
            .sum();
        f[m] = integral / div;
    }
    Ok(())
}
