//! Flat walls, fixed or moving along their normal (a piston): partners of infinite mass and
//! radius, through the same laws as particle pairs (`MaterialPair::wall`).

use super::state::VecD;
use crate::piston::Piston;

/// How a wall moves along its normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Fixed.
    Fixed,
    /// McNamara & Falcon's piston: displacement z(t) along the normal (two joined parabolas,
    /// peak to peak A, lowest at t = 0).
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
    /// Displacement along the normal (m) and its rate (m/s) at time `t` (s).
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

    /// The largest speed of the wall (m/s).
    pub fn peak_speed(&self) -> f64 {
        match self {
            Motion::Fixed => 0.0,
            Motion::Piston(p) => p.peak_speed(),
            Motion::Sine { amplitude, freq } => amplitude.abs() * 2.0 * std::f64::consts::PI * freq,
        }
    }
}

/// A flat wall: the half-space `(x − p)·n < 0` is solid, particles live on the side `n` points to.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall<const D: usize> {
    /// A point of the plane at t = 0 (m).
    pub point: VecD<D>,
    /// Unit normal, pointing into the particles' side.
    pub normal: VecD<D>,
    /// Its motion along `normal`.
    pub motion: Motion,
}

/// A wall's plane at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallState<const D: usize> {
    /// A point of the plane (m).
    pub point: VecD<D>,
    /// Unit normal.
    pub normal: VecD<D>,
    /// Velocity of the wall (m/s).
    pub velocity: VecD<D>,
}

impl<const D: usize> WallState<D> {
    /// How far a sphere of radius `r` (m) at `x` reaches past the plane (m): its overlap with
    /// the wall, negative when apart. The one expression every wall test uses, so that they
    /// agree on every contact.
    #[inline(always)]
    pub fn overlap(&self, x: &VecD<D>, r: f64) -> f64 {
        r - (x - self.point).dot(&self.normal)
    }

    /// The plane's offset along its normal (m): point · normal.
    #[inline]
    pub fn offset(&self) -> f64 {
        self.point.dot(&self.normal)
    }
}

impl<const D: usize> Wall<D> {
    /// A fixed wall through `point` with normal `normal` (normalised here; must be non-zero).
    pub fn fixed(point: VecD<D>, normal: VecD<D>) -> Wall<D> {
        Wall {
            point,
            normal: normal.normalize(),
            motion: Motion::Fixed,
        }
    }

    /// The plane at time `t` (s).
    #[inline]
    pub fn at(&self, t: f64) -> WallState<D> {
        let (z, v) = self.motion.at(t);
        WallState {
            point: self.point + self.normal * z,
            normal: self.normal,
            velocity: self.normal * v,
        }
    }
}

impl<const D: usize> Wall<D> {
    /// A plane through `point` (at t = 0) with normal `normal` (normalised here; must be
    /// non-zero), moving along its normal by `motion`.
    pub fn plane(point: VecD<D>, normal: VecD<D>, motion: Motion) -> Wall<D> {
        Wall {
            point,
            normal: normal.normalize(),
            motion,
        }
    }

    /// The wall in words, for messages.
    pub fn describe(&self) -> String {
        let v = |x: &VecD<D>| format!("{:?}", x.as_slice());
        format!("plane through {} m, normal {}", v(&self.point), v(&self.normal))
    }
}
