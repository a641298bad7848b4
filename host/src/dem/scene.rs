//! The scene format of `dashpot dem --scene FILE.toml`, and a generator of random polydisperse
//! packings.
//!
//! ```toml
//! dimension = 2                      # 2: disks (ω about z), 3: spheres
//! gravity = [0.0, -9.81]             # m/s²
//! duration = 0.5                     # s
//! # dt = 1e-6                        # s; else τ/steps_per_collision at impact_speed (printed)
//! # steps_per_collision = 50
//! # impact_speed = 1.0               # m/s; else estimated
//! # skin = 4e-4                      # m; else 0.3 of the smallest diameter
//! # snapshots = 10                   # frames written to --out (trajectory.xyz)
//! # allow_initial_overlap = false    # true: particles may start overlapping (a pre-compressed
//! #                                  # packing), up to 0.5 of the smaller radius
//! [law]
//! name = "hsd"
//! params = { eps = 0.5 }
//! [tangential]                       # optional
//! name = "mindlin"
//! params = { mu = 0.3 }
//! [rolling]                          # optional (sdk 0.3): rolling resistance
//! name = "rolling-sds"
//! params = { k = 1000.0, mu = 0.1 }
//! [twisting]                         # optional (sdk 0.3): twisting resistance (3D)
//! name = "twisting-sds"
//! params = { k = 1e-3, mu = 1e-4 }
//! [heat]                             # optional (sdk 0.4): heat conduction through contacts;
//! name = "heat-radius"               # then heat_capacity and every particle's temperature
//! params = { k = 40.0 }              # are required, walls conduct if they have a temperature
//! [material]
//! young = 1.0e8                      # Pa
//! poisson = 0.3
//! density = 7800.0                   # kg/m³
//! disk_mass = "sphere"               # 2D: "sphere" (m = π ρ d³/6, I = 2/5 m R²) or "disk" (m = π ρ d³/4, I = m R²/2)
//! # heat_capacity = 500.0            # J/(kg·K), with [heat]
//! [box]                              # optional
//! lo = [0.0, 0.0]
//! hi = [0.2, 0.1]
//! periodic = [true, false]
//! bounded = false                    # true: a particle leaving [lo, hi] along an open axis is an error
//! [[wall]]
//! point = [0.0, 0.0]
//! normal = [0.0, 1.0]
//! # motion = { kind = "piston", amplitude = 0.025, frequency = 20.0 }   # or kind = "sine"
//! # temperature = 300.0              # K, with [heat]; or { mean = 300.0, amplitude = 20.0, frequency = 5.0 }
//! #                                  # (K, K, Hz: T0 + A sin(2π f t)); without, the wall does not conduct
//! [[particle]]
//! position = [0.1, 0.001]
//! velocity = [1.0, 0.0]
//! angular_velocity = 0.0             # 2D: a number (about z); 3D: [x, y, z]
//! diameter = 0.002
//! # temperature = 300.0              # K, with [heat]
//! [generate]                         # optional: random polydisperse particles added to [[particle]]
//! count = 2000
//! diameter = [0.0018, 0.0022]        # uniform in [min, max] (m), or one number
//! lo = [0.0, 0.0]                    # the region filled (m)
//! hi = [0.2, 0.1]
//! speed = 0.1                        # random velocities of this magnitude (m/s), default 0
//! seed = 1
//! # temperature = 300.0              # K, with [heat]
//! ```

mod bind;
mod check;
mod generate;
mod pairs;
mod walls;

pub use generate::packing;
pub use pairs::{ClassPlan, LawChoice, PairPlan, Partners};

use super::cells::Domain;
use super::heat::HeatSetup;
use super::integrator::{check_steps_per_collision, EngineConfig};
use super::state::{Body, DiskMass, Material, Vec3, VecD};
use super::walls::Wall;
use dashpot_sdk::ParamValue;
use serde::Deserialize;
use std::collections::BTreeMap;

/// Why a scene is refused; the message names the key and the value.
#[derive(Debug, thiserror::Error)]
#[error("scene: {0}")]
pub struct SceneError(pub String);

pub(crate) fn bad(msg: String) -> SceneError {
    SceneError(msg)
}

/// A law table: `name` and `params`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LawTable {
    /// The law's name.
    pub name: String,
    /// Its parameters.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

impl LawTable {
    /// The parameters as the registry takes them.
    pub fn param_values(&self) -> Vec<ParamValue> {
        self.params.iter().map(|(k, v)| ParamValue::new(k, *v)).collect()
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialTable {
    young: f64,
    poisson: f64,
    density: f64,
    #[serde(default)]
    disk_mass: Option<DiskMass>,
    /// Specific heat capacity c (J/(kg·K)), with a heat law.
    #[serde(default)]
    heat_capacity: Option<f64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxTable {
    lo: Vec<f64>,
    hi: Vec<f64>,
    #[serde(default)]
    periodic: Option<Vec<bool>>,
    #[serde(default)]
    bounded: bool,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(
    untagged,
    expecting = "a number (2D: rad/s about z) or an array [x, y, z] of numbers (3D, rad/s)"
)]
enum Spin {
    Scalar(f64),
    Vector(Vec<f64>),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParticleTable {
    position: Vec<f64>,
    #[serde(default)]
    velocity: Option<Vec<f64>>,
    #[serde(default)]
    angular_velocity: Option<Spin>,
    diameter: f64,
    /// The particle's species (a `[[species]]` name).
    #[serde(default)]
    species: Option<String>,
    /// The particle's temperature (K), with a heat law.
    #[serde(default)]
    temperature: Option<f64>,
}

/// The scene file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    dimension: usize,
    #[serde(default)]
    gravity: Option<Vec<f64>>,
    duration: f64,
    #[serde(default)]
    dt: Option<f64>,
    #[serde(default)]
    steps_per_collision: Option<f64>,
    #[serde(default)]
    impact_speed: Option<f64>,
    #[serde(default)]
    skin: Option<f64>,
    #[serde(default)]
    snapshots: Option<usize>,
    /// Particles may start overlapping each other or a wall (a deliberately pre-compressed
    /// packing), up to 0.5 of the smaller radius; else any overlap at the start is refused.
    #[serde(default)]
    allow_initial_overlap: bool,
    /// Energy accounting by family (the laws' energy outputs: `dem --json`'s `energy_initial`,
    /// `elastic` and `dissipated`, the trajectory's per-particle dissipated power). On by
    /// default; `energy = false` skips the laws' energy functions, which with friction and
    /// rolling cost about as much as the rest of a step.
    #[serde(default = "accounting_on")]
    energy: bool,
    /// The normal law: of every pair not named by a `[[pair]]` table (required unless every
    /// pair is).
    #[serde(default)]
    pub law: Option<LawTable>,
    /// The tangential law, if any.
    #[serde(default)]
    pub tangential: Option<LawTable>,
    /// The rolling-resistance law, if any.
    #[serde(default)]
    pub rolling: Option<LawTable>,
    /// The twisting-resistance law, if any.
    #[serde(default)]
    pub twisting: Option<LawTable>,
    /// The heat-conduction law, if any (sdk 0.4).
    #[serde(default)]
    pub heat: Option<LawTable>,
    #[serde(default)]
    material: Option<MaterialTable>,
    /// The species, each of its material (instead of `[material]`).
    #[serde(default)]
    species: Vec<pairs::SpeciesTable>,
    /// The laws of pairs of species, and of species against walls.
    #[serde(default)]
    pair: Vec<pairs::PairTable>,
    #[serde(default, rename = "box")]
    domain: Option<BoxTable>,
    #[serde(default)]
    wall: Vec<walls::WallTable>,
    #[serde(default)]
    particle: Vec<ParticleTable>,
    #[serde(default)]
    generate: Option<generate::Generates>,
}

/// A scene of dimension `D`, checked.
#[derive(Debug, Clone)]
pub struct Scene<const D: usize> {
    /// Engine settings.
    pub config: EngineConfig<D>,
    /// Simulated time (s).
    pub duration: f64,
    /// Frames of the trajectory (0: none).
    pub snapshots: usize,
    /// The particles.
    pub bodies: Vec<Body<D>>,
    /// Each particle's species (indices into `plan.species`).
    pub species: Vec<u8>,
    /// The walls.
    pub walls: Vec<Wall<D>>,
    /// The species and the laws of every class of contacts, by name (see [`PairPlan::bind`]).
    pub plan: PairPlan,
    /// The temperatures, in a scene with a heat law (see [`crate::dem::Engine::with_heat`]).
    pub heat: Option<HeatSetup>,
}

fn accounting_on() -> bool {
    true
}

impl SceneFile {
    /// Parses TOML text.
    pub fn parse(text: &str) -> Result<SceneFile, SceneError> {
        crate::config::from_toml(text).map_err(bad)
    }

    /// The particles listed one by one (`[[particle]]` tables).
    pub fn particle_tables(&self) -> usize {
        self.particle.len()
    }

    /// The dimension (2 or 3).
    pub fn dimension(&self) -> Result<usize, SceneError> {
        match self.dimension {
            2 | 3 => Ok(self.dimension),
            d => Err(bad(format!(
                "dimension = {d} is out of range: it must be 2 (disks) or 3 (spheres)"
            ))),
        }
    }

    /// The checked scene; `D` must equal [`SceneFile::dimension`].
    pub fn scene<const D: usize>(&self) -> Result<Scene<D>, SceneError> {
        if self.dimension()? != D {
            return Err(bad(format!(
                "dimension = {} but a {D}D scene was asked for",
                self.dimension
            )));
        }
        let material = match &self.material {
            Some(m) => {
                let material = Material {
                    young: m.young,
                    poisson: m.poisson,
                    density: m.density,
                    disk_mass: m.disk_mass.unwrap_or(DiskMass::Sphere),
                };
                material
                    .particle(1.0)
                    .validate()
                    .map_err(|e| bad(format!("[material]: {}", e.message)))?;
                Some(material)
            }
            None => None,
        };
        let (kinds, named) = pairs::species_of(&self.species, material)?;
        let mut config = EngineConfig::<D>::new(kinds[0].material);
        config.energy = self.energy;
        if let Some(g) = &self.gravity {
            config.gravity = vector::<D>("gravity", g)?;
        }
        positive("duration", "s", self.duration)?;
        if let Some(dt) = self.dt {
            positive("dt", "s", dt)?;
        }
        config.dt = self.dt;
        if let Some(s) = self.steps_per_collision {
            check_steps_per_collision("steps_per_collision", s).map_err(bad)?;
            config.steps_per_collision = s;
        }
        if let Some(v) = self.impact_speed {
            positive("impact_speed", "m/s", v)?;
        }
        config.impact_speed = self.impact_speed;
        if let Some(s) = self.skin {
            positive("skin", "m", s)?;
        }
        config.skin = self.skin;
        if let Some(b) = &self.domain {
            let lo = vector::<D>("box.lo", &b.lo)?;
            let hi = vector::<D>("box.hi", &b.hi)?;
            for k in 0..D {
                if hi[k] <= lo[k] {
                    return Err(bad(format!(
                        "box: hi[{k}] = {} must exceed lo[{k}] = {}",
                        hi[k], lo[k]
                    )));
                }
            }
            let mut periodic = [false; D];
            if let Some(p) = &b.periodic {
                if p.len() != D {
                    return Err(bad(format!(
                        "box.periodic = {p:?} has {} entries: dimension = {D} needs {D}",
                        p.len()
                    )));
                }
                periodic.copy_from_slice(p);
            }
            config.domain = Domain {
                lo,
                hi,
                periodic,
                bounded: b.bounded,
            };
        }
        let walls = self
            .wall
            .iter()
            .enumerate()
            .map(|(k, w)| w.wall::<D>(k))
            .collect::<Result<Vec<Wall<D>>, _>>()?;
        let wall_names: Vec<Option<String>> = self.wall.iter().map(|w| w.name.clone()).collect();
        for (k, n) in wall_names.iter().enumerate() {
            if let Some(n) = n {
                if wall_names[..k].iter().any(|m| m.as_ref() == Some(n)) {
                    return Err(bad(format!(
                        "wall[{k}].name = {n:?} is given twice: each wall needs its own name"
                    )));
                }
            }
        }
        let mut bodies = Vec::with_capacity(self.particle.len());
        let mut species = Vec::with_capacity(self.particle.len());
        // each particle's temperature and where the scene gives it
        let mut temps: Vec<(Option<f64>, String)> = Vec::with_capacity(self.particle.len());
        for (k, p) in self.particle.iter().enumerate() {
            temps.push((p.temperature, format!("particle[{k}].temperature")));
            species.push(match &p.species {
                Some(name) => pairs::species_index(&kinds, named, &format!("particle[{k}].species"), name)?,
                None if kinds.len() > 1 => {
                    return Err(bad(format!(
                        "particle[{k}].species is missing: with several [[species]] give each particle's"
                    )))
                }
                None => 0,
            });
            let position = vector::<D>(&format!("particle[{k}].position"), &p.position)?;
            let velocity = match &p.velocity {
                Some(v) => vector::<D>(&format!("particle[{k}].velocity"), v)?,
                None => VecD::<D>::zeros(),
            };
            let key = format!("particle[{k}].angular_velocity");
            let angular_velocity = match (&p.angular_velocity, D) {
                (None, _) => Vec3::zeros(),
                (Some(Spin::Scalar(w)), 2) => Vec3::new(0.0, 0.0, finite(&key, "rad/s", *w)?),
                (Some(Spin::Vector(v)), 3) => Vec3::from(vector::<3>(&key, v)?),
                (Some(Spin::Vector(v)), 2) if v.len() == 3 && v[0] == 0.0 && v[1] == 0.0 => {
                    Vec3::new(0.0, 0.0, finite(&key, "rad/s", v[2])?)
                }
                (Some(s), _) => {
                    return Err(bad(format!(
                        "{key} = {s:?}: in 2D give a number (rad/s about z), in 3D a vector [x, y, z]"
                    )))
                }
            };
            positive(&format!("particle[{k}].diameter"), "m", p.diameter)?;
            bodies.push(Body {
                position,
                velocity,
                angular_velocity,
                diameter: p.diameter,
            });
        }
        if let Some(g) = &self.generate {
            for (k, t) in g.0.iter().enumerate() {
                let (b, s) = generate::generate::<D>(t, k, g.0.len(), &kinds, named, (&walls, &wall_names))?;
                let key = if g.0.len() > 1 {
                    format!("generate[{k}].temperature")
                } else {
                    "generate.temperature".into()
                };
                temps.extend(std::iter::repeat_n((t.temperature, key), b.len()));
                bodies.extend(b);
                species.extend(s);
            }
        }
        if bodies.is_empty() {
            return Err(bad(
                "no particles: give [[particle]] entries or a [generate] table".into(),
            ));
        }
        // (a diameter so small its mass or moment of inertia is 0 in f64, e.g. 1e-320 m)
        let material_of = |k: usize| kinds[species.get(k).map_or(0, |&s| s as usize)].material;
        if let Some((k, b)) = bodies.iter().enumerate().find(|(k, b)| {
            let (m, i) = material_of(*k).mass_inertia(D, b.diameter);
            let normal = |x: f64| x.is_finite() && x >= f64::MIN_POSITIVE;
            !(normal(m) && normal(i) && normal(0.5 * b.diameter))
        }) {
            return Err(bad(format!(
                "particle {k}: diameter = {:e} m is out of range: its mass and moment of inertia at density {} kg/m³ are not finite normal numbers in f64 (between {:e} and {:e}): give the diameters in metres",
                b.diameter,
                material_of(k).density,
                f64::MIN_POSITIVE,
                f64::MAX
            )));
        }
        let problems = check::start_problems(&bodies, &walls, &config.domain, self.allow_initial_overlap);
        if !problems.is_empty() {
            return Err(bad(problems.join("\nscene: ")));
        }
        let mut count = vec![0usize; kinds.len()];
        for &s in &species {
            count[s as usize] += 1;
        }
        let given = pairs::Given {
            law: self.law.as_ref(),
            tangential: self.tangential.as_ref(),
            rolling: self.rolling.as_ref(),
            twisting: self.twisting.as_ref(),
            heat: self.heat.as_ref(),
            wall_names,
            wall_materials: self.wall.iter().map(|w| w.material.clone()).collect(),
            count,
        };
        let plan = pairs::plan(kinds, named, &self.pair, &given)?;
        let heat = self.heat_setup(&plan, temps)?;
        Ok(Scene {
            config,
            duration: self.duration,
            snapshots: self.snapshots.unwrap_or(0),
            bodies,
            species,
            walls,
            plan,
            heat,
        })
    }

    /// The temperatures of a scene whose `plan` has a heat law (else none): each species'
    /// heat capacity, each particle's temperature (`temps`, with where the scene gives it),
    /// each wall's; a missing or bad value refused, naming it.
    fn heat_setup(
        &self,
        plan: &PairPlan,
        temps: Vec<(Option<f64>, String)>,
    ) -> Result<Option<HeatSetup>, SceneError> {
        if !plan.pair.iter().chain(&plan.wall).any(|c| c.laws.heat.is_some()) {
            return Ok(None);
        }
        let capacity = |c: Option<f64>, key: &str| {
            match c {
            Some(c) => positive(key, "J/(kg·K)", c),
            None => Err(bad(format!(
                "{key} is missing: a scene with a heat law needs each material's specific heat capacity (J/(kg·K), e.g. 500 for steel)"
            ))),
        }
        };
        let specific_heat = if self.species.is_empty() {
            vec![capacity(
                self.material.as_ref().and_then(|m| m.heat_capacity),
                "[material].heat_capacity",
            )?]
        } else {
            self.species
                .iter()
                .enumerate()
                .map(|(k, s)| capacity(s.heat_capacity, &format!("species[{k}].heat_capacity")))
                .collect::<Result<_, _>>()?
        };
        let temperature = temps
            .into_iter()
            .map(|(t, key)| match t {
                Some(t) if t.is_finite() && t >= 0.0 => Ok(t),
                Some(t) => Err(bad(format!(
                    "{key} = {t} K is out of range: it must be finite and >= 0"
                ))),
                None => Err(bad(format!(
                    "{key} is missing: a scene with a heat law gives every particle's temperature (K)"
                ))),
            })
            .collect::<Result<_, _>>()?;
        let walls = self
            .wall
            .iter()
            .enumerate()
            .map(|(k, w)| w.temperature.as_ref().map(|t| t.temperature(k)).transpose())
            .collect::<Result<_, _>>()?;
        Ok(Some(HeatSetup {
            temperature,
            specific_heat,
            walls,
        }))
    }
}

fn finite(key: &str, unit: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(bad(format!("{key} = {v} {unit} is not a finite number")))
    }
}

pub(super) fn positive(key: &str, unit: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(bad(format!(
            "{key} = {v} {unit} is out of range: it must be finite and > 0"
        )))
    }
}

pub(super) fn non_negative(key: &str, unit: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(bad(format!(
            "{key} = {v} {unit} is out of range: it must be finite and >= 0"
        )))
    }
}

pub(super) fn vector<const D: usize>(key: &str, v: &[f64]) -> Result<VecD<D>, SceneError> {
    if v.len() != D {
        return Err(bad(format!(
            "{key} = {v:?} has {} components: dimension {D} needs {D}",
            v.len()
        )));
    }
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(bad(format!(
            "{key} = {v:?}: component {x} is not a finite number"
        )));
    }
    Ok(VecD::<D>::from_iterator(v.iter().cloned()))
}
