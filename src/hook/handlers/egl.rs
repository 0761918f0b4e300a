//! EGL: context life cycle, current bindings and the swap frame boundaries.

use crate::gl::egl::types::{
    __eglMustCastToProperFunctionPointerType as EglProc, EGLBoolean, EGLConfig, EGLContext, EGLDisplay, EGLSurface,
    EGLint,
};
use crate::state::Platform;
use core::ffi::c_char;

pub(crate) fn eglCreateContext(
    real: impl Fn(EGLDisplay, EGLConfig, EGLContext, *const EGLint) -> EGLContext,
    dpy: EGLDisplay,
    config: EGLConfig,
    share: EGLContext,
    attribs: *const EGLint,
) -> EGLContext {
    let ctx = real(dpy, config, share, attribs);
    if !ctx.is_null() {
        crate::state::context_created(Platform::Egl, ctx as usize, dpy as usize, share as usize);
    }
    ctx
}

pub(crate) fn eglMakeCurrent(
    real: impl Fn(EGLDisplay, EGLSurface, EGLSurface, EGLContext) -> EGLBoolean,
    dpy: EGLDisplay,
    draw: EGLSurface,
    read: EGLSurface,
    ctx: EGLContext,
) -> EGLBoolean {
    let ok = real(dpy, draw, read, ctx);
    if ok != 0 {
        super::surfaces_made_current(Platform::Egl, ctx as usize, dpy as usize, draw as usize, read as usize);
    }
    ok
}

pub(crate) fn eglDestroyContext(
    real: impl Fn(EGLDisplay, EGLContext) -> EGLBoolean,
    dpy: EGLDisplay,
    ctx: EGLContext,
) -> EGLBoolean {
    let ok = real(dpy, ctx);
    if ok != 0 {
        crate::state::context_destroyed(Platform::Egl, ctx as usize);
    }
    ok
}

pub(crate) fn eglTerminate(real: impl Fn(EGLDisplay) -> EGLBoolean, dpy: EGLDisplay) -> EGLBoolean {
    let ok = real(dpy);
    if ok != 0 {
        crate::state::display_terminated(Platform::Egl, dpy as usize);
    }
    ok
}

pub(crate) fn eglSwapBuffers(
    real: impl Fn(EGLDisplay, EGLSurface) -> EGLBoolean,
    dpy: EGLDisplay,
    surface: EGLSurface,
) -> EGLBoolean {
    let mut ok = 0;
    crate::hook::frame::boundary(surface as usize, || ok = real(dpy, surface));
    ok
}

pub(crate) fn eglSwapBuffersWithDamageKHR(
    real: impl Fn(EGLDisplay, EGLSurface, *mut EGLint, EGLint) -> EGLBoolean,
    dpy: EGLDisplay,
    surface: EGLSurface,
    rects: *mut EGLint,
    n: EGLint,
) -> EGLBoolean {
    let mut ok = 0;
    crate::hook::frame::boundary(surface as usize, || ok = real(dpy, surface, rects, n));
    ok
}

pub(crate) fn eglGetProcAddress(real: impl Fn(*const c_char) -> EglProc, name: *const c_char) -> EglProc {
    // SAFETY: the EGL spec requires `procname` to be a NUL-terminated string.
    let proc = unsafe { super::proc_name(name) };
    super::proc_result(proc, real(name).cast()) as EglProc
}
