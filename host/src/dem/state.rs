//! Particle state: positions, velocities, spins, sizes and inertia, structure of arrays.

use nalgebra::{SVector, Vector3};

/// A D-dimensional vector (m, m/s, N).
pub type VecD<const D: usize> = SVector<f64, D>;
/// A 3D vector: angular velocities (rad/s) and torques (N·m) are 3D in both dimensions (2D uses
/// the z component only).
pub type Vec3 = Vector3<f64>;

/// The third dimension of a 2D run: what a disk's mass and moment of inertia are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiskMass {
    /// The disk is a sphere of the same diameter confined to the plane (McNamara & Falcon's
    /// convention, m = (π/6) ρ d³ ≈ 3×10⁻⁵ kg for 2 mm steel), I = (2/5) m R².
    Sphere,
    /// A uniform cylinder of length d (its own diameter): m = (π/4) ρ d³, I = (1/2) m R².
    Disk,
}

impl DiskMass {
    /// `"sphere"` or `"disk"`.
    pub fn as_str(&self) -> &'static str {
        match self {
            DiskMass::Sphere => "sphere",
            DiskMass::Disk => "disk",
        }
    }
}

/// The particles' material (one material per run).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus (Pa).
    pub young: f64,
    /// Poisson's ratio, in (−1, 0.5).
    pub poisson: f64,
    /// Density (kg/m³).
    pub density: f64,
    /// In 2D: how a disk's mass and moment of inertia are defined (ignored in 3D: spheres).
    pub disk_mass: DiskMass,
}

impl Material {
    /// Steel: E = 200 GPa, ν = 0.3, ρ = 7800 kg/m³, 2D disks with a sphere's mass (the paper's).
    pub const STEEL: Material = Material {
        young: 2.0e11,
        poisson: 0.3,
        density: 7800.0,
        disk_mass: DiskMass::Sphere,
    };

    /// Mass (kg) and moment of inertia (kg·m²) of a particle of diameter `d` (m) in dimension `dim`.
    pub fn mass_inertia(&self, dim: usize, d: f64) -> (f64, f64) {
        let r = 0.5 * d;
        let sphere = std::f64::consts::PI / 6.0 * self.density * d.powi(3);
        if dim == 2 && self.disk_mass == DiskMass::Disk {
            let m = std::f64::consts::PI / 4.0 * self.density * d.powi(3);
            (m, 0.5 * m * r * r)
        } else {
            (sphere, 0.4 * sphere * r * r)
        }
    }

    /// The sdk's particle of diameter `d` (m) (for the material pairs the laws bind to).
    pub fn particle(&self, d: f64) -> dashpot_sdk::Particle {
        dashpot_sdk::Particle {
            diameter: d,
            density: self.density,
            young: self.young,
            poisson: self.poisson,
        }
    }
}

/// One particle as given by a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body<const D: usize> {
    /// Position of the centre (m).
    pub position: VecD<D>,
    /// Velocity (m/s).
    pub velocity: VecD<D>,
    /// Angular velocity (rad/s); in 2D only z.
    pub angular_velocity: Vec3,
    /// Diameter (m).
    pub diameter: f64,
}

/// Every particle, structure of arrays.
#[derive(Debug, Clone, Default)]
pub struct Particles<const D: usize> {
    /// Positions (m); wrapped into the box along periodic axes at every neighbour rebuild.
    pub pos: Vec<VecD<D>>,
    /// Velocities (m/s).
    pub vel: Vec<VecD<D>>,
    /// Angular velocities (rad/s), [`spin_len`]`(D)` components per particle: ω_z in 2D,
    /// (ω_x, ω_y, ω_z) in 3D (see [`Particles::angular_velocity`]).
    pub omega: Vec<f64>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Masses (kg).
    pub mass: Vec<f64>,
    /// Moments of inertia (kg·m²).
    pub inertia: Vec<f64>,
    /// Forces of the last evaluation (N), gravity excluded.
    pub force: Vec<VecD<D>>,
    /// Torques of the last evaluation (N·m), laid out as `omega` (see [`Particles::torque`]).
    pub torque: Vec<f64>,
}

impl<const D: usize> Particles<D> {
    /// The particles of `bodies`, of material `mat`.
    pub fn new(bodies: &[Body<D>], mat: &Material) -> Particles<D> {
        Particles::of_species(bodies, &[], std::slice::from_ref(mat))
    }

    /// The particles of `bodies`, each of the material `materials[species[k]]` (`species`
    /// empty: every particle of `materials[0]`).
    pub fn of_species(bodies: &[Body<D>], species: &[u8], materials: &[Material]) -> Particles<D> {
        let n = bodies.len();
        let mut p = Particles {
            pos: Vec::with_capacity(n),
            vel: Vec::with_capacity(n),
            omega: Vec::with_capacity(n * spin_len(D)),
            radius: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inertia: Vec::with_capacity(n),
            force: vec![VecD::<D>::zeros(); n],
            torque: vec![0.0; n * spin_len(D)],
        };
        for (k, b) in bodies.iter().enumerate() {
            let mat = &materials[species.get(k).map_or(0, |&s| s as usize)];
            let (m, i) = mat.mass_inertia(D, b.diameter);
            p.pos.push(b.position);
            p.vel.push(b.velocity);
            // (2D: the z component only)
            if D == 2 {
                p.omega.push(b.angular_velocity.z);
            } else {
                p.omega.extend_from_slice(b.angular_velocity.as_slice());
            }
            p.radius.push(0.5 * b.diameter);
            p.mass.push(m);
            p.inertia.push(i);
        }
        p
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// No particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Particle `i` as a [`Body`].
    pub fn body(&self, i: usize) -> Body<D> {
        Body {
            position: self.pos[i],
            velocity: self.vel[i],
            angular_velocity: self.angular_velocity(i),
            diameter: 2.0 * self.radius[i],
        }
    }

    /// Angular velocity of particle `i` (rad/s) (2D: (0, 0, ω_z)).
    #[inline]
    pub fn angular_velocity(&self, i: usize) -> Vec3 {
        spin::<D>(&self.omega, i)
    }

    /// Sets the angular velocity of particle `i` (rad/s) (2D: its z component only).
    #[inline]
    pub fn set_angular_velocity(&mut self, i: usize, w: &Vec3) {
        set_spin::<D>(&mut self.omega, i, w)
    }

    /// Torque on particle `i` at the last evaluation (N·m) (2D: (0, 0, τ_z)).
    #[inline]
    pub fn torque(&self, i: usize) -> Vec3 {
        spin::<D>(&self.torque, i)
    }
}

/// Components stored per particle for a spin (angular velocity, torque) in dimension `d`: one
/// in 2D (about z: disks turn in the plane), three in 3D. A 2D step moves a third of the bytes
/// a 3-vector would.
pub const fn spin_len(d: usize) -> usize {
    if d == 2 {
        1
    } else {
        3
    }
}

/// Spin `i` (rad/s or N·m) of the flat array `w` ([`spin_len`]`(D)` components per particle),
/// as a 3D vector (2D: (0, 0, z)).
#[inline(always)]
pub fn spin<const D: usize>(w: &[f64], i: usize) -> Vec3 {
    if D == 2 {
        Vec3::new(0.0, 0.0, w[i])
    } else {
        Vec3::new(w[3 * i], w[3 * i + 1], w[3 * i + 2])
    }
}

/// Stores `v` as spin `i` of the flat array `w` (2D: its z component only).
#[inline(always)]
pub fn set_spin<const D: usize>(w: &mut [f64], i: usize, v: &Vec3) {
    if D == 2 {
        w[i] = v.z;
    } else {
        w[3 * i..3 * i + 3].copy_from_slice(v.as_slice());
    }
}

/// A D-vector as a 3D one (z = 0 in 2D).
#[inline(always)]
pub fn to3<const D: usize>(v: &VecD<D>) -> Vec3 {
    let mut o = Vec3::zeros();
    for k in 0..D.min(3) {
        o[k] = v[k];
    }
    o
}

/// The first D components of a 3D vector.
#[inline(always)]
pub fn from3<const D: usize>(v: &Vec3) -> VecD<D> {
    let mut o = VecD::<D>::zeros();
    for k in 0..D.min(3) {
        o[k] = v[k];
    }
    o
}
