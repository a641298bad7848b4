//! Species and the laws of each pair of them, as a scene writes them: `[[species]]` tables,
//! `[[pair]]` tables (per pair of species, or per species and wall), walls' own materials, and
//! the top-level law tables as the default of every pair not named. What it gives: each
//! particle's species, and the classes of contacts with their laws (names and parameters) and
//! materials, which [`PairPlan::bind`] turns into the engine's
//! [`SpeciesLaws`](crate::dem::species::SpeciesLaws) through the registry.

use super::{bad, LawTable, SceneError};
use crate::dem::species::{SpeciesInfo, MAX_SPECIES};
use crate::dem::state::{DiskMass, Material};
use dashpot_sdk::{MaterialPair, Particle};
use serde::Deserialize;

/// `[[species]]`: a species and its material.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpeciesTable {
    name: String,
    young: f64,
    poisson: f64,
    density: f64,
    #[serde(default)]
    disk_mass: Option<DiskMass>,
    /// Specific heat capacity c (J/(kg·K)), for a run with a heat law.
    #[serde(default)]
    pub(super) heat_capacity: Option<f64>,
}

/// One name or a list of names.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged, expecting = "a species' name or an array of one or two names")]
pub(super) enum Names {
    One(String),
    Many(Vec<String>),
}

impl Names {
    pub(super) fn list(&self) -> Vec<&str> {
        match self {
            Names::One(s) => vec![s.as_str()],
            Names::Many(v) => v.iter().map(String::as_str).collect(),
        }
    }
}

/// A wall named by its index in `[[wall]]` (from 0) or by its `name`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(
    untagged,
    expecting = "a wall's index (from 0, in the order of [[wall]]) or its name"
)]
pub(super) enum WallRef {
    Index(usize),
    Name(String),
}

/// One wall or a list of walls.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged, expecting = "a wall's index or name, or an array of them")]
pub(super) enum WallRefs {
    One(WallRef),
    Many(Vec<WallRef>),
}

/// `[[pair]]`: the laws of a pair of species (`species = ["a", "b"]`), or of a species against
/// walls (`species = "a"`, `wall = K`); each family not given is the top-level default's.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PairTable {
    species: Names,
    #[serde(default)]
    wall: Option<WallRefs>,
    #[serde(default)]
    law: Option<LawTable>,
    #[serde(default)]
    tangential: Option<LawTable>,
    #[serde(default)]
    rolling: Option<LawTable>,
    #[serde(default)]
    twisting: Option<LawTable>,
    #[serde(default)]
    heat: Option<LawTable>,
}

/// A wall's material: a species' (by name) or its own moduli.
#[derive(Debug, Clone, Deserialize)]
#[serde(
    untagged,
    expecting = "a species' name, or a table { young = Pa, poisson = ratio }"
)]
pub(super) enum WallMaterial {
    Species(String),
    Moduli { young: f64, poisson: f64 },
}

/// The laws of one class of contacts, by name and parameters: a normal law and the optional
/// others. A family's law named `"none"` in a `[[pair]]` table means no law of that family
/// for the pair, whatever the default.
#[derive(Debug, Clone, PartialEq)]
pub struct LawChoice {
    /// The normal law.
    pub normal: LawTable,
    /// The tangential law, if any.
    pub tangential: Option<LawTable>,
    /// The rolling resistance, if any.
    pub rolling: Option<LawTable>,
    /// The twisting resistance, if any.
    pub twisting: Option<LawTable>,
    /// The heat conduction, if any.
    pub heat: Option<LawTable>,
}

impl LawChoice {
    /// Every law table, the normal law first.
    pub fn tables(&self) -> impl Iterator<Item = &LawTable> {
        std::iter::once(&self.normal)
            .chain(self.tangential.as_ref())
            .chain(self.rolling.as_ref())
            .chain(self.twisting.as_ref())
            .chain(self.heat.as_ref())
    }

    /// `"hsd (eps = 0.5) + mindlin (mu = 0.3)"`.
    pub fn described(&self) -> String {
        self.tables()
            .map(|t| {
                if t.params.is_empty() {
                    t.name.clone()
                } else {
                    let p: Vec<String> = t.params.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                    format!("{} ({})", t.name, p.join(", "))
                }
            })
            .collect::<Vec<_>>()
            .join(" + ")
    }

    /// `"hsd + mindlin"`.
    pub fn names(&self) -> String {
        self.tables()
            .map(|t| t.name.as_str())
            .collect::<Vec<_>>()
            .join(" + ")
    }
}

/// What a class's laws are bound to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Partners {
    /// Two species (indices; the same twice for a species with itself).
    Species(usize, usize),
    /// A species against a rigid wall.
    RigidWall(usize),
    /// A species against a wall of Young's modulus (Pa) and Poisson's ratio.
    Wall(usize, f64, f64),
}

/// One class of contacts: its laws, what they are bound to, and what it is, for messages.
#[derive(Debug, Clone)]
pub struct ClassPlan {
    /// The laws.
    pub laws: LawChoice,
    /// The materials they are bound to (the class's first pair).
    pub partners: Partners,
    /// Every pair of the class, for messages: `"powder–beads"`, `"beads–wall 0"`.
    pub label: String,
}

/// Every contact's laws, by class, as a scene gives them (see [`SpeciesLaws`]).
#[derive(Debug, Clone)]
pub struct PairPlan {
    /// The species.
    pub species: Vec<SpeciesInfo>,
    /// Whether the scene names its species (`[[species]]`): outputs then name each
    /// particle's.
    pub named: bool,
    /// The class of each pair of species, `pair_class[a * species + b]`.
    pub pair_class: Vec<u8>,
    /// The pair classes.
    pub pair: Vec<ClassPlan>,
    /// The class of each species against each wall, `wall_class[s * walls + w]` (empty: one
    /// class, the default laws against a rigid wall, for every species and wall: a scene
    /// without walls).
    pub wall_class: Vec<u8>,
    /// The wall classes.
    pub wall: Vec<ClassPlan>,
}

/// The species of a scene: its `[[species]]`, or the one species of its `[material]`.
pub(super) fn species_of(
    tables: &[SpeciesTable],
    material: Option<Material>,
) -> Result<(Vec<SpeciesInfo>, bool), SceneError> {
    if tables.is_empty() {
        let material = material.ok_or_else(|| {
            bad(
                "no material: give a [material] table (young, poisson, density), or [[species]] tables"
                    .into(),
            )
        })?;
        return Ok((
            vec![SpeciesInfo {
                name: String::new(),
                material,
            }],
            false,
        ));
    }
    if material.is_some() {
        return Err(bad(
            "[material] and [[species]] both given: with species, each [[species]] table gives its own material (young, poisson, density); remove [material]".into(),
        ));
    }
    if tables.len() > MAX_SPECIES {
        return Err(bad(format!(
            "{} [[species]] tables: a scene holds at most {MAX_SPECIES}",
            tables.len()
        )));
    }
    let mut out: Vec<SpeciesInfo> = Vec::with_capacity(tables.len());
    for (k, t) in tables.iter().enumerate() {
        if t.name.trim().is_empty() || t.name == "none" {
            return Err(bad(format!(
                "species[{k}].name = {:?}: give each species a name (not empty, not \"none\")",
                t.name
            )));
        }
        if out.iter().any(|s| s.name == t.name) {
            return Err(bad(format!(
                "species[{k}].name = {:?} is given twice: each species needs its own name",
                t.name
            )));
        }
        let material = Material {
            young: t.young,
            poisson: t.poisson,
            density: t.density,
            disk_mass: t.disk_mass.unwrap_or(DiskMass::Sphere),
        };
        material
            .particle(1.0)
            .validate()
            .map_err(|e| bad(format!("species[{k}] ('{}'): {}", t.name, e.message)))?;
        out.push(SpeciesInfo {
            name: t.name.clone(),
            material,
        });
    }
    Ok((out, true))
}

/// The index of the species `name` of `species`, for the key `key`; an unknown name refused
/// with the closest one.
pub(super) fn species_index(
    species: &[SpeciesInfo],
    named: bool,
    key: &str,
    name: &str,
) -> Result<u8, SceneError> {
    if !named {
        return Err(bad(format!(
            "{key} = {name:?}: the scene has no [[species]] tables; add one named {name:?} (with young, poisson, density) in place of [material], or remove {key}"
        )));
    }
    if let Some(k) = species.iter().position(|s| s.name == name) {
        return Ok(k as u8);
    }
    let names: Vec<&str> = species.iter().map(|s| s.name.as_str()).collect();
    let hint = crate::registry::did_you_mean(name, names.iter().copied());
    Err(bad(format!(
        "{key} = {name:?} is not a species{hint}: the species are {}",
        names
            .iter()
            .map(|n| format!("{n:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    )))
}

/// What the pair plan needs to know of the scene: the default law tables, the walls' names
/// and materials, and how many particles of each species there are.
pub(super) struct Given<'a> {
    pub(super) law: Option<&'a LawTable>,
    pub(super) tangential: Option<&'a LawTable>,
    pub(super) rolling: Option<&'a LawTable>,
    pub(super) twisting: Option<&'a LawTable>,
    pub(super) heat: Option<&'a LawTable>,
    pub(super) wall_names: Vec<Option<String>>,
    pub(super) wall_materials: Vec<Option<WallMaterial>>,
    pub(super) count: Vec<usize>,
}

/// Family `fam` of a pair's laws: the pair's own table if given (`"none"`: no law), else the
/// default.
fn family(own: Option<&LawTable>, default: Option<&LawTable>) -> Option<LawTable> {
    match own {
        Some(t) if t.name == "none" => None,
        Some(t) => Some(t.clone()),
        None => default.cloned(),
    }
}

/// The classes of a scene's contacts (see the module doc).
pub(super) fn plan(
    species: Vec<SpeciesInfo>,
    named: bool,
    pairs: &[PairTable],
    g: &Given<'_>,
) -> Result<PairPlan, SceneError> {
    let n = species.len();
    let nw = g.wall_names.len();
    let label = |s: usize| {
        if named {
            species[s].name.clone()
        } else {
            "particle".to_string()
        }
    };
    // which [[pair]] table names each pair of species, and each species–wall pair
    let mut of_pair: Vec<Option<usize>> = vec![None; n * n];
    let mut of_wall: Vec<Option<usize>> = vec![None; n * nw];
    for (k, p) in pairs.iter().enumerate() {
        let names = p.species.list();
        let idx = names
            .iter()
            .map(|s| species_index(&species, named, &format!("pair[{k}].species"), s))
            .collect::<Result<Vec<u8>, _>>()?;
        if let Some(law) = &p.law {
            if law.name == "none" {
                return Err(bad(format!(
                    "pair[{k}].law.name = \"none\": a pair needs a normal law (\"none\" removes only a tangential, rolling, twisting or heat law)"
                )));
            }
        }
        match &p.wall {
            None => {
                let (a, b) = match idx[..] {
                    [a] => (a, a),
                    [a, b] => (a, b),
                    _ => {
                        return Err(bad(format!(
                            "pair[{k}].species = {names:?}: give one species (with itself) or two, or one with `wall = K`"
                        )))
                    }
                };
                let (a, b) = (a as usize, b as usize);
                for slot in [a * n + b, b * n + a] {
                    if let Some(other) = of_pair[slot].replace(k) {
                        if other != k {
                            return Err(bad(format!(
                                "pair[{k}] and pair[{other}] both give the laws of ({}, {}): give each pair once",
                                species[a].name, species[b].name
                            )));
                        }
                    }
                }
            }
            Some(walls) => {
                let [s] = idx[..] else {
                    return Err(bad(format!(
                        "pair[{k}].species = {names:?} with wall: give one species (its laws against the walls named)"
                    )));
                };
                let refs = match walls {
                    WallRefs::One(r) => vec![r.clone()],
                    WallRefs::Many(v) => v.clone(),
                };
                for r in refs {
                    let w = wall_index(&g.wall_names, &format!("pair[{k}].wall"), &r)?;
                    if let Some(other) = of_wall[s as usize * nw + w].replace(k) {
                        return Err(bad(format!(
                            "pair[{k}] and pair[{other}] both give the laws of ({}, wall {w}): give each pair once",
                            species[s as usize].name
                        )));
                    }
                }
            }
        }
    }
    let choice = |own: Option<&PairTable>, what: &str| -> Result<LawChoice, SceneError> {
        let normal = own.and_then(|p| p.law.as_ref()).or(g.law).cloned().ok_or_else(|| {
            bad(format!(
                "no law for the pair {what}: give a [[pair]] table naming it, with its [pair.law], or a top-level [law] for every pair not named"
            ))
        })?;
        Ok(LawChoice {
            normal,
            tangential: family(own.and_then(|p| p.tangential.as_ref()), g.tangential),
            rolling: family(own.and_then(|p| p.rolling.as_ref()), g.rolling),
            twisting: family(own.and_then(|p| p.twisting.as_ref()), g.twisting),
            heat: family(own.and_then(|p| p.heat.as_ref()), g.heat),
        })
    };
    let mat_key = |p: Partners| -> Result<MaterialPair, SceneError> { partners_materials(&species, p) };
    // the pair classes: one per distinct (laws, materials) among the pairs that can touch
    let mut pair: Vec<(ClassPlan, MaterialPair)> = Vec::new();
    let mut pair_class = vec![0u8; n * n];
    for a in 0..n {
        for b in a..n {
            let touches = if a == b {
                g.count[a] >= 2 || n == 1
            } else {
                g.count[a] > 0 && g.count[b] > 0
            };
            if !touches {
                continue;
            }
            let what = if named {
                format!("({}, {})", species[a].name, species[b].name)
            } else {
                "of particles".into()
            };
            let laws = choice(of_pair[a * n + b].map(|k| &pairs[k]), &what)?;
            let partners = Partners::Species(a, b);
            let mp = mat_key(partners)?;
            let text = format!("{}–{}", label(a), label(b));
            let c = class_of(&mut pair, laws, partners, mp, text)?;
            pair_class[a * n + b] = c;
            pair_class[b * n + a] = c;
        }
    }
    if pair.is_empty() {
        // (no pair can touch: a class all the same, the first species with itself, if a law
        // for it is at hand; the engine needs one)
        let laws = choice(of_pair[0].map(|k| &pairs[k]), "of particles")?;
        let p = Partners::Species(0, 0);
        pair.push((
            ClassPlan {
                laws,
                partners: p,
                label: format!("{}–{}", label(0), label(0)),
            },
            mat_key(p)?,
        ));
    }
    // the wall classes: one per distinct (laws, materials) among the species–wall pairs
    let mut wall: Vec<(ClassPlan, MaterialPair)> = Vec::new();
    let mut wall_class = Vec::new();
    if nw == 0 {
        // no walls: the default laws against a rigid wall, as the step's choice has always
        // counted them, if there are default laws
        if g.law.is_some() {
            let laws = choice(None, "")?;
            let p = Partners::RigidWall(0);
            wall.push((
                ClassPlan {
                    laws,
                    partners: p,
                    label: format!("{}–wall", label(0)),
                },
                mat_key(p)?,
            ));
        }
    } else {
        wall_class = vec![0u8; n * nw];
        for s in 0..n {
            if g.count[s] == 0 {
                continue;
            }
            for w in 0..nw {
                let wname = g.wall_names[w]
                    .as_ref()
                    .map(|x| format!("wall {w} ('{x}')"))
                    .unwrap_or(format!("wall {w}"));
                let what = if named {
                    format!("({}, {wname})", species[s].name)
                } else {
                    format!("of particles and {wname}")
                };
                let laws = choice(of_wall[s * nw + w].map(|k| &pairs[k]), &what)?;
                let partners = match &g.wall_materials[w] {
                    None => Partners::RigidWall(s),
                    Some(WallMaterial::Species(name)) => {
                        let m = species
                            [species_index(&species, named, &format!("wall[{w}].material"), name)? as usize]
                            .material;
                        Partners::Wall(s, m.young, m.poisson)
                    }
                    Some(WallMaterial::Moduli { young, poisson }) => Partners::Wall(s, *young, *poisson),
                };
                let mp = mat_key(partners)?;
                let text = format!("{}–{wname}", label(s));
                wall_class[s * nw + w] = class_of(&mut wall, laws, partners, mp, text)?;
            }
        }
    }
    Ok(PairPlan {
        species,
        named,
        pair_class,
        pair: pair.into_iter().map(|(c, _)| c).collect(),
        wall_class,
        wall: wall.into_iter().map(|(c, _)| c).collect(),
    })
}

/// The class of `laws` bound to `mp` in `classes`: an existing one with the same laws and
/// material pair (its label extended by `text`), or a new one.
fn class_of(
    classes: &mut Vec<(ClassPlan, MaterialPair)>,
    laws: LawChoice,
    partners: Partners,
    mp: MaterialPair,
    text: String,
) -> Result<u8, SceneError> {
    if let Some(k) = classes.iter().position(|(c, m)| c.laws == laws && *m == mp) {
        let label = &mut classes[k].0.label;
        label.push_str(", ");
        label.push_str(&text);
        return Ok(k as u8);
    }
    if classes.len() > u8::MAX as usize {
        return Err(bad(format!(
            "more than {} distinct combinations of laws and materials: too many for one scene",
            u8::MAX as usize + 1
        )));
    }
    classes.push((
        ClassPlan {
            laws,
            partners,
            label: text,
        },
        mp,
    ));
    Ok((classes.len() - 1) as u8)
}

/// A species' material as the sdk's particle (the diameter is not used by the bindings).
fn particle(m: &Material) -> Particle {
    m.particle(1.0)
}

/// The material pair a class's laws are bound to.
pub(super) fn partners_materials(species: &[SpeciesInfo], p: Partners) -> Result<MaterialPair, SceneError> {
    let r = match p {
        Partners::Species(a, b) => {
            MaterialPair::spheres(&particle(&species[a].material), &particle(&species[b].material))
        }
        Partners::RigidWall(s) => MaterialPair::wall(&particle(&species[s].material)),
        Partners::Wall(s, young, poisson) => MaterialPair::spheres(
            &particle(&species[s].material),
            &Particle {
                diameter: 1.0,
                density: 1.0,
                young,
                poisson,
            },
        ),
    };
    r.map_err(|e| bad(format!("materials: {}", e.message)))
}

/// The index of the wall `r` among walls named `names`, for the key `key`.
pub(super) fn wall_index(names: &[Option<String>], key: &str, r: &WallRef) -> Result<usize, SceneError> {
    match r {
        WallRef::Index(w) if *w < names.len() => Ok(*w),
        WallRef::Index(w) => Err(bad(format!(
            "{key} = {w} is out of range: the scene has {} wall(s), numbered from 0",
            names.len()
        ))),
        WallRef::Name(s) => names.iter().position(|n| n.as_deref() == Some(s)).ok_or_else(|| {
            let known: Vec<&str> = names.iter().flatten().map(String::as_str).collect();
            let hint = crate::registry::did_you_mean(s, known.iter().copied());
            bad(format!(
                "{key} = {s:?} names no wall{hint}: give a wall's index (from 0) or the `name` of a [[wall]]"
            ))
        }),
    }
}

impl PairPlan {
    /// Renames the rolling and twisting laws given by LAMMPS's short names (`sds`, `epsd`,
    /// `marshall`) to the laws they mean (`rolling-sds`, ...), as `pair_style dashpot` does.
    pub fn resolve_names(&mut self, reg: &crate::Registry) {
        use dashpot_sdk::LawKind::{Rolling, Twisting};
        for c in self.pair.iter_mut().chain(self.wall.iter_mut()) {
            for (t, kind) in [(&mut c.laws.rolling, Rolling), (&mut c.laws.twisting, Twisting)] {
                if let Some(t) = t {
                    t.name = crate::checks::family_name(reg, &t.name, kind);
                }
            }
        }
    }

    /// The normal laws' names, each once: `"hsd"`, `"hsd, jkr"`.
    pub fn law_names(&self) -> String {
        let mut names: Vec<&str> = Vec::new();
        for c in self.pair.iter().chain(&self.wall) {
            if !names.contains(&c.laws.normal.name.as_str()) {
                names.push(&c.laws.normal.name);
            }
        }
        names.join(", ")
    }

    /// Every distinct law table of every class (for the provenance of a run's laws).
    pub fn tables(&self) -> Vec<&LawTable> {
        let mut out: Vec<&LawTable> = Vec::new();
        for c in self.pair.iter().chain(&self.wall) {
            for t in c.laws.tables() {
                if !out.contains(&t) {
                    out.push(t);
                }
            }
        }
        out
    }

    /// The classes as JSON: for each, what it is (`pairs`: its pairs) and its laws' names.
    pub fn json(&self) -> serde_json::Value {
        let class = |c: &ClassPlan| {
            serde_json::json!({
                "pairs": c.label,
                "law": c.laws.normal.name,
                "tangential": c.laws.tangential.as_ref().map(|t| &t.name),
                "rolling": c.laws.rolling.as_ref().map(|t| &t.name),
                "twisting": c.laws.twisting.as_ref().map(|t| &t.name),
                "heat": c.laws.heat.as_ref().map(|t| &t.name),
            })
        };
        serde_json::json!({
            "species": self.species.iter().map(|s| serde_json::json!({
                "name": s.name, "young": s.material.young, "poisson": s.material.poisson,
                "density": s.material.density,
            })).collect::<Vec<_>>(),
            "particle_pairs": self.pair.iter().map(class).collect::<Vec<_>>(),
            "wall_pairs": self.wall.iter().map(class).collect::<Vec<_>>(),
        })
    }
}
