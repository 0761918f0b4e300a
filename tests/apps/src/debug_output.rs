//! `--debug-output`: every GL error the context reports (KHR_debug, `GL_DEBUG_OUTPUT` in
//! synchronous mode) is counted and the count printed at exit, so a test can show that a
//! layer between the app and GL introduces none — not only at the app's `glGetError` calls.

use crate::gl::{self, Gl};
use std::ffi::c_void;
use std::sync::atomic::{AtomicU64, Ordering};

static ERRORS: AtomicU64 = AtomicU64::new(0);

extern "system" fn on_message(
    _source: gl::types::GLenum,
    ty: gl::types::GLenum,
    _id: gl::types::GLuint,
    _severity: gl::types::GLenum,
    length: gl::types::GLsizei,
    message: *const gl::types::GLchar,
    _user: *mut c_void,
) {
    if ty == gl::DEBUG_TYPE_ERROR {
        ERRORS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: GL passes `length` bytes of message text.
        let text = unsafe { std::slice::from_raw_parts(message.cast::<u8>(), length.max(0) as usize) };
        eprintln!("gl-debug: error: {}", String::from_utf8_lossy(text));
    }
}

/// Turns on synchronous debug output with our callback (GL 4.3 / KHR_debug).
pub fn enable(gl: &Gl) -> Result<(), String> {
    if !gl.DebugMessageCallback.is_loaded() {
        return Err("--debug-output needs KHR_debug (GL 4.3)".into());
    }
    unsafe {
        gl.Enable(gl::DEBUG_OUTPUT);
        gl.Enable(gl::DEBUG_OUTPUT_SYNCHRONOUS);
        gl.DebugMessageCallback(Some(on_message), std::ptr::null());
        // Proves the channel works: one deliberate GL_INVALID_ENUM.
        if std::env::var_os("HOLOAPPS_DEBUG_SELFTEST").is_some() {
            gl.Enable(0xFFFF);
        }
    }
    Ok(())
}

pub fn report() {
    eprintln!("gl-debug: errors={}", ERRORS.load(Ordering::Relaxed));
}
