//! Species and the laws of each pair of them.
//!
//! A run may hold several species of particles, each of its own [`Material`]. Each pair of
//! species, and each species against each wall, has its own laws (a normal law and optional
//! tangential, rolling and twisting laws: a [`LawSet`]), each bound to that pair's materials:
//! `MaterialPair::spheres` of the two species' moduli, `MaterialPair::wall` against a rigid
//! wall, or `MaterialPair::spheres` of the species and the wall's own material. The contacts
//! are sorted by *class*: the pairs of species (or the species–wall pairs) that share one bound
//! [`LawSet`]. Each class's contacts live in their own contact sets ([`super::contacts::
//! Contacts`]), with their laws' own history widths, and go to their laws in their own batch
//! calls. A run of one species has one class of pair contacts and one of wall contacts: the
//! engine then runs exactly as it did before species existed.

use super::contacts::ClassMap;
use super::state::Material;
use super::{DemError, Laws};
use crate::laws::{HeatConduction, NormalLaw, RollingResistance, TangentialForce, TwistingResistance};

/// The laws of one class of contacts, bound to its pair of materials.
pub struct LawSet {
    /// The normal law.
    pub normal: Box<dyn NormalLaw>,
    /// The tangential law (none: frictionless).
    pub tangential: Option<Box<dyn TangentialForce>>,
    /// The rolling resistance (sdk 0.3), if any.
    pub rolling: Option<Box<dyn RollingResistance>>,
    /// The twisting resistance (sdk 0.3), if any.
    pub twisting: Option<Box<dyn TwistingResistance>>,
    /// The heat conduction (sdk 0.4), if any: it acts in a run with temperatures
    /// ([`crate::dem::Engine::with_heat`]).
    pub heat: Option<Box<dyn HeatConduction>>,
}

impl LawSet {
    /// The history slots per contact of the laws (see [`super::contacts::Slots`]).
    pub fn slots(&self) -> super::contacts::Slots {
        super::contacts::Slots {
            n: self.normal.history_slots(),
            t: self.tangential.as_ref().map_or(0, |t| t.history_slots()),
            r: self.rolling.as_ref().map(|l| l.history_slots()),
            w: self.twisting.as_ref().map(|l| l.history_slots()),
        }
    }

    /// The laws' names, `normal + tangential + ...`.
    pub fn names(&self) -> String {
        let mut s = self.normal.name().to_string();
        let more = [
            self.tangential.as_ref().map(|l| l.name().to_string()),
            self.rolling.as_ref().map(|l| l.name().to_string()),
            self.twisting.as_ref().map(|l| l.name().to_string()),
            self.heat.as_ref().map(|l| l.name().to_string()),
        ];
        for n in more.into_iter().flatten() {
            s.push_str(" + ");
            s.push_str(&n);
        }
        s
    }
}

/// A species: its name and material.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeciesInfo {
    /// The name the scene gives it (empty for the one species of a scene without species).
    pub name: String,
    /// Its material.
    pub material: Material,
}

/// The most species a run holds (a particle's species is kept in a byte).
pub const MAX_SPECIES: usize = 255;

/// Every contact's laws: the species, the classes of the pairs of species and of the
/// species–wall pairs, and each class's laws.
pub struct SpeciesLaws {
    /// The species (at least one).
    pub species: Vec<SpeciesInfo>,
    /// The class of the pair of species `(a, b)`: `pair_class[a * species + b]`, symmetric;
    /// empty: every pair is of class 0.
    pub pair_class: Vec<u8>,
    /// Each class's laws between particles.
    pub pair: Vec<LawSet>,
    /// What each pair class is, for messages (`"powder–beads"`).
    pub pair_labels: Vec<String>,
    /// The class of species `s` against wall `w`: `wall_class[s * walls + w]`; empty: every
    /// particle–wall contact is of class 0.
    pub wall_class: Vec<u8>,
    /// Each class's laws against walls (at least one: the step is chosen against a wall even
    /// in a run without walls, as it always was).
    pub wall: Vec<LawSet>,
    /// What each wall class is, for messages (`"beads–wall 0"`).
    pub wall_labels: Vec<String>,
}

impl SpeciesLaws {
    /// The table of a run of one species of material `material`, with the laws `laws`.
    pub fn single(laws: Laws, material: Material) -> SpeciesLaws {
        let Laws {
            pair,
            wall,
            pair_tangential,
            wall_tangential,
            rotation,
        } = laws;
        SpeciesLaws {
            species: vec![SpeciesInfo {
                name: String::new(),
                material,
            }],
            pair_class: Vec::new(),
            pair: vec![LawSet {
                normal: pair,
                tangential: pair_tangential,
                rolling: rotation.pair_rolling,
                twisting: rotation.pair_twisting,
                heat: rotation.pair_heat,
            }],
            pair_labels: vec!["particle–particle".into()],
            wall_class: Vec::new(),
            wall: vec![LawSet {
                normal: wall,
                tangential: wall_tangential,
                rolling: rotation.wall_rolling,
                twisting: rotation.wall_twisting,
                heat: rotation.wall_heat,
            }],
            wall_labels: vec!["particle–wall".into()],
        }
    }

    /// The class of the pair of species `a`, `b`.
    #[inline(always)]
    pub fn pair_class(&self, a: u8, b: u8) -> usize {
        if self.pair_class.is_empty() {
            0
        } else {
            self.pair_class[a as usize * self.species.len() + b as usize] as usize
        }
    }

    /// The class of species `s` against wall `w` of `walls`.
    #[inline(always)]
    pub fn wall_class(&self, s: u8, w: usize, walls: usize) -> usize {
        if self.wall_class.is_empty() {
            0
        } else {
            self.wall_class[s as usize * walls + w] as usize
        }
    }

    /// Checks the table against a run of `walls` walls and the particles' `species` (one per
    /// particle, or empty: all of species 0).
    pub fn check(&self, walls: usize, species: &[u8], particles: usize) -> Result<(), DemError> {
        let n = self.species.len();
        let bad = |m: String| Err(DemError::Invalid(m));
        if n == 0 || n > MAX_SPECIES {
            return bad(format!("{n} species: a run holds 1 to {MAX_SPECIES}"));
        }
        if !species.is_empty() && species.len() != particles {
            return bad(format!(
                "{} species given for {particles} particles: give one per particle",
                species.len()
            ));
        }
        if let Some((i, &s)) = species.iter().enumerate().find(|(_, &s)| s as usize >= n) {
            return bad(format!(
                "particle {i}: species {s} is out of range: there are {n} species"
            ));
        }
        if self.pair.is_empty() || self.wall.is_empty() {
            return bad("no laws: every run needs a class of pair laws and one of wall laws".into());
        }
        if !self.pair_class.is_empty() {
            if self.pair_class.len() != n * n {
                return bad(format!(
                    "the pair classes: {} entries for {n} species",
                    self.pair_class.len()
                ));
            }
            for a in 0..n {
                for b in 0..n {
                    let c = self.pair_class[a * n + b];
                    if c != self.pair_class[b * n + a] || c as usize >= self.pair.len() {
                        return bad(format!(
                            "the pair class of species {a} and {b} is {c}: out of range or not symmetric"
                        ));
                    }
                }
            }
        }
        if !self.wall_class.is_empty() {
            if self.wall_class.len() != n * walls {
                return bad(format!(
                    "the wall classes: {} entries for {n} species and {walls} walls",
                    self.wall_class.len()
                ));
            }
            if let Some(c) = self.wall_class.iter().find(|&&c| c as usize >= self.wall.len()) {
                return bad(format!(
                    "wall class {c} is out of range: there are {}",
                    self.wall.len()
                ));
            }
        }
        for (k, m) in self.species.iter().enumerate() {
            m.material
                .particle(1.0)
                .validate()
                .map_err(|e| DemError::Invalid(format!("species {k} ('{}'): {}", m.name, e.message)))?;
        }
        Ok(())
    }

    /// How the gatherings sort a run's contacts into their classes, for a run of `walls` walls.
    pub fn class_map(&self, walls: usize) -> ClassMap<'_> {
        ClassMap {
            species: self.species.len(),
            walls,
            pair: &self.pair_class,
            wall: &self.wall_class,
        }
    }
}
