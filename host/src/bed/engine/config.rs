//! The parameters of a bed and their validation.

use super::super::BedError;
use serde::Serialize;

/// The parameters of a bed. Defaults ([`BedConfig::paper`]) are McNamara & Falcon's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BedConfig {
    /// Number of layers n = N d / L (dimensionless); N = round(n L/d) disks.
    pub layers: f64,
    /// Piston frequency f (Hz).
    pub freq: f64,
    /// Gravity g (m/s², pointing down; 0 for none).
    pub gravity: f64,
    /// Piston amplitude A, peak to peak (m); 0 is a fixed floor.
    pub amplitude: f64,
    /// Box width L (m), periodic.
    pub width: f64,
    /// Disk diameter d (m).
    pub diameter: f64,
    /// Disk mass m (kg).
    pub mass: f64,
    /// Headroom h − h0 (m): the lid is at A/2 + n d + headroom.
    pub headroom: f64,
    /// Tangential restitution r_t ∈ [−1, 1] (rough disks that rotate), or None: smooth disks.
    pub tangential: Option<f64>,
    /// The TC model's time t_c (s): a collision of a disk that collided less than t_c ago is
    /// elastic. None: off.
    pub tc: Option<f64>,
    /// Seed of the initial state.
    pub seed: u64,
    /// Largest initial velocity component (m/s).
    pub initial_speed: f64,
}

impl BedConfig {
    /// The paper's bed with `layers` layers at frequency `freq` (Hz): d = 2 mm,
    /// m = 3.27e-5 kg, L = 0.2 m, A = 25 mm, h − h0 = 15 mm, g = 9.8 m/s², smooth disks, no TC.
    pub fn paper(layers: f64, freq: f64) -> BedConfig {
        BedConfig {
            layers,
            freq,
            gravity: 9.8,
            amplitude: 0.025,
            width: 0.2,
            diameter: 0.002,
            mass: 3.27e-5,
            headroom: 0.015,
            tangential: None,
            tc: None,
            seed: 1,
            initial_speed: 0.5,
        }
    }

    /// Number of disks N = round(n L / d).
    pub fn disks(&self) -> usize {
        (self.layers * self.width / self.diameter).round().max(0.0) as usize
    }

    /// Height of the lid (m): A/2 + n d + (h − h0).
    pub fn lid(&self) -> f64 {
        0.5 * self.amplitude + self.layers * self.diameter + self.headroom
    }

    /// Checks every value; the message names the value and its valid range.
    /// Checks the protocol's lengths: `transient` ≥ 0 and `cycles` > 0 periods, finite; the
    /// error names the value (as `name = value periods`) and its range. The one check of every
    /// run of either engine and of [`BedSpec`](crate::bed::spec::BedSpec).
    pub fn check_protocol(transient: f64, cycles: f64) -> Result<(), BedError> {
        if !(transient >= 0.0 && transient.is_finite()) {
            return Err(BedError::Invalid(format!(
                "transient = {transient} periods is out of range: must be >= 0"
            )));
        }
        if !(cycles > 0.0 && cycles.is_finite()) {
            return Err(BedError::Invalid(format!(
                "cycles = {cycles} periods is out of range: must be > 0"
            )));
        }
        Ok(())
    }

    /// Checks every value of the configuration; the error names the value and its range.
    pub fn validate(&self) -> Result<(), BedError> {
        let bad = |s: String| Err(BedError::Invalid(s));
        let fin = |name: &str, v: f64| -> Result<(), BedError> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(BedError::Invalid(format!("{name} = {v} is not a finite number")))
            }
        };
        for (n, v) in [
            ("layers", self.layers),
            ("freq", self.freq),
            ("gravity", self.gravity),
            ("amplitude", self.amplitude),
            ("width", self.width),
            ("diameter", self.diameter),
            ("mass", self.mass),
            ("headroom", self.headroom),
            ("initial speed", self.initial_speed),
        ] {
            fin(n, v)?;
        }
        // (the value as a message names it, its unit, the symbol its range is stated for,
        // whether 0 is in the range)
        for (what, v, unit, sym, zero_ok) in [
            ("layers n", self.layers, "", "n", false),
            ("frequency f", self.freq, " Hz", "f", false),
            ("gravity g", self.gravity, " m/s²", "g", true),
            ("amplitude A", self.amplitude, " m", "A", true),
            ("diameter d", self.diameter, " m", "d", false),
            ("mass m", self.mass, " kg", "m", false),
        ] {
            if v < 0.0 || (v == 0.0 && !zero_ok) {
                let range = if zero_ok { ">= 0" } else { "> 0" };
                return bad(format!(
                    "{what} = {v}{unit} is out of range: {sym} must be {range}"
                ));
            }
        }
        if self.width < 3.0 * self.diameter {
            return bad(format!(
                "the box is too small: width L = {} m must be at least 3 diameters ({} m)",
                self.width,
                3.0 * self.diameter
            ));
        }
        if self.disks() == 0 {
            return bad(format!(
                "layers n = {} gives no disk (N = n L/d = {:.3}); raise n",
                self.layers,
                self.layers * self.width / self.diameter
            ));
        }
        if self.layers * self.diameter + self.headroom < self.diameter {
            return bad(format!(
                "the box is too small: the gap between the piston at its highest and the lid, \
                 n d + (h - h0) = {} m, must be at least one diameter ({} m); raise --headroom",
                self.layers * self.diameter + self.headroom,
                self.diameter
            ));
        }
        if let Some(rt) = self.tangential {
            if !(-1.0..=1.0).contains(&rt) {
                return bad(format!(
                    "tangential restitution r_t = {rt} is out of range: r_t must be in [-1, 1]"
                ));
            }
        }
        if let Some(tc) = self.tc {
            if !(tc.is_finite() && tc >= 0.0) {
                return bad(format!("TC time t_c = {tc} s is out of range: t_c must be >= 0"));
            }
        }
        if self.initial_speed < 0.0 {
            return bad(format!(
                "initial speed = {} m/s is out of range: must be >= 0",
                self.initial_speed
            ));
        }
        Ok(())
    }
}
