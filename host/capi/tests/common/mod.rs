//! What the C-ABI tests share: where the plugins are, and the last error's text.
#![allow(dead_code)]

use dashpot_capi::dashpot_last_error;
use std::ffi::{CStr, CString};

/// The directory of the test executable (`target/<profile>/deps`), where the workspace's plugin
/// libraries are, as a C string for `dashpot_registry_*`.
pub fn deps_dir() -> CString {
    let exe = std::env::current_exe().expect("current_exe");
    let dir = exe.parent().expect("exe dir").to_str().expect("UTF-8 path");
    CString::new(dir).expect("no NUL")
}

/// The calling thread's last error message.
pub fn last_error() -> String {
    // SAFETY: dashpot_last_error returns a valid NUL-terminated string owned by the library.
    unsafe { CStr::from_ptr(dashpot_last_error()) }
        .to_string_lossy()
        .into_owned()
}
