//! Framebuffer 0 as the app sees it (see `multiview::framebuffer`): bindings and buffer
//! selection are translated to the quilt, viewport/scissor are recorded for per-view mapping,
//! clears, reads and blits address the right tiles.

use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::replay::framebuffer as fb;
use crate::multiview::replay::transfers;
use core::ffi::c_void;

pub(crate) fn glBindFramebuffer(real: impl Fn(GLenum, GLuint), target: GLenum, fbo: GLuint) {
    crate::state::with_app(|app| app.bind_framebuffer(target, fbo));
    let mapped = with_active(|_, _, mv, _| fb::bind(mv, fbo));
    real(target, mapped.unwrap_or(fbo))
}

/// The quilt's attachment in place of framebuffer 0's `buf` (GL_BACK is invalid on a
/// framebuffer object), when framebuffer 0 is the quilt.
fn on_quilt(fb0: bool, buf: GLenum) -> Option<GLenum> {
    fb0.then(|| with_active(|_, _, mv, _| mv.quilt_fbo().map(|_| fb::map_buffer(buf))))
        .flatten()
        .flatten()
}

/// The app's buffer choice for framebuffer 0 is remembered and answered back; GL gets the
/// quilt's attachment instead.
pub(crate) fn glDrawBuffer(real: impl Fn(GLenum), buf: GLenum) {
    let fb0 = crate::state::with_app(|app| app.set_draw_buffer(buf)).unwrap_or(false);
    real(on_quilt(fb0, buf).unwrap_or(buf));
    draw_buffers_changed(&[buf]);
}

pub(crate) fn glReadBuffer(real: impl Fn(GLenum), buf: GLenum) {
    let fb0 = crate::state::with_app(|app| app.set_read_buffer(buf)).unwrap_or(false);
    real(on_quilt(fb0, buf).unwrap_or(buf))
}

/// New draw buffers on a shadowed framebuffer: its view framebuffers get the same (many
/// renderers set them every frame, so the shadow is kept, not rebuilt).
fn draw_buffers_changed(bufs: &[GLenum]) {
    with_active(|_, app, mv, gl| {
        let Some(s) = mv.shadows.get(&app.draw_fbo).filter(|_| app.draw_fbo != 0) else {
            return;
        };
        for &view in s.views.iter() {
            // SAFETY: our own view framebuffers, named (no binding change).
            unsafe { gl.NamedFramebufferDrawBuffers(view, bufs.len() as i32, bufs.as_ptr()) };
        }
    });
}

pub(crate) fn glDrawBuffers(real: impl Fn(GLsizei, *const GLenum), n: GLsizei, bufs: *const GLenum) {
    // SAFETY: glDrawBuffers reads `n` buffer names from `bufs`.
    let asked = unsafe { super::super::app_slice(bufs, n) };
    let fb0 = !asked.is_empty() && crate::state::with_app(|app| app.set_draw_buffer(asked[0])).unwrap_or(false);
    if on_quilt(fb0, asked.first().copied().unwrap_or(0)).is_none() {
        real(n, bufs);
        if !asked.is_empty() {
            draw_buffers_changed(asked);
        }
        return;
    }
    let mapped: Vec<GLenum> = asked.iter().map(|&b| fb::map_buffer(b)).collect();
    real(n, mapped.as_ptr())
}

pub(crate) fn glViewport(real: impl Fn(GLint, GLint, GLsizei, GLsizei), x: GLint, y: GLint, w: GLsizei, h: GLsizei) {
    crate::state::with_app(|app| app.viewport = [x, y, w, h]);
    real(x, y, w, h)
}

pub(crate) fn glScissor(real: impl Fn(GLint, GLint, GLsizei, GLsizei), x: GLint, y: GLint, w: GLsizei, h: GLsizei) {
    crate::state::with_app(|app| app.scissor = [x, y, w, h]);
    real(x, y, w, h)
}

/// Box 0 (x, y, w, h) of the `n` boxes an array call sets from index `first`, if it sets it.
///
/// # Safety
/// `v` is null or points to `n` boxes of four values, as the GL call requires.
unsafe fn box_0<T: Copy>(first: GLuint, n: GLsizei, v: *const T) -> Option<[T; 4]> {
    // SAFETY: the caller's guarantee; read before the real call.
    let all = unsafe { super::super::app_slice(v, n.saturating_mul(4)) };
    all.first_chunk::<4>().copied().filter(|_| first == 0)
}

/// Viewport 0 as whole pixels (the layer maps tiles and copies depth in pixels; a blitter's
/// half-pixel offsets round away).
fn viewport_0(v: Option<[GLfloat; 4]>) {
    if let Some(v) = v.filter(|v| v.iter().all(|c| c.is_finite())) {
        crate::state::with_app(|app| app.viewport = v.map(|c| c.round() as GLint));
    }
}

fn scissor_0(b: Option<[GLint; 4]>) {
    if let Some(b) = b {
        crate::state::with_app(|app| app.scissor = b);
    }
}

pub(crate) fn glViewportArrayv(
    real: impl Fn(GLuint, GLsizei, *const GLfloat),
    first: GLuint,
    n: GLsizei,
    v: *const GLfloat,
) {
    // SAFETY: `n` viewports of four floats, as the call requires.
    viewport_0(unsafe { box_0(first, n, v) });
    real(first, n, v)
}

pub(crate) fn glViewportIndexedf(
    real: impl Fn(GLuint, GLfloat, GLfloat, GLfloat, GLfloat),
    i: GLuint,
    x: GLfloat,
    y: GLfloat,
    w: GLfloat,
    h: GLfloat,
) {
    viewport_0(Some([x, y, w, h]).filter(|_| i == 0));
    real(i, x, y, w, h)
}

pub(crate) fn glViewportIndexedfv(real: impl Fn(GLuint, *const GLfloat), i: GLuint, v: *const GLfloat) {
    // SAFETY: one viewport of four floats, as the call requires.
    viewport_0(unsafe { box_0(i, 1, v) });
    real(i, v)
}

pub(crate) fn glScissorArrayv(
    real: impl Fn(GLuint, GLsizei, *const GLint),
    first: GLuint,
    n: GLsizei,
    v: *const GLint,
) {
    // SAFETY: `n` boxes of four integers, as the call requires.
    scissor_0(unsafe { box_0(first, n, v) });
    real(first, n, v)
}

pub(crate) fn glScissorIndexed(
    real: impl Fn(GLuint, GLint, GLint, GLsizei, GLsizei),
    i: GLuint,
    x: GLint,
    y: GLint,
    w: GLsizei,
    h: GLsizei,
) {
    scissor_0(Some([x, y, w, h]).filter(|_| i == 0));
    real(i, x, y, w, h)
}

pub(crate) fn glScissorIndexedv(real: impl Fn(GLuint, *const GLint), i: GLuint, v: *const GLint) {
    // SAFETY: one box of four integers, as the call requires.
    scissor_0(unsafe { box_0(i, 1, v) });
    real(i, v)
}

/// A clear (`depth`: of the depth buffer too; `stencil`: of the stencil buffer too), per
/// tile or layer; a scene depth it would erase is copied first for auto-convergence.
fn clear_tiles((depth, stencil): (bool, bool), f: impl Fn()) {
    let done = with_active(|_, app, mv, gl| {
        crate::multiview::scene::convergence::before_erase(gl, app, mv, app.draw_fbo, depth);
        transfers::clear(gl, app, mv, stencil, &f)
    });
    if done.is_none() {
        f()
    }
}

pub(crate) fn glClear(real: impl Fn(GLbitfield), mask: GLbitfield) {
    let (depth, stencil) = (crate::gl::DEPTH_BUFFER_BIT, crate::gl::STENCIL_BUFFER_BIT);
    clear_tiles((mask & depth != 0, mask & stencil != 0), || real(mask))
}

pub(crate) fn glClearBufferfv(
    real: impl Fn(GLenum, GLint, *const GLfloat),
    buffer: GLenum,
    i: GLint,
    v: *const GLfloat,
) {
    clear_tiles((buffer == crate::gl::DEPTH, false), || real(buffer, i, v))
}

pub(crate) fn glClearBufferiv(real: impl Fn(GLenum, GLint, *const GLint), buffer: GLenum, i: GLint, v: *const GLint) {
    clear_tiles((false, buffer == crate::gl::STENCIL), || real(buffer, i, v))
}

pub(crate) fn glClearBufferuiv(
    real: impl Fn(GLenum, GLint, *const GLuint),
    buffer: GLenum,
    i: GLint,
    v: *const GLuint,
) {
    clear_tiles((false, false), || real(buffer, i, v))
}

pub(crate) fn glClearBufferfi(
    real: impl Fn(GLenum, GLint, GLfloat, GLint),
    buffer: GLenum,
    i: GLint,
    d: GLfloat,
    s: GLint,
) {
    let both = buffer == crate::gl::DEPTH_STENCIL;
    clear_tiles((both, both), || real(buffer, i, d, s))
}

/// Reads from framebuffer 0 see the centre view at the app's resolution.
pub(crate) fn glReadPixels(
    real: impl Fn(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, *mut c_void),
    x: GLint,
    y: GLint,
    w: GLsizei,
    h: GLsizei,
    format: GLenum,
    ty: GLenum,
    data: *mut c_void,
) {
    centre_read([x, y, w, h], |r| real(r[0], r[1], w, h, format, ty, data))
}

/// Runs a read of the app's read framebuffer so it sees the centre view: the centre tile of
/// framebuffer 0, or the centre layer of a shadowed framebuffer.
fn centre_read(rect: [i32; 4], read: impl Fn([i32; 4])) {
    let done = with_active(|_, app, mv, gl| {
        if transfers::read_centre_layer(gl, app, mv) {
            read(rect);
            fb::rebind(gl, app, mv);
        } else if let Some((centre, rebind)) = transfers::centre_rect(gl, app, mv, rect) {
            read(centre);
            if rebind {
                fb::rebind(gl, app, mv);
            }
        } else {
            read(rect);
        }
    });
    if done.is_none() {
        read(rect)
    }
}

pub(crate) fn glCopyTexSubImage2D(
    real: impl Fn(GLenum, GLint, GLint, GLint, GLint, GLint, GLsizei, GLsizei),
    target: GLenum,
    level: GLint,
    xoff: GLint,
    yoff: GLint,
    x: GLint,
    y: GLint,
    w: GLsizei,
    h: GLsizei,
) {
    centre_read([x, y, w, h], |r| real(target, level, xoff, yoff, r[0], r[1], w, h))
}

pub(crate) fn glCopyTexImage2D(
    real: impl Fn(GLenum, GLint, GLenum, GLint, GLint, GLsizei, GLsizei, GLint),
    target: GLenum,
    level: GLint,
    format: GLenum,
    x: GLint,
    y: GLint,
    w: GLsizei,
    h: GLsizei,
    border: GLint,
) {
    centre_read([x, y, w, h], |r| real(target, level, format, r[0], r[1], w, h, border))
}

pub(crate) fn glBlitFramebuffer(
    real: impl Fn(GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLbitfield, GLenum),
    sx0: GLint,
    sy0: GLint,
    sx1: GLint,
    sy1: GLint,
    dx0: GLint,
    dy0: GLint,
    dx1: GLint,
    dy1: GLint,
    mask: GLbitfield,
    filter: GLenum,
) {
    let f = |s: [i32; 4], d: [i32; 4]| real(s[0], s[1], s[2], s[3], d[0], d[1], d[2], d[3], mask, filter);
    if with_active(|_, app, mv, gl| transfers::blit(gl, app, mv, [sx0, sy0, sx1, sy1], [dx0, dy0, dx1, dy1], f))
        .is_none()
    {
        f([sx0, sy0, sx1, sy1], [dx0, dy0, dx1, dy1])
    }
}

/// Invalidation is only a hint; framebuffer 0's attachment names are invalid on our quilt,
/// so the hint is dropped while the quilt stands in for it.
pub(crate) fn glInvalidateFramebuffer(
    real: impl Fn(GLenum, GLsizei, *const GLenum),
    target: GLenum,
    n: GLsizei,
    atts: *const GLenum,
) {
    let depth = invalidates_depth(n, atts);
    let on_fb0 = with_active(|_, app, mv, gl| {
        let fbo = if target == crate::gl::READ_FRAMEBUFFER {
            app.read_fbo
        } else {
            app.draw_fbo
        };
        // Engines for tiled GPUs invalidate the scene's depth once it is drawn.
        crate::multiview::scene::convergence::before_erase(gl, app, mv, fbo, depth);
        mv.quilt_fbo().is_some() && fbo == 0
    });
    if on_fb0 != Some(true) {
        real(target, n, atts)
    }
}

/// Whether the `n` attachments at `atts` include depth.
fn invalidates_depth(n: GLsizei, atts: *const GLenum) -> bool {
    use crate::gl::{DEPTH, DEPTH_ATTACHMENT, DEPTH_STENCIL_ATTACHMENT};
    if atts.is_null() || n <= 0 {
        return false;
    }
    // SAFETY: the app passes `n` attachment names.
    let list = unsafe { std::slice::from_raw_parts(atts, n as usize) };
    list.iter()
        .any(|a| matches!(*a, DEPTH | DEPTH_ATTACHMENT | DEPTH_STENCIL_ATTACHMENT))
}
