//! Objects owned by a plugin and their functions: the macros that declare a vtable and its
//! handle, and [`Owned`], which frees such an object through its vtable.

use crate::error::FfiError;
use abi_stable::std_types::{RResult, RVec};

/// Declares an object owned by a plugin: an opaque pointer and its functions (a static vtable).
/// `Send + Sync`: the objects behind them are (the law traits require it), and the vtables are
/// immutable statics.
macro_rules! ffi_handle {
    ($(#[$doc:meta])* $name:ident $(<$g:ident>)?, $vt:ty) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(abi_stable::StableAbi)]
        pub struct $name$(<$g: 'static>)? {
            /// Opaque pointer to the object.
            pub obj: *mut std::ffi::c_void,
            /// Its functions.
            pub vtable: &'static $vt,
        }

        // SAFETY: see above.
        unsafe impl$(<$g>)? Send for $name$(<$g>)? {}
        // SAFETY: see above.
        unsafe impl$(<$g>)? Sync for $name$(<$g>)? {}
    };
}
pub(crate) use ffi_handle;

/// Declares the functions of a plugin object and its handle ([`ffi_handle!`]-style): a
/// configured law (`law`: its entries, then `drop`) or a bound one (`model`: its entries, then
/// `take_panic` and `drop`; `model_with_coefficients`: its entries, `coefficients`,
/// `take_panic` and `drop`). The entries are written out (abi_stable reads function pointer types
/// from the tokens); the common ones are appended in this order.
macro_rules! ffi_object {
    (law $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::object::ffi_object!(@vtable $(#[$doc])* $vt $(<$g>)? { $($body)* });
        $crate::abi::object::ffi_handle!($(#[$hdoc])* $handle $(<$g>)?, $vt $(<$g>)?);
        $crate::abi::object::ffi_object!(@free $handle $(<$g>)?);
    };
    (model $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::object::ffi_object!(@vtable $(#[$doc])* $vt $(<$g>)? {
            $($body)*
            /// The message of the last panic caught on this thread by this plugin (empty if none).
            pub take_panic: extern "C" fn() -> abi_stable::std_types::RString,
        });
        $crate::abi::object::ffi_handle!($(#[$hdoc])* $handle $(<$g>)?, $vt $(<$g>)?);
        $crate::abi::object::ffi_object!(@free $handle $(<$g>)?);
    };
    (model_with_coefficients $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* } $(#[$hdoc:meta])* $handle:ident) => {
        $crate::abi::object::ffi_object!(model $(#[$doc])* $vt $(<$g>)? {
            $($body)*
            /// Derived constants for a contact of effective `mass` (kg) and `radius` (m).
            pub coefficients: unsafe extern "C" fn(
                obj: *const std::ffi::c_void,
                mass: f64,
                radius: f64,
            ) -> abi_stable::std_types::RResult<
                abi_stable::std_types::RVec<$crate::abi::ffi::Coefficient>,
                $crate::error::FfiError,
            >,
        } $(#[$hdoc])* $handle);
    };
    (@vtable $(#[$doc:meta])* $vt:ident $(<$g:ident>)? { $($body:tt)* }) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(abi_stable::StableAbi)]
        pub struct $vt$(<$g: 'static>)? {
            $($body)*
            /// Frees `obj`.
            pub drop: unsafe extern "C" fn(obj: *mut std::ffi::c_void),
        }
    };
    (@free $handle:ident $(<$g:ident>)?) => {
        impl$(<$g: 'static>)? $crate::abi::object::FfiObject for $handle$(<$g>)? {
            unsafe fn free(&self) {
                // SAFETY: as the caller promises.
                unsafe { (self.vtable.drop)(self.obj) }
            }
        }
    };
}
pub(crate) use ffi_object;

/// A plugin object (every [`ffi_object!`] handle), which its vtable's `drop` frees.
pub(crate) trait FfiObject {
    /// Frees the object.
    ///
    /// # Safety
    /// Once, and the object is not used after.
    unsafe fn free(&self);
}

/// A plugin object this side owns: freed through its vtable when dropped.
pub(crate) struct Owned<H: FfiObject>(pub(crate) H);

impl<H: FfiObject> Owned<H> {
    /// The object a plugin's call returned, now owned here, or the call's error.
    pub(crate) fn take(r: RResult<H, FfiError>) -> Result<Owned<H>, crate::LawError> {
        r.into_result().map(Owned).map_err(Into::into)
    }
}

impl<H: FfiObject> std::ops::Deref for Owned<H> {
    type Target = H;
    fn deref(&self) -> &H {
        &self.0
    }
}

impl<H: FfiObject> Drop for Owned<H> {
    fn drop(&mut self) {
        // SAFETY: the object is this side's, freed here once, and unreachable after.
        unsafe { self.0.free() }
    }
}

/// A plugin's coefficients as plain values.
pub(crate) fn coefficients(
    r: RResult<RVec<super::ffi::Coefficient>, FfiError>,
) -> Result<Vec<crate::Coefficient>, crate::LawError> {
    Ok(super::ffi::to_plain(r.into_result()?))
}
