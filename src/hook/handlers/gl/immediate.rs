//! Immediate mode and display-list compilation.
//!
//! A `glBegin`…`glEnd` block drawn to framebuffer 0 is recorded into a display list of ours
//! (compiled, not executed) and then replayed once per view like any other draw. While the
//! app is itself compiling a list nothing is replayed: its list must contain its calls once.

use crate::gl::types::*;
use crate::multiview::with_active;

pub(crate) fn glBegin(real: impl Fn(GLenum), mode: GLenum) {
    with_active(|_, mv, gl| crate::multiview::immediate::begin(gl, mv));
    real(mode)
}

pub(crate) fn glEnd(real: impl Fn()) {
    real();
    let list = with_active(|_, mv, gl| crate::multiview::immediate::end(gl, mv)).flatten();
    if let Some(list) = list {
        super::per_view_gl(|gl| crate::multiview::immediate::call(gl, list));
    }
}

pub(crate) fn glNewList(real: impl Fn(GLuint, GLenum), list: GLuint, mode: GLenum) {
    with_active(|_, mv, _| mv.compiling_list = true);
    real(list, mode)
}

pub(crate) fn glEndList(real: impl Fn()) {
    real();
    with_active(|_, mv, _| mv.compiling_list = false);
}

pub(crate) fn glBeginTransformFeedback(real: impl Fn(GLenum), mode: GLenum) {
    with_active(|_, mv, _| mv.transform_feedback = true);
    real(mode)
}

pub(crate) fn glEndTransformFeedback(real: impl Fn()) {
    real();
    with_active(|_, mv, _| mv.transform_feedback = false);
}
