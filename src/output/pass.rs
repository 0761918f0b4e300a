//! Our own full-screen passes (lenticular weave, anaglyph), compiled once per context from
//! `glsl-patches/`. Sources are written as GLSL 3.30 core; ES 3 contexts get the same code
//! under `#version 300 es` with explicit precision.

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

fn for_context(source: &str, info: GlInfo) -> String {
    if !info.es {
        return source.to_string();
    }
    let body = source.split_once('\n').map_or("", |(_, rest)| rest);
    format!("#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n{body}")
}

fn compile(gl: &Gl, kind: GLenum, source: &str) -> Result<u32, String> {
    let c = CString::new(source).map_err(|_| "NUL in shader source")?;
    // SAFETY: creating and compiling our own shader object.
    unsafe {
        let s = gl.CreateShader(kind);
        gl.ShaderSource(s, 1, &c.as_ptr(), core::ptr::null());
        gl.CompileShader(s);
        let mut ok = 0;
        gl.GetShaderiv(s, COMPILE_STATUS, &mut ok);
        if ok == 0 {
            let log = info_log(|n, l, b| gl.GetShaderInfoLog(s, n, l, b));
            gl.DeleteShader(s);
            return Err(log);
        }
        Ok(s)
    }
}

fn info_log(get: impl Fn(i32, *mut i32, *mut types::GLchar)) -> String {
    let mut buf = vec![0u8; 4096];
    let mut n = 0;
    get(buf.len() as i32, &mut n, buf.as_mut_ptr().cast());
    buf.truncate(n.max(0) as usize);
    String::from_utf8_lossy(&buf).lines().next().unwrap_or("").to_string()
}

fn link(gl: &Gl, info: GlInfo, frag: &str) -> Result<u32, String> {
    let vs = compile(gl, VERTEX_SHADER, &for_context(FULLSCREEN_VERT, info))?;
    let fs = compile(gl, FRAGMENT_SHADER, &for_context(frag, info))?;
    // SAFETY: linking our own program from our own shaders.
    unsafe {
        let p = gl.CreateProgram();
        gl.AttachShader(p, vs);
        gl.AttachShader(p, fs);
        gl.LinkProgram(p);
        gl.DeleteShader(vs);
        gl.DeleteShader(fs);
        let mut ok = 0;
        gl.GetProgramiv(p, LINK_STATUS, &mut ok);
        if ok == 0 {
            let log = info_log(|n, l, b| gl.GetProgramInfoLog(p, n, l, b));
            gl.DeleteProgram(p);
            return Err(log);
        }
        Ok(p)
    }
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
        let p = link(gl, info, frag).map_err(|e| format!("{name} pass: {e}"));
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

/// Fixed-function state a full-screen pass of ours must not inherit from the app (the caller
/// holds a `StateGuard::for_pass` that puts it all back).
pub fn neutral_state(gl: &Gl, info: GlInfo) {
    let mut off = vec![BLEND, DEPTH_TEST, STENCIL_TEST, CULL_FACE, SCISSOR_TEST, DITHER];
    if info.es || info.at_least(3, 0) {
        off.push(RASTERIZER_DISCARD);
    }
    if !info.es {
        off.extend([FRAMEBUFFER_SRGB, COLOR_LOGIC_OP]);
    }
    // SAFETY: toggles and masks valid in this context, restored by the caller's guard.
    unsafe {
        for cap in off {
            gl.Disable(cap);
        }
        gl.ColorMask(TRUE, TRUE, TRUE, TRUE);
        if !info.es {
            gl.PolygonMode(FRONT_AND_BACK, FILL);
        }
        if info.es && info.at_least(3, 0) || !info.es && info.at_least(3, 3) {
            gl.BindSampler(0, 0);
        }
    }
}
