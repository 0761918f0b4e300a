//! Projections that live in uniform blocks (`layout(std140) uniform Camera { mat4
//! projection; … }`). Their uploads go through buffer objects, not `glUniform*`, so the
//! matrix is read back from the bound buffer range — only after a buffer write or binding
//! change (tracked by the buffer hooks), because on a real GPU a buffer read can wait for it.

use crate::gl::*;
use crate::state::share::UboMember;
use std::ffi::CString;
use std::sync::atomic::{AtomicU64, Ordering};

static GENERATION: AtomicU64 = AtomicU64::new(1);

/// Any buffer write or uniform-buffer binding change may have changed a block-held matrix.
/// (Persistently mapped, coherent buffers change without a call: those stay stale.)
pub fn buffers_changed() {
    GENERATION.fetch_add(1, Ordering::Relaxed);
}

pub fn generation() -> u64 {
    GENERATION.load(Ordering::Relaxed)
}

/// The block member called `name` in `program`, if it is one (desktop GL 3.1+).
pub fn find(gl: &Gl, program: u32, name: &str) -> Option<UboMember> {
    if !gl.GetUniformIndices.is_loaded() || !gl.GetActiveUniformsiv.is_loaded() {
        return None;
    }
    let c = CString::new(name).ok()?;
    let mut index = INVALID_INDEX;
    // SAFETY: one NUL-terminated name, one index out.
    unsafe { gl.GetUniformIndices(program, 1, &c.as_ptr(), &mut index) };
    if index == INVALID_INDEX {
        return None;
    }
    let query = |pname: GLenum| {
        let mut v = -1;
        // SAFETY: one uniform index, one integer answer.
        unsafe { gl.GetActiveUniformsiv(program, 1, &index, pname, &mut v) };
        v
    };
    let block = query(UNIFORM_BLOCK_INDEX);
    (block >= 0).then(|| UboMember {
        block: block as u32,
        offset: query(UNIFORM_OFFSET),
        row_major: query(UNIFORM_IS_ROW_MAJOR) != 0,
    })
}

/// The member's current value (column-major), read from the buffer bound to its block.
pub fn read(gl: &Gl, program: u32, m: UboMember) -> Option<[f32; 16]> {
    if !gl.GetNamedBufferSubData.is_loaded() {
        return None;
    }
    let (mut binding, mut buffer, mut start) = (0i32, 0i32, 0i64);
    // SAFETY: single-value queries; the buffer read below writes 64 bytes into `m16`.
    unsafe {
        gl.GetActiveUniformBlockiv(program, m.block, UNIFORM_BLOCK_BINDING, &mut binding);
        gl.GetIntegeri_v(UNIFORM_BUFFER_BINDING, binding as u32, &mut buffer);
        gl.GetInteger64i_v(UNIFORM_BUFFER_START, binding as u32, &mut start);
    }
    if buffer <= 0 {
        return None;
    }
    let mut m16 = [0f32; 16];
    let mut size = 0i64;
    // SAFETY: reading 64 bytes only when the buffer holds them.
    unsafe {
        gl.GetNamedBufferParameteri64v(buffer as u32, BUFFER_SIZE, &mut size);
        if start + m.offset as i64 + 64 > size {
            return None;
        }
        gl.GetNamedBufferSubData(
            buffer as u32,
            (start + m.offset as i64) as isize,
            64,
            m16.as_mut_ptr().cast(),
        );
    }
    if m.row_major {
        let t = m16;
        for r in 0..4 {
            for c in 0..4 {
                m16[c * 4 + r] = t[r * 4 + c];
            }
        }
    }
    Some(m16)
}
