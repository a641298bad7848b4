//! # dashpot C ABI
//!
//! Every dashpot law (built-in or third-party plugin) callable from C, C++ and Fortran through
//! `include/dashpot.h`, which cbindgen generates from this crate (one Rust module per section of
//! the header). The header is committed; `tests/header.rs` fails when it is stale
//! (`DASHPOT_BLESS_HEADER=1 cargo test -p dashpot-capi --test header` rewrites it).
//!
//! ## Conventions shared by every function
//! - Every function returns a [`DashpotStatus`] (except the few that cannot fail, which say so).
//!   On failure a message is stored for the calling thread: [`dashpot_last_error`].
//! - Outputs go through pointer arguments and are written only on success.
//! - A null pointer where an object is required gives `DASHPOT_ERR_NULL_POINTER`; array
//!   pointers may be null only when their length is 0. Lengths that disagree give
//!   `DASHPOT_ERR_BAD_LENGTH`. Nothing is ever read through a pointer that failed a check.
//! - Every entry point runs inside `catch_unwind`: no Rust panic crosses into C. A law that
//!   panics inside its plugin gives `DASHPOT_ERR_PANIC`, and the law stays usable.
//! - Handles are opaque. Each `*_new`/`*_open`/`*_bind` has a matching `*_free`, which accepts
//!   null. Handles are independent: a law or a bound law may outlive the registry that made it
//!   (plugin libraries are never unloaded).
//! - Every kind of law (contact, tangential, restitution, rolling, twisting, heat) has the same
//!   `new`/`free`/binding functions, generated from one shape per step (`handle.rs`, listed per
//!   kind in `kinds.rs`) and declared in the header by the `DASHPOT_LAW_FUNCTIONS`,
//!   `DASHPOT_MODEL_FUNCTIONS` and `DASHPOT_PAIR_FUNCTIONS` macros. The batch calls of the
//!   models, with and without sdk 0.3's energy outputs, come from one parameter list per shape
//!   (`contact_model.rs`, `energy.rs`), declared by `DASHPOT_CONTACT_BATCH` and
//!   `DASHPOT_MOTION_BATCH`.
//! - Thread safety: every handle may be used from several threads at once (all calls on them
//!   are read-only), except that a `*_free` must not race with any other use of that handle.
//!
//! ## What breaks the ABI
//! [`DASHPOT_ABI_VERSION`] is bumped when a function is removed or renamed, when a parameter or
//! return type changes, when a `#[repr(C)]` struct changes layout, or when an existing status
//! code or enum value changes meaning. Adding a function, or a status code at the end, does not.
//! A program built against header version N must check `dashpot_abi_version() == N`.

#![deny(unsafe_op_in_unsafe_fn)]

pub mod calibrate;
pub mod contact;
pub mod contact_model;
pub mod energy;
pub mod error;
mod handle;
pub mod heat;
pub mod kinds;
pub mod materials;
pub mod pair;
pub mod registry;
pub mod restitution;
pub mod version;

pub use calibrate::*;
pub use contact::*;
pub use contact_model::*;
pub use energy::*;
pub use error::*;
pub use heat::*;
pub use kinds::*;
pub use materials::*;
pub use pair::*;
pub use registry::*;
pub use restitution::*;
pub use version::*;

// The thread-safety promises of the header, checked by the compiler: every handle may be shared
// between threads.
const _: () = {
    const fn shareable<T: Send + Sync>() {}
    shareable::<DashpotRegistry>();
    shareable::<DashpotContactLaw>();
    shareable::<DashpotBoundContact>();
    shareable::<DashpotContactModel>();
    shareable::<DashpotTangentialLaw>();
    shareable::<DashpotTangentialModel>();
    shareable::<DashpotRestitutionLaw>();
    shareable::<DashpotBoundRestitution>();
    shareable::<DashpotHeatModel>();
};
