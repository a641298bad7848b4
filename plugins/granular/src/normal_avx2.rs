//! The normal laws' force-and-context batch in AVX2 registers, four contacts at a time (x86-64
//! CPUs with AVX2, chosen at run time): LAMMPS's `hooke`, `hertz`, `dmt` and `jkr` with each
//! damping model, [`crate::normal::evaluate`] operation for operation on four lanes
//! ([`dashpot_sdk::simd`]), JKR's cube roots included ([`cbrt`], [`crate::cbrt::cbrt`]'s
//! arithmetic), so every contact gets the per-contact form's bits (a test checks); branches
//! become selects. Also the reach (JKR's pull-off distance) of a batch.

use crate::cbrt::{GUESS, HIGHEST, LOW, LOWEST, SIGN};
use crate::normal::{lane, DampingModel, NormalModel, INVROOT6, JKRPREFIX, PI27SQ, SIXROOT6, THREEROOT3};
use dashpot_sdk::simd::{put_triples, F64x4, V3};
use dashpot_sdk::{NormalBatch, NormalContext};
use std::arch::x86_64::*;
use std::f64::consts::PI;

/// [`crate::cbrt::cbrt`] lane by lane, the same bits: its arithmetic on four lanes when every
/// lane is within 2^±1000, else lane by lane through it.
///
/// # Safety
/// The CPU must support AVX2.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn cbrt(x: F64x4) -> F64x4 {
    let bits = _mm256_castpd_si256(x.0);
    let abs = _mm256_andnot_si256(_mm256_set1_epi64x(SIGN as i64), bits);
    // LOWEST <= abs < HIGHEST (all below 2⁶³: the signed comparison is the unsigned one)
    let low = _mm256_cmpgt_epi64(_mm256_set1_epi64x(LOWEST as i64), abs);
    let high = _mm256_cmpgt_epi64(abs, _mm256_set1_epi64x(HIGHEST as i64 - 1));
    if _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_or_si256(low, high))) != 0 {
        let v = x.to_array().map(crate::cbrt::cbrt);
        return F64x4(_mm256_loadu_pd(v.as_ptr()));
    }
    // the guess bits(a)/3 + GUESS, lane by lane (no 64-bit division in AVX2)
    let mut g = [0u64; 4];
    _mm256_storeu_si256(g.as_mut_ptr() as *mut __m256i, abs);
    let g = g.map(|b| b / 3 + GUESS);
    let a = F64x4(_mm256_castsi256_pd(abs));
    let mut t = F64x4(_mm256_loadu_pd(g.as_ptr() as *const f64));
    for _ in 0..2 {
        let t3 = t.mul(t).mul(t);
        t = t.mul(t3.add(a).add(a).div(t3.add(t3).add(a)));
    }
    // rounded to 26 significant bits: t² is then exact
    let tb = _mm256_add_epi64(_mm256_castpd_si256(t.0), _mm256_set1_epi64x(1 << 26));
    let t = F64x4(_mm256_castsi256_pd(_mm256_andnot_si256(
        _mm256_set1_epi64x(LOW as i64),
        tb,
    )));
    let s = t.mul(t);
    let r = a.div(s);
    let r = r.sub(t).div(t.add(t).add(r));
    let root = t.add(t.mul(r));
    let sign = _mm256_and_si256(bits, _mm256_set1_epi64x(SIGN as i64));
    F64x4(_mm256_castsi256_pd(_mm256_or_si256(
        _mm256_castpd_si256(root.0),
        sign,
    )))
}

/// A normal model's constants as the lanes read them
/// ([`NormalModel::lane_constants`]): k, E_eff (JKR) and γ.
#[derive(Clone, Copy)]
pub(crate) struct Consts {
    pub(crate) k: f64,
    pub(crate) emix: f64,
    pub(crate) cohesion: f64,
}

/// JKR's pull-off distance (`Jkr::pulloff_distance`) at effective radius `reff` (> 0).
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn pulloff_distance(m: &Consts, reff: F64x4) -> F64x4 {
    let coh = F64x4::splat(m.cohesion);
    let x = reff.mul(coh).mul(coh).div(F64x4::splat(m.emix * m.emix));
    let d = F64x4::splat(JKRPREFIX).mul(cbrt(x));
    F64x4::select(reff.gt(F64x4::splat(0.0)), d, F64x4::splat(0.0))
}

/// `Jkr::radius_at`: the JKR contact radius at effective radius `reff` and dR = δ R.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn jkr_radius(m: &Consts, reff: F64x4, dr: F64x4) -> F64x4 {
    let zero = F64x4::splat(0.0);
    let (coh, e) = (F64x4::splat(m.cohesion), F64x4::splat(m.emix));
    let r2 = reff.mul(reff);
    let dr2 = dr.mul(dr);
    let t0 = coh.mul(coh).mul(r2).mul(r2).mul(e);
    let t1 = F64x4::splat(PI27SQ).mul(t0);
    let t2 = F64x4::splat(8.0).mul(dr).mul(dr2).mul(e).mul(e).mul(e);
    let t3 = F64x4::splat(4.0).mul(dr2).mul(e);
    let sqrt1 = zero.max(t0.mul(t1.add(F64x4::splat(2.0).mul(t2))));
    let t4 = cbrt(t1.add(t2).add(F64x4::splat(THREEROOT3 * PI).mul(sqrt1.sqrt())));
    let t5 = t3.div(t4).add(t4.div(e));
    let sqrt2 = zero.max(F64x4::splat(2.0).mul(dr).add(t5));
    let t6 = sqrt2.sqrt();
    let c = F64x4::splat(SIXROOT6 * m.cohesion * PI);
    let sqrt3 = zero.max(F64x4::splat(4.0).mul(dr).sub(t5).add(c.mul(r2).div(e.mul(t6))));
    F64x4::splat(INVROOT6).mul(t6.add(sqrt3.sqrt()))
}

/// Model `M` with damping `D` (coefficient `coef`, `limit_damping` `limit`) on contacts
/// `i .. i + 4` of `b`: force and history written, the contexts returned as lanes
/// `[a, F_c, η_n]` (0 where the contact does not act).
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn step<M: NormalModel, D: DampingModel>(
    m: &Consts,
    coef: f64,
    limit: bool,
    b: &mut NormalBatch<'_>,
    i: usize,
) -> V3 {
    let zero = F64x4::splat(0.0);
    let (delta, rate) = (F64x4::load(b.delta, i), F64x4::load(b.rate, i));
    let (meff, reff) = (F64x4::load(b.mass, i), F64x4::load(b.radius, i));
    let k = F64x4::splat(m.k);
    // whether the contact acts (JKR: a formed contact down to its pull-off distance)
    let pressed = delta.gt(zero);
    let acts = if M::LANE == lane::JKR {
        let touching = F64x4::load(b.history, i).ne(zero);
        let pulled = touching.and(delta.not_gt(zero));
        let mut acts = pressed;
        if _mm256_movemask_pd(pulled.0) != 0 {
            acts = acts.or(touching.and(delta.gt(pulloff_distance(m, reff).neg())));
        }
        let flag = F64x4::select(acts, F64x4::splat(1.0), zero);
        _mm256_storeu_pd(b.history.as_mut_ptr().add(i), flag.0);
        acts
    } else {
        pressed
    };
    let a = if M::LANE == lane::JKR {
        jkr_radius(m, reff, delta.mul(reff))
    } else {
        delta.mul(reff).sqrt()
    };
    let (fne, pulloff) = match M::LANE {
        lane::HOOKE => (k.mul(delta), zero),
        lane::HERTZ => (k.mul(a).mul(delta), zero),
        lane::DMT => {
            let p = F64x4::splat(4.0 * PI * m.cohesion).mul(reff);
            (k.mul(a).mul(delta).sub(p), p)
        }
        _ => {
            let a2 = a.mul(a);
            let root = F64x4::splat(4.0 * m.cohesion * m.emix)
                .div(F64x4::splat(PI).mul(a))
                .sqrt();
            let f = k
                .mul(a)
                .mul(a2)
                .div(reff)
                .sub(F64x4::splat(2.0 * PI).mul(a2).mul(root));
            (f, F64x4::splat(3.0 * PI * m.cohesion).mul(reff))
        }
    };
    let c = F64x4::splat(coef);
    let damping = match D::LANE {
        lane::VELOCITY => c,
        lane::MASS_VELOCITY => c.mul(meff),
        lane::VISCOELASTIC => c.mul(meff).mul(a),
        _ => {
            // √(max(0, m F/δ)) for δ > 0, else 0
            let s = F64x4::select(pressed, zero.max(meff.mul(fne).div(delta)), zero);
            c.mul(s.sqrt())
        }
    };
    let mut force = fne.add(damping.mul(rate));
    if limit {
        force = F64x4::select(force.lt(zero), zero, force);
    }
    let cap = if M::COHESIVE {
        fne.add(F64x4::splat(2.0).mul(pulloff)).abs()
    } else {
        force.abs()
    };
    _mm256_storeu_pd(b.force.as_mut_ptr().add(i), F64x4::select(acts, force, zero).0);
    [
        F64x4::select(acts, a, zero),
        F64x4::select(acts, cap, zero),
        F64x4::select(acts, damping, zero),
    ]
}

/// [`crate::normal_laws::GranNormalBound`]'s force and context of the contacts
/// `0..n − n % 4` of batch `b` into `b.force` and `out`, its history updated; returns where the
/// lanes stopped (the rest is the caller's).
///
/// # Safety
/// The CPU must support AVX2; `M::LANE` and `D::LANE` name lane forms.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn force_context<M: NormalModel, D: DampingModel>(
    m: &Consts,
    coef: f64,
    limit: bool,
    b: &mut NormalBatch<'_>,
    out: &mut [NormalContext],
) -> usize {
    let n = b.force.len();
    let slots = usize::from(M::LANE == lane::JKR);
    assert!(
        b.delta.len() == n
            && b.rate.len() == n
            && b.mass.len() == n
            && b.radius.len() == n
            && out.len() == n
            && b.slots == slots
            && b.history.len() == slots * n,
        "a batch's arrays have its contacts' lengths"
    );
    // SAFETY: NormalContext is three f64 (repr(C))
    let flat = unsafe { std::slice::from_raw_parts_mut(out.as_mut_ptr() as *mut f64, 3 * n) };
    let n4 = n - n % 4;
    let mut i = 0;
    while i < n4 {
        let x = step::<M, D>(m, coef, limit, b, i);
        put_triples(x, flat, i);
        i += 4;
    }
    n4
}

/// JKR's reach of the contacts `0..n − n % 4` of a batch just evaluated into `out`: its
/// pull-off distance where the contact acts (history slot 0), else 0; returns where the lanes
/// stopped.
///
/// # Safety
/// The CPU must support AVX2; the model is JKR (one history slot).
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn jkr_reach(m: &Consts, b: &NormalBatch<'_>, out: &mut [f64]) -> usize {
    let n = out.len();
    assert!(
        b.radius.len() >= n && b.slots == 1 && b.history.len() >= n,
        "a batch's arrays have its contacts' lengths"
    );
    let zero = F64x4::splat(0.0);
    let n4 = n - n % 4;
    let mut i = 0;
    while i < n4 {
        let acts = F64x4::load(b.history, i).ne(zero);
        let r = if _mm256_movemask_pd(acts.0) != 0 {
            F64x4::select(acts, pulloff_distance(m, F64x4::load(b.radius, i)), zero)
        } else {
            zero
        };
        _mm256_storeu_pd(out.as_mut_ptr().add(i), r.0);
        i += 4;
    }
    n4
}
