//! Temperatures and the heat the contacts conduct (sdk 0.4).
//!
//! A run with a heat law (a class's [`crate::dem::LawSet::heat`]) and temperatures
//! ([`crate::dem::Engine::with_heat`]) gives each particle a temperature T_i (K) and a heat
//! capacity C_i = m_i c_i (J/K). At every step, in the force pass (each contact right after its
//! forces), each contact's heat law gets the two temperatures of the step's start, the normal
//! force, the overlap, the effective radius and the normal law's context (its contact radius a)
//! at the step's end, and returns the heat flow Q into particle i (W) and the contact's
//! conductance H (W/K); the partner gets −Q exactly. A wall
//! with a temperature ([`WallTemperature`]) is a reservoir: it gives Q and is not heated; a
//! wall without one does not conduct. After the pass, as LAMMPS's `fix heat/flow`, each
//! temperature steps by explicit Euler, T_i += dt Q_i / C_i, the flows summed per particle in
//! one order whatever the number of threads (the same bits on one thread or many).
//!
//! The books: Σ C_i T_i − (Σ C_i T_i at the start) − (the heat the walls gave) = 0 to
//! rounding ([`HeatBooks`]). Explicit Euler is stable for dt < 2 C_i/Σ_j H_ij and monotone
//! below C_i/Σ_j H_ij: the engine keeps the smallest C_i/Σ_j H_ij met
//! ([`HeatBooks::stability_limit`]) and a run whose step exceeds it is warned about
//! ([`HeatBooks::warning`]). A run without temperatures does none of this (no array, no work
//! per contact).

use serde::{Deserialize, Serialize};

/// A wall's temperature (K): fixed, or T0 + A sin(2π f t).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum WallTemperature {
    /// A fixed temperature (K).
    Fixed(f64),
    /// `mean` + `amplitude` sin(2π `frequency` t): mean and amplitude in K, frequency in Hz,
    /// t the run's time (s).
    Sine {
        /// Mean temperature T0 (K).
        mean: f64,
        /// Amplitude A (K), |A| ≤ T0.
        amplitude: f64,
        /// Frequency f (Hz): ω = 2π f.
        frequency: f64,
    },
}

impl WallTemperature {
    /// The temperature at time `t` (s), K.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        match *self {
            WallTemperature::Fixed(x) => x,
            WallTemperature::Sine {
                mean,
                amplitude,
                frequency,
            } => mean + amplitude * (2.0 * std::f64::consts::PI * frequency * t).sin(),
        }
    }

    /// Why this temperature is out of range, if it is (`key`: where the scene gives it).
    pub fn problem(&self, key: &str) -> Option<String> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        match *self {
            WallTemperature::Fixed(x) if !ok(x) => Some(format!(
                "{key} = {x} K is out of range: it must be finite and >= 0"
            )),
            WallTemperature::Sine {
                mean,
                amplitude,
                frequency,
            } if !(ok(mean) && amplitude.is_finite() && amplitude.abs() <= mean && ok(frequency)) => {
                Some(format!(
                    "{key} = {{ mean = {mean} K, amplitude = {amplitude} K, frequency = {frequency} Hz }} is out of range: mean and frequency must be finite and >= 0, |amplitude| <= mean (the wall stays at >= 0 K)"
                ))
            }
            _ => None,
        }
    }
}

/// What a run's temperatures start from: [`crate::dem::Engine::with_heat`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HeatSetup {
    /// Each particle's temperature (K), in the user's numbering.
    pub temperature: Vec<f64>,
    /// Each species' specific heat capacity c (J/(kg·K)), > 0: C_i = m_i c.
    pub specific_heat: Vec<f64>,
    /// Each wall's temperature (`None`: the wall does not conduct).
    pub walls: Vec<Option<WallTemperature>>,
}

/// The thermal books of a run (J), and the explicit step's stability.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HeatBooks {
    /// Σ C_i T_i now (J).
    pub thermal: f64,
    /// Σ C_i T_i at the start (J).
    pub thermal_initial: f64,
    /// The heat the walls gave the particles since the start (J; negative: they took it).
    pub wall_heat: f64,
    /// thermal − thermal_initial − wall_heat (J): 0 to rounding.
    pub balance: f64,
    /// The smallest C_i / Σ_j H_ij met so far (s; infinite: no contact conducted): explicit
    /// Euler is monotone for dt below it, stable below twice it.
    pub stability_limit: f64,
    /// The step (s).
    pub dt: f64,
}

impl HeatBooks {
    /// The warning when the step exceeds [`HeatBooks::stability_limit`].
    pub fn warning(&self) -> Option<String> {
        (self.dt > self.stability_limit).then(|| {
            format!(
                "dt = {:.4e} s exceeds the thermal limit min C/ΣH = {:.4e} s met during the run: the explicit temperature update overshoots{} (a smaller dt, a larger heat_capacity or a smaller conductance)",
                self.dt,
                self.stability_limit,
                if self.dt > 2.0 * self.stability_limit {
                    " and is unstable (dt > 2 C/ΣH)"
                } else {
                    " (monotone only below it, stable below twice it)"
                }
            )
        })
    }

    /// The books as `dem --json` prints them (`heat`).
    pub fn json(&self) -> serde_json::Value {
        let mut v = serde_json::json!({
            "thermal": self.thermal,
            "thermal_initial": self.thermal_initial,
            "wall_heat": self.wall_heat,
            "balance": self.balance,
            "stability_limit": self.stability_limit.is_finite().then_some(self.stability_limit),
        });
        v["warning"] = serde_json::json!(self.warning());
        v
    }
}

/// What a checkpoint keeps of a run's temperatures (in the user's numbering).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeatState {
    /// Each particle's temperature (K).
    pub temperature: Vec<f64>,
    /// Σ C T at the start (J).
    pub thermal_initial: f64,
    /// The heat the walls gave (J).
    pub wall_heat: f64,
    /// The smallest C/ΣH met (s).
    pub limit: f64,
}
