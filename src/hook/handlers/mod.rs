//! Hook bodies: a few lines each, handing over to `state` (contexts, app state),
//! `multiview` (replay), and `super::frame` (frame boundaries).
//! Each receives `real`, the real entry point, and must call it exactly once unless it
//! deliberately replaces the call.

use core::ffi::{c_char, c_void};

#[allow(non_snake_case)]
pub mod egl;
#[allow(non_snake_case)]
pub mod gl;
#[allow(non_snake_case)]
pub mod glx;
#[allow(non_snake_case)]
pub mod osmesa;

/// What a `*GetProcAddress` hook returns: our hook when we wrap `name` *and* the real loader
/// found it (libglvnd answers non-NULL for any name, so existence is whatever the real loader
/// says: we never turn a NULL into a hook), otherwise the real answer untouched.
pub fn proc_result(name: *const c_char, real: *const c_void) -> *const c_void {
    if real.is_null() {
        return real;
    }
    if name.is_null() {
        return real;
    }
    // SAFETY: callers of GetProcAddress pass a NUL-terminated name.
    let Some(id) = crate::real::find(unsafe { core::ffi::CStr::from_ptr(name) }) else {
        return real;
    };
    if super::HOOKS[id].api != super::HookApi::Gl {
        crate::real::remember(id, real);
    }
    crate::log::debug(format_args!(
        "GetProcAddress({}) -> hook",
        super::HOOKS[id].name.to_string_lossy()
    ));
    super::ADDRS[id].0
}
