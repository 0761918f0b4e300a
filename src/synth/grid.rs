//! The passes of the adaptive quad-grid warp (see the module comment of `synth`).

use super::programs::Programs;
use super::resources::{COMMAND_STRIDE, LEVELS, Resources, level_size};
use super::{Job, Source};
use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::*;
use std::ffi::CString;

/// Rows of a column segment (`SEGMENT` in synth_columns.comp).
const COLUMN_SEGMENT: u32 = 32;

/// Window depth between a stretched (disocclusion) quad and the surface it lies on.
const STRETCHED_BIAS: f32 = 1.0 / 16384.0;

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

pub fn loc(gl: &Gl, program: u32, name: &str) -> i32 {
    let c = CString::new(name).unwrap_or_default();
    // SAFETY: a NUL-terminated name for our linked program.
    unsafe { gl.GetUniformLocation(program, c.as_ptr()) }
}

pub struct Pass<'a> {
    pub gl: &'a Gl,
    pub programs: &'a Programs,
    pub res: &'a Resources,
    pub fbo: u32,
    pub vao: u32,
    /// The sources' depth is in our array already (`Synthesizer::capture_depth`).
    pub depth_ready: bool,
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

/// `rect` of framebuffer `read` onto the bound draw framebuffer's `(w, h)`.
fn blit(gl: &Gl, read: u32, r: [i32; 4], (w, h): (i32, i32), mask: u32) {
    // SAFETY: a blit between a framebuffer of the layer's and ours.
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, read);
        gl.BlitFramebuffer(r[0], r[1], r[0] + r[2], r[1] + r[3], 0, 0, w, h, mask, NEAREST);
    }
}

/// The depth of `src` (framebuffer, rectangle) into layer `j` of our depth array through our
/// framebuffer `fbo` (depth blits need the source's own format, which our array has).
pub fn copy_depth(gl: &Gl, fbo: u32, res: &Resources, j: usize, src: (u32, [i32; 4]), format: GLenum) {
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
    blit(gl, src.0, src.1, res.tile, DEPTH_BUFFER_BIT);
    // SAFETY: our framebuffer's draw buffer back to its colour attachment.
    unsafe { gl.DrawBuffer(COLOR_ATTACHMENT0) };
    detach_all(gl, fbo);
}

impl Pass<'_> {
    pub fn run(&self, job: &Job) -> Result<(), String> {
        if !(self.programs.has_grid() && self.res.has_grid()) {
            return Err("the grid's programs or storage are missing".into());
        }
        let mut profile = super::profile::Profile::new(self.gl);
        for (j, source) in job.sources.iter().enumerate() {
            self.copy_source(j, source, job)?;
            profile.lap("copy");
            self.parallax(j, job);
            self.pyramid(j);
            profile.lap("pyramid");
            self.list_leaves(j, job);
            profile.lap("grid");
            if profile.on() {
                profile.leaves += self.leaf_count(j);
            }
        }
        // SAFETY: the leaf lists are read as vertex attributes and draw commands next.
        unsafe {
            self.gl
                .MemoryBarrier(VERTEX_ATTRIB_ARRAY_BARRIER_BIT | COMMAND_BARRIER_BIT)
        };
        self.draw_targets(job);
        profile.lap("warp");
        Ok(())
    }

    /// Leaves listed for source `j` (a read-back: for the trace profile only).
    fn leaf_count(&self, j: usize) -> u64 {
        let mut command = [0u32; 4];
        // SAFETY: 16 bytes of our own command buffer into a local of that size.
        unsafe {
            self.gl.BindBuffer(DRAW_INDIRECT_BUFFER, self.res.commands);
            self.gl.GetBufferSubData(
                DRAW_INDIRECT_BUFFER,
                j as isize * COMMAND_STRIDE,
                16,
                command.as_mut_ptr().cast(),
            );
        }
        u64::from(command[0] / 6)
    }

    /// Attaches layer `layer` of `texture` (0: nothing) at `point` of our framebuffer, bound
    /// for drawing.
    pub fn attach(&self, point: GLenum, texture: u32, layer: usize) {
        attach(self.gl, self.fbo, point, texture, layer);
    }

    /// The source's colour (and, unless `depth_ready`, its depth) into layer `j` of our
    /// arrays.
    pub fn copy_source(&self, j: usize, s: &Source, job: &Job) -> Result<(), String> {
        let (tw, th) = job.tile;
        detach_all(self.gl, self.fbo);
        self.attach(COLOR_ATTACHMENT0, self.res.color, j);
        blit(self.gl, s.color.0, s.color.1, (tw, th), COLOR_BUFFER_BIT);
        detach_all(self.gl, self.fbo);
        if !self.depth_ready {
            copy_depth(self.gl, self.fbo, self.res, j, s.depth, job.depth_format);
        }
        Ok(())
    }

    /// A full-screen pass of `program` into layer `j` of `texture`, `size` pixels.
    fn fullscreen(&self, program: u32, texture: u32, j: usize, size: (i32, i32)) {
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
        // SAFETY: uniforms of our own program.
        unsafe {
            gl.UseProgram(p.parallax);
            gl.Uniform1i(loc(gl, p.parallax, "u_depth"), 0);
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

    /// The min/max pyramid of source `j`'s parallax.
    fn pyramid(&self, j: usize) {
        let (gl, p, res) = (self.gl, self.programs, self.res);
        for l in 0..LEVELS {
            let src = if l == 0 { res.parallax } else { res.levels[l - 1] };
            self.bind_array(0, src);
            // SAFETY: as above.
            unsafe {
                gl.UseProgram(p.minmax);
                gl.Uniform1i(loc(gl, p.minmax, "u_src"), 0);
                gl.Uniform1i(loc(gl, p.minmax, "u_layer"), j as i32);
                gl.Uniform1i(loc(gl, p.minmax, "u_first"), (l == 0) as i32);
            }
            self.fullscreen(p.minmax, res.levels[l], j, level_size(res.tile, l));
        }
        self.attach(COLOR_ATTACHMENT0, 0, 0);
    }

    /// Source `j`'s leaf cells, appended to its list by one dispatch per level, then its
    /// columns of single pixels.
    fn list_leaves(&self, j: usize, job: &Job) {
        let (gl, res) = (self.gl, self.res);
        let reach = job
            .targets
            .iter()
            .filter(|t| t.sources.contains(&j))
            .map(|t| (t.u - job.sources[j].u).abs())
            .fold(0.0, f64::max);
        let scale = job.depthiness.abs() * job.tile.0 as f64 / 2.0 * reach;
        let command: [u32; 4] = [0, 1, 0, 0];
        // SAFETY: our buffers; bindings are restored by the guard.
        unsafe {
            gl.BindBuffer(DRAW_INDIRECT_BUFFER, res.commands);
            gl.BufferSubData(
                DRAW_INDIRECT_BUFFER,
                j as isize * COMMAND_STRIDE,
                16,
                command.as_ptr().cast(),
            );
            gl.BindBufferRange(
                SHADER_STORAGE_BUFFER,
                0,
                res.leaves,
                j as isize * res.leaf_stride,
                res.leaf_stride,
            );
            gl.BindBufferRange(SHADER_STORAGE_BUFFER, 1, res.commands, j as isize * COMMAND_STRIDE, 16);
        }
        let common = |p: u32| {
            // SAFETY: uniforms of our own program.
            unsafe {
                gl.UseProgram(p);
                gl.Uniform1i(loc(gl, p, "u_parallax"), 0);
                gl.Uniform1i(loc(gl, p, "u_level"), 1);
                gl.Uniform1i(loc(gl, p, "u_depth"), 3);
                gl.Uniform1i(loc(gl, p, "u_layer"), j as i32);
                gl.Uniform1f(loc(gl, p, "u_scale"), scale as f32);
                gl.Uniform1f(loc(gl, p, "u_threshold"), job.threshold as f32);
                gl.Uniform2i(loc(gl, p, "u_tile"), res.tile.0, res.tile.1);
            }
        };
        let p = self.programs.leaves;
        common(p);
        // SAFETY: as above.
        unsafe { gl.Uniform1i(loc(gl, p, "u_parent"), 2) };
        self.bind_array(0, res.parallax);
        self.bind_array(3, res.depth);
        for l in (0..LEVELS).rev() {
            self.bind_array(1, res.levels[l]);
            self.bind_array(2, res.levels[(l + 1).min(LEVELS - 1)]);
            let (cw, ch) = level_size(res.tile, l);
            // SAFETY: as above; the barrier orders the appends of consecutive levels.
            unsafe {
                gl.Uniform1i(loc(gl, p, "u_cell"), 2 << l);
                gl.Uniform1i(loc(gl, p, "u_top"), (l == LEVELS - 1) as i32);
                gl.DispatchCompute((cw as u32).div_ceil(8), (ch as u32).div_ceil(8), 1);
                gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
            }
        }
        common(self.programs.columns);
        self.bind_array(1, res.levels[0]);
        let (w, h) = (res.tile.0 as u32, res.tile.1 as u32);
        // SAFETY: as above.
        unsafe {
            gl.DispatchCompute(w.div_ceil(64), h.div_ceil(COLUMN_SEGMENT), 1);
            gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
        }
    }

    /// Every target tile: depth cleared to the far value, then each of its sources' leaves
    /// drawn, the preferred source last (it wins depth ties).
    fn draw_targets(&self, job: &Job) {
        let (gl, p, res) = (self.gl, self.programs.warp, self.res);
        let far = [job.model.far_depth()];
        let (tw, th) = job.tile;
        // Well inside any viewport size and bounds GL 4.3 guarantees.
        let overhang = tw.min(4096);
        // SAFETY: our program, vertex array and buffers; the destination is the layer's own
        // framebuffer. All of it is restored by the guard.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
            gl.Enable(DEPTH_TEST);
            // Or-equal: the background at the far value itself must be drawn over the clear.
            gl.DepthFunc(if job.model.reversed { GEQUAL } else { LEQUAL });
            gl.DepthMask(TRUE);
            gl.Enable(SCISSOR_TEST);
            gl.UseProgram(p);
            gl.Uniform1i(loc(gl, p, "u_color"), 0);
            gl.Uniform1i(loc(gl, p, "u_depth"), 1);
            gl.Uniform1i(loc(gl, p, "u_parallax"), 2);
            gl.DepthRange(0.0, 1.0);
            gl.Uniform1i(loc(gl, p, "u_zero_to_one"), zero_to_one(gl) as i32);
            gl.Uniform2f(loc(gl, p, "u_tile"), tw as f32, th as f32);
            let px = job.tile.0 as f64 / 2.0;
            gl.Uniform2f(
                loc(gl, p, "u_px"),
                (job.depthiness * px) as f32,
                (job.focus * px) as f32,
            );
            gl.Uniform1f(loc(gl, p, "u_margin"), 0.5);
            gl.Uniform1f(loc(gl, p, "u_overhang"), overhang as f32);
            let bias = if job.model.reversed {
                -STRETCHED_BIAS
            } else {
                STRETCHED_BIAS
            };
            gl.Uniform1f(loc(gl, p, "u_far_bias"), bias);
            gl.BindVertexArray(self.vao);
            gl.Uniform1i(loc(gl, p, "u_leaves"), 4);
            gl.ActiveTexture(TEXTURE4);
            gl.BindTexture(TEXTURE_BUFFER, res.leaf_view);
            gl.BindBuffer(DRAW_INDIRECT_BUFFER, res.commands);
        }
        self.bind_array(0, res.color);
        self.bind_array(1, res.depth);
        self.bind_array(2, res.parallax);
        let (u_du, u_layer) = (loc(gl, p, "u_du"), loc(gl, p, "u_layer"));
        for t in job.targets {
            let r = t.rect;
            // SAFETY: as above.
            unsafe {
                gl.Viewport(r[0] - overhang, r[1], r[2] + 2 * overhang, r[3]);
                gl.Scissor(r[0], r[1], r[2], r[3]);
                gl.ClearBufferfv(DEPTH, 0, far.as_ptr());
            }
            let second = (t.sources[1] != t.sources[0]).then_some(t.sources[1]);
            for j in second.into_iter().chain(std::iter::once(t.sources[0])) {
                let base = j as isize * res.leaf_stride;
                // SAFETY: as above; the buffer texture views source j's leaf list.
                unsafe {
                    gl.ActiveTexture(TEXTURE4);
                    gl.TexBufferRange(TEXTURE_BUFFER, RGBA32UI, res.leaves, base, res.leaf_stride);
                    gl.Uniform1f(u_du, (t.u - job.sources[j].u) as f32);
                    gl.Uniform1i(u_layer, j as i32);
                    gl.DrawArraysIndirect(TRIANGLES, (j as isize * COMMAND_STRIDE) as *const _);
                }
            }
        }
    }
}
