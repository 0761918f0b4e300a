//! Texture units and the objects behind layered images: the bindings the per-view texture
//! substitution needs, and every call that may retire an image (new storage or content,
//! deletion) or needs mirroring (mipmaps). Attachments are in `attachment`, sampling
//! parameters in `texparam`.

use super::super::app_slice;
use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::shadows::layered::AppImage;
use crate::multiview::shadows::lifetime;
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
            lifetime::mipmaps_generated(gl, mv, tex);
        }
    });
}

/// The object bound to `binding` (a `GL_TEXTURE_BINDING_*` or `GL_RENDERBUFFER_BINDING`).
fn bound(gl: &crate::gl::Gl, binding: GLenum) -> u32 {
    crate::gl::guard::get_i(gl, binding) as u32
}

/// Storage given to the bound object; `data`: the texel source of a `glTexImage2D` (uploads
/// when not NULL, or when an unpack buffer is bound). Its image stays if nothing changed (see
/// `lifetime::storage_changed`).
fn storage_changed(target: GLenum, binding: GLenum, data: Option<*const c_void>) {
    with_active(|_, _, mv, gl| {
        if mv.images.is_empty() {
            return;
        }
        let renderbuffer = target == crate::gl::RENDERBUFFER;
        let app = AppImage {
            name: bound(gl, binding),
            renderbuffer,
        };
        let uploads = data.is_some_and(|d| !d.is_null() || bound(gl, crate::gl::PIXEL_UNPACK_BUFFER_BINDING) != 0);
        lifetime::storage_changed(gl, mv, app, target, uploads);
    });
}

/// Storage given to `name` through direct state access.
fn named_storage_changed(name: u32, renderbuffer: bool, target: GLenum) {
    with_active(|_, _, mv, gl| {
        let app = AppImage { name, renderbuffer };
        lifetime::storage_changed(gl, mv, app, target, false);
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
        storage_changed(target, crate::gl::TEXTURE_BINDING_2D, Some(data));
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
        storage_changed(target, crate::gl::TEXTURE_BINDING_2D, None);
    }
}

pub(crate) fn glTexImage2DMultisample(
    real: impl Fn(GLenum, GLsizei, GLenum, GLsizei, GLsizei, GLboolean),
    target: GLenum,
    samples: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
    fixed: GLboolean,
) {
    real(target, samples, format, w, h, fixed);
    if target == crate::gl::TEXTURE_2D_MULTISAMPLE {
        storage_changed(target, crate::gl::TEXTURE_BINDING_2D_MULTISAMPLE, None);
    }
}

pub(crate) fn glTexStorage2DMultisample(
    real: impl Fn(GLenum, GLsizei, GLenum, GLsizei, GLsizei, GLboolean),
    target: GLenum,
    samples: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
    fixed: GLboolean,
) {
    real(target, samples, format, w, h, fixed);
    if target == crate::gl::TEXTURE_2D_MULTISAMPLE {
        storage_changed(target, crate::gl::TEXTURE_BINDING_2D_MULTISAMPLE, None);
    }
}

pub(crate) fn glTextureStorage2D(
    real: impl Fn(GLuint, GLsizei, GLenum, GLsizei, GLsizei),
    texture: GLuint,
    levels: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(texture, levels, format, w, h);
    named_storage_changed(texture, false, crate::gl::TEXTURE_2D);
}

pub(crate) fn glRenderbufferStorage(
    real: impl Fn(GLenum, GLenum, GLsizei, GLsizei),
    target: GLenum,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(target, format, w, h);
    storage_changed(crate::gl::RENDERBUFFER, crate::gl::RENDERBUFFER_BINDING, None);
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
    storage_changed(crate::gl::RENDERBUFFER, crate::gl::RENDERBUFFER_BINDING, None);
}

pub(crate) fn glNamedRenderbufferStorage(
    real: impl Fn(GLuint, GLenum, GLsizei, GLsizei),
    rb: GLuint,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(rb, format, w, h);
    named_storage_changed(rb, true, crate::gl::RENDERBUFFER);
}

pub(crate) fn glNamedRenderbufferStorageMultisample(
    real: impl Fn(GLuint, GLsizei, GLenum, GLsizei, GLsizei),
    rb: GLuint,
    samples: GLsizei,
    format: GLenum,
    w: GLsizei,
    h: GLsizei,
) {
    real(rb, samples, format, w, h);
    named_storage_changed(rb, true, crate::gl::RENDERBUFFER);
}

pub(crate) fn glDeleteFramebuffers(real: impl Fn(GLsizei, *const GLuint), n: GLsizei, fbos: *const GLuint) {
    // SAFETY: glDeleteFramebuffers reads `n` names from `fbos`.
    let gone = unsafe { app_slice(fbos, n) };
    with_active(|_, _, mv, gl| lifetime::framebuffers_deleted(gl, mv, gone));
    real(n, fbos)
}

pub(crate) fn glDeleteTextures(real: impl Fn(GLsizei, *const GLuint), n: GLsizei, textures: *const GLuint) {
    // SAFETY: glDeleteTextures reads `n` names from `textures`.
    let gone = unsafe { app_slice(textures, n) };
    with_group(|g| g.textures.deleted(gone));
    with_active(|_, _, mv, gl| lifetime::objects_deleted(gl, mv, gone.iter().map(|&t| AppImage::texture(t))));
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
    let gone = gone.iter().map(|&name| AppImage {
        name,
        renderbuffer: true,
    });
    with_active(|_, _, mv, gl| lifetime::objects_deleted(gl, mv, gone));
    real(n, rbs)
}
