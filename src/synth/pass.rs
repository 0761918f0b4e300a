//! What every warp's passes share: the context they run in (`Pass`: our framebuffer, vertex
//! array, programs and working storage), the state guard that puts back what they change,
//! the copies of the sources into our arrays and the parallax pass every warp starts with.
//! The grid, row and per-pixel warps each build on it; none of them owns it.

use super::programs::Programs;
use super::resources::Resources;
use super::{Job, Source};
use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::*;

/// Everything the passes change, put back when dropped.
pub fn guard(gl: &Gl, info: GlInfo) -> StateGuard<'_> {
    StateGuard::new(gl, info)
        .framebuffers()
        .for_pass()
        .scissor()
        .depth_func()
        .textures(TEXTURE_2D_ARRAY, TEXTURE_BINDING_2D_ARRAY, 0..4)
        .textures(TEXTURE_BUFFER, TEXTURE_BINDING_BUFFER, 4..5)
        .samplers(0..5)
        .depth_range()
        .buffer(ARRAY_BUFFER, ARRAY_BUFFER_BINDING)
        .buffer(DRAW_INDIRECT_BUFFER, DRAW_INDIRECT_BUFFER_BINDING)
        .indexed_buffers(
            SHADER_STORAGE_BUFFER,
            SHADER_STORAGE_BUFFER_BINDING,
            SHADER_STORAGE_BUFFER_START,
            SHADER_STORAGE_BUFFER_SIZE,
            0..5,
        )
}

/// The context's clip depth mode is `GL_ZERO_TO_ONE` (GL 4.5 `glClipControl`).
pub fn zero_to_one(gl: &Gl) -> bool {
    gl.ClipControl.is_loaded() && crate::gl::guard::get_i(gl, CLIP_DEPTH_MODE) as u32 == ZERO_TO_ONE
}

// The passes set many uniforms: a short name keeps each call on one line.
pub use crate::gl::program::uniform as loc;

/// What a warp's passes run with: our framebuffer and vertex array, the programs and the
/// working storage of this context.
pub struct Pass<'a> {
    pub gl: &'a Gl,
    pub info: GlInfo,
    pub programs: &'a Programs,
    pub res: &'a Resources,
    pub fbo: u32,
    pub vao: u32,
    /// The sources' depth is in our array already (`Synthesizer::capture_depth`).
    pub depth_ready: bool,
    /// Bit j: source j's disparity record is in `res.record` (else its depth is converted).
    pub recorded: u64,
}

/// Each source's disparity record (read framebuffer, rectangle, and its guard band) into its
/// layer of our record array, scaled to the tile like its depth; the bits of those copied.
pub fn copy_records(gl: &Gl, fbo: u32, res: &Resources, job: &Job) -> u64 {
    let mut bits = 0;
    for (j, s) in job.sources.iter().enumerate().take(64) {
        let Some(src) = s.record else { continue };
        detach_all(gl, fbo);
        attach(gl, fbo, COLOR_ATTACHMENT0, res.record, j);
        for (from, to) in s.parts(src.1, job.tile, job.guard) {
            blit(gl, src.0, from, to, COLOR_BUFFER_BIT);
        }
        bits |= 1 << j;
    }
    detach_all(gl, fbo);
    bits
}

/// Attaches layer `layer` of `texture` (0: nothing) at `point` of our framebuffer `fbo`,
/// bound for drawing.
fn attach(gl: &Gl, fbo: u32, point: GLenum, texture: u32, layer: usize) {
    // SAFETY: our own framebuffer and textures.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
        gl.FramebufferTextureLayer(DRAW_FRAMEBUFFER, point, texture, 0, layer as i32);
    }
}

fn detach_all(gl: &Gl, fbo: u32) {
    for point in [COLOR_ATTACHMENT0, DEPTH_ATTACHMENT, STENCIL_ATTACHMENT] {
        attach(gl, fbo, point, 0, 0);
    }
}

/// `r` of framebuffer `read` onto `d` of the bound draw framebuffer.
fn blit(gl: &Gl, read: u32, r: [i32; 4], d: [i32; 4], mask: u32) {
    // SAFETY: a blit between a framebuffer of the layer's and ours.
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, read);
        gl.BlitFramebuffer(
            r[0],
            r[1],
            r[0] + r[2],
            r[1] + r[3],
            d[0],
            d[1],
            d[0] + d[2],
            d[1] + d[3],
            mask,
            NEAREST,
        );
    }
}

/// The depth of `src` (framebuffer, and its parts: each rectangle and where it goes,
/// `Source::parts`) into layer `j` of our depth array through our framebuffer `fbo` (depth
/// blits need the source's own format, which our array has).
pub fn copy_depth(gl: &Gl, fbo: u32, res: &Resources, j: usize, src: (u32, &[super::Part]), format: GLenum) {
    let stencil = matches!(format, DEPTH24_STENCIL8 | DEPTH32F_STENCIL8);
    let point = if stencil {
        DEPTH_STENCIL_ATTACHMENT
    } else {
        DEPTH_ATTACHMENT
    };
    detach_all(gl, fbo);
    attach(gl, fbo, point, res.depth, j);
    // SAFETY: no colour buffer to draw into while only depth is attached.
    unsafe { gl.DrawBuffer(NONE) };
    for &(from, to) in src.1 {
        blit(gl, src.0, from, to, DEPTH_BUFFER_BIT);
    }
    // SAFETY: our framebuffer's draw buffer back to its colour attachment.
    unsafe { gl.DrawBuffer(COLOR_ATTACHMENT0) };
    detach_all(gl, fbo);
}

impl Pass<'_> {
    /// Attaches layer `layer` of `texture` (0: nothing) at `point` of our framebuffer, bound
    /// for drawing.
    pub fn attach(&self, point: GLenum, texture: u32, layer: usize) {
        attach(self.gl, self.fbo, point, texture, layer);
    }

    /// The source's colour (and, unless `depth_ready`, its depth) into layer `j` of our
    /// arrays.
    pub fn copy_source(&self, j: usize, s: &Source, job: &Job) -> Result<(), String> {
        detach_all(self.gl, self.fbo);
        self.attach(COLOR_ATTACHMENT0, self.res.color, j);
        for (from, to) in s.parts(s.color.1, job.tile, job.guard) {
            blit(self.gl, s.color.0, from, to, COLOR_BUFFER_BIT);
        }
        detach_all(self.gl, self.fbo);
        if !self.depth_ready {
            let parts = s.parts(s.depth.1, job.tile, job.guard);
            copy_depth(self.gl, self.fbo, self.res, j, (s.depth.0, &parts), job.depth_format);
        }
        Ok(())
    }

    /// A full-screen pass of `program` into layer `j` of `texture`, `size` pixels.
    pub(super) fn fullscreen(&self, program: u32, texture: u32, j: usize, size: (i32, i32)) {
        self.attach(COLOR_ATTACHMENT0, texture, j);
        // SAFETY: our program, framebuffer and empty vertex array.
        unsafe {
            self.gl.Viewport(0, 0, size.0, size.1);
            self.gl.UseProgram(program);
            self.gl.BindVertexArray(self.vao);
            self.gl.DrawArrays(TRIANGLES, 0, 3);
        }
    }

    pub fn bind_array(&self, unit: u32, texture: u32) {
        // SAFETY: our texture on a unit the guard restores.
        unsafe {
            self.gl.ActiveTexture(TEXTURE0 + unit);
            self.gl.BindTexture(TEXTURE_2D_ARRAY, texture);
        }
    }

    /// Parallax per pixel of source `j`.
    pub fn parallax(&self, j: usize, job: &Job) {
        let (gl, p, res) = (self.gl, self.programs, self.res);
        self.bind_array(0, res.depth);
        self.bind_array(1, res.record);
        // SAFETY: uniforms of our own program.
        unsafe {
            gl.UseProgram(p.parallax);
            gl.Uniform1i(loc(gl, p.parallax, "u_depth"), 0);
            gl.Uniform1i(loc(gl, p.parallax, "u_record"), 1);
            gl.Uniform1i(loc(gl, p.parallax, "u_recorded"), (self.recorded >> j & 1) as i32);
            gl.Uniform1i(loc(gl, p.parallax, "u_layer"), j as i32);
            let m = job.model;
            gl.Uniform4f(loc(gl, p.parallax, "u_model"), m.a_hi, m.a_lo, m.scale, 0.0);
            let r = job.remap;
            gl.Uniform4f(loc(gl, p.parallax, "u_remap"), r[0], r[1], r[2], r[3]);
            let k = job.depthiness * job.tile.0 as f64 / 2.0;
            gl.Uniform1f(loc(gl, p.parallax, "u_px_per_parallax"), k as f32);
        }
        self.fullscreen(p.parallax, res.parallax, j, res.tile);
        self.attach(COLOR_ATTACHMENT0, 0, 0);
    }
}
