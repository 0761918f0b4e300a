//! Pixel rectangles (`glBitmap` text, `glDrawPixels`, `glCopyPixels`) at each view's tile,
//! `glRenderMode` (selection/feedback draws are never replayed: picking counts each once).
//! `glAccum` is left alone: the quilt has no accumulation buffer, so programs that use one
//! get GL's error for it while multiview is on (documented in README).

use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::replay::{draw, raster};
use core::ffi::c_void;

/// Replays a raster operation per view with the raster position moved into each tile;
/// `advance` is how far the app's single call moves the raster position.
fn per_view_raster(advance: (f32, f32), f: impl Fn(Option<[i32; 4]>)) {
    let done = with_active(|cur, app, mv, gl| {
        if mv.info.es || !mv.on_default_draw(app) {
            return false;
        }
        let Some(layout) = mv.layout() else { return false };
        let saved = raster::save(gl);
        crate::multiview::replay::record_fixed::unrepeatable(|| {
            draw::draw_views(gl, app, mv, &cur.ctx.group, |i| {
                if i != draw::SINGLE {
                    raster::place(gl, &saved, &layout, i);
                }
                f((i != draw::SINGLE).then(|| layout.tile_rect(i)))
            })
        });
        raster::finish(gl, &saved, advance);
        true
    });
    if done != Some(true) {
        f(None)
    }
}

pub(crate) fn glBitmap(
    real: impl Fn(GLsizei, GLsizei, GLfloat, GLfloat, GLfloat, GLfloat, *const GLubyte),
    w: GLsizei,
    h: GLsizei,
    xorig: GLfloat,
    yorig: GLfloat,
    xmove: GLfloat,
    ymove: GLfloat,
    bitmap: *const GLubyte,
) {
    per_view_raster((xmove, ymove), |_| real(w, h, xorig, yorig, xmove, ymove, bitmap))
}

pub(crate) fn glDrawPixels(
    real: impl Fn(GLsizei, GLsizei, GLenum, GLenum, *const c_void),
    w: GLsizei,
    h: GLsizei,
    f: GLenum,
    t: GLenum,
    p: *const c_void,
) {
    per_view_raster((0.0, 0.0), |_| real(w, h, f, t, p))
}

/// The source rectangle is in window coordinates too: each view copies from the same place
/// in its own tile (exact when tiles are the window's size; scaled tiles copy the window-sized
/// rectangle from the tile's origin).
pub(crate) fn glCopyPixels(
    real: impl Fn(GLint, GLint, GLsizei, GLsizei, GLenum),
    x: GLint,
    y: GLint,
    w: GLsizei,
    h: GLsizei,
    ty: GLenum,
) {
    per_view_raster((0.0, 0.0), |tile| match tile {
        Some(t) => real(t[0] + x, t[1] + y, w, h, ty),
        None => real(x, y, w, h, ty),
    })
}

pub(crate) fn glRenderMode(real: impl Fn(GLenum) -> GLint, mode: GLenum) -> GLint {
    crate::state::with_app(|app| app.selecting = mode != crate::gl::RENDER);

    real(mode)
}
