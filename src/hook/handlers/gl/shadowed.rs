//! State the replay needs on every draw, shadowed here instead of asked of GL per draw (see
//! `state::AppState`): the scissor and rasterizer-discard enables, the matrix mode and the
//! fixed-function projection. Shadowed while multiview is on (the only time a draw asks).
//! `glPopAttrib` and display lists change state without the layer seeing each call, so they
//! make it unknown, to be asked of GL once at the next draw — except lists the layer saw
//! compiled without such calls. Calls compiled into a list (`GL_COMPILE`) do not run, and
//! change no shadow.

use crate::gl::types::*;
use crate::state::app::ListEffect;

fn shadowing() -> bool {
    crate::config::settings().multiview()
}

pub(crate) fn glEnable(real: impl Fn(GLenum), cap: GLenum) {
    real(cap);
    enabled(cap, true);
}

pub(crate) fn glDisable(real: impl Fn(GLenum), cap: GLenum) {
    real(cap);
    enabled(cap, false);
}

fn enabled(cap: GLenum, on: bool) {
    if (cap == crate::gl::SCISSOR_TEST || cap == crate::gl::RASTERIZER_DISCARD) && shadowing() {
        crate::state::with_app(|app| app.shadowed_call(ListEffect::Anything, |app| app.set_enabled(cap, on)));
    }
}

pub(crate) fn glPopAttrib(real: impl Fn()) {
    real();
    forget_shadowed();
}

/// Something changed shadowed state without the layer seeing each call.
fn forget_shadowed() {
    if shadowing() {
        crate::state::with_app(|app| app.shadowed_call(ListEffect::Anything, |app| app.forget_shadowed()));
    }
}

pub(crate) fn glMatrixMode(real: impl Fn(GLenum), mode: GLenum) {
    real(mode);
    if shadowing() {
        crate::state::with_app(|app| app.shadowed_call(ListEffect::Anything, |app| app.matrix_mode = Some(mode)));
    }
}

/// The handler of every `matrix` entry of the policy table (generated shims call it after
/// the real call): the projection may have changed (`mode` given by the direct-state-access
/// spellings, else the current matrix mode).
pub(crate) fn matrix_changed(mode: Option<GLenum>) {
    if shadowing() {
        let effect = match mode {
            None => ListEffect::CurrentMatrix,
            Some(crate::gl::PROJECTION | crate::gl::MODELVIEW) => ListEffect::NamedMatrix,
            Some(_) => ListEffect::Nothing,
        };
        crate::state::with_app(|app| app.shadowed_call(effect, |app| app.matrix_changed(mode)));
    }
}

/// Display lists may hold any of the calls above.
pub(crate) fn glCallList(real: impl Fn(GLuint), list: GLuint) {
    crate::multiview::replay::record_fixed::unrepeatable(|| per_view_list(Some(list), || real(list)));
    if shadowing() {
        crate::state::with_app(|app| app.list_called(Some(list)));
    }
}

/// (Names relative to `glListBase`, in one of several types: taken as unknown lists.)
pub(crate) fn glCallLists(
    real: impl Fn(GLsizei, GLenum, *const core::ffi::c_void),
    n: GLsizei,
    ty: GLenum,
    lists: *const core::ffi::c_void,
) {
    crate::multiview::replay::record_fixed::unrepeatable(|| per_view_list(None, || real(n, ty, lists)));
    if shadowing() {
        crate::state::with_app(|app| app.list_called(None));
    }
}

/// `per_view` for display lists (`None`: lists the layer cannot name): each view's call
/// starts from the matrices the app called it with (`replay::lists`).
fn per_view_list(list: Option<GLuint>, call: impl Fn()) {
    let done = crate::hook::layer::with_active(|cur, app, mv, gl| {
        let effect = list
            .and_then(|l| app.lists.get(&l).copied())
            .unwrap_or(ListEffect::Anything);
        let matrices = crate::multiview::replay::lists::ListMatrices::new(effect);
        crate::multiview::replay::draw::draw(gl, app, mv, &cur.ctx.group, || matrices.around(gl, &call))
    });
    if done.is_none() {
        call()
    }
}
