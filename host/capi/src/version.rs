//! Version of the C ABI.

use std::ffi::c_char;

/// The ABI version this header describes. A program must check at start-up that
/// `dashpot_abi_version() == DASHPOT_ABI_VERSION`; any other value means the library and the
/// header disagree and no other function may be called. See the crate documentation (and the
/// README) for the rule of what changes bump it.
pub const DASHPOT_ABI_VERSION: u32 = 1;

/// The ABI version of the library actually loaded. Cannot fail; thread-safe.
#[no_mangle]
pub extern "C" fn dashpot_abi_version() -> u32 {
    DASHPOT_ABI_VERSION
}

/// The library's release version, e.g. `"0.1.0"` (static, NUL-terminated; never free it).
/// Cannot fail; thread-safe.
#[no_mangle]
pub extern "C" fn dashpot_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}
