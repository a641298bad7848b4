//! How a batch call fails: its status, where it found a bad number, and the errors a host
//! makes of them.

use crate::error::{ErrorKind, LawError};
use abi_stable::StableAbi;

/// Outcome of a batch call (sdk 0.2 and later).
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq)]
pub enum BatchStatus {
    /// Every output was written.
    Ok = 0,
    /// The law panicked; the message is available from the vtable's `take_panic`.
    Panic = 1,
    /// An output is NaN or infinite; [`BatchFault`] names the contact.
    NonFiniteOutput = 2,
    /// An input is not finite (or a mass or radius not > 0); [`BatchFault`] names the contact
    /// and the input. Nothing was computed for that block.
    BadInput = 3,
}

/// Where a batch call found a bad number.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BatchFault {
    /// Index of the contact.
    pub index: usize,
    /// Which array: [`BatchFault::OUTPUT`] or one of the input codes.
    pub field: u8,
}

impl BatchFault {
    /// The output (force).
    pub const OUTPUT: u8 = 0;
    /// Input `delta`.
    pub const DELTA: u8 = 1;
    /// Input `rate`.
    pub const RATE: u8 = 2;
    /// Input `mass`.
    pub const MASS: u8 = 3;
    /// Input `radius`.
    pub const RADIUS: u8 = 4;
    /// Input `normal`.
    pub const NORMAL: u8 = 5;
    /// Input `velocity`.
    pub const VELOCITY: u8 = 6;
    /// Input `normal_force`.
    pub const NORMAL_FORCE: u8 = 7;
    /// Input `dt`.
    pub const DT: u8 = 8;
    /// Output `power` (sdk 0.3).
    pub const POWER: u8 = 9;
    /// Output `elastic` (sdk 0.3).
    pub const ELASTIC: u8 = 10;
    /// Output `reach` (sdk 0.3).
    pub const REACH: u8 = 11;
    /// Output `torque` (sdk 0.3).
    pub const TORQUE: u8 = 12;
    /// Output `context` of a normal law (sdk 0.4): a field not finite and ≥ 0.
    pub const CONTEXT: u8 = 13;
    /// Input `context` of a tangential, rolling, twisting or heat law (sdk 0.4): a field not
    /// finite and ≥ 0.
    pub const CONTEXT_INPUT: u8 = 14;
    /// Input `temperature` of a heat law (sdk 0.4).
    pub const TEMPERATURE: u8 = 15;
    /// Output `heat` of a heat law (sdk 0.4): not finite.
    pub const HEAT: u8 = 16;
    /// Output `conductance` of a heat law (sdk 0.4): not finite and ≥ 0.
    pub const CONDUCTANCE: u8 = 17;

    /// Whether array `field` is an output (the force, torque, power, elastic energy or reach)
    /// rather than an input.
    pub fn is_output(field: u8) -> bool {
        matches!(
            field,
            Self::OUTPUT
                | Self::POWER
                | Self::ELASTIC
                | Self::REACH
                | Self::TORQUE
                | Self::CONTEXT
                | Self::HEAT
                | Self::CONDUCTANCE
        )
    }

    /// The name of array `field`.
    pub fn field_name(field: u8) -> &'static str {
        match field {
            Self::OUTPUT => "force",
            Self::DELTA => "delta",
            Self::RATE => "rate",
            Self::MASS => "mass",
            Self::RADIUS => "radius",
            Self::NORMAL => "normal",
            Self::VELOCITY => "velocity",
            Self::NORMAL_FORCE => "normal_force",
            Self::DT => "dt",
            Self::POWER => "power",
            Self::ELASTIC => "elastic",
            Self::REACH => "reach",
            Self::TORQUE => "torque",
            Self::CONTEXT | Self::CONTEXT_INPUT => "context",
            Self::TEMPERATURE => "temperature",
            Self::HEAT => "heat",
            Self::CONDUCTANCE => "conductance",
            _ => "?",
        }
    }
}

/// The error for the bad input `value` of array `field` of contact `index` of a batch of a
/// `kind` law `name`, which the plugin refused before evaluating it.
pub(crate) fn bad_input(kind: &str, name: &str, field: u8, index: usize, value: f64) -> LawError {
    let what = BatchFault::field_name(field);
    let rule = match field {
        BatchFault::MASS => "must be finite and > 0 (kg)",
        BatchFault::RADIUS => "must be finite and > 0 (m)",
        BatchFault::DT => "must be finite and ≥ 0 (s)",
        BatchFault::CONTEXT_INPUT => {
            "must have every field finite and ≥ 0 (contact radius m, cap force N, damping N·s/m)"
        }
        _ => "must be finite",
    };
    LawError::new(
        ErrorKind::NonFinite,
        format!("{kind} law '{name}': input {what}[{index}] = {value} {rule}; refused before evaluation"),
    )
}
