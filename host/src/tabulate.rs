//! Any contact law as a restitution law: r(v) tabulated from the integrator on a log grid in v
//! and interpolated by a cubic spline in ln v, refined until the interpolation error, checked
//! against the integrator at every interval midpoint, is below the tolerance.

use crate::collide::two_body::{collide, CollideError, ContactForce, Options};
use dashpot_sdk::{BoundRestitution, EndCriterion, LawError, Pair, ParamValue, Particle};
use rayon::prelude::*;

/// r(v) of a contact law for one pair, as a table.
#[derive(Debug, Clone)]
pub struct TabulatedRestitution {
    x0: f64,
    dx: f64,
    r: Vec<f64>,
    /// Second derivatives of the natural spline in x = ln v.
    m: Vec<f64>,
    /// Smallest speed of the table (m/s).
    pub v_min: f64,
    /// Largest speed of the table (m/s).
    pub v_max: f64,
    /// Largest interpolation error found at the midpoints of the final grid.
    pub max_error: f64,
    /// The end criterion of the tabulated collisions.
    pub end: EndCriterion,
    /// Power-law tails: r ≈ 1 − a v^p below v_min (from the first two nodes), r ≈ b v^q above v_max.
    low: (f64, f64),
    high: (f64, f64),
}

fn spline_second_derivatives(y: &[f64], dx: f64) -> Vec<f64> {
    // natural cubic spline on a uniform grid (Thomas algorithm)
    let n = y.len();
    let mut m = vec![0.0; n];
    if n < 3 {
        return m;
    }
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    for i in 1..n - 1 {
        let rhs = 6.0 * (y[i + 1] - 2.0 * y[i] + y[i - 1]) / (dx * dx);
        let (a, b, cc) = (1.0, 4.0, 1.0);
        let denom = b - a * c[i - 1];
        c[i] = cc / denom;
        d[i] = (rhs - a * d[i - 1]) / denom;
    }
    for i in (1..n - 1).rev() {
        m[i] = d[i] - c[i] * m[i + 1];
    }
    m
}

impl TabulatedRestitution {
    /// Tabulates r(v) = realized restitution of `law` (bound to a pair of effective mass `mass`)
    /// for v in [`v_min`, `v_max`], refining the grid until the spline is within `tol` of the
    /// integrator at every midpoint. Collisions run in parallel.
    pub fn build<C: ContactForce + Sync>(
        law: &C,
        mass: f64,
        end: EndCriterion,
        v_min: f64,
        v_max: f64,
        tol: f64,
        options: &Options,
    ) -> Result<TabulatedRestitution, CollideError> {
        if !(v_min > 0.0 && v_max > v_min && v_max.is_finite()) {
            return Err(CollideError::BadSpeed(if v_min > 0.0 { v_max } else { v_min }));
        }
        let eps =
            |v: f64| -> Result<f64, CollideError> { Ok(collide(law, mass, v, end, options)?.restitution) };
        // a law with memory holds one collision's history at a time: its collisions run one
        // after the other
        let serial = law.has_history();
        let many = |xs: Vec<f64>| -> Result<Vec<f64>, CollideError> {
            if serial {
                xs.into_iter().map(|x| eps(x.exp())).collect()
            } else {
                xs.into_par_iter().map(|x| eps(x.exp())).collect()
            }
        };
        let (x0, x1) = (v_min.ln(), v_max.ln());
        let mut n = 33usize;
        let mut r: Vec<f64> = many(
            (0..n)
                .map(|i| x0 + (x1 - x0) * i as f64 / (n - 1) as f64)
                .collect(),
        )?;
        loop {
            let dx = (x1 - x0) / (n - 1) as f64;
            let m = spline_second_derivatives(&r, dx);
            let mids: Vec<f64> = many((0..n - 1).map(|i| x0 + (i as f64 + 0.5) * dx).collect())?;
            let t = TabulatedRestitution::from_nodes(x0, dx, r.clone(), m, v_min, v_max, end);
            let err = mids
                .iter()
                .enumerate()
                .map(|(i, &e)| (t.interpolate(x0 + (i as f64 + 0.5) * dx) - e).abs())
                .fold(0.0, f64::max);
            if err <= tol || n > 4096 {
                return Ok(TabulatedRestitution { max_error: err, ..t });
            }
            // refine: interleave the midpoints (already computed) with the nodes
            let mut rr = Vec::with_capacity(2 * n - 1);
            for i in 0..n - 1 {
                rr.push(r[i]);
                rr.push(mids[i]);
            }
            rr.push(r[n - 1]);
            r = rr;
            n = 2 * n - 1;
        }
    }

    fn from_nodes(
        x0: f64,
        dx: f64,
        r: Vec<f64>,
        m: Vec<f64>,
        v_min: f64,
        v_max: f64,
        end: EndCriterion,
    ) -> TabulatedRestitution {
        let n = r.len();
        let tail = |ra: f64, rb: f64, xa: f64, xb: f64| {
            // log-log slope of y = (1 − r) (low) or y = r (high)
            let p = (rb.max(1e-300).ln() - ra.max(1e-300).ln()) / (xb - xa);
            (ra.max(1e-300) * (-p * xa).exp(), p)
        };
        let low = tail(1.0 - r[0], 1.0 - r[1], x0, x0 + dx);
        let high = tail(
            r[n - 2],
            r[n - 1],
            x0 + (n - 2) as f64 * dx,
            x0 + (n - 1) as f64 * dx,
        );
        TabulatedRestitution {
            x0,
            dx,
            r,
            m,
            v_min,
            v_max,
            max_error: f64::NAN,
            end,
            low,
            high,
        }
    }

    fn interpolate(&self, x: f64) -> f64 {
        let n = self.r.len();
        let f = ((x - self.x0) / self.dx).clamp(0.0, (n - 1) as f64);
        let i = (f.floor() as usize).min(n - 2);
        let t = f - i as f64;
        let (a, b) = (1.0 - t, t);
        let h2 = self.dx * self.dx / 6.0;
        a * self.r[i]
            + b * self.r[i + 1]
            + ((a * a * a - a) * self.m[i] + (b * b * b - b) * self.m[i + 1]) * h2
    }

    /// r at impact speed `v` (m/s); power-law tails outside the table.
    pub fn at(&self, v: f64) -> f64 {
        let v = v.abs();
        if v <= 0.0 {
            return 1.0 - if self.low.1 > 0.0 { 0.0 } else { self.low.0 };
        }
        if v < self.v_min {
            return 1.0 - self.low.0 * v.powf(self.low.1);
        }
        if v > self.v_max {
            return self.high.0 * v.powf(self.high.1);
        }
        self.interpolate(v.ln())
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// Whether the table is empty (never, once built).
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }
}

impl BoundRestitution for TabulatedRestitution {
    /// r(v), with values above 1 by no more than the table's accuracy (1e-6 or its measured error) (an elastic law's
    /// integrated 1 + 1e-12, a spline's overshoot at a plastic law's yield kink) read as 1.
    #[inline]
    fn restitution(&self, speed: f64) -> f64 {
        let r = self.at(speed);
        if r > 1.0 && r <= 1.0 + self.max_error.max(1e-6) {
            1.0
        } else {
            r
        }
    }
}

/// Contact law `name` with `params` as restitution laws for two particles `p` (diameter,
/// density, Young's modulus, Poisson's ratio) and for `p` against a wall: r(v) is the restitution
/// the collision driver realizes at impact speed v, under the end-of-contact criterion the law
/// declares, tabulated on a log grid over [1e-4, 20] m/s to within 1e-6 (power-law tails
/// outside). Returns (particle–particle, particle–wall). The bed's `--restitution from:LAW`
/// uses it with the disks' material (steel unless `--young`/`--poisson` say otherwise), so that
/// the event-driven and DEM engines can be compared on one material.
pub fn contact_restitution(
    reg: &crate::Registry,
    name: &str,
    params: &[ParamValue],
    p: &Particle,
) -> Result<(TabulatedRestitution, TabulatedRestitution), LawError> {
    use crate::collide::Options;
    let law = reg.contact(name, params)?;
    let end = reg.end_criterion(name)?;
    let (pp, pw) = (Pair::spheres(p, p)?, Pair::wall(p)?);
    let opt = Options {
        rtol: 1e-10,
        ..Options::default()
    };
    let (mp, mw) = (
        dashpot_sdk::MaterialPair::spheres(p, p)?,
        dashpot_sdk::MaterialPair::wall(p)?,
    );
    let table = |pair: &Pair, materials| -> Result<TabulatedRestitution, LawError> {
        let b = crate::collide::PairLaw::new(law.bind(materials)?, pair.mass, pair.radius);
        TabulatedRestitution::build(&b, pair.mass, end, 1e-4, 20.0, 1e-6, &opt).map_err(|e| match e {
            CollideError::Law(l) => l,
            other => LawError::new(
                dashpot_sdk::ErrorKind::Other,
                format!("contact law '{name}' as a restitution law: {other}"),
            ),
        })
    };
    Ok((table(&pp, &mp)?, table(&pw, &mw)?))
}
