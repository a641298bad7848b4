//! The panic guard every function a plugin exports runs inside: a panic becomes an
//! [`ErrorKind::Panic`] error (or, on the hot path, a status whose message the host fetches with
//! `take_panic`), never an unwind into the host.

use super::fault::{BatchFault, BatchStatus};
use crate::error::{ErrorKind, FfiError, LawError};
use abi_stable::std_types::{RResult, RString};
use std::cell::RefCell;
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

thread_local! {
    static LAST_PANIC: RefCell<String> = const { RefCell::new(String::new()) };
    static PANIC_LOCATION: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Called once when a plugin library is loaded (from its root-module constructor, so only in
/// the cdylib, whose standard library is its own): panics inside the plugin no longer print
/// to stderr; their message and location travel to the host as an error instead.
pub fn install_quiet_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let loc = info
            .location()
            .map(|l| format!("{}:{}", l.file(), l.line()))
            .unwrap_or_default();
        PANIC_LOCATION.with(|s| *s.borrow_mut() = loc);
    }));
}

fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    let msg = if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_string()
    };
    match PANIC_LOCATION.with(|s| std::mem::take(&mut *s.borrow_mut())) {
        loc if loc.is_empty() => msg,
        loc => format!("{msg} (at {loc})"),
    }
}

/// Runs `f`, turning a panic into an `ErrorKind::Panic` error.
pub fn guard<T>(what: &str, f: impl FnOnce() -> Result<T, LawError>) -> RResult<T, FfiError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(v)) => RResult::ROk(v),
        Ok(Err(e)) => RResult::RErr(e.into()),
        Err(p) => RResult::RErr(FfiError {
            kind: ErrorKind::Panic,
            message: format!("{what} panicked: {}", panic_message(p)).into(),
        }),
    }
}

/// Runs a hot-path call; on a panic stashes its message for `take_panic` and returns `None`.
#[inline(always)]
pub(crate) fn hot<T>(f: impl FnOnce() -> T) -> Option<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(v) => Some(v),
        Err(p) => {
            let msg = panic_message(p);
            LAST_PANIC.with(|s| *s.borrow_mut() = msg);
            None
        }
    }
}

/// The message of the last panic caught on this thread (and forgets it).
pub extern "C" fn take_panic() -> RString {
    LAST_PANIC.with(|s| std::mem::take(&mut *s.borrow_mut())).into()
}

/// Frees the `T` at `obj` (a plugin object's vtable `drop`).
pub(crate) unsafe extern "C" fn drop_box<T>(obj: *mut c_void) {
    // A panic in a destructor is swallowed here rather than unwinding into the host.
    let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(obj as *mut T) })));
}

/// The status of a checked batch: `res` is `None` after a panic, else the first bad contact and
/// array, if any (described in `*fault`).
#[inline(always)]
pub(crate) fn finish(res: Option<Result<(), (usize, u8)>>, fault: &mut BatchFault) -> BatchStatus {
    match res {
        None => BatchStatus::Panic,
        Some(Ok(())) => BatchStatus::Ok,
        Some(Err((index, field))) => {
            *fault = BatchFault { index, field };
            if BatchFault::is_output(field) {
                BatchStatus::NonFiniteOutput
            } else {
                BatchStatus::BadInput
            }
        }
    }
}
