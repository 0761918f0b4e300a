//! OSMesa: contexts render into app memory and never swap; see `gl::glFinish` for the frame
//! boundary.

use crate::gl::types::{GLboolean, GLenum, GLint, GLsizei};
use crate::state::{Binding, Platform};
use core::ffi::{c_char, c_int, c_void};

fn created(ctx: *mut c_void, share: *mut c_void) -> *mut c_void {
    if !ctx.is_null() {
        crate::state::context_created(Platform::Osmesa, ctx as usize, 0, share as usize);
    }
    ctx
}

pub(crate) fn OSMesaCreateContext(
    real: impl Fn(GLenum, *mut c_void) -> *mut c_void,
    format: GLenum,
    share: *mut c_void,
) -> *mut c_void {
    created(real(format, share), share)
}

pub(crate) fn OSMesaCreateContextExt(
    real: impl Fn(GLenum, GLint, GLint, GLint, *mut c_void) -> *mut c_void,
    format: GLenum,
    depth: GLint,
    stencil: GLint,
    accum: GLint,
    share: *mut c_void,
) -> *mut c_void {
    created(real(format, depth, stencil, accum, share), share)
}

pub(crate) fn OSMesaCreateContextAttribs(
    real: impl Fn(*const c_int, *mut c_void) -> *mut c_void,
    attribs: *const c_int,
    share: *mut c_void,
) -> *mut c_void {
    created(real(attribs, share), share)
}

pub(crate) fn OSMesaMakeCurrent(
    real: impl Fn(*mut c_void, *mut c_void, GLenum, GLsizei, GLsizei) -> GLboolean,
    ctx: *mut c_void,
    buffer: *mut c_void,
    ty: GLenum,
    width: GLsizei,
    height: GLsizei,
) -> GLboolean {
    let ok = real(ctx, buffer, ty, width, height);
    if ok != 0 {
        let size = Some((width.max(0) as u32, height.max(0) as u32));
        let binding = Binding {
            display: 0,
            draw: buffer as usize,
            read: buffer as usize,
            size,
        };
        super::made_current(Platform::Osmesa, ctx as usize, binding);
    }
    ok
}

pub(crate) fn OSMesaDestroyContext(real: impl Fn(*mut c_void), ctx: *mut c_void) {
    real(ctx);
    crate::state::context_destroyed(Platform::Osmesa, ctx as usize);
}

pub(crate) fn OSMesaGetProcAddress(
    real: impl Fn(*const c_char) -> *const c_void,
    name: *const c_char,
) -> *const c_void {
    // SAFETY: OSMesa requires `funcName` to be a NUL-terminated string.
    let proc = unsafe { super::proc_name(name) };
    super::proc_result(proc, real(name))
}
