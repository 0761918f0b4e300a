//! GLX: context life cycle, current bindings and the swap frame boundary.

use crate::gl::glx::types::{
    __GLXextFuncPtr, Bool, Display, GLXContext, GLXDrawable, GLXFBConfig, GLubyte, XVisualInfo,
};
use crate::state::Platform;
use core::ffi::c_int;

fn created(ctx: GLXContext, dpy: *mut Display, share: GLXContext) -> GLXContext {
    if !ctx.is_null() {
        crate::state::context_created(Platform::Glx, ctx as usize, dpy as usize, share as usize);
    }
    ctx
}

pub(crate) fn glXCreateContext(
    real: impl Fn(*mut Display, *mut XVisualInfo, GLXContext, Bool) -> GLXContext,
    dpy: *mut Display,
    vis: *mut XVisualInfo,
    share: GLXContext,
    direct: Bool,
) -> GLXContext {
    created(real(dpy, vis, share, direct), dpy, share)
}

pub(crate) fn glXCreateNewContext(
    real: impl Fn(*mut Display, GLXFBConfig, c_int, GLXContext, Bool) -> GLXContext,
    dpy: *mut Display,
    config: GLXFBConfig,
    render_type: c_int,
    share: GLXContext,
    direct: Bool,
) -> GLXContext {
    created(real(dpy, config, render_type, share, direct), dpy, share)
}

pub(crate) fn glXCreateContextAttribsARB(
    real: impl Fn(*mut Display, GLXFBConfig, GLXContext, Bool, *const c_int) -> GLXContext,
    dpy: *mut Display,
    config: GLXFBConfig,
    share: GLXContext,
    direct: Bool,
    attribs: *const c_int,
) -> GLXContext {
    created(real(dpy, config, share, direct, attribs), dpy, share)
}

fn made_current(ok: Bool, dpy: *mut Display, draw: GLXDrawable, read: GLXDrawable, ctx: GLXContext) -> Bool {
    if ok != 0 {
        super::surfaces_made_current(Platform::Glx, ctx as usize, dpy as usize, draw as usize, read as usize);
    }
    ok
}

pub(crate) fn glXMakeCurrent(
    real: impl Fn(*mut Display, GLXDrawable, GLXContext) -> Bool,
    dpy: *mut Display,
    drawable: GLXDrawable,
    ctx: GLXContext,
) -> Bool {
    made_current(real(dpy, drawable, ctx), dpy, drawable, drawable, ctx)
}

pub(crate) fn glXMakeContextCurrent(
    real: impl Fn(*mut Display, GLXDrawable, GLXDrawable, GLXContext) -> Bool,
    dpy: *mut Display,
    draw: GLXDrawable,
    read: GLXDrawable,
    ctx: GLXContext,
) -> Bool {
    made_current(real(dpy, draw, read, ctx), dpy, draw, read, ctx)
}

pub(crate) fn glXDestroyContext(real: impl Fn(*mut Display, GLXContext), dpy: *mut Display, ctx: GLXContext) {
    real(dpy, ctx);
    crate::state::context_destroyed(Platform::Glx, ctx as usize);
}

pub(crate) fn glXSwapBuffers(real: impl Fn(*mut Display, GLXDrawable), dpy: *mut Display, drawable: GLXDrawable) {
    crate::hook::frame::boundary(drawable as usize, || real(dpy, drawable));
}

/// (Also the handler of `glXGetProcAddress`, an alias in the policy table.)
pub(crate) fn glXGetProcAddressARB(
    real: impl Fn(*const GLubyte) -> __GLXextFuncPtr,
    name: *const GLubyte,
) -> __GLXextFuncPtr {
    // SAFETY: the GLX spec requires `procName` to be a NUL-terminated string.
    let proc = unsafe { super::proc_name(name.cast()) };
    super::proc_result(proc, real(name).cast()) as __GLXextFuncPtr
}
