//! Attachments of the app's framebuffers. Renderers attach the same objects before every
//! pass and detach them after it (VTK's render passes do both every frame), so a call only
//! marks the framebuffer's shadow stale when it changes what is attached; the shadow is
//! pointed at the new set before its next use, keeping every image's content
//! (`multiview::lifetime`).

use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::shadows::layered::AppImage;
use crate::multiview::shadows::lifetime;

/// The app's framebuffer `fbo` (None: the one bound to `target`) got `name` (0: nothing) at
/// `point`, mip `level`.
fn attached(fbo: Option<u32>, target: GLenum, point: GLenum, name: u32, renderbuffer: bool, level: GLint) {
    with_active(|_, app, mv, _| {
        let fbo = fbo.unwrap_or(if target == crate::gl::READ_FRAMEBUFFER {
            app.read_fbo
        } else {
            app.draw_fbo
        });
        let object = (name != 0).then_some(AppImage { name, renderbuffer });
        lifetime::attachment_changed(mv, fbo, point, object, level);
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
    attached(None, target, att, tex, false, level);
}

pub(crate) fn glFramebufferTexture(
    real: impl Fn(GLenum, GLenum, GLuint, GLint),
    target: GLenum,
    att: GLenum,
    tex: GLuint,
    level: GLint,
) {
    real(target, att, tex, level);
    attached(None, target, att, tex, false, level);
}

/// A layer of an array or 3D texture: never shadowed, but it replaces what was attached.
pub(crate) fn glFramebufferTextureLayer(
    real: impl Fn(GLenum, GLenum, GLuint, GLint, GLint),
    target: GLenum,
    att: GLenum,
    tex: GLuint,
    level: GLint,
    layer: GLint,
) {
    real(target, att, tex, level, layer);
    attached(None, target, att, tex, false, level);
}

pub(crate) fn glFramebufferRenderbuffer(
    real: impl Fn(GLenum, GLenum, GLenum, GLuint),
    target: GLenum,
    att: GLenum,
    rbt: GLenum,
    rb: GLuint,
) {
    real(target, att, rbt, rb);
    attached(None, target, att, rb, true, 0);
}

pub(crate) fn glNamedFramebufferTexture(
    real: impl Fn(GLuint, GLenum, GLuint, GLint),
    fbo: GLuint,
    att: GLenum,
    tex: GLuint,
    level: GLint,
) {
    real(fbo, att, tex, level);
    attached(Some(fbo), 0, att, tex, false, level);
}

pub(crate) fn glNamedFramebufferTextureLayer(
    real: impl Fn(GLuint, GLenum, GLuint, GLint, GLint),
    fbo: GLuint,
    att: GLenum,
    tex: GLuint,
    level: GLint,
    layer: GLint,
) {
    real(fbo, att, tex, level, layer);
    attached(Some(fbo), 0, att, tex, false, level);
}

pub(crate) fn glNamedFramebufferRenderbuffer(
    real: impl Fn(GLuint, GLenum, GLenum, GLuint),
    fbo: GLuint,
    att: GLenum,
    rbt: GLenum,
    rb: GLuint,
) {
    real(fbo, att, rbt, rb);
    attached(Some(fbo), 0, att, rb, true, 0);
}
