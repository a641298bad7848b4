//! Status codes and the thread-local last-error message.

use dashpot_sdk::{ErrorKind, LawError};
use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What a call returned. `DASHPOT_OK` is 0; every other value is an error whose message is
/// available from [`dashpot_last_error`] on the same thread.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DashpotStatus {
    /// Success; the outputs were written.
    DASHPOT_OK = 0,
    /// A required pointer argument was null (the message names it).
    DASHPOT_ERR_NULL_POINTER = 1,
    /// Array lengths that must agree do not (the message gives them).
    DASHPOT_ERR_BAD_LENGTH = 2,
    /// Another malformed argument: a string that is not UTF-8, an index out of range, an
    /// unknown coefficient or end-criterion value.
    DASHPOT_ERR_INVALID_ARGUMENT = 3,
    /// No law of that name (or a law of the other kind); the message lists the laws.
    DASHPOT_ERR_UNKNOWN_LAW = 4,
    /// A parameter name that is not in the law's schema.
    DASHPOT_ERR_UNKNOWN_PARAMETER = 5,
    /// A parameter value outside its documented range, NaN or infinite.
    DASHPOT_ERR_INVALID_PARAMETER = 6,
    /// A particle or pair property outside its physical range.
    DASHPOT_ERR_INVALID_PAIR = 7,
    /// The law returned NaN or an infinite value (the message names the inputs).
    DASHPOT_ERR_NON_FINITE = 8,
    /// The law (or this library) panicked; the panic was caught and the handle stays usable.
    DASHPOT_ERR_PANIC = 9,
    /// The law does not offer this operation (for example no closed-form calibration).
    DASHPOT_ERR_UNSUPPORTED = 10,
    /// A plugin could not be loaded or is incompatible with this library.
    DASHPOT_ERR_LOAD = 11,
    /// Anything else; the message says what.
    DASHPOT_ERR_OTHER = 12,
}

use DashpotStatus::*;

/// An error on its way to C: a status and a message.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{message}")]
pub struct CError {
    /// The status returned to the caller.
    pub status: DashpotStatus,
    /// The message stored for `dashpot_last_error`.
    pub message: String,
}

impl CError {
    /// An error of `status` with `message`.
    pub fn new(status: DashpotStatus, message: impl Into<String>) -> CError {
        CError {
            status,
            message: message.into(),
        }
    }
}

impl From<LawError> for CError {
    fn from(e: LawError) -> CError {
        let status = match e.kind {
            ErrorKind::UnknownLaw => DASHPOT_ERR_UNKNOWN_LAW,
            ErrorKind::UnknownParameter => DASHPOT_ERR_UNKNOWN_PARAMETER,
            ErrorKind::InvalidParameter => DASHPOT_ERR_INVALID_PARAMETER,
            ErrorKind::InvalidPair => DASHPOT_ERR_INVALID_PAIR,
            ErrorKind::NonFinite => DASHPOT_ERR_NON_FINITE,
            ErrorKind::Panic => DASHPOT_ERR_PANIC,
            ErrorKind::Unsupported => DASHPOT_ERR_UNSUPPORTED,
            ErrorKind::Load => DASHPOT_ERR_LOAD,
            ErrorKind::Other => DASHPOT_ERR_OTHER,
        };
        CError::new(status, e.message)
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn store(message: &str) {
    // An interior NUL would truncate the C string: replace it rather than lose the message.
    let c = CString::new(message.replace('\0', "\u{FFFD}")).unwrap_or_default();
    LAST_ERROR.with(|s| *s.borrow_mut() = c);
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_string()
    }
}

/// Runs the body of an entry point: a panic becomes `DASHPOT_ERR_PANIC`, an error its status;
/// both leave their message in the thread's last error.
#[inline(always)]
pub(crate) fn guard(f: impl FnOnce() -> Result<(), CError>) -> DashpotStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => DASHPOT_OK,
        Ok(Err(e)) => failed(e),
        Err(p) => panicked(p),
    }
}

/// A refused call: its message stored, its status returned.
#[cold]
#[inline(never)]
fn failed(e: CError) -> DashpotStatus {
    store(&e.message);
    e.status
}

/// A caught panic: reported as `DASHPOT_ERR_PANIC`.
#[cold]
#[inline(never)]
fn panicked(p: Box<dyn std::any::Any + Send>) -> DashpotStatus {
    store(&format!(
        "internal error: the dashpot C library panicked: {}",
        panic_text(&*p)
    ));
    DASHPOT_ERR_PANIC
}

/// The body of an entry point that writes one value: each pointer argument checked in the
/// order given (`arg`: a handle or struct, `string`: a C string; a null one is named by its
/// parameter's name) and bound under that name, then the output pointer, then
/// `*$out = $value` (a `?` in `$value` returns its error).
macro_rules! output {
    ($($check:ident $p:ident),* => $out:ident = $value:expr) => {
        $crate::error::guard(|| {
            $(let $p = unsafe { $crate::error::$check($p, stringify!($p)) }?;)*
            let o = unsafe { $crate::error::out($out, stringify!($out)) }?;
            *o = $value;
            Ok(())
        })
    };
}
pub(crate) use output;

/// `what`'s arrays (`(name, length)`, the output last) have one length, or
/// `DASHPOT_ERR_BAD_LENGTH` giving them all.
pub(crate) fn same_lengths(what: &str, arrays: &[(&str, usize)]) -> Result<(), CError> {
    if arrays.windows(2).all(|w| w[0].1 == w[1].1) {
        return Ok(());
    }
    let and = |items: Vec<String>| match items.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    };
    Err(CError::new(
        DASHPOT_ERR_BAD_LENGTH,
        format!(
            "{what}: {} must have the same length, got {}",
            and(arrays.iter().map(|a| a.0.to_string()).collect()),
            and(arrays.iter().map(|a| a.1.to_string()).collect())
        ),
    ))
}

/// `p` as a reference, or `DASHPOT_ERR_NULL_POINTER` naming `what`.
///
/// # Safety
/// A non-null `p` must point to a valid `T` for `'a`.
#[inline(always)]
pub(crate) unsafe fn arg<'a, T>(p: *const T, what: &str) -> Result<&'a T, CError> {
    // SAFETY: checked non-null; validity is the caller's contract.
    unsafe { p.as_ref() }.ok_or_else(|| null(what))
}

/// `p` as a mutable reference, or `DASHPOT_ERR_NULL_POINTER` naming `what`.
///
/// # Safety
/// A non-null `p` must point to a valid, writable `T` for `'a`.
#[inline(always)]
pub(crate) unsafe fn out<'a, T>(p: *mut T, what: &str) -> Result<&'a mut T, CError> {
    // SAFETY: checked non-null; validity is the caller's contract.
    unsafe { p.as_mut() }.ok_or_else(|| null(what))
}

#[cold]
#[inline(never)]
pub(crate) fn null(what: &str) -> CError {
    CError::new(DASHPOT_ERR_NULL_POINTER, format!("{what} is a null pointer"))
}

/// A NUL-terminated UTF-8 string argument.
///
/// # Safety
/// A non-null `p` must point to a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn string<'a>(p: *const c_char, what: &str) -> Result<&'a str, CError> {
    if p.is_null() {
        return Err(null(what));
    }
    // SAFETY: non-null and NUL-terminated by contract.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| CError::new(DASHPOT_ERR_INVALID_ARGUMENT, format!("{what} is not valid UTF-8")))
}

/// Refuses an array of `n` values of `T` whose size in bytes exceeds `isize::MAX` (no array in
/// memory is that large: such a length is a caller's error, e.g. a negative count cast to
/// `size_t`, and making a slice of it is undefined behaviour).
#[inline(always)]
fn fits<T>(n: usize, what: &str) -> Result<(), CError> {
    let most = isize::MAX as usize / std::mem::size_of::<T>().max(1);
    if n <= most {
        return Ok(());
    }
    Err(too_long(n, most, std::mem::size_of::<T>(), what))
}

#[cold]
#[inline(never)]
fn too_long(n: usize, most: usize, size: usize, what: &str) -> CError {
    CError::new(
        DASHPOT_ERR_BAD_LENGTH,
        format!("{what}: length {n} is out of range: an array of {size} bytes each holds at most {most} values (isize::MAX bytes)"),
    )
}

/// A null array whose length `n` is not 0.
#[cold]
#[inline(never)]
fn null_array(n: usize, what: &str) -> CError {
    CError::new(
        DASHPOT_ERR_NULL_POINTER,
        format!("{what} is a null pointer but its length is {n}"),
    )
}

/// An input array of `n` values; null is allowed only when `n == 0`.
///
/// # Safety
/// A non-null `p` must point to `n` valid values for `'a`.
#[inline(always)]
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], CError> {
    if n == 0 {
        return Ok(&[]);
    }
    fits::<T>(n, what)?;
    if p.is_null() {
        return Err(null_array(n, what));
    }
    // SAFETY: non-null, n elements by contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// An output array of `n` values; null is allowed only when `n == 0`.
///
/// # Safety
/// A non-null `p` must point to `n` writable values for `'a`, not aliasing other arguments.
#[inline(always)]
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], CError> {
    if n == 0 {
        return Ok(&mut []);
    }
    fits::<T>(n, what)?;
    if p.is_null() {
        return Err(null_array(n, what));
    }
    // SAFETY: non-null, n elements by contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// The message of the last failed call on the calling thread (NUL-terminated UTF-8, empty if
/// no call has failed on this thread yet). A successful call does not clear it.
///
/// Ownership: the string belongs to the library; it stays valid until the next failing call
/// on the same thread. Copy it to keep it. Never free it. Thread-safe: each thread has its own.
#[no_mangle]
pub extern "C" fn dashpot_last_error() -> *const c_char {
    catch_unwind(|| LAST_ERROR.with(|s| s.borrow().as_ptr())).unwrap_or(c"".as_ptr())
}

/// The symbolic name of a status value, e.g. `"DASHPOT_ERR_NULL_POINTER"` (static string,
/// never free it; `"DASHPOT_UNKNOWN_STATUS"` for a value that is not a status). Cannot fail;
/// thread-safe.
#[no_mangle]
pub extern "C" fn dashpot_status_name(status: c_int) -> *const c_char {
    let s: &CStr = match status {
        0 => c"DASHPOT_OK",
        1 => c"DASHPOT_ERR_NULL_POINTER",
        2 => c"DASHPOT_ERR_BAD_LENGTH",
        3 => c"DASHPOT_ERR_INVALID_ARGUMENT",
        4 => c"DASHPOT_ERR_UNKNOWN_LAW",
        5 => c"DASHPOT_ERR_UNKNOWN_PARAMETER",
        6 => c"DASHPOT_ERR_INVALID_PARAMETER",
        7 => c"DASHPOT_ERR_INVALID_PAIR",
        8 => c"DASHPOT_ERR_NON_FINITE",
        9 => c"DASHPOT_ERR_PANIC",
        10 => c"DASHPOT_ERR_UNSUPPORTED",
        11 => c"DASHPOT_ERR_LOAD",
        12 => c"DASHPOT_ERR_OTHER",
        _ => c"DASHPOT_UNKNOWN_STATUS",
    };
    s.as_ptr()
}
