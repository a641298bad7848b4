//! Walls: planes, cylinders and boxes, fixed or moving, partners of infinite mass and radius
//! through the same laws as particle pairs (`MaterialPair::wall`, or the wall's own material).
//!
//! A wall is a [`Shape`] as it is at t = 0, and its motion: a displacement along a direction
//! (McNamara & Falcon's piston, a sine), a constant translation, and a rotation about an axis
//! at a constant angular velocity, combined (the rotation's axis moves with the translations).
//! Its state at an instant ([`Wall::surfaces`]) is one or more [`WallState`]s, the *surfaces*
//! a particle can touch: one for a plane, a cylinder or a box seen from outside, one per face
//! for a box holding the particles (a particle in a corner touches two or three faces at once,
//! each its own contact with its own history). A surface's velocity at a point is the wall's
//! rigid motion there: what the contact's normal rate, slip and rolling see.
//!
//! In 2D a cylinder is a circle in the plane (its `axis` is not used), a box a rectangle, and a
//! rotation is about z.

mod outline;

pub use outline::Segments;

use super::state::{from3, to3, Vec3, VecD};
use crate::piston::Piston;
use nalgebra::{Rotation3, SMatrix};

/// How a wall moves along its `direction` (see [`Wall::direction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Fixed.
    Fixed,
    /// McNamara & Falcon's piston: displacement z(t) (two joined parabolas, peak to peak A,
    /// lowest at t = 0).
    Piston(Piston),
    /// Sinusoidal: z(t) = amplitude · sin(2π f t) (m), `amplitude` half the peak to peak.
    Sine {
        /// Amplitude (m).
        amplitude: f64,
        /// Frequency (Hz).
        freq: f64,
    },
}

impl Motion {
    /// Displacement along the direction (m) and its rate (m/s) at time `t` (s).
    pub fn at(&self, t: f64) -> (f64, f64) {
        match self {
            Motion::Fixed => (0.0, 0.0),
            Motion::Piston(p) => {
                let s = p.state(t);
                (s.z, s.v)
            }
            Motion::Sine { amplitude, freq } => {
                let w = 2.0 * std::f64::consts::PI * freq;
                (amplitude * (w * t).sin(), amplitude * w * (w * t).cos())
            }
        }
    }

    /// The largest speed of the displacement (m/s).
    pub fn peak_speed(&self) -> f64 {
        match self {
            Motion::Fixed => 0.0,
            Motion::Piston(p) => p.peak_speed(),
            Motion::Sine { amplitude, freq } => amplitude.abs() * 2.0 * std::f64::consts::PI * freq,
        }
    }
}

/// A wall's rotation about an axis at a constant angular velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spin<const D: usize> {
    /// A point of the axis at t = 0 (m); it moves with the wall's displacement and translation.
    pub center: VecD<D>,
    /// The angular velocity (rad/s): in 3D along the axis, right-handed; in 2D its z
    /// component, about z (x and y must be 0).
    pub omega: Vec3,
}

/// A wall's shape at t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape<const D: usize> {
    /// The half-space `(x − point)·normal < 0` is solid; particles live on the side `normal`
    /// (unit) points to.
    Plane {
        /// A point of the plane (m).
        point: VecD<D>,
        /// Unit normal, into the particles' side.
        normal: VecD<D>,
    },
    /// A cylinder of `radius` about the axis through `point` along `axis` (unit; 3D), infinite
    /// along it; in 2D a circle about `point`. `inside`: the particles are inside it (a drum),
    /// else outside (a post).
    Cylinder {
        /// A point of the axis (m).
        point: VecD<D>,
        /// Unit direction of the axis (3D; unused in 2D).
        axis: VecD<D>,
        /// Radius (m).
        radius: f64,
        /// Whether the particles are inside.
        inside: bool,
    },
    /// The box `lo..hi` (m, along the axes at t = 0). `inside`: the particles are inside it
    /// (each face a surface of its own), else outside (an obstacle: its nearest point).
    Box {
        /// Lower corner (m).
        lo: VecD<D>,
        /// Upper corner (m).
        hi: VecD<D>,
        /// Whether the particles are inside.
        inside: bool,
    },
}

/// A wall: its shape at t = 0 and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall<const D: usize> {
    /// The shape at t = 0.
    pub shape: Shape<D>,
    /// The displacement along `direction` (a piston, a sine), if any.
    pub motion: Motion,
    /// The unit direction of `motion` (a plane's: its normal).
    pub direction: VecD<D>,
    /// A constant translation (m/s).
    pub velocity: VecD<D>,
    /// A rotation, if any.
    pub spin: Option<Spin<D>>,
}

/// What kind of surface a [`WallState`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Surface {
    /// A plane ([`WallState::point`], [`WallState::normal`]).
    Plane,
    /// A cylinder holding the particles (axis through `point` along `normal`; `radius`).
    CylinderIn,
    /// A cylinder the particles stay out of.
    CylinderOut,
    /// A box the particles stay out of (centre `point`, half extents `half` along the columns
    /// of `frame`).
    BoxOut,
}

/// One surface of a wall at one instant (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WallState<const D: usize> {
    /// What it is.
    pub kind: Surface,
    /// A plane's point, a cylinder's axis point, a box's centre (m).
    pub point: VecD<D>,
    /// A plane's unit normal (into the particles' side); a cylinder's axis (3D).
    pub normal: VecD<D>,
    /// A cylinder's radius (m).
    pub radius: f64,
    /// A box's half extents (m).
    pub half: VecD<D>,
    /// A box's axes (columns).
    pub frame: SMatrix<f64, D, D>,
    /// The velocity of the wall's translation (m/s).
    pub velocity: VecD<D>,
    /// The wall's angular velocity (rad/s; 2D: z), zero without a rotation.
    pub omega: Vec3,
    /// A point of the rotation's axis (m).
    pub center: VecD<D>,
}

impl<const D: usize> WallState<D> {
    /// A plane through `point` of normal `normal` moving at `velocity`, not rotating.
    pub fn plane(point: VecD<D>, normal: VecD<D>, velocity: VecD<D>) -> WallState<D> {
        WallState {
            kind: Surface::Plane,
            point,
            normal,
            radius: 0.0,
            half: VecD::<D>::zeros(),
            frame: SMatrix::<f64, D, D>::identity(),
            velocity,
            omega: Vec3::zeros(),
            center: VecD::<D>::zeros(),
        }
    }

    /// How far a sphere of radius `r` (m) at `x` reaches into the wall (m): its overlap with
    /// it, negative when apart. The one expression every wall test uses, so that they agree
    /// on every contact.
    #[inline(always)]
    pub fn overlap(&self, x: &VecD<D>, r: f64) -> f64 {
        match self.kind {
            Surface::Plane => r - (x - self.point).dot(&self.normal),
            Surface::CylinderIn => r + self.rho(x).norm() - self.radius,
            Surface::CylinderOut => r - (self.rho(x).norm() - self.radius),
            Surface::BoxOut => r - self.box_gap(x).0,
        }
    }

    /// The overlaps of the spheres `xs`, `rs` with the wall, each kept in `worst` where larger
    /// (or NaN): [`WallState::overlap`] over many particles, one loop per kind of surface.
    #[inline]
    pub fn overlaps_into(&self, xs: &[VecD<D>], rs: &[f64], worst: &mut [f64]) {
        macro_rules! each {
            ($f:expr) => {
                for ((m, x), r) in worst.iter_mut().zip(xs).zip(rs) {
                    let d = $f(x, *r);
                    *m = if d > *m || d.is_nan() { d } else { *m };
                }
            };
        }
        match self.kind {
            Surface::Plane => each!(|x: &VecD<D>, r: f64| r - (x - self.point).dot(&self.normal)),
            _ => each!(|x: &VecD<D>, r: f64| self.overlap(x, r)),
        }
    }

    /// The offset of `x` from the cylinder's axis, perpendicular to it (m) (2D: from the
    /// centre).
    #[inline(always)]
    fn rho(&self, x: &VecD<D>) -> VecD<D> {
        let d = x - self.point;
        if D == 2 {
            d
        } else {
            d - self.normal * d.dot(&self.normal)
        }
    }

    /// The distance (m) from `x` to the box seen from outside (negative inside: minus the
    /// depth to the nearest face), and the unit normal from the box to `x`.
    #[inline]
    fn box_gap(&self, x: &VecD<D>) -> (f64, VecD<D>) {
        let y = self.frame.transpose() * (x - self.point);
        let mut out = VecD::<D>::zeros();
        let mut inside = true;
        for k in 0..D {
            let e = y[k].abs() - self.half[k];
            if e > 0.0 {
                out[k] = e * y[k].signum();
                inside = false;
            }
        }
        if !inside {
            let d = out.norm();
            return (d, self.frame * (out / d));
        }
        // inside: the nearest face
        let (mut best, mut axis) = (f64::INFINITY, 0);
        for k in 0..D {
            let depth = self.half[k] - y[k].abs();
            if depth < best {
                best = depth;
                axis = k;
            }
        }
        let mut n = VecD::<D>::zeros();
        n[axis] = if y[axis] >= 0.0 { 1.0 } else { -1.0 };
        (-best, self.frame * n)
    }

    /// The contact of a sphere of radius `r` at `x` overlapping the wall by `delta` (from
    /// [`WallState::overlap`]): the unit normal from the wall to the sphere and the wall's
    /// velocity at the contact point (m/s).
    #[inline(always)]
    pub fn contact(&self, x: &VecD<D>, r: f64, delta: f64) -> (VecD<D>, VecD<D>) {
        let n = match self.kind {
            Surface::Plane => self.normal,
            Surface::CylinderIn => -self.rho(x).normalize(),
            Surface::CylinderOut => self.rho(x).normalize(),
            Surface::BoxOut => self.box_gap(x).1,
        };
        if self.omega == Vec3::zeros() {
            return (n, self.velocity);
        }
        // the contact point: on the wall's surface, below the sphere's centre
        let at = x - n * (r - delta);
        (n, self.velocity_at(&at))
    }

    /// The wall's velocity at the point `x` (m/s): its translation and its rotation.
    #[inline]
    pub fn velocity_at(&self, x: &VecD<D>) -> VecD<D> {
        if self.omega == Vec3::zeros() {
            return self.velocity;
        }
        self.velocity + from3::<D>(&self.omega.cross(&to3(&(x - self.center))))
    }

    /// The plane's offset along its normal (m): point · normal.
    #[inline]
    pub fn offset(&self) -> f64 {
        self.point.dot(&self.normal)
    }

    /// A bound on how far the surface has moved (m) since it was `then`: a plane along its
    /// normal, a cylinder across its axis, a box by its centre; infinite if it has turned.
    pub fn moved_since(&self, then: &WallState<D>) -> f64 {
        match self.kind {
            Surface::Plane if self.normal == then.normal => (self.offset() - then.offset()).abs(),
            Surface::CylinderIn | Surface::CylinderOut if self.normal == then.normal => {
                let d = self.point - then.point;
                if D == 2 {
                    d.norm()
                } else {
                    (d - self.normal * d.dot(&self.normal)).norm()
                }
            }
            Surface::BoxOut if self.frame == then.frame => (self.point - then.point).norm(),
            _ => f64::INFINITY,
        }
    }
}

/// The rotation by the angle |ω| t about ω (3D), or by ω_z t about z (2D), as a D × D matrix.
fn rotation<const D: usize>(omega: &Vec3, t: f64) -> SMatrix<f64, D, D> {
    if D == 2 {
        let (s, c) = (omega.z * t).sin_cos();
        SMatrix::<f64, D, D>::from_fn(|i, j| match (i, j) {
            (0, 0) | (1, 1) => c,
            (0, 1) => -s,
            _ => s,
        })
    } else {
        let r = Rotation3::new(omega * t);
        SMatrix::<f64, D, D>::from_fn(|i, j| r[(i, j)])
    }
}

impl<const D: usize> Wall<D> {
    /// A fixed plane through `point` with normal `normal` (normalised here; must be non-zero).
    pub fn fixed(point: VecD<D>, normal: VecD<D>) -> Wall<D> {
        Wall::plane(point, normal, Motion::Fixed)
    }

    /// A plane through `point` (at t = 0) with normal `normal` (normalised here; must be
    /// non-zero), moving along its normal by `motion`.
    pub fn plane(point: VecD<D>, normal: VecD<D>, motion: Motion) -> Wall<D> {
        let normal = normal.normalize();
        Wall {
            shape: Shape::Plane { point, normal },
            motion,
            direction: normal,
            velocity: VecD::<D>::zeros(),
            spin: None,
        }
    }

    /// A fixed wall of shape `shape`.
    pub fn of_shape(shape: Shape<D>) -> Wall<D> {
        let direction = match shape {
            Shape::Plane { normal, .. } => normal,
            _ => {
                let mut e = VecD::<D>::zeros();
                e[D - 1] = 1.0;
                e
            }
        };
        Wall {
            shape,
            motion: Motion::Fixed,
            direction,
            velocity: VecD::<D>::zeros(),
            spin: None,
        }
    }

    /// The surfaces a particle can touch: one, or a box's faces when it holds the particles
    /// (2D: 4, 3D: 6).
    pub fn surface_count(&self) -> usize {
        match self.shape {
            Shape::Box { inside: true, .. } => 2 * D,
            _ => 1,
        }
    }

    /// The lowest and highest points of the shape at t = 0 along the unit direction `up`
    /// (m): a plane's point (twice), a cylinder's axis point ± its radius, a box's corners.
    pub fn heights(&self, up: &VecD<D>) -> [f64; 2] {
        match self.shape {
            Shape::Plane { point, .. } => {
                let h = point.dot(up);
                [h, h]
            }
            Shape::Cylinder { point, radius, .. } => {
                let h = point.dot(up);
                [h - radius, h + radius]
            }
            Shape::Box { lo, hi, .. } => {
                let (c, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
                let span: f64 = (0..D).map(|k| (half[k] * up[k]).abs()).sum();
                [c.dot(up) - span, c.dot(up) + span]
            }
        }
    }

    /// Whether the wall moves (a displacement, a translation or a rotation).
    pub fn moves(&self) -> bool {
        self.motion != Motion::Fixed
            || self.velocity != VecD::<D>::zeros()
            || self.spin.is_some_and(|s| s.omega != Vec3::zeros())
    }

    /// Checks the wall: finite numbers, unit normals and axes, a positive radius, a box with
    /// `hi > lo`, a 2D rotation about z; the message names the value and the valid range.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |v: &VecD<D>| v.iter().all(|x| x.is_finite());
        let unit = |v: &VecD<D>| finite(v) && (v.norm() - 1.0).abs() < 1e-9;
        match self.shape {
            Shape::Plane { point, normal } => {
                if !finite(&point) || !unit(&normal) {
                    return Err(format!(
                        "plane: point {:?} must be finite and normal {:?} a unit vector",
                        point.as_slice(),
                        normal.as_slice()
                    ));
                }
            }
            Shape::Cylinder {
                point, axis, radius, ..
            } => {
                if !finite(&point) || (D == 3 && !unit(&axis)) {
                    return Err(format!(
                        "cylinder: point {:?} must be finite and axis {:?} a unit vector",
                        point.as_slice(),
                        axis.as_slice()
                    ));
                }
                if !(radius.is_finite() && radius > 0.0) {
                    return Err(format!(
                        "cylinder: radius = {radius} m is out of range: it must be finite and > 0"
                    ));
                }
            }
            Shape::Box { lo, hi, .. } => {
                if !finite(&lo) || !finite(&hi) || (0..D).any(|k| hi[k] <= lo[k]) {
                    return Err(format!(
                        "box: lo = {:?} .. hi = {:?} m: both finite, hi > lo along every axis",
                        lo.as_slice(),
                        hi.as_slice()
                    ));
                }
            }
        }
        if !unit(&self.direction) || !finite(&self.velocity) {
            return Err(format!(
                "motion: direction {:?} must be a unit vector and velocity {:?} finite",
                self.direction.as_slice(),
                self.velocity.as_slice()
            ));
        }
        if let Some(s) = self.spin {
            if !finite(&s.center)
                || !s.omega.iter().all(|x| x.is_finite())
                || (D == 2 && (s.omega.x != 0.0 || s.omega.y != 0.0))
            {
                return Err(format!(
                    "rotation: centre {:?} and angular velocity {:?} rad/s must be finite (2D: about z only)",
                    s.center.as_slice(),
                    s.omega.as_slice()
                ));
            }
        }
        Ok(())
    }

    /// A point of the shape at t = 0 (m): a plane's point, a cylinder's axis point, a box's
    /// centre.
    pub fn reference_point(&self) -> VecD<D> {
        match self.shape {
            Shape::Plane { point, .. } | Shape::Cylinder { point, .. } => point,
            Shape::Box { lo, hi, .. } => (lo + hi) * 0.5,
        }
    }

    /// Whether the rotation leaves the shape where it is (a plane turning about its normal, a
    /// cylinder about its own axis): only the surface's velocity turns.
    pub fn spins_in_place(&self) -> bool {
        let Some(s) = self.spin else { return true };
        if s.omega == Vec3::zeros() {
            return true;
        }
        let w = s.omega.norm();
        let along = |v: &VecD<D>| to3(v).cross(&s.omega).norm() <= 1e-12 * w * v.norm();
        match self.shape {
            Shape::Plane { normal, .. } => D == 3 && along(&normal),
            Shape::Cylinder {
                point, axis, radius, ..
            } => {
                let d = s.center - point;
                let off = if D == 2 { d } else { d - axis * d.dot(&axis) };
                (D == 2 || along(&axis)) && off.norm() <= 1e-12 * radius
            }
            Shape::Box { .. } => false,
        }
    }

    /// The largest speed of the wall's surface (m/s) within `reach` (m) of its rotation's axis
    /// (for a rotating plane; a cylinder's and a box's own size is counted).
    pub fn peak_speed(&self, reach: f64) -> f64 {
        let mut v = self.motion.peak_speed() + self.velocity.norm();
        if let Some(s) = self.spin {
            let size = match self.shape {
                Shape::Plane { .. } => reach,
                Shape::Cylinder { point, radius, .. } => radius + (point - s.center).norm(),
                Shape::Box { lo, hi, .. } => ((lo + hi) * 0.5 - s.center).norm() + 0.5 * (hi - lo).norm(),
            };
            v += s.omega.norm() * size;
        }
        v
    }

    /// The wall's surfaces at time `t` (s), appended to `out` ([`Wall::surface_count`] of them).
    pub fn surfaces_into(&self, t: f64, out: &mut Vec<WallState<D>>) {
        let (z, v) = self.motion.at(t);
        let mut shift = self.direction * z;
        let mut velocity = self.direction * v;
        if self.velocity != VecD::<D>::zeros() {
            shift += self.velocity * t;
            velocity += self.velocity;
        }
        let (turn, omega, center) = match self.spin {
            Some(s) if s.omega != Vec3::zeros() => {
                let turn = (!self.spins_in_place()).then(|| rotation::<D>(&s.omega, t));
                (turn.map(|r| (r, s.center)), s.omega, s.center + shift)
            }
            _ => (None, Vec3::zeros(), VecD::<D>::zeros()),
        };
        // a point and a direction of the shape at t = 0, now
        let place = |p: VecD<D>| match turn {
            None => p + shift,
            Some((r, c0)) => c0 + shift + r * (p - c0),
        };
        let orient = |n: VecD<D>| match turn {
            None => n,
            Some((r, _)) => r * n,
        };
        let base = WallState {
            kind: Surface::Plane,
            point: VecD::<D>::zeros(),
            normal: VecD::<D>::zeros(),
            radius: 0.0,
            half: VecD::<D>::zeros(),
            frame: SMatrix::<f64, D, D>::identity(),
            velocity,
            omega,
            center,
        };
        match self.shape {
            Shape::Plane { point, normal } => out.push(WallState {
                point: place(point),
                normal: orient(normal),
                ..base
            }),
            Shape::Cylinder {
                point,
                axis,
                radius,
                inside,
            } => out.push(WallState {
                kind: if inside {
                    Surface::CylinderIn
                } else {
                    Surface::CylinderOut
                },
                point: place(point),
                normal: orient(axis),
                radius,
                ..base
            }),
            Shape::Box { lo, hi, inside } => {
                let (c, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
                if inside {
                    for k in 0..D {
                        for s in [-1.0, 1.0] {
                            let mut e = VecD::<D>::zeros();
                            e[k] = 1.0;
                            out.push(WallState {
                                point: place(c + e * (s * half[k])),
                                normal: orient(e * -s),
                                ..base
                            });
                        }
                    }
                } else {
                    out.push(WallState {
                        kind: Surface::BoxOut,
                        point: place(c),
                        half,
                        frame: turn.map_or(SMatrix::<f64, D, D>::identity(), |(r, _)| r),
                        ..base
                    });
                }
            }
        }
    }

    /// The wall's surfaces at time `t` (s).
    pub fn surfaces(&self, t: f64) -> Vec<WallState<D>> {
        let mut out = Vec::with_capacity(self.surface_count());
        self.surfaces_into(t, &mut out);
        out
    }

    /// The first surface at time `t` (s): for a plane, the plane.
    pub fn at(&self, t: f64) -> WallState<D> {
        self.surfaces(t)[0]
    }

    /// The wall in words, for messages: `"plane through [0, 0] m, normal [0, 1]"`.
    pub fn describe(&self) -> String {
        let v = |x: &VecD<D>| format!("{:?}", x.as_slice());
        match self.shape {
            Shape::Plane { point, normal } => format!("plane through {} m, normal {}", v(&point), v(&normal)),
            Shape::Cylinder {
                point,
                axis,
                radius,
                inside,
            } => {
                let side = if inside { "inside" } else { "outside" };
                if D == 2 {
                    format!(
                        "circle of radius {radius} m about {} m, particles {side}",
                        v(&point)
                    )
                } else {
                    format!(
                        "cylinder of radius {radius} m, axis through {} m along {}, particles {side}",
                        v(&point),
                        v(&axis)
                    )
                }
            }
            Shape::Box { lo, hi, inside } => {
                format!(
                    "box {} .. {} m, particles {}",
                    v(&lo),
                    v(&hi),
                    if inside { "inside" } else { "outside" }
                )
            }
        }
    }
}
