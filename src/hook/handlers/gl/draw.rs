//! Every draw entry point: replayed once per view (see `multiview::replay`).

use crate::gl::types::*;
use core::ffi::c_void;

/// `name(args)` → a handler that replays the real call per view.
macro_rules! per_view_draws {
    ($($name:ident($($arg:ident: $ty:ty),*);)*) => {$(
        pub(crate) fn $name(real: impl Fn($($ty),*), $($arg: $ty),*) {
            super::per_view(|| real($($arg),*))
        }
    )*};
}

per_view_draws! {
    glDrawArrays(mode: GLenum, first: GLint, count: GLsizei);
    glDrawElements(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void);
    glDrawArraysInstanced(mode: GLenum, first: GLint, count: GLsizei, instances: GLsizei);
    glDrawElementsInstanced(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void, instances: GLsizei);
    glDrawRangeElements(mode: GLenum, start: GLuint, end: GLuint, count: GLsizei, ty: GLenum, indices: *const c_void);
    glDrawElementsBaseVertex(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void, base: GLint);
    glDrawRangeElementsBaseVertex(mode: GLenum, start: GLuint, end: GLuint, count: GLsizei, ty: GLenum, indices: *const c_void, base: GLint);
    glDrawElementsInstancedBaseVertex(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void, instances: GLsizei, base: GLint);
    glDrawArraysInstancedBaseInstance(mode: GLenum, first: GLint, count: GLsizei, instances: GLsizei, base_instance: GLuint);
    glDrawElementsInstancedBaseInstance(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void, instances: GLsizei, base_instance: GLuint);
    glDrawElementsInstancedBaseVertexBaseInstance(mode: GLenum, count: GLsizei, ty: GLenum, indices: *const c_void, instances: GLsizei, base: GLint, base_instance: GLuint);
    glMultiDrawArrays(mode: GLenum, first: *const GLint, count: *const GLsizei, draws: GLsizei);
    glMultiDrawElements(mode: GLenum, count: *const GLsizei, ty: GLenum, indices: *const *const c_void, draws: GLsizei);
    glMultiDrawElementsBaseVertex(mode: GLenum, count: *const GLsizei, ty: GLenum, indices: *const *const c_void, draws: GLsizei, base: *const GLint);
    glDrawArraysIndirect(mode: GLenum, indirect: *const c_void);
    glDrawElementsIndirect(mode: GLenum, ty: GLenum, indirect: *const c_void);
    glMultiDrawArraysIndirect(mode: GLenum, indirect: *const c_void, draws: GLsizei, stride: GLsizei);
    glMultiDrawElementsIndirect(mode: GLenum, ty: GLenum, indirect: *const c_void, draws: GLsizei, stride: GLsizei);
    glCallList(list: GLuint);
    glCallLists(n: GLsizei, ty: GLenum, lists: *const c_void);
    glRectf(x1: GLfloat, y1: GLfloat, x2: GLfloat, y2: GLfloat);
    glRecti(x1: GLint, y1: GLint, x2: GLint, y2: GLint);
}
