//! Framebuffer read-back and PNG output.
use crate::gl::{self, Gl};
use std::path::Path;

/// Reads the bound read framebuffer as RGBA and returns top-down RGB rows.
pub fn read_rgb(gl: &Gl, w: u32, h: u32) -> Vec<u8> {
    let mut rgba = vec![0u8; w as usize * h as usize * 4];
    unsafe {
        gl.PixelStorei(gl::PACK_ALIGNMENT, 1);
        gl.ReadPixels(
            0,
            0,
            w as i32,
            h as i32,
            gl::RGBA,
            gl::UNSIGNED_BYTE,
            rgba.as_mut_ptr().cast(),
        );
    }
    let row = w as usize * 4;
    let mut rgb = Vec::with_capacity(w as usize * h as usize * 3);
    // GL rows start at the bottom; PNG rows at the top.
    for r in rgba.chunks_exact(row).rev() {
        for px in r.chunks_exact(4) {
            rgb.extend_from_slice(&px[..3]);
        }
    }
    rgb
}

/// OpenGL ES context? ES 2.0 has neither glReadBuffer nor GL_DRAW_BUFFER, and
/// ES reads the one colour buffer of the default framebuffer anyway.
pub fn is_es(gl: &Gl) -> bool {
    let v = unsafe { gl.GetString(gl::VERSION) };
    !v.is_null()
        && unsafe { std::ffi::CStr::from_ptr(v.cast()) }
            .to_bytes()
            .starts_with(b"OpenGL ES")
}

/// Screenshot of the default framebuffer, from the buffer being drawn to
/// (GL_BACK for double-buffered windows, GL_FRONT/BACK for pbuffers).
pub fn read_default_framebuffer(gl: &Gl, w: u32, h: u32) -> Vec<u8> {
    unsafe {
        gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        if !is_es(gl) {
            let mut buf = 0;
            gl.GetIntegerv(gl::DRAW_BUFFER, &mut buf);
            gl.ReadBuffer(buf as u32);
        }
        let mut samples = 0;
        gl.GetIntegerv(gl::SAMPLE_BUFFERS, &mut samples);
        if samples > 0 {
            return read_resolved(gl, w, h);
        }
    }
    read_rgb(gl, w, h)
}

/// A multisampled default framebuffer as it is shown: resolved by a blit (Mesa's
/// glReadPixels of it returns each pixel's first sample instead).
unsafe fn read_resolved(gl: &Gl, w: u32, h: u32) -> Vec<u8> {
    let (mut fbo, mut rb) = (0, 0);
    let (wi, hi) = (w as i32, h as i32);
    unsafe {
        gl.GenRenderbuffers(1, &mut rb);
        gl.BindRenderbuffer(gl::RENDERBUFFER, rb);
        gl.RenderbufferStorage(gl::RENDERBUFFER, gl::RGBA8, wi, hi);
        gl.GenFramebuffers(1, &mut fbo);
        gl.BindFramebuffer(gl::DRAW_FRAMEBUFFER, fbo);
        gl.FramebufferRenderbuffer(gl::DRAW_FRAMEBUFFER, gl::COLOR_ATTACHMENT0, gl::RENDERBUFFER, rb);
        // The stored values, neither scissored nor converted.
        let caps = if is_es(gl) {
            &[gl::SCISSOR_TEST][..]
        } else {
            &[gl::SCISSOR_TEST, gl::FRAMEBUFFER_SRGB]
        };
        let on: Vec<bool> = caps.iter().map(|&c| gl.IsEnabled(c) != 0).collect();
        caps.iter().for_each(|&c| gl.Disable(c));
        gl.BlitFramebuffer(0, 0, wi, hi, 0, 0, wi, hi, gl::COLOR_BUFFER_BIT, gl::NEAREST);
        for (&c, _) in caps.iter().zip(&on).filter(|(_, on)| **on) {
            gl.Enable(c);
        }
        gl.BindFramebuffer(gl::FRAMEBUFFER, fbo);
        let rgb = read_rgb(gl, w, h);
        gl.BindFramebuffer(gl::FRAMEBUFFER, 0);
        gl.DeleteFramebuffers(1, &fbo);
        gl.DeleteRenderbuffers(1, &rb);
        rgb
    }
}

/// OpenGL ES cannot read GL_DEPTH_COMPONENT with glReadPixels (checked at start-up, so the
/// app does not render all its frames before failing).
pub fn check_depth_readable(gl: &Gl) -> Result<(), String> {
    if is_es(gl) {
        return Err(
            "--depth-out/--reference-depth-out need desktop OpenGL: OpenGL ES cannot glReadPixels GL_DEPTH_COMPONENT"
                .into(),
        );
    }
    Ok(())
}

/// Depth of the default framebuffer as floats in [0, 1], rows bottom-up (GL order).
pub fn read_default_depth(gl: &Gl, w: u32, h: u32) -> Result<Vec<f32>, String> {
    unsafe { gl.BindFramebuffer(gl::FRAMEBUFFER, 0) };
    read_depth(gl, w, h)
}

/// Depth of the bound read framebuffer as floats in [0, 1], rows bottom-up.
pub fn read_depth(gl: &Gl, w: u32, h: u32) -> Result<Vec<f32>, String> {
    check_depth_readable(gl)?;
    let mut depth = vec![0f32; w as usize * h as usize];
    unsafe {
        gl.PixelStorei(gl::PACK_ALIGNMENT, 4);
        gl.ReadPixels(
            0,
            0,
            w as i32,
            h as i32,
            gl::DEPTH_COMPONENT,
            gl::FLOAT,
            depth.as_mut_ptr().cast(),
        );
    }
    Ok(depth)
}

/// Raw little-endian f32 values, no header (`numpy.fromfile(path, '<f4')`).
pub fn write_f32(path: &Path, values: &[f32]) -> Result<(), String> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).map_err(|e| format!("writing {}: {e}", path.display()))
}

pub fn write_png(path: &Path, w: u32, h: u32, rgb: &[u8]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("writing {}: {e}", path.display());
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut wr = enc.write_header().map_err(|e| err(&e))?;
    wr.write_image_data(rgb).map_err(|e| err(&e))
}
