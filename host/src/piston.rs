//! The bottom piston: McNamara & Falcon's two joined parabolas, with the corrected formula of
//! docs/physics.md (the printed formula lacks the 1/t0² factor).
//!
//! z(t) = (A/(2 t0²))(t² − t0²) on [−t0, t0] and the mirror image −(A/(2 t0²))((t − 2t0)² − t0²)
//! on [t0, 3t0], repeated with period 1/f = 4 t0, t0 = 1/(4f). Peak to peak A (z ∈ [−A/2, A/2]),
//! peak speed V = A/t0 = 4Af, acceleration ±a with a = A/t0² = 16 A f², constant on each *piece*.
//! Piece k covers [(2k − 1) t0, (2k + 1) t0]: even k accelerate upward (+a, around the lowest
//! position z = −A/2, reached at t = k·2t0), odd k downward (−a, around the highest z = +A/2).
//! At t = 0 the piston is at its lowest position, at rest.

/// The piston's waveform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piston {
    /// Peak-to-peak amplitude A (m); 0 is a fixed floor at z = 0.
    pub amplitude: f64,
    /// Frequency f (Hz), > 0.
    pub freq: f64,
    /// Quarter period t0 = 1/(4f) (s).
    pub t0: f64,
    /// Magnitude of the acceleration a = A/t0² = 16 A f² (m/s²).
    pub accel: f64,
}

/// The piston's state at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PistonState {
    /// Height z (m).
    pub z: f64,
    /// Velocity dz/dt (m/s).
    pub v: f64,
    /// Acceleration d²z/dt² (m/s²), constant over the piece.
    pub a: f64,
}

impl Piston {
    /// The waveform of amplitude `amplitude` (m, peak to peak) and frequency `freq` (Hz).
    pub fn new(amplitude: f64, freq: f64) -> Piston {
        let t0 = 0.25 / freq;
        Piston {
            amplitude,
            freq,
            t0,
            accel: amplitude / (t0 * t0),
        }
    }

    /// Peak speed V = 4 A f (m/s).
    pub fn peak_speed(&self) -> f64 {
        4.0 * self.amplitude * self.freq
    }

    /// Highest position A/2 (m).
    pub fn top(&self) -> f64 {
        0.5 * self.amplitude
    }

    /// The index of the piece containing time `t` (s).
    #[inline]
    pub fn piece(&self, t: f64) -> i64 {
        let x = (t + self.t0) / (2.0 * self.t0);
        // ⌊x⌋ without a call: x86-64's baseline has no rounding instruction, and `floor`
        // resolved to a software routine that cost the bed's event loop 0.4 % of its
        // instructions. Truncation saturates as `floor() as i64` does; one less where it
        // rounded up (x < 0, not whole). Exactly `x.floor() as i64`, NaN and ±∞ included.
        let i = x as i64;
        i.saturating_sub(i64::from(i as f64 > x))
    }

    /// Start time (s) of piece `k`; it ends where piece k + 1 starts.
    #[inline]
    pub fn piece_start(&self, k: i64) -> f64 {
        (2 * k - 1) as f64 * self.t0
    }

    /// The state at time `t` (s) evaluated on piece `k` (the formula of that piece, used also
    /// at its end points so that roots are found on one parabola).
    #[inline]
    pub fn state_on(&self, k: i64, t: f64) -> PistonState {
        let u = t - (2 * k) as f64 * self.t0;
        let s = if k & 1 == 0 { 1.0 } else { -1.0 };
        PistonState {
            z: s * 0.5 * self.accel * (u * u - self.t0 * self.t0),
            v: s * self.accel * u,
            a: s * self.accel,
        }
    }

    /// The state at time `t` (s).
    #[inline]
    pub fn state(&self, t: f64) -> PistonState {
        self.state_on(self.piece(t), t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_to_peak_peak_speed_and_continuity() {
        let p = Piston::new(0.025, 20.0);
        let s0 = p.state(0.0);
        assert!((s0.z + 0.0125).abs() < 1e-15 && s0.v == 0.0 && s0.a > 0.0);
        let half = p.state(0.5 / 20.0);
        assert!((half.z - 0.0125).abs() < 1e-15 && half.v.abs() < 1e-12 && half.a < 0.0);
        assert!((p.accel - 16.0 * 0.025 * 400.0).abs() < 1e-9);
        // peak speed V = 4Af at the piece boundaries, position and speed continuous there
        for k in -2..4 {
            let tb = p.piece_start(k);
            let (a, b) = (p.state_on(k - 1, tb), p.state_on(k, tb));
            assert!((a.z - b.z).abs() < 1e-15 && (a.v - b.v).abs() < 1e-12);
            assert!((a.v.abs() - p.peak_speed()).abs() < 1e-12 && a.z.abs() < 1e-15);
        }
        // one period later, same state
        let t = 0.0123;
        let (a, b) = (p.state(t), p.state(t + 1.0 / 20.0));
        assert!((a.z - b.z).abs() < 1e-14 && (a.v - b.v).abs() < 1e-11);
    }

    #[test]
    fn piece_is_the_floor_of_the_time_in_half_periods() {
        // the call-free floor is `floor() as i64` exactly: at piece boundaries, just either side
        // of them, at negative times, and at NaN, ±∞ and beyond i64's range
        let p = Piston::new(0.025, 30.0);
        let floor = |t: f64| ((t + p.t0) / (2.0 * p.t0)).floor() as i64;
        let mut ts = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e300,
            -1e300,
        ];
        for k in -5..5 {
            let b = p.piece_start(k);
            ts.extend([
                b,
                b * (1.0 + 1e-15),
                b * (1.0 - 1e-15),
                b + 1e-18,
                b - 1e-18,
                b + 0.3 * p.t0,
                -b,
            ]);
        }
        for t in ts {
            assert_eq!(p.piece(t), floor(t), "t = {t:e}");
        }
    }
}
