//! Sampling parameters of the app's textures, mirrored onto the layer views that stand in
//! for them (`multiview::sampling`): a filter, wrap, compare mode or swizzle set after a
//! shadow exists must reach every view, or view i would sample its layer differently from
//! how the app samples its texture. Every variant is mirrored with the app's own values
//! through the matching direct-state call.

use super::super::app_slice;
use crate::gl::Gl;
use crate::gl::types::*;
use crate::hook::layer::with_active;
use crate::multiview::shadows::{lifetime, sampling};

/// `glTexParameter*(target, pname, …)`: the app's texture is the one bound to `target` on the
/// active unit (only `GL_TEXTURE_2D` textures have layer views). Calls compiled into a
/// display list are not executed now, so they change nothing yet.
fn bound_changed(target: GLenum, pname: GLenum, set: impl Fn(&Gl, u32)) {
    if target != crate::gl::TEXTURE_2D {
        return;
    }
    with_active(|_, app, mv, gl| {
        let compiled_only = matches!(app.list, Some((_, crate::gl::COMPILE, _)));
        let tex = app.units.bound_2d.get(app.units.active as usize).copied().unwrap_or(0);
        if !mv.images.is_empty() && tex != 0 && !compiled_only {
            lifetime::parameter_changed(gl, mv, tex, pname, set);
        }
    });
}

/// `glTextureParameter*(texture, pname, …)`.
fn named_changed(texture: GLuint, pname: GLenum, set: impl Fn(&Gl, u32)) {
    with_active(|_, _, mv, gl| {
        if !mv.images.is_empty() {
            lifetime::parameter_changed(gl, mv, texture, pname, set);
        }
    });
}

/// Our texture `t` gets `pname` = `v`, as the app set it on its own.
fn set_i(gl: &Gl, t: u32, pname: GLenum, v: GLint) {
    // SAFETY: a parameter of our own texture, with the app's value.
    unsafe { gl.TextureParameteri(t, pname, v) }
}

fn set_f(gl: &Gl, t: u32, pname: GLenum, v: GLfloat) {
    // SAFETY: as in `set_i`.
    unsafe { gl.TextureParameterf(t, pname, v) }
}

fn set_iv(gl: &Gl, t: u32, pname: GLenum, v: &[GLint]) {
    // SAFETY: as in `set_i`; `v` holds the values `pname` takes (`sampling::values`).
    unsafe { gl.TextureParameteriv(t, pname, v.as_ptr()) }
}

fn set_fv(gl: &Gl, t: u32, pname: GLenum, v: &[GLfloat]) {
    // SAFETY: as in `set_iv`.
    unsafe { gl.TextureParameterfv(t, pname, v.as_ptr()) }
}

fn set_iiv(gl: &Gl, t: u32, pname: GLenum, v: &[GLint]) {
    // SAFETY: as in `set_iv`.
    unsafe { gl.TextureParameterIiv(t, pname, v.as_ptr()) }
}

fn set_iuiv(gl: &Gl, t: u32, pname: GLenum, v: &[GLuint]) {
    // SAFETY: as in `set_iv`.
    unsafe { gl.TextureParameterIuiv(t, pname, v.as_ptr()) }
}

/// The values the app passed for `pname` (none for a null pointer: nothing to mirror).
///
/// # Safety
/// `v` is null or points to as many values as `pname` takes, as the `*v` entry points
/// require of the app.
unsafe fn values<'a, T>(v: *const T, pname: GLenum) -> Option<&'a [T]> {
    // SAFETY: the caller's guarantee.
    let v = unsafe { app_slice(v, sampling::values(pname)) };
    (!v.is_empty()).then_some(v)
}

pub(crate) fn glTexParameteri(real: impl Fn(GLenum, GLenum, GLint), target: GLenum, pname: GLenum, param: GLint) {
    real(target, pname, param);
    bound_changed(target, pname, |gl, t| set_i(gl, t, pname, param));
}

pub(crate) fn glTexParameterf(real: impl Fn(GLenum, GLenum, GLfloat), target: GLenum, pname: GLenum, param: GLfloat) {
    real(target, pname, param);
    bound_changed(target, pname, |gl, t| set_f(gl, t, pname, param));
}

pub(crate) fn glTexParameteriv(
    real: impl Fn(GLenum, GLenum, *const GLint),
    target: GLenum,
    pname: GLenum,
    v: *const GLint,
) {
    real(target, pname, v);
    // SAFETY: glTexParameteriv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        bound_changed(target, pname, |gl, t| set_iv(gl, t, pname, v));
    }
}

pub(crate) fn glTexParameterfv(
    real: impl Fn(GLenum, GLenum, *const GLfloat),
    target: GLenum,
    pname: GLenum,
    v: *const GLfloat,
) {
    real(target, pname, v);
    // SAFETY: glTexParameterfv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        bound_changed(target, pname, |gl, t| set_fv(gl, t, pname, v));
    }
}

pub(crate) fn glTexParameterIiv(
    real: impl Fn(GLenum, GLenum, *const GLint),
    target: GLenum,
    pname: GLenum,
    v: *const GLint,
) {
    real(target, pname, v);
    // SAFETY: glTexParameterIiv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        bound_changed(target, pname, |gl, t| set_iiv(gl, t, pname, v));
    }
}

pub(crate) fn glTexParameterIuiv(
    real: impl Fn(GLenum, GLenum, *const GLuint),
    target: GLenum,
    pname: GLenum,
    v: *const GLuint,
) {
    real(target, pname, v);
    // SAFETY: glTexParameterIuiv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        bound_changed(target, pname, |gl, t| set_iuiv(gl, t, pname, v));
    }
}

pub(crate) fn glTextureParameteri(real: impl Fn(GLuint, GLenum, GLint), texture: GLuint, pname: GLenum, param: GLint) {
    real(texture, pname, param);
    named_changed(texture, pname, |gl, t| set_i(gl, t, pname, param));
}

pub(crate) fn glTextureParameterf(
    real: impl Fn(GLuint, GLenum, GLfloat),
    texture: GLuint,
    pname: GLenum,
    param: GLfloat,
) {
    real(texture, pname, param);
    named_changed(texture, pname, |gl, t| set_f(gl, t, pname, param));
}

pub(crate) fn glTextureParameteriv(
    real: impl Fn(GLuint, GLenum, *const GLint),
    texture: GLuint,
    pname: GLenum,
    v: *const GLint,
) {
    real(texture, pname, v);
    // SAFETY: glTextureParameteriv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        named_changed(texture, pname, |gl, t| set_iv(gl, t, pname, v));
    }
}

pub(crate) fn glTextureParameterfv(
    real: impl Fn(GLuint, GLenum, *const GLfloat),
    texture: GLuint,
    pname: GLenum,
    v: *const GLfloat,
) {
    real(texture, pname, v);
    // SAFETY: glTextureParameterfv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        named_changed(texture, pname, |gl, t| set_fv(gl, t, pname, v));
    }
}

pub(crate) fn glTextureParameterIiv(
    real: impl Fn(GLuint, GLenum, *const GLint),
    texture: GLuint,
    pname: GLenum,
    v: *const GLint,
) {
    real(texture, pname, v);
    // SAFETY: glTextureParameterIiv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        named_changed(texture, pname, |gl, t| set_iiv(gl, t, pname, v));
    }
}

pub(crate) fn glTextureParameterIuiv(
    real: impl Fn(GLuint, GLenum, *const GLuint),
    texture: GLuint,
    pname: GLenum,
    v: *const GLuint,
) {
    real(texture, pname, v);
    // SAFETY: glTextureParameterIuiv reads the values `pname` takes from `v`.
    if let Some(v) = unsafe { values(v, pname) } {
        named_changed(texture, pname, |gl, t| set_iuiv(gl, t, pname, v));
    }
}
