//! `[[wall]]` tables: planes, cylinders and boxes, and their motions (a piston or a sine along
//! a direction, a constant translation, a rotation about an axis), as the engine's
//! [`Wall`]s.

use super::pairs::WallMaterial;
use super::{bad, non_negative, positive, vector, SceneError};
use crate::dem::state::{Vec3, VecD};
use crate::dem::walls::{Motion, Shape, Spin, Wall};
use crate::piston::Piston;
use serde::Deserialize;

/// A wall's shape.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
enum WallKind {
    Plane,
    Cylinder,
    Box,
}

/// One motion of a wall.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "kebab-case")]
enum MotionTable {
    Fixed,
    Piston {
        amplitude: f64,
        frequency: f64,
        #[serde(default)]
        direction: Option<Vec<f64>>,
    },
    Sine {
        amplitude: f64,
        frequency: f64,
        #[serde(default)]
        direction: Option<Vec<f64>>,
    },
    Translate {
        velocity: Vec<f64>,
    },
    Rotate {
        #[serde(default)]
        angular_velocity: Option<f64>,
        #[serde(default)]
        rpm: Option<f64>,
        #[serde(default)]
        axis: Option<Vec<f64>>,
        #[serde(default)]
        point: Option<Vec<f64>>,
    },
}

/// `motion = { ... }` or `motion = [{ ... }, { ... }]`, each table's errors with its own path.
#[derive(Debug, Clone, Default)]
pub(super) struct Motions(Vec<MotionTable>);

impl<'de> Deserialize<'de> for Motions {
    fn deserialize<Dz: serde::Deserializer<'de>>(d: Dz) -> Result<Self, Dz::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Motions;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a motion table { kind = ... } or an array of them")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, m: A) -> Result<Motions, A::Error> {
                let one = MotionTable::deserialize(serde::de::value::MapAccessDeserializer::new(m))?;
                Ok(Motions(vec![one]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, s: A) -> Result<Motions, A::Error> {
                Vec::<MotionTable>::deserialize(serde::de::value::SeqAccessDeserializer::new(s)).map(Motions)
            }
        }
        d.deserialize_any(V)
    }
}

/// `[[wall]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct WallTable {
    /// A name, for `[[pair]]` tables (`wall = "drum"`) and messages.
    #[serde(default)]
    pub(super) name: Option<String>,
    #[serde(default)]
    kind: Option<WallKind>,
    #[serde(default)]
    point: Option<Vec<f64>>,
    #[serde(default)]
    normal: Option<Vec<f64>>,
    #[serde(default)]
    axis: Option<Vec<f64>>,
    #[serde(default)]
    radius: Option<f64>,
    #[serde(default)]
    lo: Option<Vec<f64>>,
    #[serde(default)]
    hi: Option<Vec<f64>>,
    #[serde(default)]
    inside: Option<bool>,
    #[serde(default)]
    motion: Option<Motions>,
    /// The wall's own material: a species' name or `{ young, poisson }` (else rigid).
    #[serde(default)]
    pub(super) material: Option<WallMaterial>,
    /// The wall's temperature, in a run with a heat law (else it does not conduct).
    #[serde(default)]
    pub(super) temperature: Option<TemperatureTable>,
}

/// `temperature = K` or `temperature = { mean = K, amplitude = K, frequency = Hz }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(
    untagged,
    expecting = "a temperature (K) or a table { mean = K, amplitude = K, frequency = Hz }"
)]
pub(super) enum TemperatureTable {
    Fixed(f64),
    Sine {
        mean: f64,
        amplitude: f64,
        frequency: f64,
    },
}

impl TemperatureTable {
    /// The wall's temperature, checked (`k`: the wall's index).
    pub(super) fn temperature(&self, k: usize) -> Result<crate::dem::heat::WallTemperature, SceneError> {
        use crate::dem::heat::WallTemperature;
        let t = match *self {
            TemperatureTable::Fixed(x) => WallTemperature::Fixed(x),
            TemperatureTable::Sine {
                mean,
                amplitude,
                frequency,
            } => WallTemperature::Sine {
                mean,
                amplitude,
                frequency,
            },
        };
        match t.problem(&format!("wall[{k}].temperature")) {
            Some(m) => Err(bad(m)),
            None => Ok(t),
        }
    }
}

/// A non-zero vector of dimension `D` as a unit one.
fn unit<const D: usize>(key: &str, v: &[f64]) -> Result<VecD<D>, SceneError> {
    let x = vector::<D>(key, v)?;
    if x.norm() == 0.0 {
        return Err(bad(format!("{key} = {v:?} must be a non-zero vector")));
    }
    Ok(x.normalize())
}

impl WallTable {
    /// The wall of this table, the `k`-th.
    pub(super) fn wall<const D: usize>(&self, k: usize) -> Result<Wall<D>, SceneError> {
        let key = |s: &str| format!("wall[{k}].{s}");
        let kind = self.kind.unwrap_or(WallKind::Plane);
        let kind_name = match kind {
            WallKind::Plane => "plane",
            WallKind::Cylinder => "cylinder",
            WallKind::Box => "box",
        };
        // the keys each kind takes
        let given = [
            ("point", self.point.is_some()),
            ("normal", self.normal.is_some()),
            ("axis", self.axis.is_some()),
            ("radius", self.radius.is_some()),
            ("lo", self.lo.is_some()),
            ("hi", self.hi.is_some()),
            ("inside", self.inside.is_some()),
        ];
        let takes: &[&str] = match kind {
            WallKind::Plane => &["point", "normal"],
            WallKind::Cylinder if D == 2 => &["point", "radius", "inside"],
            WallKind::Cylinder => &["point", "axis", "radius", "inside"],
            WallKind::Box => &["lo", "hi", "inside"],
        };
        if let Some((bad_key, _)) = given.iter().find(|(n, g)| *g && !takes.contains(n)) {
            return Err(bad(format!(
                "{} is not a key of a {kind_name} wall (kind = \"{kind_name}\"): its keys are {}",
                key(bad_key),
                takes.join(", ")
            )));
        }
        let need = |name: &str, v: &Option<Vec<f64>>| -> Result<Vec<f64>, SceneError> {
            v.clone().ok_or_else(|| {
                bad(format!(
                    "{} is missing: a {kind_name} wall needs {}",
                    key(name),
                    takes.join(", ")
                ))
            })
        };
        let shape = match kind {
            WallKind::Plane => Shape::Plane {
                point: vector::<D>(&key("point"), &need("point", &self.point)?)?,
                normal: unit::<D>(&key("normal"), &need("normal", &self.normal)?)?,
            },
            WallKind::Cylinder => {
                let radius = self.radius.ok_or_else(|| {
                    bad(format!(
                        "{} is missing: a cylinder wall needs a radius (m)",
                        key("radius")
                    ))
                })?;
                positive(&key("radius"), "m", radius)?;
                let axis = if D == 2 {
                    VecD::<D>::zeros()
                } else {
                    unit::<D>(&key("axis"), &need("axis", &self.axis)?)?
                };
                Shape::Cylinder {
                    point: vector::<D>(&key("point"), &need("point", &self.point)?)?,
                    axis,
                    radius,
                    inside: self.inside.unwrap_or(true),
                }
            }
            WallKind::Box => {
                let lo = vector::<D>(&key("lo"), &need("lo", &self.lo)?)?;
                let hi = vector::<D>(&key("hi"), &need("hi", &self.hi)?)?;
                if let Some(a) = (0..D).find(|&a| hi[a] <= lo[a]) {
                    return Err(bad(format!(
                        "{}[{a}] = {} m must exceed {}[{a}] = {} m",
                        key("hi"),
                        hi[a],
                        key("lo"),
                        lo[a]
                    )));
                }
                Shape::Box {
                    lo,
                    hi,
                    inside: self.inside.unwrap_or(true),
                }
            }
        };
        let mut wall = Wall::of_shape(shape);
        let motions = self.motion.as_ref().map_or(&[][..], |m| &m.0[..]);
        let (mut moved, mut translated, mut turned) = (false, false, false);
        for (m, t) in motions.iter().enumerate() {
            let mk = |s: &str| {
                if motions.len() > 1 {
                    format!("wall[{k}].motion[{m}].{s}")
                } else {
                    format!("wall[{k}].motion.{s}")
                }
            };
            let twice = |what: &str| {
                bad(format!(
                    "wall[{k}].motion: {what} is given twice; give each kind of motion once"
                ))
            };
            match t {
                MotionTable::Fixed => {}
                MotionTable::Piston {
                    amplitude,
                    frequency,
                    direction,
                }
                | MotionTable::Sine {
                    amplitude,
                    frequency,
                    direction,
                } => {
                    if std::mem::replace(&mut moved, true) {
                        return Err(twice("a piston or sine"));
                    }
                    non_negative(&mk("amplitude"), "m", *amplitude)?;
                    positive(&mk("frequency"), "Hz", *frequency)?;
                    wall.motion = match t {
                        MotionTable::Piston { .. } => Motion::Piston(Piston::new(*amplitude, *frequency)),
                        _ => Motion::Sine {
                            amplitude: *amplitude,
                            freq: *frequency,
                        },
                    };
                    wall.direction = match (direction, kind) {
                        (Some(d), _) => unit::<D>(&mk("direction"), d)?,
                        (None, WallKind::Plane) => wall.direction,
                        (None, _) => {
                            return Err(bad(format!(
                                "{} is missing: a {kind_name} moves along a direction you give ([x, y{}])",
                                mk("direction"),
                                if D == 3 { ", z" } else { "" }
                            )))
                        }
                    };
                }
                MotionTable::Translate { velocity } => {
                    if std::mem::replace(&mut translated, true) {
                        return Err(twice("a translation"));
                    }
                    wall.velocity = vector::<D>(&mk("velocity"), velocity)?;
                }
                MotionTable::Rotate {
                    angular_velocity,
                    rpm,
                    axis,
                    point,
                } => {
                    if std::mem::replace(&mut turned, true) {
                        return Err(twice("a rotation"));
                    }
                    let w = match (angular_velocity, rpm) {
                        (Some(w), None) => *w,
                        (None, Some(r)) => r * 2.0 * std::f64::consts::PI / 60.0,
                        _ => {
                            return Err(bad(format!(
                                "{}: give the rotation's angular_velocity (rad/s) or rpm (revolutions per minute), one of them",
                                mk("angular_velocity")
                            )))
                        }
                    };
                    if !w.is_finite() {
                        return Err(bad(format!(
                            "{} = {w} rad/s is not a finite number",
                            mk("angular_velocity")
                        )));
                    }
                    let omega = if D == 2 {
                        if axis.is_some() {
                            return Err(bad(format!(
                                "{}: in 2D a wall turns about z; give no axis (a positive angular velocity turns it counter-clockwise)",
                                mk("axis")
                            )));
                        }
                        Vec3::new(0.0, 0.0, w)
                    } else {
                        let a = match (axis, shape) {
                            (Some(a), _) => unit::<D>(&mk("axis"), a)?,
                            (None, Shape::Cylinder { axis, .. }) => axis,
                            (None, _) => {
                                return Err(bad(format!(
                                    "{} is missing: the axis of the rotation ([x, y, z]; a cylinder turns about its own by default)",
                                    mk("axis")
                                )))
                            }
                        };
                        Vec3::new(a[0], a[1], a[2]) * w
                    };
                    let center = match point {
                        Some(p) => vector::<D>(&mk("point"), p)?,
                        None => wall.reference_point(),
                    };
                    wall.spin = Some(Spin { center, omega });
                }
            }
        }
        wall.validate().map_err(|m| bad(format!("wall[{k}]: {m}")))?;
        Ok(wall)
    }
}
