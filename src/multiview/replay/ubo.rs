//! Projections that live in uniform blocks (`layout(std140) uniform Camera { mat4
//! projection; … }`). Their uploads go through buffer objects, not `glUniform*`, so the
//! matrix is read back from the bound buffer range — only after a write that can reach a
//! uniform binding (tracked by the buffer hooks), because on a real GPU a buffer read can
//! wait for it. Vertex and index uploads, by far the most frequent writes, cost nothing here
//! unless a program with a block-held projection exists and the written buffer has been bound
//! to a uniform binding. (Persistently mapped, coherent buffers change without a call: those
//! stay stale.)

use crate::gl::*;
use crate::state::share::UboMember;
use std::collections::HashSet;
use std::ffi::CString;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

static GENERATION: AtomicU64 = AtomicU64::new(1);
/// A program whose projection lives in a uniform block has been linked (in any context).
static BLOCK_PROJECTIONS: AtomicBool = AtomicBool::new(false);
/// Buffers bound to an indexed uniform-buffer binding at some point (names are shared by the
/// share group; one set for the process errs on the side of reading again).
static UNIFORM_BUFFERS: Mutex<Option<HashSet<u32>>> = Mutex::new(None);

fn changed() {
    GENERATION.fetch_add(1, Ordering::Relaxed);
}

fn uniform_buffers() -> std::sync::MutexGuard<'static, Option<HashSet<u32>>> {
    UNIFORM_BUFFERS.lock().unwrap_or_else(|e| e.into_inner())
}

/// `glBindBufferBase`/`Range(target, …, buffer)`.
pub fn bound(target: GLenum, buffer: u32) {
    if target == UNIFORM_BUFFER {
        uniform_buffers().get_or_insert_with(HashSet::new).insert(buffer);
        changed();
    }
}

/// A write to the buffer named `buffer` (direct state access).
pub fn wrote_buffer(buffer: u32) {
    if BLOCK_PROJECTIONS.load(Ordering::Relaxed) && uniform_buffers().as_ref().is_some_and(|s| s.contains(&buffer)) {
        changed();
    }
}

/// A write to the buffer bound to `target` (asked of GL only when it could matter).
pub fn wrote_target(gl: &Gl, target: GLenum) {
    if !BLOCK_PROJECTIONS.load(Ordering::Relaxed) {
        return;
    }
    match binding_of(target) {
        Some(pname) => wrote_buffer(crate::gl::guard::get_i(gl, pname) as u32),
        None => changed(),
    }
}

/// The binding query of a buffer target (None: one the layer does not know; assume it
/// matters).
fn binding_of(target: GLenum) -> Option<GLenum> {
    Some(match target {
        ARRAY_BUFFER => ARRAY_BUFFER_BINDING,
        ELEMENT_ARRAY_BUFFER => ELEMENT_ARRAY_BUFFER_BINDING,
        UNIFORM_BUFFER => UNIFORM_BUFFER_BINDING,
        COPY_READ_BUFFER => COPY_READ_BUFFER_BINDING,
        COPY_WRITE_BUFFER => COPY_WRITE_BUFFER_BINDING,
        PIXEL_PACK_BUFFER => PIXEL_PACK_BUFFER_BINDING,
        PIXEL_UNPACK_BUFFER => PIXEL_UNPACK_BUFFER_BINDING,
        TRANSFORM_FEEDBACK_BUFFER => TRANSFORM_FEEDBACK_BUFFER_BINDING,
        SHADER_STORAGE_BUFFER => SHADER_STORAGE_BUFFER_BINDING,
        DRAW_INDIRECT_BUFFER => DRAW_INDIRECT_BUFFER_BINDING,
        DISPATCH_INDIRECT_BUFFER => DISPATCH_INDIRECT_BUFFER_BINDING,
        ATOMIC_COUNTER_BUFFER => ATOMIC_COUNTER_BUFFER_BINDING,
        QUERY_BUFFER => QUERY_BUFFER_BINDING,
        _ => return None,
    })
}

pub fn generation() -> u64 {
    GENERATION.load(Ordering::Relaxed)
}

/// The block member called `name` in `program`, if it is one (desktop GL 3.1+); from then
/// on, buffer writes are followed.
pub fn find(gl: &Gl, program: u32, name: &str) -> Option<UboMember> {
    let found = find_member(gl, program, name);
    if found.is_some() {
        BLOCK_PROJECTIONS.store(true, Ordering::Relaxed);
        changed();
    }
    found
}

fn find_member(gl: &Gl, program: u32, name: &str) -> Option<UboMember> {
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
