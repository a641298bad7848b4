//! Errors a law can report, in a form that crosses the plugin boundary unchanged.

use abi_stable::{std_types::RString, StableAbi};

/// What went wrong, as a stable discriminant (`#[repr(u8)]`) shared by the Rust ABI and the C ABI.
#[repr(u8)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ErrorKind {
    /// No law of that name is exported by the plugin or registry.
    UnknownLaw = 1,
    /// A parameter name that is not in the law's schema.
    UnknownParameter = 2,
    /// A parameter value outside its documented range, NaN or infinite.
    InvalidParameter = 3,
    /// A particle or pair property outside its physical range (mass, radius, modulus, ...).
    InvalidPair = 4,
    /// The law produced NaN or an infinite value.
    NonFinite = 5,
    /// The law panicked; the panic was caught at the plugin boundary.
    Panic = 6,
    /// The law does not offer this operation (for example no closed-form calibration).
    Unsupported = 7,
    /// A plugin could not be loaded or is incompatible with this host.
    Load = 8,
    /// Anything else; the message says what.
    Other = 9,
}

/// An error from a law: a kind and a human-readable message that names the offending value and,
/// where there is one, the valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct LawError {
    /// The category of the error.
    pub kind: ErrorKind,
    /// A complete sentence for the user.
    pub message: String,
}

impl LawError {
    /// An error of `kind` with `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
        }
    }

    /// A parameter value outside its range.
    pub fn invalid_parameter(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::InvalidParameter, message)
    }

    /// A pair or particle property outside its range.
    pub fn invalid_pair(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::InvalidPair, message)
    }

    /// An operation the law does not offer.
    pub fn unsupported(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Unsupported, message)
    }

    /// The same error with its message rewritten by `f`.
    pub fn with_message(mut self, f: impl FnOnce(&str) -> String) -> Self {
        self.message = f(&self.message);
        self
    }
}

/// The FFI-safe form of [`LawError`].
#[repr(C)]
#[derive(StableAbi, Debug, Clone)]
pub struct FfiError {
    /// The category of the error.
    pub kind: ErrorKind,
    /// The message, allocated by whichever side created it (an `RString` frees itself correctly).
    pub message: RString,
}

impl From<LawError> for FfiError {
    fn from(e: LawError) -> Self {
        Self {
            kind: e.kind,
            message: e.message.into(),
        }
    }
}

impl From<FfiError> for LawError {
    fn from(e: FfiError) -> Self {
        Self {
            kind: e.kind,
            message: e.message.into_string(),
        }
    }
}
