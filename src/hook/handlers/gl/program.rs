//! Programs: link-time injection, the current program, and the matrices uploaded to it.

use crate::gl::types::*;

pub(crate) fn glLinkProgram(real: impl Fn(GLuint), program: GLuint) {
    if !crate::config::settings().multiview() {
        return real(program);
    }
    let done = crate::state::with_current(|cur| {
        let cur = cur?;
        let (gl, info) = cur.ctx.gl()?;
        crate::multiview::replay::link::link_program(gl, *info, &cur.ctx.group, program, || real(program));
        Some(())
    });
    if done.is_none() {
        real(program)
    }
}

/// The current program, and (with multiview on) the layer's snapshot of what it knows about
/// it, so that draws need not ask the share group (see `state::program`).
pub(crate) fn glUseProgram(real: impl Fn(GLuint), program: GLuint) {
    let multiview = crate::config::settings().multiview();
    crate::state::with_current(|cur| {
        let cur = cur?;
        let mut tracked = cur.ctx.tracked()?;
        let app = tracked.app.as_mut()?;
        app.program = program;
        if multiview && program != 0 {
            app.current.take(&cur.ctx.group, program);
        }
        Some(())
    });
    real(program)
}

/// The app replaced a shader's source: what we stored about its old one no longer applies.
pub(crate) fn glShaderSource(
    real: impl Fn(GLuint, GLsizei, *const *const GLchar, *const GLint),
    shader: GLuint,
    count: GLsizei,
    strings: *const *const GLchar,
    lengths: *const GLint,
) {
    real(shader, count, strings, lengths);
    crate::state::with_current(|cur| cur.map(|c| c.ctx.group.lock().original_sources.remove(&shader)));
}

fn column_major(value: &[f32; 16], transpose: GLboolean) -> [f32; 16] {
    let mut m = *value;
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

/// The first matrix of a `glUniformMatrix4fv`-style upload.
///
/// # Safety
/// `value` is null or points to `count` 4x4 matrices, as those calls require.
unsafe fn first_matrix<'a>(value: *const GLfloat, count: GLsizei) -> Option<&'a [f32; 16]> {
    // SAFETY: `count` matrices of 16 floats each, as the caller guarantees.
    unsafe { super::super::app_slice(value, count.saturating_mul(16)) }.first_chunk::<16>()
}

/// Records a `mat4` upload in the share group (for other contexts, relinks and screen-space
/// passes) and in this context's snapshot of its current program. `program` None: the
/// current one.
fn track_matrix(program: Option<u32>, loc: GLint, transpose: GLboolean, value: Option<&[f32; 16]>) {
    let Some(value) = value.filter(|_| loc >= 0) else {
        return;
    };
    let m = column_major(value, transpose);
    crate::state::with_current(|cur| {
        let cur = cur?;
        let mut tracked = cur.ctx.tracked()?;
        let app = tracked.app.as_mut()?;
        let program = program.unwrap_or(app.program);
        let before = cur.ctx.group.uploaded(program, loc, m);
        app.current.uploaded(program, loc, m, before);
        Some(())
    });
}

pub(crate) fn glUniformMatrix4fv(
    real: impl Fn(GLint, GLsizei, GLboolean, *const GLfloat),
    loc: GLint,
    count: GLsizei,
    transpose: GLboolean,
    value: *const GLfloat,
) {
    real(loc, count, transpose, value);
    if crate::config::settings().multiview() {
        // SAFETY: glUniformMatrix4fv reads `count` matrices from `value`.
        let first = unsafe { first_matrix(value, count) };
        track_matrix(None, loc, transpose, first);
    }
}

pub(crate) fn glProgramUniformMatrix4fv(
    real: impl Fn(GLuint, GLint, GLsizei, GLboolean, *const GLfloat),
    program: GLuint,
    loc: GLint,
    count: GLsizei,
    transpose: GLboolean,
    value: *const GLfloat,
) {
    real(program, loc, count, transpose, value);
    if crate::config::settings().multiview() {
        // SAFETY: glProgramUniformMatrix4fv reads `count` matrices from `value`.
        let first = unsafe { first_matrix(value, count) };
        track_matrix(Some(program), loc, transpose, first);
    }
}

/// A `vec4` array upload that covers all four elements of a program's projection held there
/// (`ProgramInfo::projection_vec4`, wined3d's `vs_c[]`) is that matrix's upload. Only
/// looked at once such a program was linked.
fn track_vec4(program: Option<u32>, loc: GLint, count: GLsizei, value: *const GLfloat) {
    if !crate::state::share::VEC4_PROJECTIONS.load(std::sync::atomic::Ordering::Relaxed) || loc < 0 || count < 4 {
        return;
    }
    crate::state::with_current(|cur| {
        let cur = cur?;
        let mut tracked = cur.ctx.tracked()?;
        let app = tracked.app.as_mut()?;
        let program = program.unwrap_or(app.program);
        let (first, rows) = cur.ctx.group.vec4_projection(program)?;
        if first < loc || first + 4 > loc.saturating_add(count) {
            return None;
        }
        // SAFETY: glUniform4fv reads `count` vec4s from `value`.
        let all = unsafe { super::super::app_slice(value, count.saturating_mul(4)) };
        let at = (first - loc) as usize * 4;
        let m: &[f32; 16] = all.get(at..at + 16)?.try_into().ok()?;
        // Rows laid out one after another are the matrix transposed, as GL reads it.
        let m = column_major(m, GLboolean::from(rows));
        let before = cur.ctx.group.uploaded(program, first, m);
        app.current.uploaded(program, first, m, before);
        Some(())
    });
}

pub(crate) fn glUniform4fv(
    real: impl Fn(GLint, GLsizei, *const GLfloat),
    loc: GLint,
    count: GLsizei,
    value: *const GLfloat,
) {
    real(loc, count, value);
    if crate::config::settings().multiview() {
        track_vec4(None, loc, count, value);
    }
}

pub(crate) fn glProgramUniform4fv(
    real: impl Fn(GLuint, GLint, GLsizei, *const GLfloat),
    program: GLuint,
    loc: GLint,
    count: GLsizei,
    value: *const GLfloat,
) {
    real(program, loc, count, value);
    if crate::config::settings().multiview() {
        track_vec4(Some(program), loc, count, value);
    }
}
