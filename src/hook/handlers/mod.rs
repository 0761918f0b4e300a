//! Hook bodies: a few lines each, handing over to `state` (contexts, app state),
//! `multiview` (replay), and `super::frame` (frame boundaries).
//! Each receives `real`, the real entry point, and must call it exactly once unless it
//! deliberately replaces the call.
//!
//! Handlers are the FFI boundary. Only the generated shims call them (hence `pub(crate)`),
//! with the app's arguments, which the entry point's specification requires to be valid: an
//! array of `n` names, a NUL-terminated name, room for a query's answer. A handler that reads
//! or writes through one of them first makes a safe view of it ([`app_slice`], [`app_out`],
//! [`proc_name`]) under a SAFETY comment citing that requirement; everything it hands over to
//! takes slices and `&CStr`, never raw pointers.

use crate::gl::types::GLsizei;
use crate::state::{Binding, Platform};
use core::ffi::{CStr, c_char, c_void};

#[allow(non_snake_case)]
pub(crate) mod egl;
// GL's own names and parameter lists.
#[allow(non_snake_case, clippy::too_many_arguments)]
pub(crate) mod gl;
#[allow(non_snake_case)]
pub(crate) mod glx;
#[allow(non_snake_case)]
pub(crate) mod osmesa;

/// After a make-current that succeeded, on any platform: the context is tracked with what it
/// is bound to, then the layer sets it up, which reads that binding.
fn made_current(platform: Platform, ctx: usize, binding: Binding) {
    crate::state::make_current(platform, ctx, binding);
    crate::hook::layer::on_make_current();
}

/// A window-system make-current (GLX, EGL) that succeeded: bound to a display and its
/// surfaces, whose size the platform does not say here.
fn surfaces_made_current(platform: Platform, ctx: usize, display: usize, draw: usize, read: usize) {
    let binding = Binding {
        display,
        draw,
        read,
        size: None,
    };
    made_current(platform, ctx, binding);
}

/// The `n` values an app passed at `p`; empty when `p` is null or `n` is not positive.
///
/// # Safety
/// `p` is null or points to `n` initialised values that nothing writes while the slice lives.
unsafe fn app_slice<'a, T>(p: *const T, n: GLsizei) -> &'a [T] {
    match usize::try_from(n) {
        Ok(n) if n > 0 && !p.is_null() => {
            // SAFETY: non-null and `n` values long, as the caller guarantees.
            unsafe { std::slice::from_raw_parts(p, n) }
        }
        _ => &[],
    }
}

/// The `n` values an app's buffer has room for; empty when `p` is null or `n` is not positive.
///
/// # Safety
/// `p` is null or valid for writing `n` values, and not accessed otherwise while the slice
/// lives (make it after any real call that uses it).
unsafe fn app_buffer<'a, T>(p: *mut T, n: GLsizei) -> &'a mut [T] {
    match usize::try_from(n) {
        Ok(n) if n > 0 && !p.is_null() => {
            // SAFETY: non-null, `n` values long and unaliased, as the caller guarantees.
            unsafe { std::slice::from_raw_parts_mut(p, n) }
        }
        _ => &mut [],
    }
}

/// Where the app wants a query's single answer; `None` for null.
///
/// # Safety
/// `p` is null or valid for writing one `T`, and not accessed otherwise while the reference
/// lives (make it after the real call that fills it).
unsafe fn app_out<'a, T>(p: *mut T) -> Option<&'a mut T> {
    // SAFETY: null or writable and unaliased, as the caller guarantees.
    unsafe { p.as_mut() }
}

/// The name an app passed to a `*GetProcAddress`; `None` for null.
///
/// # Safety
/// `name` is null or a NUL-terminated string that outlives the reference.
unsafe fn proc_name<'a>(name: *const c_char) -> Option<&'a CStr> {
    // SAFETY: non-null and NUL-terminated, as the caller guarantees.
    (!name.is_null()).then(|| unsafe { CStr::from_ptr(name) })
}

/// What a `*GetProcAddress` hook returns: our hook when we wrap `name` *and* the real loader
/// found it (libglvnd answers non-NULL for any name, so existence is whatever the real loader
/// says: we never turn a NULL into a hook), otherwise the real answer untouched.
fn proc_result(name: Option<&CStr>, real: *const c_void) -> *const c_void {
    if real.is_null() {
        return real;
    }
    let Some(id) = name.and_then(crate::real::find) else {
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
