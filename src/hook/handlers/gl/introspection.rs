//! Program introspection without the layer's own uniforms: `holoinject_view` and
//! `holoinject_fragcoord` are left out of the active-uniform count and list, and the app's
//! indices are renumbered around them, so engines that build uniform tables by enumeration
//! see exactly their own uniforms.

use crate::gl::types::*;

const ACTIVE_UNIFORMS: GLenum = 0x8B86;
const UNIFORM_INTERFACE: GLenum = 0x92E1;
const ACTIVE_RESOURCES: GLenum = 0x92F5;

/// Our uniforms' indices in `program` (ascending), when it has any.
fn hidden(program: GLuint) -> Option<Vec<u32>> {
    if !crate::config::settings().multiview() {
        return None;
    }
    crate::state::with_current(|cur| {
        let group = cur?.ctx.group.lock();
        group
            .programs
            .get(&program)
            .map(|p| p.hidden_uniforms.clone())
            .filter(|h| !h.is_empty())
    })
}

/// The real index of the app's `index`: every hidden index at or below it shifts it up.
fn real_index(hidden: &[u32], index: GLuint) -> GLuint {
    hidden
        .iter()
        .fold(index, |r, &h| if h <= r { r.saturating_add(1) } else { r })
}

fn map_index(program: GLuint, index: GLuint) -> GLuint {
    hidden(program).map_or(index, |h| real_index(&h, index))
}

/// Lowers a count the app gets by the number of our uniforms.
fn lower(count: Option<&mut GLint>, by: usize) {
    if let Some(count) = count {
        *count = (*count - by as GLint).max(0);
    }
}

pub(crate) fn glGetProgramiv(
    real: impl Fn(GLuint, GLenum, *mut GLint),
    program: GLuint,
    pname: GLenum,
    params: *mut GLint,
) {
    real(program, pname, params);
    if pname == ACTIVE_UNIFORMS
        && let Some(h) = hidden(program)
    {
        // SAFETY: GL_ACTIVE_UNIFORMS answers one integer into `params`, written just above.
        lower(unsafe { super::super::app_out(params) }, h.len());
    }
}

pub(crate) fn glGetActiveUniform(
    real: impl Fn(GLuint, GLuint, GLsizei, *mut GLsizei, *mut GLint, *mut GLenum, *mut GLchar),
    program: GLuint,
    index: GLuint,
    buf_size: GLsizei,
    length: *mut GLsizei,
    size: *mut GLint,
    type_: *mut GLenum,
    name: *mut GLchar,
) {
    real(program, map_index(program, index), buf_size, length, size, type_, name)
}

pub(crate) fn glGetActiveUniformName(
    real: impl Fn(GLuint, GLuint, GLsizei, *mut GLsizei, *mut GLchar),
    program: GLuint,
    index: GLuint,
    buf_size: GLsizei,
    length: *mut GLsizei,
    name: *mut GLchar,
) {
    real(program, map_index(program, index), buf_size, length, name)
}

pub(crate) fn glGetActiveUniformsiv(
    real: impl Fn(GLuint, GLsizei, *const GLuint, GLenum, *mut GLint),
    program: GLuint,
    count: GLsizei,
    indices: *const GLuint,
    pname: GLenum,
    params: *mut GLint,
) {
    // SAFETY: glGetActiveUniformsiv reads `count` indices from `indices`.
    let app = unsafe { super::super::app_slice(indices, count) };
    let Some(h) = hidden(program).filter(|_| !app.is_empty()) else {
        return real(program, count, indices, pname, params);
    };
    let mapped: Vec<GLuint> = app.iter().map(|&i| real_index(&h, i)).collect();
    real(program, count, mapped.as_ptr(), pname, params)
}

pub(crate) fn glGetProgramInterfaceiv(
    real: impl Fn(GLuint, GLenum, GLenum, *mut GLint),
    program: GLuint,
    interface: GLenum,
    pname: GLenum,
    params: *mut GLint,
) {
    real(program, interface, pname, params);
    if interface == UNIFORM_INTERFACE
        && pname == ACTIVE_RESOURCES
        && let Some(h) = hidden(program)
    {
        // SAFETY: GL_ACTIVE_RESOURCES answers one integer into `params`, written just above.
        lower(unsafe { super::super::app_out(params) }, h.len());
    }
}

pub(crate) fn glGetProgramResourceName(
    real: impl Fn(GLuint, GLenum, GLuint, GLsizei, *mut GLsizei, *mut GLchar),
    program: GLuint,
    interface: GLenum,
    index: GLuint,
    buf_size: GLsizei,
    length: *mut GLsizei,
    name: *mut GLchar,
) {
    let index = if interface == UNIFORM_INTERFACE {
        map_index(program, index)
    } else {
        index
    };
    real(program, interface, index, buf_size, length, name)
}

pub(crate) fn glGetProgramResourceiv(
    real: impl Fn(GLuint, GLenum, GLuint, GLsizei, *const GLenum, GLsizei, *mut GLsizei, *mut GLint),
    program: GLuint,
    interface: GLenum,
    index: GLuint,
    prop_count: GLsizei,
    props: *const GLenum,
    count: GLsizei,
    length: *mut GLsizei,
    params: *mut GLint,
) {
    let index = if interface == UNIFORM_INTERFACE {
        map_index(program, index)
    } else {
        index
    };
    real(program, interface, index, prop_count, props, count, length, params)
}

#[cfg(test)]
mod tests {
    use super::real_index;

    #[test]
    fn app_indices_skip_ours() {
        // Real list: a, ours(1), b, c, ours(4), d.
        let hidden = [1, 4];
        let got: Vec<u32> = (0..4).map(|i| real_index(&hidden, i)).collect();
        assert_eq!(got, vec![0, 2, 3, 5]);
        assert_eq!(real_index(&hidden, 4), 6, "one past the app's last stays out of range");
        assert_eq!(real_index(&[0], 0), 1);
    }
}
