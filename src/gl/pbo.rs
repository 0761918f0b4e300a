//! Asynchronous read-back through pixel pack buffers: `glReadPixels` into a buffer object
//! returns once the copy is queued, and the pixels are mapped a frame later, when the GPU has
//! long finished. Used by `--record`, which must not stall the program's frame for a
//! synchronous read of the whole quilt. Read state is saved and restored as in `readback`.

use super::readback::PixelStateGuard;
use super::{Gl, GlInfo};

/// Whether this context can read into buffer objects and map them.
pub fn available(gl: &Gl, info: GlInfo) -> bool {
    info.has_pack_buffer() && gl.MapBufferRange.is_loaded() && gl.ReadPixels.is_loaded()
}

/// A pack buffer of `bytes` bytes (GL_STREAM_READ).
pub fn create(gl: &Gl, bytes: usize) -> u32 {
    let mut pbo = 0;
    // SAFETY: our own buffer; the app's pack-buffer binding is put back.
    unsafe {
        let mut bound = 0;
        gl.GetIntegerv(super::PIXEL_PACK_BUFFER_BINDING, &mut bound);
        gl.GenBuffers(1, &mut pbo);
        gl.BindBuffer(super::PIXEL_PACK_BUFFER, pbo);
        gl.BufferData(
            super::PIXEL_PACK_BUFFER,
            bytes as isize,
            std::ptr::null(),
            super::STREAM_READ,
        );
        gl.BindBuffer(super::PIXEL_PACK_BUFFER, bound as u32);
    }
    pbo
}

/// Queues a read of `rect` of colour attachment 0 of framebuffer `fbo` as RGBA8 into `pbo`.
pub fn start_read(gl: &Gl, info: GlInfo, fbo: u32, rect: [i32; 4], pbo: u32) {
    use super::*;
    let guard = PixelStateGuard::save(gl, info);
    // SAFETY: `pbo` holds at least w*h*4 bytes (the caller made it for this size); alignment 1
    // and no row length or skips, so the read writes exactly that range of it.
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
        gl.ReadBuffer(COLOR_ATTACHMENT0);
        gl.BindBuffer(PIXEL_PACK_BUFFER, pbo);
        guard.pack_tightly(gl, 1);
        gl.ReadPixels(
            rect[0],
            rect[1],
            rect[2],
            rect[3],
            RGBA,
            UNSIGNED_BYTE,
            std::ptr::null_mut(),
        );
    }
    drop(guard);
}

/// The `bytes` bytes a finished [`start_read`] left in `pbo`.
pub fn take(gl: &Gl, pbo: u32, bytes: usize) -> Result<Vec<u8>, String> {
    use super::*;
    // SAFETY: mapping our own buffer for reading `bytes` (its size); the copy is done before
    // unmapping, and the app's pack-buffer binding is put back.
    unsafe {
        let mut bound = 0;
        gl.GetIntegerv(PIXEL_PACK_BUFFER_BINDING, &mut bound);
        gl.BindBuffer(PIXEL_PACK_BUFFER, pbo);
        let p = gl.MapBufferRange(PIXEL_PACK_BUFFER, 0, bytes as isize, MAP_READ_BIT);
        let out = if p.is_null() {
            Err("the read-back buffer could not be mapped".to_string())
        } else {
            let v = std::slice::from_raw_parts(p as *const u8, bytes).to_vec();
            gl.UnmapBuffer(PIXEL_PACK_BUFFER);
            Ok(v)
        };
        gl.BindBuffer(PIXEL_PACK_BUFFER, bound as u32);
        out
    }
}

pub fn delete(gl: &Gl, pbos: &[u32]) {
    // SAFETY: deleting our own buffers.
    unsafe { gl.DeleteBuffers(pbos.len() as i32, pbos.as_ptr()) };
}
