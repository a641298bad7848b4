//! The heat kind (new in sdk 0.4: no plugin of an older sdk exports one).

use super::*;
use crate::heat::{BoundHeat, HeatBatch, HeatFlow, HeatLaw};

/// A raw heat batch (sdk 0.4): `n` contacts, structure of arrays.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy)]
pub struct FfiHeatBatch {
    /// Number of contacts.
    pub n: usize,
    /// History slots per contact.
    pub slots: usize,
    /// Time step (s).
    pub dt: f64,
    /// Temperatures `[T_i, T_j]` (K), `2 n` values.
    pub temperature: *const f64,
    /// Normal forces (N), `n` values.
    pub normal_force: *const f64,
    /// Overlaps (m), `n` values.
    pub delta: *const f64,
    /// Effective radii (m), `n` values.
    pub radius: *const f64,
    /// Each contact's normal context (`n` values), or null (the defaults).
    pub context: *const NormalContext,
    /// History, `n × slots` values, read and updated in place.
    pub history: *mut f64,
    /// Output: heat flow into particle i (W) and conductance (W/K), `n` values.
    pub flow: *mut HeatFlow,
}

/// The heat kind.
pub struct Heat;

impl Kind for Heat {
    type Ffi = FfiHeatBatch;
    // new in 0.4: its own batch stands in for the 0.3 one it never had
    type Ffi03 = FfiHeatBatch;
    type Batch<'a> = HeatBatch<'a>;
    const KIND: LawKind = LawKind::Heat;
    fn len(b: &HeatBatch<'_>) -> usize {
        b.flow.len()
    }
    fn check_lengths(name: &str, slots: usize, b: &HeatBatch<'_>) -> Result<(), LawError> {
        b.lengths().check("heat", name, slots)
    }
    fn raw(b: &mut HeatBatch<'_>, _power: *mut f64, _elastic: *mut f64) -> FfiHeatBatch {
        FfiHeatBatch {
            n: b.flow.len(),
            slots: b.slots,
            dt: b.dt,
            temperature: b.temperature.as_ptr() as *const f64,
            normal_force: b.normal_force.as_ptr(),
            delta: b.delta.as_ptr(),
            radius: b.radius.as_ptr(),
            context: context_ptr(b.context),
            history: b.history.as_mut_ptr(),
            flow: b.flow.as_mut_ptr(),
        }
    }
    fn ffi03(b: &FfiHeatBatch) -> &FfiHeatBatch {
        b
    }
    fn fault_error(name: &str, b: &HeatBatch<'_>, st: BatchStatus, f: BatchFault) -> LawError {
        let i = f.index.min(b.flow.len().saturating_sub(1));
        match (st, f.field) {
            (BatchStatus::NonFiniteOutput, field) => LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "heat law '{name}' returned {} on contact {i} (heat {:e} W, conductance {:e} W/K; \
                     temperatures {:?} K, normal force {:e} N): the heat must be finite and the \
                     conductance finite and ≥ 0",
                    if field == BatchFault::CONDUCTANCE {
                        "a bad conductance"
                    } else {
                        "a non-finite heat flow"
                    },
                    b.flow[i].heat,
                    b.flow[i].conductance,
                    b.temperature[i],
                    b.normal_force[i]
                ),
            ),
            (_, BatchFault::TEMPERATURE) => LawError::new(
                ErrorKind::NonFinite,
                format!(
                    "heat law '{name}': input temperature[{i}] = {:?} must be finite (K); refused \
                     before evaluation",
                    b.temperature[i]
                ),
            ),
            (_, BatchFault::CONTEXT_INPUT) => bad_context("heat", name, i, b.context),
            (_, field) => {
                let c = b.contact(i);
                let v = motion_input(field, [c.normal_force, c.delta, 1.0, c.radius, c.dt]);
                bad_input("heat", name, field, i, v)
            }
        }
    }
}

/// Whether a block's inputs are surely good: every temperature, normal force and overlap
/// finite, every radius finite and > 0. One branch-free pass that vectorises, four contacts at
/// a time: a sum of v − v over every value (0 unless one of them is NaN or ±∞) and a running
/// minimum of the radii. (Four separate checks cost each its own set-up, tail and reduction: a
/// tenth of a heat call on the DEM engine's small batches.) When it says no, the exact checks
/// name the culprit.
#[inline(always)]
#[allow(clippy::eq_op)]
fn inputs_ok(t: &[[f64; 2]], f: &[f64], d: &[f64], a: &[f64]) -> bool {
    let n = f.len();
    let (t, d, a) = (t[..n].as_flattened(), &d[..n], &a[..n]);
    let (mut sum, mut low) = ([0.0f64; 4], [f64::INFINITY; 4]);
    let (tc, fc, dc, ac) = (
        t.chunks_exact(8),
        f.chunks_exact(4),
        d.chunks_exact(4),
        a.chunks_exact(4),
    );
    let tail = n - n % 4;
    for (((t, f), d), a) in tc.zip(fc).zip(dc).zip(ac) {
        for j in 0..4 {
            let (x, y) = (t[j] - t[j], t[j + 4] - t[j + 4]);
            sum[j] += ((x + y) + (f[j] - f[j])) + ((d[j] - d[j]) + (a[j] - a[j]));
            low[j] = if a[j] < low[j] { a[j] } else { low[j] };
        }
    }
    for k in tail..n {
        let v = [t[2 * k], t[2 * k + 1], f[k], d[k], a[k]];
        sum[0] += v.iter().fold(0.0, |s, v| s + (v - v));
        low[0] = if a[k] < low[0] { a[k] } else { low[0] };
    }
    let low = low[0].min(low[1]).min(low[2].min(low[3]));
    (sum[0] + sum[1]) + (sum[2] + sum[3]) == 0.0 && low > 0.0
}

/// Whether every heat and conductance of `flow` is finite and every conductance ≥ 0 (−0
/// included): over the flat array of the pairs, in one branch-free pass that vectorises, a sum
/// of v − v (0 unless a value is NaN or ±∞) and a running minimum of the conductances (the odd
/// positions: lanes 1 and 3 of four). (A fold over the pairs was vectorised with shuffles that
/// split them, some 16 instructions a contact.)
#[inline(always)]
#[allow(clippy::eq_op)]
fn flows_ok(flow: &[HeatFlow]) -> bool {
    const _: () = assert!(std::mem::size_of::<HeatFlow>() == 2 * std::mem::size_of::<f64>());
    // SAFETY: `HeatFlow` is `repr(C)` of two f64 (asserted above), the conductance second
    let flat = unsafe { std::slice::from_raw_parts(flow.as_ptr().cast::<f64>(), 2 * flow.len()) };
    let (mut sum, mut low) = ([0.0f64; 4], [0.0f64; 4]);
    let mut it = flat.chunks_exact(4);
    for c in &mut it {
        for j in 0..4 {
            sum[j] += c[j] - c[j];
            low[j] = if c[j] < low[j] { c[j] } else { low[j] };
        }
    }
    for (j, &v) in it.remainder().iter().enumerate() {
        sum[j] += v - v;
        low[j] = if v < low[j] { v } else { low[j] };
    }
    low[1] >= 0.0 && low[3] >= 0.0 && (sum[0] + sum[1]) + (sum[2] + sum[3]) == 0.0
}

/// The first contact of `flow` whose heat is not finite, or whose conductance is not finite
/// and ≥ 0, with the array at fault.
#[inline(always)]
fn bad_flow(flow: &[HeatFlow]) -> Option<(usize, u8)> {
    if flows_ok(flow) {
        return None;
    }
    flow.iter().enumerate().find_map(|(i, f)| {
        if !is_finite(f.heat) {
            Some((i, BatchFault::HEAT))
        } else if !(0.0..f64::INFINITY).contains(&f.conductance) {
            Some((i, BatchFault::CONDUCTANCE))
        } else {
            None
        }
    })
}

impl<B: BoundHeat> KindBound<Heat> for B {
    #[inline(always)]
    unsafe fn run(&self, r: &FfiHeatBatch) -> Result<bool, (usize, u8)> {
        if !(r.dt >= 0.0 && r.dt < f64::INFINITY) {
            return Err((0, BatchFault::DT));
        }
        let (n, slots) = (r.n, r.slots);
        let (temperature, fnorm, delta, radius, history, flow) = unsafe {
            (
                slice(r.temperature as *const [f64; 2], n),
                slice(r.normal_force, n),
                slice(r.delta, n),
                slice(r.radius, n),
                slice_mut(r.history, n * slots),
                slice_mut(r.flow, n),
            )
        };
        let context = unsafe { contexts(r.context, n) };
        blocks!(n, |lo, hi| {
            let t = &temperature[lo..hi];
            let (f, d, a) = (&fnorm[lo..hi], &delta[lo..hi], &radius[lo..hi]);
            if !inputs_ok(t, f, d, a) {
                first_bad(
                    lo,
                    [
                        (
                            first_non_finite(t.as_flattened()).map(|i| i / 2),
                            BatchFault::TEMPERATURE,
                        ),
                        (first_non_finite(f), BatchFault::NORMAL_FORCE),
                        (first_non_finite(d), BatchFault::DELTA),
                        (first_non_positive(a), BatchFault::RADIUS),
                    ],
                )?;
            }
            let x = context_block(context, lo, hi)?;
            let o = &mut flow[lo..hi];
            self.heat_batch(HeatBatch {
                dt: r.dt,
                temperature: t,
                normal_force: f,
                delta: d,
                radius: a,
                context: x,
                slots,
                history: &mut history[lo * slots..hi * slots],
                flow: &mut *o,
            });
            match bad_flow(o) {
                Some((i, field)) => Err((lo + i, field)),
                None => Ok(()),
            }
        });
        Ok(false)
    }
    fn kind_coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        self.coefficients(mass, radius)
    }
}

kind_law!(Heat, HeatLaw, T::READS_CONTEXT);

#[cfg(test)]
mod tests {
    use super::*;

    /// The fused input check says no exactly when a temperature, normal force or overlap is
    /// not finite, or a radius not finite and > 0, wherever it is.
    #[test]
    fn the_input_check_finds_every_bad_input() {
        for n in [1, 3, 4, 5, 9, 64] {
            let t = vec![[300.0, 400.0]; n];
            let (f, d, a) = (vec![1.0; n], vec![1e-6; n], vec![1e-3; n]);
            assert!(inputs_ok(&t, &f, &d, &a), "{n} good contacts");
            let bad = [f64::NAN, f64::INFINITY, -f64::INFINITY];
            for i in 0..n {
                for v in bad.into_iter().chain([-0.0, 0.0, -1.0, 5e-324, -1e300]) {
                    let finite = v.is_finite();
                    for s in 0..2 {
                        let mut x = t.clone();
                        x[i][s] = v;
                        assert_eq!(inputs_ok(&x, &f, &d, &a), finite, "{n}: T[{i}][{s}] = {v}");
                    }
                    let mut x = f.clone();
                    x[i] = v;
                    assert_eq!(inputs_ok(&t, &x, &d, &a), finite, "{n}: F[{i}] = {v}");
                    let mut x = d.clone();
                    x[i] = v;
                    assert_eq!(inputs_ok(&t, &f, &x, &a), finite, "{n}: delta[{i}] = {v}");
                    let mut x = a.clone();
                    x[i] = v;
                    let ok = finite && v > 0.0;
                    assert_eq!(inputs_ok(&t, &f, &d, &x), ok, "{n}: radius[{i}] = {v}");
                }
            }
        }
    }

    /// The fused check refuses exactly a non-finite heat or a conductance not finite and ≥ 0,
    /// at any contact, and names it.
    #[test]
    fn the_flow_check_finds_every_bad_flow() {
        let good = HeatFlow {
            heat: -3.0,
            conductance: 0.5,
        };
        for n in [1, 3, 4, 65] {
            assert_eq!(bad_flow(&vec![good; n]), None);
            for i in 0..n {
                for v in [-0.0, 5e-324, -1e-300, f64::NAN, f64::INFINITY, -f64::INFINITY] {
                    let mut x = vec![good; n];
                    x[i].heat = v;
                    let want = (!v.is_finite()).then_some((i, BatchFault::HEAT));
                    assert_eq!(bad_flow(&x), want, "{n} flows, heat[{i}] = {v}");
                    let mut x = vec![good; n];
                    x[i].conductance = v;
                    let ok = v == 0.0 || (v > 0.0 && v.is_finite());
                    let want = (!ok).then_some((i, BatchFault::CONDUCTANCE));
                    assert_eq!(bad_flow(&x), want, "{n} flows, conductance[{i}] = {v}");
                }
            }
        }
    }
}
