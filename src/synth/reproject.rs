//! Kept views moved by the camera's motion (`--reuse`, DESIGN §5; Hathaway 2009 keeps
//! rendered points and reprojects them into the new camera).
//!
//! A view rendered a few frames ago, with the camera elsewhere, is still exact for the
//! static parts of the scene once its pixels are put where the camera sees them now. Where
//! that helps is known: the tile already holds this frame's synthesised view, right wherever
//! the rendered views saw the surface, moving objects included, and a guess only over the
//! disocclusions, which the row warp stretches the farther side over and marks. So only
//! those pixels are looked up, backwards (reverse reprojection): the stretch's depth, moved
//! back by the inverse of the view's clip-space motion (`camera::ViewRig::clip_motion`, made
//! in f64 on the CPU), lands on a pixel of the kept render, taken when its own depth agrees
//! with the moved point's within a tolerance (`glsl-patches/reuse_reproject.frag`).
//!
//! Why not a forward splat of every kept pixel (`synth::pixel`'s points) merged where it
//! agrees in depth with the synthesised view: measured on `cubes` orbiting (README
//! "--reuse"), it doubled the frame time (a point per pixel per view through llvmpipe's
//! rasteriser) and, taken outside the holes, lowered the PSNR: one-pixel points resample
//! every edge, the row warp only vertical ones. Restricted to the holes it gained what this
//! gains, for a full-tile pass less.

use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::*;

const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const REPROJECT_FRAG: &str = include_str!("../../glsl-patches/reuse_reproject.frag");

/// One kept view to move into its tile.
#[derive(Clone, Copy, Debug)]
pub struct MovedView {
    /// Its tile's first texel in the kept textures.
    pub origin: (i32, i32),
    /// Its tile in the destination framebuffer.
    pub rect: [i32; 4],
    /// Its index among the synthesis job's targets (its hole marks).
    pub layer: i32,
    /// Its motion `clip ↦ m · clip + offset` given by `back = m⁻¹` (column-major) and
    /// `offset`.
    pub back: [f64; 16],
    pub offset: [f64; 4],
}

pub struct ReprojectJob<'a> {
    /// The kept renders: colour and depth textures, rows stored top-down when `flipped`.
    pub color: u32,
    pub depth: u32,
    pub flipped: bool,
    /// Where the synthesised tiles are, and its depth format.
    pub dest_fbo: u32,
    pub depth_format: GLenum,
    pub tile: (i32, i32),
    /// The depth model `z_ndc = -a + b/w`.
    pub depth_model: crate::camera::projection::DepthRange,
    /// Relative eye-distance tolerance of the merge.
    pub tolerance: f64,
    /// The row warp's output, whose depth sign bits mark holes (`Synthesizer::hole_marks`).
    pub marks: u32,
    pub views: &'a [MovedView],
}

/// Per-context state: the program and the copy of a tile's synthesised depth.
#[derive(Default)]
pub struct Reprojector {
    program: Option<Result<u32, String>>,
    /// The depth copy's texture and framebuffer, and what they were made for.
    texture: u32,
    fbo: u32,
    vao: u32,
    made_for: Option<((i32, i32), GLenum)>,
}

fn depth_point(format: GLenum) -> GLenum {
    match format {
        DEPTH24_STENCIL8 | DEPTH32F_STENCIL8 => DEPTH_STENCIL_ATTACHMENT,
        _ => DEPTH_ATTACHMENT,
    }
}

impl Reprojector {
    /// Fetches every view of `job` into the holes of its tile. All state it touches is put
    /// back.
    pub fn run(&mut self, gl: &Gl, info: GlInfo, job: &ReprojectJob) -> Result<(), String> {
        if job.views.is_empty() {
            return Ok(());
        }
        let _guard = StateGuard::new(gl, info)
            .framebuffers()
            .for_pass()
            .textures(TEXTURE_2D, TEXTURE_BINDING_2D, 0..3)
            .samplers(0..3)
            .indexed_buffers(
                SHADER_STORAGE_BUFFER,
                SHADER_STORAGE_BUFFER_BINDING,
                SHADER_STORAGE_BUFFER_START,
                SHADER_STORAGE_BUFFER_SIZE,
                4..5,
            );
        crate::gl::guard::neutral_pass_state(gl, info);
        let program = self.program(gl, info)?;
        self.make(gl, job)?;
        self.prepare(gl, program, job);
        let mut profile = super::profile::Profile::new(gl);
        for v in job.views {
            self.copy_synthesised_depth(gl, job, v.rect);
            profile.lap("reproject depth copy");
            self.fetch(gl, program, job, v);
            profile.lap("reproject fetch");
        }
        Ok(())
    }

    fn program(&mut self, gl: &Gl, info: GlInfo) -> Result<u32, String> {
        if self.program.is_none() {
            let p = crate::gl::program::link(gl, info, FULLSCREEN_VERT, REPROJECT_FRAG);
            self.program = Some(p.map_err(|e| format!("reprojection pass: {e}")));
        }
        self.program.clone().unwrap_or(Err("unlinked".into()))
    }

    /// The depth copy for `job`'s tile and depth format, (re)made on change.
    fn make(&mut self, gl: &Gl, job: &ReprojectJob) -> Result<(), String> {
        let key = (job.tile, job.depth_format);
        if self.made_for == Some(key) {
            return Ok(());
        }
        self.delete_images(gl);
        self.texture = crate::gl::depth_copy::storage(gl, job.depth_format, job.tile);
        // SAFETY: our own framebuffer and vertex array; bindings restored by the guard.
        unsafe {
            if self.vao == 0 {
                gl.GenVertexArrays(1, &mut self.vao);
            }
            gl.GenFramebuffers(1, &mut self.fbo);
            gl.BindFramebuffer(FRAMEBUFFER, self.fbo);
            let point = depth_point(job.depth_format);
            gl.FramebufferTexture2D(FRAMEBUFFER, point, TEXTURE_2D, self.texture, 0);
            gl.DrawBuffer(NONE);
            gl.ReadBuffer(NONE);
            let status = gl.CheckFramebufferStatus(FRAMEBUFFER);
            if status != FRAMEBUFFER_COMPLETE {
                return Err(format!("reprojection depth copy incomplete ({status:#x})"));
            }
        }
        self.made_for = Some(key);
        Ok(())
    }

    /// The synthesised view's depth in `rect` of the destination into our copy.
    fn copy_synthesised_depth(&self, gl: &Gl, job: &ReprojectJob, [x, y, w, h]: [i32; 4]) {
        // SAFETY: a same-format depth blit between framebuffers; bindings restored by the guard.
        unsafe {
            gl.BindFramebuffer(READ_FRAMEBUFFER, job.dest_fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            gl.BlitFramebuffer(x, y, x + w, y + h, 0, 0, w, h, DEPTH_BUFFER_BIT, NEAREST);
        }
    }

    /// What every view shares: program, textures, marks, the depth model.
    fn prepare(&self, gl: &Gl, program: u32, job: &ReprojectJob) {
        let loc = |n| super::pass::loc(gl, program, n);
        let m = job.depth_model;
        // SAFETY: our program, textures and buffer; state restored by the guard. Alpha is
        // left as the synthesis wrote it, and so is depth (depth test and writes are off).
        unsafe {
            gl.UseProgram(program);
            gl.BindVertexArray(self.vao);
            gl.ColorMask(TRUE, TRUE, TRUE, FALSE);
            for (unit, t) in [job.color, job.depth, self.texture].into_iter().enumerate() {
                bind(gl, unit as u32, t);
            }
            gl.Uniform1i(loc("u_kept"), 0);
            gl.Uniform1i(loc("u_kept_depth"), 1);
            gl.Uniform1i(loc("u_synth_depth"), 2);
            gl.Uniform1i(loc("u_flip"), job.flipped as i32);
            gl.Uniform2i(loc("u_tile"), job.tile.0, job.tile.1);
            gl.Uniform2f(loc("u_model"), m.a as f32, m.b as f32);
            gl.Uniform1i(loc("u_zero_to_one"), super::pass::zero_to_one(gl) as i32);
            gl.Uniform1f(loc("u_tolerance"), job.tolerance as f32);
            gl.BindBufferBase(SHADER_STORAGE_BUFFER, 4, job.marks);
        }
    }

    /// The kept pixels of `v` into the holes of its tile.
    fn fetch(&self, gl: &Gl, program: u32, job: &ReprojectJob, v: &MovedView) {
        let loc = |n| super::pass::loc(gl, program, n);
        let [x, y, w, h] = v.rect;
        let (back, offset) = (v.back.map(|x| x as f32), v.offset.map(|x| x as f32));
        // SAFETY: our program into the destination tile; state restored by the guard.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
            gl.Viewport(x, y, w, h);
            gl.Uniform2i(loc("u_origin"), v.origin.0, v.origin.1);
            gl.Uniform2i(loc("u_rect_origin"), x, y);
            gl.Uniform1i(loc("u_layer"), v.layer);
            gl.UniformMatrix4fv(loc("u_back"), 1, FALSE, back.as_ptr());
            gl.Uniform4fv(loc("u_offset"), 1, offset.as_ptr());
            gl.DrawArrays(TRIANGLES, 0, 3);
        }
    }

    fn delete_images(&mut self, gl: &Gl) {
        // SAFETY: deleting our own objects; zero names are ignored.
        unsafe {
            gl.DeleteTextures(1, &self.texture);
            gl.DeleteFramebuffers(1, &self.fbo);
        }
        (self.texture, self.fbo, self.made_for) = (0, 0, None);
    }

    pub fn delete(&mut self, gl: &Gl) {
        self.delete_images(gl);
        if let Some(Ok(p)) = self.program.take() {
            // SAFETY: our own program and vertex array.
            unsafe {
                gl.DeleteProgram(p);
                gl.DeleteVertexArrays(1, &self.vao);
            }
        }
        self.vao = 0;
    }

    /// Per-context objects: (framebuffers, vertex arrays).
    pub fn context_objects(&self) -> (usize, usize) {
        (usize::from(self.fbo != 0), usize::from(self.vao != 0))
    }

    /// Shared with the share group: (textures, programs).
    pub fn shared_objects(&self) -> (Vec<u32>, Vec<u32>) {
        let program = match &self.program {
            Some(Ok(p)) => vec![*p],
            _ => vec![],
        };
        (vec![self.texture].into_iter().filter(|&t| t != 0).collect(), program)
    }
}

/// `texture` on 2D unit `unit`.
fn bind(gl: &Gl, unit: u32, texture: u32) {
    // SAFETY: a texture binding the caller's guard restores.
    unsafe {
        gl.ActiveTexture(TEXTURE0 + unit);
        gl.BindTexture(TEXTURE_2D, texture);
    }
}
