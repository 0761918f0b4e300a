//! Programs: link-time injection, the current program, and the matrices uploaded to it.

use crate::gl::types::*;

pub fn glLinkProgram(real: impl Fn(GLuint), program: GLuint) {
    if !crate::config::settings().multiview() {
        return real(program);
    }
    let done = crate::state::with_current(|cur| {
        let cur = cur?;
        let (gl, _) = cur.ctx.gl()?;
        crate::multiview::link::link_program(gl, &cur.ctx.group, program, || real(program));
        Some(())
    });
    if done.is_none() {
        real(program)
    }
}

pub fn glUseProgram(real: impl Fn(GLuint), program: GLuint) {
    crate::state::with_app(|app| app.program = program);
    real(program)
}

/// The app replaced a shader's source: what we stored about its old one no longer applies.
pub fn glShaderSource(
    real: impl Fn(GLuint, GLsizei, *const *const GLchar, *const GLint),
    shader: GLuint,
    count: GLsizei,
    strings: *const *const GLchar,
    lengths: *const GLint,
) {
    real(shader, count, strings, lengths);
    crate::state::with_current(|cur| cur.map(|c| c.ctx.group.lock().original_sources.remove(&shader)));
}

fn column_major(value: *const GLfloat, transpose: GLboolean) -> [f32; 16] {
    let mut m = [0f32; 16];
    // SAFETY: the app passes at least one 4x4 matrix.
    m.copy_from_slice(unsafe { std::slice::from_raw_parts(value, 16) });
    if transpose != 0 {
        let t = m;
        for r in 0..4 {
            for c in 0..4 {
                m[c * 4 + r] = t[r * 4 + c];
            }
        }
    }
    m
}

fn track_matrix(program: u32, loc: GLint, count: GLsizei, transpose: GLboolean, value: *const GLfloat) {
    if loc < 0 || count < 1 || value.is_null() {
        return;
    }
    let m = column_major(value, transpose);
    crate::state::with_current(|cur| cur.map(|c| c.ctx.group.lock().matrices.insert((program, loc), m)));
}

pub fn glUniformMatrix4fv(
    real: impl Fn(GLint, GLsizei, GLboolean, *const GLfloat),
    loc: GLint,
    count: GLsizei,
    transpose: GLboolean,
    value: *const GLfloat,
) {
    real(loc, count, transpose, value);
    if let Some(program) = crate::config::settings()
        .multiview()
        .then(|| crate::state::with_app(|app| app.program))
        .flatten()
    {
        track_matrix(program, loc, count, transpose, value);
    }
}

pub fn glProgramUniformMatrix4fv(
    real: impl Fn(GLuint, GLint, GLsizei, GLboolean, *const GLfloat),
    program: GLuint,
    loc: GLint,
    count: GLsizei,
    transpose: GLboolean,
    value: *const GLfloat,
) {
    real(program, loc, count, transpose, value);
    if crate::config::settings().multiview() {
        track_matrix(program, loc, count, transpose, value);
    }
}
