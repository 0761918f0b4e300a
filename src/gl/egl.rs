//! EGL types from the Khronos registry, with the platform aliases the template leaves to us.

#![allow(non_camel_case_types, dead_code)]

use std::os::raw::c_void;

pub type khronos_utime_nanoseconds_t = u64;
pub type khronos_uint64_t = u64;
pub type khronos_ssize_t = isize;
pub type EGLNativeDisplayType = *mut c_void;
pub type EGLNativePixmapType = *mut c_void;
pub type EGLNativeWindowType = *mut c_void;
pub type EGLint = i32;
pub type NativeDisplayType = *mut c_void;
pub type NativePixmapType = *mut c_void;
pub type NativeWindowType = *mut c_void;

#[allow(clippy::all, non_upper_case_globals, non_snake_case, non_camel_case_types, dead_code)]
#[allow(unsafe_op_in_unsafe_fn, unused_imports, missing_docs)]
#[allow(clippy::undocumented_unsafe_blocks)] // generated
mod bindings {
    pub use super::{
        EGLNativeDisplayType, EGLNativePixmapType, EGLNativeWindowType, EGLint, NativeDisplayType, NativePixmapType,
        NativeWindowType, khronos_ssize_t, khronos_uint64_t, khronos_utime_nanoseconds_t,
    };
    include!(concat!(env!("OUT_DIR"), "/egl_bindings.rs"));
}
pub use bindings::types;

pub const EGL_WIDTH: EGLint = 0x3057;
pub const EGL_HEIGHT: EGLint = 0x3056;
pub const EGL_RENDER_BUFFER: EGLint = 0x3086;
