//! Restitution-law handles (unchanged since sdk 0.1).

use super::*;

/// A configured restitution law from a plugin.
pub struct RestitutionLawHandle {
    pub(super) ffi: Owned<FfiRestitutionLaw>,
    pub(super) info: LawInfo,
}

impl RestitutionLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// Binds the law to `pair` (validated first).
    pub fn bind(&self, pair: &Pair) -> Result<BoundRestitutionHandle, LawError> {
        pair.validate()?;
        Ok(BoundRestitutionHandle {
            ffi: Owned::take(unsafe { (self.ffi.vtable.bind)(self.ffi.obj, pair) })?,
            name: self.info.name.to_string(),
        })
    }
}

/// A restitution law bound to a pair, with every input and output checked.
pub struct BoundRestitutionHandle {
    ffi: Owned<FfiBoundRestitution>,
    name: String,
}

impl BoundRestitutionHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn panic_error(&self) -> LawError {
        let msg = (self.ffi.vtable.take_panic)();
        LawError::new(
            ErrorKind::Panic,
            format!("restitution law '{}' panicked: {}", self.name, msg),
        )
    }

    fn non_finite(&self, value: f64, speed: f64) -> LawError {
        LawError::new(
            ErrorKind::NonFinite,
            format!(
                "restitution law '{}' returned {value} at impact speed {speed:e} m/s",
                self.name
            ),
        )
    }

    fn bad_speed(&self, i: usize, speed: f64) -> LawError {
        bad_input("restitution", &self.name, BatchFault::RATE, i, speed)
            .with_message(|m| m.replace("rate[", "speed["))
    }

    /// r(v) at normal impact speed `speed` (m/s, finite).
    #[inline]
    pub fn restitution(&self, speed: f64) -> Result<f64, LawError> {
        if !speed.is_finite() {
            return Err(self.bad_speed(0, speed));
        }
        let mut out = 0.0;
        match unsafe { (self.ffi.vtable.restitution)(self.ffi.obj, speed, &mut out) } {
            v1::CallStatus::Ok if out.is_finite() => Ok(out),
            v1::CallStatus::Ok | v1::CallStatus::NonFinite => Err(self.non_finite(out, speed)),
            v1::CallStatus::Panic => Err(self.panic_error()),
        }
    }

    /// `out[i] = r(speed[i])` over slices of equal length.
    pub fn restitution_batch(&self, speed: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        if speed.len() != out.len() {
            return Err(length_error(
                "restitution_batch",
                format!("speed {}, out {}", speed.len(), out.len()),
            ));
        }
        if !all_finite(speed) {
            let i = speed.iter().position(|v| !v.is_finite()).unwrap_or(0);
            return Err(self.bad_speed(i, speed[i]));
        }
        let mut bad = 0usize;
        let st = unsafe {
            (self.ffi.vtable.restitution_batch)(
                self.ffi.obj,
                speed.as_ptr(),
                out.as_mut_ptr(),
                out.len(),
                &mut bad,
            )
        };
        match st {
            v1::CallStatus::Ok => Ok(()),
            v1::CallStatus::Panic => Err(self.panic_error()),
            v1::CallStatus::NonFinite => {
                let i = bad.min(out.len().saturating_sub(1));
                Err(self.non_finite(out[i], speed[i]))
            }
        }
    }
}
