//! `glGet*` answers corrected so the app never sees the layer's objects: framebuffer 0 and
//! its buffers, the app's own shader sources, and no program-binary formats (so programs
//! are always built from source and pass through the link-time rewrite).

use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::replay::framebuffer as fb;

const NUM_PROGRAM_BINARY_FORMATS: GLenum = 0x87FE;

pub(crate) fn glGetIntegerv(real: impl Fn(GLenum, *mut GLint), pname: GLenum, data: *mut GLint) {
    if with_active(|_, app, mv, gl| fb::on_real_default(gl, app, mv, pname, || real(pname, data)))
        .flatten()
        .is_some()
    {
        return;
    }
    real(pname, data);
    if data.is_null() || !crate::config::settings().multiview() {
        return;
    }
    let fixed = if pname == NUM_PROGRAM_BINARY_FORMATS {
        Some(0)
    } else {
        with_active(|_, app, mv, _| fb::patch_get(app, mv, pname)).flatten()
    };
    // SAFETY: every glGetIntegerv query answers at least one integer into `data`, written
    // just above.
    if let (Some(v), Some(answer)) = (fixed, unsafe { super::super::app_out(data) }) {
        *answer = v;
    }
}

pub(crate) fn glGetShaderSource(
    real: impl Fn(GLuint, GLsizei, *mut GLsizei, *mut GLchar),
    shader: GLuint,
    size: GLsizei,
    length: *mut GLsizei,
    source: *mut GLchar,
) {
    let original =
        crate::state::with_current(|cur| cur.and_then(|c| c.ctx.group.lock().original_sources.get(&shader).cloned()));
    let Some(text) = original.filter(|_| size > 0 && !source.is_null()) else {
        return real(shader, size, length, source);
    };
    // SAFETY: glGetShaderSource's `source` has room for `size` characters and `length` for
    // one integer (or is null); we answer in place of the real call.
    let (buf, length) = unsafe {
        (
            super::super::app_buffer(source.cast::<u8>(), size),
            super::super::app_out(length),
        )
    };
    let n = text.len().min(buf.len() - 1);
    buf[..n].copy_from_slice(&text.as_bytes()[..n]);
    buf[n] = 0;
    if let Some(length) = length {
        *length = n as GLsizei;
    }
}

pub(crate) fn glGetShaderiv(
    real: impl Fn(GLuint, GLenum, *mut GLint),
    shader: GLuint,
    pname: GLenum,
    params: *mut GLint,
) {
    real(shader, pname, params);
    if pname != crate::gl::SHADER_SOURCE_LENGTH || params.is_null() {
        return;
    }
    let len = crate::state::with_current(|cur| {
        cur.and_then(|c| c.ctx.group.lock().original_sources.get(&shader).map(|s| s.len() + 1))
    });
    // SAFETY: GL_SHADER_SOURCE_LENGTH answers one integer into `params`, written just above.
    if let (Some(len), Some(answer)) = (len, unsafe { super::super::app_out(params) }) {
        *answer = len as GLint;
    }
}

pub(crate) fn glGetBooleanv(real: impl Fn(GLenum, *mut GLboolean), pname: GLenum, data: *mut GLboolean) {
    if with_active(|_, app, mv, gl| fb::on_real_default(gl, app, mv, pname, || real(pname, data)))
        .flatten()
        .is_none()
    {
        real(pname, data)
    }
}

pub(crate) fn glGetFramebufferAttachmentParameteriv(
    real: impl Fn(GLenum, GLenum, GLenum, *mut GLint),
    target: GLenum,
    attachment: GLenum,
    pname: GLenum,
    params: *mut GLint,
) {
    let call = || real(target, attachment, pname, params);
    if with_active(|_, app, mv, gl| fb::on_real_target(gl, app, mv, target, call))
        .flatten()
        .is_none()
    {
        real(target, attachment, pname, params)
    }
}
