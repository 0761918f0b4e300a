//! Where the presenter draws when the window is multisampled: a blit into a multisampled
//! framebuffer cannot scale (GL_INVALID_OPERATION; on ES it cannot write into one at all),
//! and the quilt, side-by-side and fitted outputs scale. They are drawn into this
//! window-sized single-sampled image, which a pass (`glsl-patches/copy.frag`) then copies
//! pixel for pixel into the window: every sample of a pixel gets the pixel's value, so the
//! window's own resolve at the swap gives it back unchanged.

use super::pass::{self, Passes};
use crate::gl::GlInfo;
use crate::gl::*;

pub const COPY_FRAG: &str = include_str!("../../glsl-patches/copy.frag");

pub struct Staging {
    pub fbo: u32,
    pub color: u32,
    size: (u32, u32),
    format: GLenum,
}

/// The linear format of the same bits: the copy pass reads stored values, and an sRGB
/// texture would be decoded.
fn linear(format: GLenum) -> GLenum {
    match format {
        SRGB8_ALPHA8 => RGBA8,
        SRGB8 => RGB8,
        f => f,
    }
}

impl Staging {
    /// `staging` made (or remade) `size` pixels holding `format` (the quilt's colour format,
    /// so that nothing is rounded on the way); returns its framebuffer.
    pub fn ensure(gl: &Gl, staging: &mut Option<Staging>, size: (u32, u32), format: GLenum) -> u32 {
        let format = linear(format);
        if let Some(s) = staging.as_ref().filter(|s| (s.size, s.format) != (size, format)) {
            s.delete(gl);
            *staging = None;
        }
        let s = staging.get_or_insert_with(|| {
            let (fbo, color) = pass::color_target(gl, format, size);
            Staging {
                fbo,
                color,
                size,
                format,
            }
        });
        s.fbo
    }

    /// Copies the staged image into the framebuffer bound for drawing (the window), with the
    /// caller's pass state (`StateGuard::for_pass`, neutral state).
    pub fn show(&self, gl: &Gl, info: GlInfo, passes: &mut Passes) -> Result<(), String> {
        let program = passes.program(gl, info, "copy", COPY_FRAG)?;
        // SAFETY: our program and texture on unit 0; the caller's guard restores them and the
        // viewport.
        unsafe {
            gl.Viewport(0, 0, self.size.0 as i32, self.size.1 as i32);
            gl.UseProgram(program);
            gl.ActiveTexture(TEXTURE0);
            gl.BindTexture(TEXTURE_2D, self.color);
            gl.Uniform1i(pass::uniform(gl, program, "u_image"), 0);
        }
        passes.draw(gl);
        Ok(())
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteFramebuffers(1, &self.fbo);
            gl.DeleteTextures(1, &self.color);
        }
    }
}
