//! Immediate mode and display-list compilation.
//!
//! A `glBegin`…`glEnd` block drawn to framebuffer 0 is recorded into a display list of ours
//! (compiled, not executed) and then replayed once per view like any other draw. While the
//! app is itself compiling a list nothing is replayed: its list must contain its calls once.

use crate::gl::types::*;
use crate::hook::layer::with_active;

pub(crate) fn glBegin(real: impl Fn(GLenum), mode: GLenum) {
    with_active(|_, app, mv, gl| crate::multiview::replay::immediate::begin(gl, app, mv));
    real(mode)
}

pub(crate) fn glEnd(real: impl Fn()) {
    real();
    let list = with_active(|_, _, mv, gl| crate::multiview::replay::immediate::end(gl, mv)).flatten();
    if let Some(list) = list {
        super::per_view_gl(|gl| crate::multiview::replay::immediate::call(gl, list));
    }
}

pub(crate) fn glNewList(real: impl Fn(GLuint, GLenum), list: GLuint, mode: GLenum) {
    crate::state::with_app(|app| app.list_begun(list, mode));
    real(list, mode)
}

pub(crate) fn glEndList(real: impl Fn()) {
    real();
    crate::state::with_app(|app| app.list_ended());
}

pub(crate) fn glBeginTransformFeedback(real: impl Fn(GLenum), mode: GLenum) {
    crate::state::with_app(|app| app.transform_feedback = true);
    real(mode)
}

pub(crate) fn glEndTransformFeedback(real: impl Fn()) {
    real();
    crate::state::with_app(|app| app.transform_feedback = false);
}
