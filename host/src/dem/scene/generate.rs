//! The random polydisperse packings of `[generate]` (or `[[generate]]`) tables, each of its
//! species.

use super::pairs::{species_index, wall_index, Names, WallRefs};
use super::{bad, non_negative, positive, vector, SceneError};
use crate::dem::species::SpeciesInfo;
use crate::dem::state::{Body, Vec3, VecD};
use crate::dem::walls::{Shape, Wall};
use serde::Deserialize;

#[derive(Debug, Clone, Deserialize)]
#[serde(
    untagged,
    expecting = "a number (m) or an array [min, max] of two numbers (m)"
)]
enum Diameters {
    One(f64),
    Range(Vec<f64>),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GenerateTable {
    count: usize,
    diameter: Diameters,
    lo: Vec<f64>,
    hi: Vec<f64>,
    #[serde(default)]
    speed: f64,
    #[serde(default = "one")]
    seed: u64,
    /// The species of the particles: one name, or several drawn at random in the proportions
    /// `fraction` (default: equal).
    #[serde(default)]
    species: Option<Names>,
    #[serde(default)]
    fraction: Option<Vec<f64>>,
    /// Only the lattice's sites inside these walls (a plane's open side, a cylinder or a box
    /// holding particles): a drum's fill.
    #[serde(default)]
    within: Option<WallRefs>,
    /// The particles' temperature (K), in a run with a heat law.
    #[serde(default)]
    pub(super) temperature: Option<f64>,
}

/// `[generate]` (one table) or `[[generate]]` (several): read as what the file holds, each
/// table's errors with their own key path.
#[derive(Debug, Clone, Default)]
pub(super) struct Generates(pub(super) Vec<GenerateTable>);

impl<'de> Deserialize<'de> for Generates {
    fn deserialize<Dz: serde::Deserializer<'de>>(d: Dz) -> Result<Self, Dz::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Generates;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a [generate] table or [[generate]] tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, m: A) -> Result<Generates, A::Error> {
                let one = GenerateTable::deserialize(serde::de::value::MapAccessDeserializer::new(m))?;
                Ok(Generates(vec![one]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, s: A) -> Result<Generates, A::Error> {
                Vec::<GenerateTable>::deserialize(serde::de::value::SeqAccessDeserializer::new(s))
                    .map(Generates)
            }
        }
        d.deserialize_any(V)
    }
}

fn one() -> u64 {
    1
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The sites of [`packing`]'s lattice (spacing 1.05 `dmax`, m) in the region `[lo, hi]` (m)
/// along each axis, and their number.
fn sites<const D: usize>(dmax: f64, lo: &VecD<D>, hi: &VecD<D>) -> Result<([usize; D], usize), SceneError> {
    let a = 1.05 * dmax;
    let mut sites = [0usize; D];
    let mut total = 1usize;
    for k in 0..D {
        if hi[k] <= lo[k] || !(hi[k] - lo[k]).is_finite() {
            return Err(bad(format!(
                "hi[{k}] = {} m must exceed lo[{k}] = {} m (the region filled is lo..hi)",
                hi[k], lo[k]
            )));
        }
        sites[k] = ((hi[k] - lo[k]) / a).floor().max(0.0) as usize;
        total = total.saturating_mul(sites[k]);
    }
    Ok((sites, total))
}

/// Why `count` particles of largest diameter `dmax` (m) do not fit in `[lo, hi]` (m), whose
/// lattice has `sites` along each axis, `total` in all.
fn crowded<const D: usize>(
    count: usize,
    dmax: f64,
    lo: &VecD<D>,
    hi: &VecD<D>,
    sites: &[usize; D],
    total: usize,
) -> String {
    format!(
        "count = {count} particles cannot fit: the region lo = {:?} .. hi = {:?} m holds at most {total} ({} sites of {:.4e} m, 1.05 times the largest diameter {dmax} m)",
        lo.as_slice(),
        hi.as_slice(),
        sites.map(|s| s.to_string()).join(" x "),
        1.05 * dmax
    )
}

/// `count` particles of diameters uniform in `[dmin, dmax]` (m) in the region `[lo, hi]`: one per
/// site of a square (cubic) lattice of spacing 1.05 dmax, filled row by row from `lo`, each
/// jittered at random within its site (no two overlap), with random velocities of magnitude
/// `speed` (m/s). Errors if the region holds fewer than `count` sites.
pub fn packing<const D: usize>(
    count: usize,
    dmin: f64,
    dmax: f64,
    lo: VecD<D>,
    hi: VecD<D>,
    speed: f64,
    seed: u64,
) -> Result<Vec<Body<D>>, SceneError> {
    packing_within(count, dmin, dmax, lo, hi, speed, seed, &|_| true)
}

/// [`packing`] on the sites whose cell (lower corner, of side 1.05 `dmax`) `keep` takes, in
/// the same order: a fill of a drum or any region inside walls. Errors if fewer than `count`
/// sites are kept.
#[allow(clippy::too_many_arguments)]
pub fn packing_within<const D: usize>(
    count: usize,
    dmin: f64,
    dmax: f64,
    lo: VecD<D>,
    hi: VecD<D>,
    speed: f64,
    seed: u64,
    keep: &dyn Fn(&VecD<D>) -> bool,
) -> Result<Vec<Body<D>>, SceneError> {
    let (sites, total) = sites::<D>(dmax, &lo, &hi)?;
    let a = 1.05 * dmax;
    let corner = |s: usize| {
        let (mut c, mut r) = (VecD::<D>::zeros(), s);
        for k in 0..D {
            c[k] = lo[k] + (r % sites[k]) as f64 * a;
            r /= sites[k];
        }
        c
    };
    // (the first `count` kept, in order: not every site of a region that may hold 10^13)
    let kept: Vec<usize> = (0..total).filter(|&s| keep(&corner(s))).take(count).collect();
    if kept.len() < count {
        return Err(bad(crowded(count, dmax, &lo, &hi, &sites, kept.len())));
    }
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x1234_5678);
    let mut out = Vec::with_capacity(count);
    for &s in &kept[..count] {
        let d = dmin + (dmax - dmin) * rng.next();
        let mut x = VecD::<D>::zeros();
        let mut r = s;
        for k in 0..D {
            let q = r % sites[k];
            r /= sites[k];
            let room = a - d;
            x[k] = lo[k] + q as f64 * a + 0.5 * d + room * rng.next();
        }
        let mut v = VecD::<D>::from_iterator((0..D).map(|_| rng.next() - 0.5));
        if v.norm() > 0.0 {
            v *= speed / v.norm();
        }
        out.push(Body {
            position: x,
            velocity: v,
            angular_velocity: Vec3::zeros(),
            diameter: d,
        });
    }
    Ok(out)
}

/// The particles of the generate table `g` (the `k`-th of `of`), with their species (indices
/// into `species`; `named`: the scene names its species).
pub(super) fn generate<const D: usize>(
    g: &GenerateTable,
    k: usize,
    of: usize,
    species: &[SpeciesInfo],
    named: bool,
    walls: (&[Wall<D>], &[Option<String>]),
) -> Result<(Vec<Body<D>>, Vec<u8>), SceneError> {
    let key = if of > 1 {
        format!("generate[{k}]")
    } else {
        "generate".to_string()
    };
    let at = |s: String| bad(s.replacen("generate", &key, 1));
    let within = within_walls(g, walls, &key)?;
    generate_one::<D>(g, &within)
        .map_err(|e| at(e.0))
        .and_then(|bodies| {
            let kinds = generated_species(g, bodies.len(), species, named, &key)?;
            Ok((bodies, kinds))
        })
}

/// Each generated particle's species: the table's one species, or several drawn at random
/// (from a generator of their own, so that the packing is the same whatever the species).
fn generated_species(
    g: &GenerateTable,
    count: usize,
    species: &[SpeciesInfo],
    named: bool,
    key: &str,
) -> Result<Vec<u8>, SceneError> {
    let names: Vec<&str> = match &g.species {
        None => {
            if species.len() > 1 {
                return Err(bad(format!(
                    "{key}.species is missing: with several [[species]] give each generated particle's (a name, or a list of names with `fraction`)"
                )));
            }
            return Ok(vec![0; count]);
        }
        Some(n) => n.list(),
    };
    let idx = names
        .iter()
        .map(|s| species_index(species, named, &format!("{key}.species"), s))
        .collect::<Result<Vec<u8>, _>>()?;
    if idx.is_empty() {
        return Err(bad(format!("{key}.species = []: give at least one species")));
    }
    let fraction = match &g.fraction {
        None => vec![1.0; idx.len()],
        Some(f) => {
            if f.len() != idx.len()
                || f.iter().any(|x| !(x.is_finite() && *x >= 0.0))
                || f.iter().sum::<f64>() <= 0.0
            {
                return Err(bad(format!(
                    "{key}.fraction = {f:?}: give one number >= 0 per species of {key}.species ({}), not all 0",
                    idx.len()
                )));
            }
            f.clone()
        }
    };
    if idx.len() == 1 {
        return Ok(vec![idx[0]; count]);
    }
    let total: f64 = fraction.iter().sum();
    let mut rng = Rng(g.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x005E_ED00_05BE_C1E5);
    Ok((0..count)
        .map(|_| {
            let mut u = rng.next() * total;
            for (k, &f) in fraction.iter().enumerate() {
                if u < f {
                    return idx[k];
                }
                u -= f;
            }
            *idx.last().expect("one species at least")
        })
        .collect())
}

/// The walls of `within` (`walls`: the scene's walls and their names), each of a shape that
/// holds particles on one side (a plane, a cylinder or a box holding them).
fn within_walls<'w, const D: usize>(
    g: &GenerateTable,
    walls: (&'w [Wall<D>], &[Option<String>]),
    key: &str,
) -> Result<Vec<&'w Wall<D>>, SceneError> {
    let refs = match &g.within {
        None => return Ok(Vec::new()),
        Some(WallRefs::One(r)) => vec![r.clone()],
        Some(WallRefs::Many(v)) => v.clone(),
    };
    refs.iter()
        .map(|r| {
            let w = &walls.0[wall_index(walls.1, &format!("{key}.within"), r)?];
            match w.shape {
                Shape::Cylinder { inside: false, .. } | Shape::Box { inside: false, .. } => Err(bad(format!(
                    "{key}.within names a wall the particles stay outside of ({}): give walls that hold them (a plane, a cylinder or a box with inside = true)",
                    w.describe()
                ))),
                _ => Ok(w),
            }
        })
        .collect()
}

/// The particles of one generate table, on the sites inside the walls `within`.
fn generate_one<const D: usize>(g: &GenerateTable, within: &[&Wall<D>]) -> Result<Vec<Body<D>>, SceneError> {
    let (dmin, dmax) = match &g.diameter {
        Diameters::One(d) => (*d, *d),
        Diameters::Range(v) if v.len() == 2 => (v[0], v[1]),
        Diameters::Range(v) => {
            return Err(bad(format!(
                "generate.diameter = {v:?}: give one number or [min, max]"
            )))
        }
    };
    positive("generate.diameter (min)", "m", dmin)?;
    positive("generate.diameter (max)", "m", dmax)?;
    if dmax < dmin {
        return Err(bad(format!(
            "generate.diameter = [{dmin}, {dmax}]: max must be >= min"
        )));
    }
    if g.count == 0 {
        return Err(bad("generate.count = 0 is out of range: it must be >= 1".into()));
    }
    non_negative("generate.speed", "m/s", g.speed)?;
    let lo = vector::<D>("generate.lo", &g.lo)?;
    let hi = vector::<D>("generate.hi", &g.hi)?;
    let (sites, total) = sites::<D>(dmax, &lo, &hi).map_err(|e| bad(format!("generate: {}", e.0)))?;
    if total < g.count {
        return Err(bad(format!(
            "generate: {}; lower generate.count to {total} or less, enlarge generate.lo/hi, or give a smaller generate.diameter",
            crowded(g.count, dmax, &lo, &hi, &sites, total)
        )));
    }
    // (before they are made: a count past the machine is refused, not an allocation failure)
    crate::dem::footprint::check_count("generate.count", g.count, D).map_err(|e| bad(e.0))?;
    // a cell is inside the walls when its corners are (the walls' open sides are convex)
    let a = 1.05 * dmax;
    let surfaces: Vec<_> = within.iter().flat_map(|w| w.surfaces(0.0)).collect();
    let keep = |c: &VecD<D>| {
        (0..1usize << D).all(|m| {
            let mut x = *c;
            for k in 0..D {
                if (m >> k) & 1 == 1 {
                    x[k] += a;
                }
            }
            surfaces.iter().all(|s| s.overlap(&x, 0.0) <= 0.0)
        })
    };
    packing_within(g.count, dmin, dmax, lo, hi, g.speed, g.seed, &keep)
}
