//! Texture units and the objects behind layered shadows: the bindings the per-view texture
//! substitution needs, and every call that makes a shadow stale (re-attachment, new storage,
//! deletion) or needs mirroring (mipmaps).

use super::super::app_slice;
use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::layers::forget;
use core::ffi::c_void;

pub(crate) fn glActiveTexture(real: impl Fn(GLenum), texture: GLenum) {
    crate::state::with_app(|app| app.units.active = texture.wrapping_sub(crate::gl::TEXTURE0));

    real(texture)
}

/// Runs `f` with the share group of the calling thread's current context, whether or not
/// multiview is on for that context (a surfaceless root context creates what others draw
/// into); nothing at all when the layer is pass-through.
fn with_group(f: impl FnOnce(&crate::state::ShareGroup)) {
    if crate::config::settings().multiview() {
        crate::state::with_current(|cur| cur.map(|cur| f(&cur.ctx.group)));
    }
}

pub(crate) fn glBindTexture(real: impl Fn(GLenum, GLuint), target: GLenum, texture: GLuint) {
    if texture != 0 {
        with_group(|g| g.textures.bound(target, texture));
    }
    if target == crate::gl::TEXTURE_2D {
        crate::state::with_app(|app| app.units.bind(app.units.active, texture));
    }
    real(target, texture)
}

pub(crate) fn glCreateTextures(
    real: impl Fn(GLenum, GLsizei, *mut GLuint),
    target: GLenum,
    n: GLsizei,
    textures: *mut GLuint,
) {
    real(target, n, textures);
    // SAFETY: `textures` has room for `n` names, which glCreateTextures has just written (with
    // an invalid target it writes none, and we record what the app's array held: integers).
    let made = unsafe { app_slice(textures, n) };
    with_group(|g| g.textures.created(target, made));
}

pub(crate) fn glBindTextureUnit(real: impl Fn(GLuint, GLuint), unit: GLuint, texture: GLuint) {
    crate::state::with_app(|app| app.units.bind(unit, texture));
    real(unit, texture)
}

pub(crate) fn glBindTextures(
    real: impl Fn(GLuint, GLsizei, *const GLuint),
    first: GLuint,
    count: GLsizei,
    textures: *const GLuint,
) {
    // SAFETY: glBindTextures reads `count` names from `textures`, or none when it is NULL
    // (which unbinds them all).
    let names = unsafe { app_slice(textures, count) };
    crate::state::with_app(|app| {
        for i in 0..count.max(0) as u32 {
            app.units.bind(first + i, names.get(i as usize).copied().unwrap_or(0));
        }
    });
    real(first, count, textures)
}

pub(crate) fn glGenerateMipmap(real: impl Fn(GLenum), target: GLenum) {
    real(target);
    with_active(|_, app, mv, gl| {
        let tex = app.units.bound_2d.get(app.units.active as usize).copied().unwrap_or(0);
        if target == crate::gl::TEXTURE_2D && tex != 0 {
            mv.shadows.values().for_each(|s| s.generate_mipmaps(gl, tex));
        }
    });
}

/// The texture bound to `binding` (a `GL_TEXTURE_BINDING_*` or `GL_RENDERBUFFER_BINDING`).
fn bound(gl: &crate::gl::Gl, binding: GLenum) -> u32 {
    crate::gl::guard::get_i(gl, binding) as u32
}

fn storage_changed(renderbuffer: bool, binding: GLenum) {
    with_active(|_, _, mv, gl| {
        let name = bound(gl, binding);
        forget(gl, mv, |_, s| s.owns(name, renderbuffer));
    });
}

pub(crate) fn glTexImage2D(
    real: impl Fn(GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, *const c_void),
    target: GLenum,
    level: GLint,
    internal: GLint,
    w: GLsizei,
    h: GLsizei,
    border: GLint,
    format: GLenum,
    ty: GLenum,
    data: *const c_void,
) {
    real(target, level, internal, w, h, border, format, ty, data);
    if target == crate::gl::TEXTURE_2D && level == 0 {
        storage_changed(false, crate::gl::TEXTURE_BINDING_2D);
    }
}

pub(crate) fn glTexStorage2D(
    real: impl Fn(GLenum, GLsizei, GLenum, GLsizei, GLsizei),
    target: GLenum,
    levels: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(target, levels, format, w, h);
    if target == crate::gl::TEXTURE_2D {
        storage_changed(false, crate::gl::TEXTURE_BINDING_2D);
    }
}

pub(crate) fn glRenderbufferStorage(
    real: impl Fn(GLenum, GLenum, GLsizei, GLsizei),
    target: GLenum,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(target, format, w, h);
    storage_changed(true, crate::gl::RENDERBUFFER_BINDING);
}

pub(crate) fn glRenderbufferStorageMultisample(
    real: impl Fn(GLenum, GLsizei, GLenum, GLsizei, GLsizei),
    target: GLenum,
    samples: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(target, samples, format, w, h);
    storage_changed(true, crate::gl::RENDERBUFFER_BINDING);
}

/// The app's framebuffer bound to `target` got `name` at `attachment`: its shadow is rebuilt
/// on demand, unless the same object is attached again (some renderers re-attach every frame;
/// rebuilding N layers each time would cost far more than the draw).
fn reattached(target: GLenum, attachment: GLenum, name: u32, renderbuffer: bool) {
    with_active(|_, app, mv, gl| {
        let fbo = if target == crate::gl::READ_FRAMEBUFFER {
            app.read_fbo
        } else {
            app.draw_fbo
        };
        mv.has_color.remove(&fbo);
        let same = mv
            .shadows
            .get(&fbo)
            .is_some_and(|s| s.attached(attachment) == Some((name, renderbuffer)));
        if !same {
            mv.unshadowable.remove(&fbo);
            forget(gl, mv, |f, _| f == fbo);
        }
    });
}

pub(crate) fn glFramebufferTexture2D(
    real: impl Fn(GLenum, GLenum, GLenum, GLuint, GLint),
    target: GLenum,
    att: GLenum,
    textarget: GLenum,
    tex: GLuint,
    level: GLint,
) {
    real(target, att, textarget, tex, level);
    reattached(target, att, tex, false);
}

pub(crate) fn glFramebufferTexture(
    real: impl Fn(GLenum, GLenum, GLuint, GLint),
    target: GLenum,
    att: GLenum,
    tex: GLuint,
    level: GLint,
) {
    real(target, att, tex, level);
    reattached(target, att, tex, false);
}

pub(crate) fn glFramebufferRenderbuffer(
    real: impl Fn(GLenum, GLenum, GLenum, GLuint),
    target: GLenum,
    att: GLenum,
    rbt: GLenum,
    rb: GLuint,
) {
    real(target, att, rbt, rb);
    reattached(target, att, rb, true);
}

pub(crate) fn glDeleteFramebuffers(real: impl Fn(GLsizei, *const GLuint), n: GLsizei, fbos: *const GLuint) {
    // SAFETY: glDeleteFramebuffers reads `n` names from `fbos`.
    let gone = unsafe { app_slice(fbos, n) };
    with_active(|_, _, mv, gl| {
        gone.iter().for_each(|f| {
            mv.unshadowable.remove(f);
            mv.has_color.remove(f);
        });
        forget(gl, mv, |f, _| gone.contains(&f));
    });
    real(n, fbos)
}

pub(crate) fn glDeleteTextures(real: impl Fn(GLsizei, *const GLuint), n: GLsizei, textures: *const GLuint) {
    // SAFETY: glDeleteTextures reads `n` names from `textures`.
    let gone = unsafe { app_slice(textures, n) };
    with_group(|g| g.textures.deleted(gone));
    with_active(|_, _, mv, gl| forget(gl, mv, |_, s| gone.iter().any(|&t| s.owns(t, false))));
    // Deleting a bound texture unbinds it.
    crate::state::with_app(|app| {
        app.units
            .bound_2d
            .iter_mut()
            .filter(|t| gone.contains(t))
            .for_each(|t| *t = 0)
    });
    real(n, textures)
}

pub(crate) fn glDeleteRenderbuffers(real: impl Fn(GLsizei, *const GLuint), n: GLsizei, rbs: *const GLuint) {
    // SAFETY: glDeleteRenderbuffers reads `n` names from `rbs`.
    let gone = unsafe { app_slice(rbs, n) };
    with_active(|_, _, mv, gl| forget(gl, mv, |_, s| gone.iter().any(|&r| s.owns(r, true))));
    real(n, rbs)
}
