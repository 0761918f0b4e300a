//! Our own full-screen passes (lenticular weave, anaglyph), compiled once per context from
//! `glsl-patches/` (by `gl::program`: GLSL 3.30 core, or `#version 300 es` on ES).

use crate::gl::GlInfo;
use crate::gl::*;

pub const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
pub const LENTICULAR_FRAG: &str = include_str!("../../glsl-patches/lenticular.frag");
pub const ANAGLYPH_FRAG: &str = include_str!("../../glsl-patches/anaglyph.frag");

/// Programs and the empty vertex array a full-screen triangle needs, per context.
#[derive(Default)]
pub struct Passes {
    pub vao: u32,
    programs: Vec<(&'static str, Result<u32, String>)>,
}

impl Passes {
    /// The program for fragment shader `frag` (named `name`), built on first use.
    pub fn program(&mut self, gl: &Gl, info: GlInfo, name: &'static str, frag: &str) -> Result<u32, String> {
        if self.vao == 0 {
            // SAFETY: our own empty vertex array.
            unsafe { gl.GenVertexArrays(1, &mut self.vao) };
        }
        if let Some((_, p)) = self.programs.iter().find(|(n, _)| *n == name) {
            return p.clone();
        }
        let p = crate::gl::program::link(gl, info, FULLSCREEN_VERT, frag).map_err(|e| format!("{name} pass: {e}"));
        self.programs.push((name, p.clone()));
        p
    }

    /// The programs linked so far (shared objects; the vertex array is per context).
    pub fn programs(&self) -> impl Iterator<Item = u32> + '_ {
        self.programs.iter().filter_map(|(_, p)| p.as_ref().ok().copied())
    }

    /// Draws the full-screen triangle with `program` bound (uniforms already set).
    pub fn draw(&self, gl: &Gl) {
        // SAFETY: our vertex array and a 3-vertex, attribute-less draw.
        unsafe {
            gl.BindVertexArray(self.vao);
            gl.DrawArrays(TRIANGLES, 0, 3);
        }
    }
}

pub use crate::gl::program::uniform;

/// A colour texture of `format`, `size` pixels (one level), and a framebuffer drawing into
/// it, as `(framebuffer, texture)`: what our passes draw into before the result is shown.
/// Both are left bound, for the caller's guard to restore.
pub fn color_target(gl: &Gl, format: GLenum, size: (u32, u32)) -> (u32, u32) {
    let (mut fbo, mut color) = (0, 0);
    // SAFETY: our own texture and framebuffer; the caller's guard restores the bindings.
    unsafe {
        gl.GenTextures(1, &mut color);
        gl.BindTexture(TEXTURE_2D, color);
        gl.TexStorage2D(TEXTURE_2D, 1, format, size.0 as i32, size.1 as i32);
        gl.GenFramebuffers(1, &mut fbo);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
        gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, color, 0);
    }
    (fbo, color)
}

/// Fixed-function state a full-screen pass of ours must not inherit from the app.
pub use crate::gl::guard::neutral_pass_state as neutral_state;
