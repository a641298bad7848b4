//! Particles and the effective properties of a contacting pair.
//!
//! Conventions (stated once, used by every law of the project):
//! - effective mass `m = m1 m2 / (m1 + m2)` (kg); against a wall (infinite mass) `m = m1`;
//! - effective radius `r = r1 r2 / (r1 + r2)` (m); against a flat wall `r = r1`;
//! - effective modulus `1/E = (1 - ν1²)/E1 + (1 - ν2²)/E2` (Pa); a wall is rigid, so `E = E1/(1 - ν1²)`.
//!
//! These are the definitions of Antypov & Elliott (EPL 2011, eq. 1 and below eq. 9). For two
//! identical spheres of diameter `d`, `r = d/4` and `m = (π/12) ρ d³`.

use crate::error::LawError;
use abi_stable::StableAbi;

/// One spherical particle, in SI units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Particle {
    /// Diameter (m), > 0.
    pub diameter: f64,
    /// Density (kg/m³), > 0.
    pub density: f64,
    /// Young's modulus (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio (dimensionless), in (−1, 0.5).
    pub poisson: f64,
}

impl Particle {
    /// The paper's MCC granule (Antypov & Elliott, fig. 1): d = 1 cm, ρ = 1500 kg/m³, E = 6 GPa,
    /// ν = 0.3.
    pub const MCC: Particle = Particle {
        diameter: 0.01,
        density: 1500.0,
        young: 6.0e9,
        poisson: 0.3,
    };

    /// Checks every property against its physical range; the error names the value and the range.
    pub fn validate(&self) -> Result<(), LawError> {
        check_positive("diameter", "m", self.diameter)?;
        check_positive("density", "kg/m³", self.density)?;
        check_positive("young", "Pa", self.young)?;
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(LawError::invalid_pair(format!(
                "poisson = {} is out of range: Poisson's ratio must lie in (-1, 0.5)",
                self.poisson
            )));
        }
        Ok(())
    }

    /// Mass (kg) of the sphere: (π/6) ρ d³.
    pub fn mass(&self) -> f64 {
        std::f64::consts::PI / 6.0 * self.density * self.diameter.powi(3)
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        0.5 * self.diameter
    }

    /// The plane-strain modulus E/(1 − ν²) (Pa).
    pub fn plane_strain_modulus(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }

    /// The shear modulus G = E/(2(1 + ν)) (Pa).
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// G/(2 − ν) (Pa): this particle's share of the Mindlin effective shear modulus.
    pub fn mindlin_shear_modulus(&self) -> f64 {
        self.shear_modulus() / (2.0 - self.poisson)
    }
}

/// What a contact law may precompute for a pair of *materials*: the effective moduli. Sizes and
/// masses are per contact and travel with each batch call, so a polydisperse packing binds a
/// law once per pair of materials.
///
/// - `young`: 1/E = (1 − ν1²)/E1 + (1 − ν2²)/E2 (Pa); against a rigid wall E = E1/(1 − ν1²);
/// - `shear`: 1/G = (2 − ν1)/G1 + (2 − ν2)/G2 (Pa, Mindlin's tangential modulus, G = E/(2(1 + ν)));
///   against a rigid wall G = G1/(2 − ν1).
///
/// `#[repr(C)]`: this struct crosses the plugin boundary and the C ABI by reference.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MaterialPair {
    /// Effective Young's modulus E_eff (Pa).
    pub young: f64,
    /// Effective shear modulus G_eff (Pa) of Mindlin's tangential stiffness 8 G_eff a.
    pub shear: f64,
}

impl MaterialPair {
    /// The materials of two particles (only `young` and `poisson` are used).
    pub fn spheres(a: &Particle, b: &Particle) -> Result<MaterialPair, LawError> {
        a.validate()?;
        b.validate()?;
        MaterialPair::new(
            1.0 / (1.0 / a.plane_strain_modulus() + 1.0 / b.plane_strain_modulus()),
            1.0 / (1.0 / a.mindlin_shear_modulus() + 1.0 / b.mindlin_shear_modulus()),
        )
    }

    /// A particle against a rigid wall.
    pub fn wall(a: &Particle) -> Result<MaterialPair, LawError> {
        a.validate()?;
        MaterialPair::new(a.plane_strain_modulus(), a.mindlin_shear_modulus())
    }

    /// From Young's moduli (Pa) and Poisson's ratios of two materials; `None` for a rigid wall.
    pub fn of_moduli(
        young1: f64,
        poisson1: f64,
        other: Option<(f64, f64)>,
    ) -> Result<MaterialPair, LawError> {
        let p = |young, poisson| Particle {
            diameter: 1.0,
            density: 1.0,
            young,
            poisson,
        };
        match other {
            Some((e2, nu2)) => MaterialPair::spheres(&p(young1, poisson1), &p(e2, nu2)),
            None => MaterialPair::wall(&p(young1, poisson1)),
        }
    }

    /// Effective moduli, checked: both finite and > 0.
    pub fn new(young: f64, shear: f64) -> Result<MaterialPair, LawError> {
        check_positive("effective Young's modulus", "Pa", young)?;
        check_positive("effective shear modulus", "Pa", shear)?;
        Ok(MaterialPair { young, shear })
    }

    /// Checks the fields of a material pair built by hand (or received through an ABI).
    pub fn validate(&self) -> Result<(), LawError> {
        MaterialPair::new(self.young, self.shear).map(|_| ())
    }

    /// The Hertz stiffness K = (4/3) E_eff √r (N/m^{3/2}) of a contact of effective radius `r`.
    #[inline]
    pub fn hertz_stiffness(&self, radius: f64) -> f64 {
        4.0 / 3.0 * self.young * radius.sqrt()
    }
}

fn check_positive(name: &str, unit: &str, v: f64) -> Result<(), LawError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(LawError::invalid_pair(format!(
            "{name} = {v} {unit} is out of range: it must be finite and > 0"
        )))
    }
}

/// The effective properties of a contacting pair, the only thing a law sees of the particles.
///
/// `#[repr(C)]`: this struct crosses the plugin boundary and the C ABI by reference.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pair {
    /// Effective (reduced) mass m1 m2/(m1 + m2) (kg); the particle's mass against a wall.
    pub mass: f64,
    /// Effective radius r1 r2/(r1 + r2) (m); the particle's radius against a flat wall.
    pub radius: f64,
    /// Effective Young's modulus, 1/E = (1 − ν1²)/E1 + (1 − ν2²)/E2 (Pa).
    pub young: f64,
    /// Test-suite only (feature `__layout_skew_for_tests`): changes the layout on purpose.
    #[cfg(feature = "__layout_skew_for_tests")]
    #[doc(hidden)]
    pub layout_skew: f64,
}

impl Pair {
    /// The pair of two spheres `a` and `b`.
    pub fn spheres(a: &Particle, b: &Particle) -> Result<Pair, LawError> {
        a.validate()?;
        b.validate()?;
        let (ma, mb) = (a.mass(), b.mass());
        let (ra, rb) = (a.radius(), b.radius());
        Pair::new(
            ma * mb / (ma + mb),
            ra * rb / (ra + rb),
            1.0 / (1.0 / a.plane_strain_modulus() + 1.0 / b.plane_strain_modulus()),
        )
    }

    /// The materials of this pair when both bodies (or the body and the wall) have Poisson's
    /// ratio `poisson`: then G_eff / E_eff = (1 − ν)/(2(2 − ν)) exactly, for two spheres and
    /// for a sphere on a rigid wall alike.
    pub fn materials(&self, poisson: f64) -> Result<MaterialPair, LawError> {
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(LawError::invalid_pair(format!(
                "poisson = {poisson} is out of range: Poisson's ratio must lie in (-1, 0.5)"
            )));
        }
        MaterialPair::new(self.young, self.young * (1.0 - poisson) / (2.0 * (2.0 - poisson)))
    }

    /// The pair of a sphere and a flat, rigid wall of infinite mass.
    pub fn wall(a: &Particle) -> Result<Pair, LawError> {
        a.validate()?;
        Pair::new(a.mass(), a.radius(), a.plane_strain_modulus())
    }

    /// A pair from effective quantities, checked: all three must be finite and > 0.
    pub fn new(mass: f64, radius: f64, young: f64) -> Result<Pair, LawError> {
        check_positive("effective mass", "kg", mass)?;
        check_positive("effective radius", "m", radius)?;
        check_positive("effective Young's modulus", "Pa", young)?;
        Ok(Pair {
            mass,
            radius,
            young,
            #[cfg(feature = "__layout_skew_for_tests")]
            layout_skew: 0.0,
        })
    }

    /// Checks the fields of a pair built by hand (or received through an ABI).
    pub fn validate(&self) -> Result<(), LawError> {
        Pair::new(self.mass, self.radius, self.young).map(|_| ())
    }

    /// The Hertz stiffness K = (4/3) E √r (N/m^{3/2}), so that the elastic force is K δ^{3/2}
    /// (Antypov & Elliott eq. 9).
    pub fn hertz_stiffness(&self) -> f64 {
        4.0 / 3.0 * self.young * self.radius.sqrt()
    }

    /// The length unit L = 4 r (m) of the HSD ↔ LSD mapping; L = d for two identical spheres.
    ///
    /// The linear spring with k = K √L (= (2/3) E d for identical spheres, the paper's choice)
    /// has the same phase trajectory as the Hertz spring after δ_H/L = (5/4)^{2/5} (δ_L/L)^{4/5}
    /// (eq. 19). For unequal spheres or a wall we keep L = 4 r_eff, which reduces to the paper's
    /// d for identical spheres.
    pub fn mapping_length(&self) -> f64 {
        4.0 * self.radius
    }

    /// The linear stiffness k = K √L = (8/3) E r (N/m) that maps the Hertz spring onto a linear one
    /// (Antypov & Elliott: k = (2/3) E_eff d for two identical spheres).
    pub fn mapped_linear_stiffness(&self) -> f64 {
        8.0 / 3.0 * self.young * self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn identical_spheres_follow_the_papers_conventions() {
        let p = Particle::MCC;
        let pair = Pair::spheres(&p, &p).unwrap();
        let d = p.diameter;
        assert_relative_eq!(pair.radius, d / 4.0, max_relative = 1e-15);
        let m = std::f64::consts::PI / 12.0 * p.density * d.powi(3);
        assert_relative_eq!(pair.mass, m, max_relative = 1e-15);
        let e_eff = p.young / (2.0 * (1.0 - 0.09));
        assert_relative_eq!(pair.young, e_eff, max_relative = 1e-15);
        // K = 2/3 E_eff sqrt(d) and k = 2/3 E_eff d for identical spheres (paper, below eq. 18)
        assert_relative_eq!(
            pair.hertz_stiffness(),
            2.0 / 3.0 * e_eff * d.sqrt(),
            max_relative = 1e-14
        );
        assert_relative_eq!(
            pair.mapped_linear_stiffness(),
            2.0 / 3.0 * e_eff * d,
            max_relative = 1e-14
        );
    }

    #[test]
    fn material_pairs_of_equal_poisson_ratios() {
        let p = Particle::MCC;
        let q = Particle {
            diameter: 0.02,
            density: 900.0,
            ..p
        };
        for (pair, mat) in [
            (
                Pair::spheres(&p, &q).unwrap(),
                MaterialPair::spheres(&p, &q).unwrap(),
            ),
            (Pair::wall(&p).unwrap(), MaterialPair::wall(&p).unwrap()),
        ] {
            let m = pair.materials(p.poisson).unwrap();
            assert_relative_eq!(m.young, mat.young, max_relative = 1e-15);
            assert_relative_eq!(m.shear, mat.shear, max_relative = 1e-14);
        }
        // Mindlin: 1/G_eff = (2 − ν1)/G1 + (2 − ν2)/G2, G = E/(2(1 + ν))
        let g = p.young / (2.0 * 1.3);
        assert_relative_eq!(
            MaterialPair::spheres(&p, &p).unwrap().shear,
            g / (2.0 * 1.7),
            max_relative = 1e-15
        );
        assert_relative_eq!(
            MaterialPair::wall(&p).unwrap().shear,
            g / 1.7,
            max_relative = 1e-15
        );
    }

    #[test]
    fn a_wall_has_infinite_mass_and_radius() {
        let p = Particle::MCC;
        let w = Pair::wall(&p).unwrap();
        assert_relative_eq!(w.mass, p.mass(), max_relative = 1e-15);
        assert_relative_eq!(w.radius, p.diameter / 2.0, max_relative = 1e-15);
        assert_relative_eq!(w.young, 6.0e9 / 0.91, max_relative = 1e-15);
    }

    #[test]
    fn bad_particles_name_the_value_and_range() {
        let mut p = Particle::MCC;
        p.poisson = 0.5;
        let e = p.validate().unwrap_err();
        assert!(e.message.contains("poisson = 0.5") && e.message.contains("(-1, 0.5)"));
        p = Particle::MCC;
        p.density = -1.0;
        assert!(p.validate().unwrap_err().message.contains("density = -1"));
        p = Particle::MCC;
        p.young = f64::NAN;
        assert!(p.validate().unwrap_err().message.contains("young = NaN"));
    }
}
