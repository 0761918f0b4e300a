//! Buffer writes and uniform-buffer bindings: they may change a projection held in a uniform
//! block (see `multiview::ubo`), so each one invalidates the cached read.

use crate::gl::types::*;
use crate::multiview::ubo::buffers_changed;
use core::ffi::c_void;

pub(crate) fn glBufferData(
    real: impl Fn(GLenum, GLsizeiptr, *const c_void, GLenum),
    t: GLenum,
    n: GLsizeiptr,
    d: *const c_void,
    u: GLenum,
) {
    real(t, n, d, u);
    buffers_changed();
}

pub(crate) fn glBufferSubData(
    real: impl Fn(GLenum, GLintptr, GLsizeiptr, *const c_void),
    t: GLenum,
    o: GLintptr,
    n: GLsizeiptr,
    d: *const c_void,
) {
    real(t, o, n, d);
    buffers_changed();
}

pub(crate) fn glNamedBufferSubData(
    real: impl Fn(GLuint, GLintptr, GLsizeiptr, *const c_void),
    b: GLuint,
    o: GLintptr,
    n: GLsizeiptr,
    d: *const c_void,
) {
    real(b, o, n, d);
    buffers_changed();
}

pub(crate) fn glUnmapBuffer(real: impl Fn(GLenum) -> GLboolean, t: GLenum) -> GLboolean {
    let r = real(t);
    buffers_changed();
    r
}

pub(crate) fn glUnmapNamedBuffer(real: impl Fn(GLuint) -> GLboolean, b: GLuint) -> GLboolean {
    let r = real(b);
    buffers_changed();
    r
}

pub(crate) fn glCopyBufferSubData(
    real: impl Fn(GLenum, GLenum, GLintptr, GLintptr, GLsizeiptr),
    r: GLenum,
    w: GLenum,
    ro: GLintptr,
    wo: GLintptr,
    n: GLsizeiptr,
) {
    real(r, w, ro, wo, n);
    buffers_changed();
}

pub(crate) fn glBindBufferBase(real: impl Fn(GLenum, GLuint, GLuint), t: GLenum, i: GLuint, b: GLuint) {
    real(t, i, b);
    buffers_changed();
}

pub(crate) fn glBindBufferRange(
    real: impl Fn(GLenum, GLuint, GLuint, GLintptr, GLsizeiptr),
    t: GLenum,
    i: GLuint,
    b: GLuint,
    o: GLintptr,
    n: GLsizeiptr,
) {
    real(t, i, b, o, n);
    buffers_changed();
}
