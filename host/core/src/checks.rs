//! Refusals every front end shares: a law whose arithmetic overflows for a pair (its derived
//! coefficients are not finite), a calibration whose closed form leaves the valid range, and a
//! rolling or twisting law named by the short name LAMMPS's `pair_style dashpot` accepts
//! (`sds` for `rolling-sds`).

use crate::registry::Registry;
use dashpot_sdk::{Coefficient, ErrorKind, LawError, LawKind, ParamSpec, ParamValue};

/// The name of the law of `kind` that `name` means: `name` itself when the registry has a law
/// of that name, else `KIND-name` when that is a law of `kind` (LAMMPS's short names: `sds`,
/// `epsd` in a rolling slot, `sds`, `marshall` in a twisting slot, as `pair_style dashpot`
/// resolves them); otherwise `name` unchanged (the registry's refusal then names it).
pub fn family_name(reg: &Registry, name: &str, kind: LawKind) -> String {
    if reg.find(name).is_ok() || kind == LawKind::Contact || kind == LawKind::Restitution {
        return name.to_string();
    }
    let long = format!("{}-{name}", kind.as_str());
    match reg.find(&long) {
        Ok((e, _)) if e.info.kind == kind => long,
        _ => name.to_string(),
    }
}

/// Whether the law, with these parameters, has finite coefficients for the pair in question.
pub type FiniteFor<'a> = dyn Fn(&[ParamValue]) -> bool + 'a;

/// Refuses coefficients of law `law` (bound to a pair of effective mass `mass` kg and radius
/// `radius` m) that are not finite: the law's arithmetic overflowed for the parameters `given`.
/// The message names the coefficient, the parameters given with their valid ranges (`schema`)
/// and, when `limit` finds one, the largest (or smallest) value of a parameter for which this
/// pair's coefficients are finite.
pub fn finite_coefficients(
    law: &str,
    given: &[ParamValue],
    schema: &[ParamSpec],
    mass: f64,
    radius: f64,
    coeffs: &[Coefficient],
    limit: Option<&FiniteFor<'_>>,
) -> Result<(), LawError> {
    let Some(bad) = coeffs.iter().find(|c| !c.value.is_finite()) else {
        return Ok(());
    };
    let shown: Vec<String> = given
        .iter()
        .map(|p| match schema.iter().find(|s| s.name == p.name.as_str()) {
            Some(s) => format!("{} = {:e} {} (valid {})", p.name, p.value, s.unit, s.range),
            None => format!("{} = {:e}", p.name, p.value),
        })
        .collect();
    let params = if shown.is_empty() {
        "its default parameters".to_string()
    } else {
        shown.join(", ")
    };
    let bound = limit
        .and_then(|ok| bound_of(given, schema, ok))
        .map(|(name, v, unit, upper)| {
            format!(
                "; for this pair {name} must be {} {v:.3e} {unit}",
                if upper { "at most" } else { "at least" }
            )
        })
        .unwrap_or_default();
    Err(LawError::new(
        ErrorKind::InvalidParameter,
        format!(
            "law '{law}' with {params} overflows for this pair (m_eff = {mass:e} kg, r_eff = {radius:e} m): \
             its coefficient {} = {} {} is not finite{bound}",
            bad.name, bad.value, bad.unit
        ),
    ))
}

/// The given parameter that, moved towards 1 alone, makes `ok` hold, and the value (to 1e-3
/// relative) where it starts to hold: (name, value, unit, whether it is an upper bound).
fn bound_of(
    given: &[ParamValue],
    schema: &[ParamSpec],
    ok: &FiniteFor<'_>,
) -> Option<(String, f64, String, bool)> {
    for (i, p) in given.iter().enumerate() {
        let v = p.value;
        if !(v.is_finite() && v > 0.0) {
            continue;
        }
        let Some(spec) = schema.iter().find(|s| s.name == p.name.as_str()) else {
            continue;
        };
        let with = |x: f64| {
            let mut q = given.to_vec();
            q[i].value = x;
            spec.range.contains(x) && ok(&q)
        };
        // decades towards 1 until the coefficients are finite
        let upper = v > 1.0;
        let step = if upper { 0.1 } else { 10.0 };
        let mut good = v;
        let mut found = false;
        for _ in 0..640 {
            good *= step;
            if with(good) {
                found = true;
                break;
            }
            if (upper && good < 1.0) || (!upper && good > 1.0) {
                break;
            }
        }
        if !found {
            continue;
        }
        // bisect in log space between the good value and the bad one
        let (mut g, mut b) = (good.ln(), v.ln());
        while (b - g).abs() > 1e-3 {
            let m = 0.5 * (g + b);
            if with(m.exp()) {
                g = m;
            } else {
                b = m;
            }
        }
        return Some((p.name.to_string(), g.exp(), spec.unit.clone(), upper));
    }
    None
}

/// Refuses calibrated values that are not finite or leave their parameter's valid range (a
/// contact time so short that the stiffness overflows, say), naming the value, the range and
/// the target that asked for it.
pub fn calibrated(
    law: &str,
    target: &str,
    schema: &[ParamSpec],
    values: &[ParamValue],
) -> Result<(), LawError> {
    for v in values {
        let Some(s) = schema.iter().find(|s| s.name == v.name.as_str()) else {
            continue;
        };
        if !s.range.contains(v.value) {
            return Err(LawError::new(
                ErrorKind::InvalidParameter,
                format!(
                    "law '{law}' cannot reproduce {target}: its closed form gives {} = {:e} {}, outside the valid \
                     range {} of {}",
                    v.name, v.value, s.unit, s.range, v.name
                ),
            ));
        }
    }
    Ok(())
}

/// How far a unit normal's length may stray from 1 (relative): rounding of a normalised
/// vector, not a vector left unnormalised.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// Refuses a normal that is not a unit vector (zero, non-finite, or of another length): the
/// tangential, rolling and twisting laws project onto the plane it defines, and a zero normal
/// would give a force in no defined direction. The message names the contact and its vector.
#[inline]
pub fn unit_normals(normal: &[[f64; 3]]) -> Result<(), String> {
    // every call of a LAMMPS step checks its normals: first one branch-free pass, without square
    // roots, that accepts lengths within half the tolerance (|n|² in [(1 − tol/2)², (1 +
    // tol/2)²], far inside the exact test's band whatever the rounding); the exact test below
    // decides (and names the culprit) only when it says no
    let (lo, hi) = (
        (1.0 - 0.5 * UNIT_TOLERANCE).powi(2),
        (1.0 + 0.5 * UNIT_TOLERANCE).powi(2),
    );
    let surely = normal.iter().fold(true, |ok, n| {
        let l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        ok & (l2 >= lo) & (l2 <= hi)
    });
    if surely {
        return Ok(());
    }
    not_unit(normal)
}

/// The search of [`unit_normals`] when its fused test says no: the first normal that is not a
/// unit vector, named.
#[cold]
#[inline(never)]
fn not_unit(normal: &[[f64; 3]]) -> Result<(), String> {
    for (i, n) in normal.iter().enumerate() {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        // (NaN fails the comparison: refused too)
        if (len - 1.0).abs().partial_cmp(&UNIT_TOLERANCE) != Some(std::cmp::Ordering::Less) {
            return Err(format!(
                "normal of contact {i} = ({}, {}, {}) has length {len}: it must be a unit vector (length 1 \
                 within {UNIT_TOLERANCE:e}), from the partner to the particle",
                n[0], n[1], n[2]
            ));
        }
    }
    Ok(())
}
