//! Our own full-screen passes (lenticular weave, anaglyph), compiled once per context from
//! `glsl-patches/` (by `gl::program`: GLSL 3.30 core, or `#version 300 es` on ES).

use crate::gl::GlInfo;
use crate::gl::*;
use std::ffi::CString;

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

pub fn uniform(gl: &Gl, program: u32, name: &str) -> i32 {
    let c = CString::new(name).unwrap_or_default();
    // SAFETY: a NUL-terminated name for our linked program.
    unsafe { gl.GetUniformLocation(program, c.as_ptr()) }
}

/// Fixed-function state a full-screen pass of ours must not inherit from the app.
pub use crate::gl::guard::neutral_pass_state as neutral_state;
