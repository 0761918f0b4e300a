//! Buffer writes and uniform-buffer bindings: they may change a projection held in a uniform
//! block (see `multiview::ubo`, which decides whether a write can reach one).

use crate::gl::types::*;
use crate::multiview::replay::ubo;
use core::ffi::c_void;

/// A write to the buffer bound to `target`, in the current context.
fn wrote_target(target: GLenum) {
    if crate::config::settings().multiview() {
        crate::state::with_current(|cur| {
            cur.and_then(|c| c.ctx.gl())
                .map(|(gl, _)| ubo::wrote_target(gl, target))
        });
    }
}

pub(crate) fn glBufferData(
    real: impl Fn(GLenum, GLsizeiptr, *const c_void, GLenum),
    t: GLenum,
    n: GLsizeiptr,
    d: *const c_void,
    u: GLenum,
) {
    real(t, n, d, u);
    wrote_target(t);
}

pub(crate) fn glBufferSubData(
    real: impl Fn(GLenum, GLintptr, GLsizeiptr, *const c_void),
    t: GLenum,
    o: GLintptr,
    n: GLsizeiptr,
    d: *const c_void,
) {
    real(t, o, n, d);
    wrote_target(t);
}

pub(crate) fn glNamedBufferSubData(
    real: impl Fn(GLuint, GLintptr, GLsizeiptr, *const c_void),
    b: GLuint,
    o: GLintptr,
    n: GLsizeiptr,
    d: *const c_void,
) {
    real(b, o, n, d);
    ubo::wrote_buffer(b);
}

pub(crate) fn glUnmapBuffer(real: impl Fn(GLenum) -> GLboolean, t: GLenum) -> GLboolean {
    let r = real(t);
    wrote_target(t);
    r
}

pub(crate) fn glUnmapNamedBuffer(real: impl Fn(GLuint) -> GLboolean, b: GLuint) -> GLboolean {
    let r = real(b);
    ubo::wrote_buffer(b);
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
    wrote_target(w);
}

pub(crate) fn glBindBufferBase(real: impl Fn(GLenum, GLuint, GLuint), t: GLenum, i: GLuint, b: GLuint) {
    real(t, i, b);
    ubo::bound(t, b);
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
    ubo::bound(t, b);
}
