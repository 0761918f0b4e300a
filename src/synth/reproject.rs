//! Kept views moved by the camera's motion (`--reuse`, DESIGN §5; Hathaway 2009 keeps
//! rendered points and reprojects them into the new camera).
//!
//! A view rendered a few frames ago, with the camera elsewhere, is still exact for the
//! static parts of the scene once each of its pixels is put where the camera sees it now.
//! Its pixels are not on a grid any more (the motion is a general 2D warp, not a
//! disparity), so they are forward-splatted one point each, depth-tested (nearer wins), into
//! a canvas of ours, as `synth:pixel` splats (`pixel`); the motion of a pixel is one matrix
//! and offset in clip space (`camera::ViewRig::clip_motion`), made in f64 on the CPU.
//!
//! The tile already holds this frame's synthesised view, which is right for moving objects
//! but has holes filled by stretching where the rendered views did not see. The merge keeps
//! a splatted pixel only where its eye distance agrees with the synthesised one's within a
//! tolerance: where they disagree (a moving object, now elsewhere or hiding it) or nothing
//! was splatted (cracks, what came into view) the synthesised pixel stays. So a moved kept
//! view sharpens static parts and fills disocclusions, and never smears what moved.

use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::*;

const SPLAT_VERT: &str = include_str!("../../glsl-patches/reuse_reproject.vert");
const SPLAT_FRAG: &str = include_str!("../../glsl-patches/synth_splat.frag");
const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const MERGE_FRAG: &str = include_str!("../../glsl-patches/reuse_merge.frag");

/// One kept view to move into its tile.
#[derive(Clone, Copy, Debug)]
pub struct MovedView {
    /// Its tile's first texel in the kept textures.
    pub origin: (i32, i32),
    /// Its tile in the destination framebuffer.
    pub rect: [i32; 4],
    /// Its index among the synthesis job's targets (its hole marks).
    pub layer: i32,
    /// `clip ↦ motion · clip + offset` (column-major).
    pub motion: [f64; 16],
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
    pub reversed: bool,
    /// Relative eye-distance tolerance of the merge.
    pub tolerance: f64,
    /// The row warp's hole marks (`Synthesizer::hole_marks`).
    pub marks: u32,
    pub views: &'a [MovedView],
}

/// Per-context state: programs, the canvas and the copy of the synthesised depth.
#[derive(Default)]
pub struct Reprojector {
    programs: Option<Result<[u32; 2], String>>,
    /// Canvas colour, canvas depth, synthesised depth; their framebuffers; the key.
    textures: [u32; 3],
    fbos: [u32; 2],
    vao: u32,
    made_for: Option<((i32, i32), GLenum)>,
}

fn texture(gl: &Gl, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut t = 0;
    // SAFETY: our own texture; the caller's guard restores the binding.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(TEXTURE_2D, t);
        gl.TexStorage2D(TEXTURE_2D, 1, format, w, h);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, NEAREST as i32);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, NEAREST as i32);
    }
    t
}

fn depth_point(format: GLenum) -> GLenum {
    match format {
        DEPTH24_STENCIL8 | DEPTH32F_STENCIL8 => DEPTH_STENCIL_ATTACHMENT,
        _ => DEPTH_ATTACHMENT,
    }
}

impl Reprojector {
    /// Moves every view of `job` into its tile over the synthesised view there. All state it
    /// touches is put back.
    pub fn run(&mut self, gl: &Gl, info: GlInfo, job: &ReprojectJob) -> Result<(), String> {
        if job.views.is_empty() {
            return Ok(());
        }
        let _guard = StateGuard::new(gl, info)
            .framebuffers()
            .for_pass()
            .depth_func()
            .depth_range()
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
        let compatibility = super::pixel::compatibility(gl);
        let _points = super::pixel::guard(gl, info, compatibility);
        super::pixel::neutral_point_state(gl, compatibility);
        let [splat, merge] = self.programs(gl, info)?;
        self.make(gl, job)?;
        // SAFETY: our vertex array; the binding is restored by the guard.
        unsafe { gl.BindVertexArray(self.vao) };
        let zero_to_one = super::grid::zero_to_one(gl) as i32;
        let mut profile = super::profile::Profile::new(gl);
        for v in job.views {
            self.copy_synthesised_depth(gl, job, v.rect);
            profile.lap("reproject depth copy");
            self.splat(gl, splat, job, v, zero_to_one);
            profile.lap("reproject splat");
            self.merge(gl, merge, job, v, zero_to_one);
            profile.lap("reproject merge");
        }
        Ok(())
    }

    fn programs(&mut self, gl: &Gl, info: GlInfo) -> Result<[u32; 2], String> {
        if self.programs.is_none() {
            let link = |v, f| crate::gl::program::link(gl, info, v, f);
            let p = link(SPLAT_VERT, SPLAT_FRAG)
                .and_then(|s| Ok([s, link(FULLSCREEN_VERT, MERGE_FRAG)?]))
                .map_err(|e| format!("reprojection passes: {e}"));
            self.programs = Some(p);
        }
        self.programs.clone().unwrap_or(Err("unlinked".into()))
    }

    /// The canvas and the depth copy for `job`'s tile and depth format, (re)made on change.
    fn make(&mut self, gl: &Gl, job: &ReprojectJob) -> Result<(), String> {
        let key = (job.tile, job.depth_format);
        if self.made_for == Some(key) {
            return Ok(());
        }
        self.delete_images(gl);
        self.textures = [
            texture(gl, RGBA16F, job.tile),
            texture(gl, DEPTH_COMPONENT32F, job.tile),
            texture(gl, job.depth_format, job.tile),
        ];
        // SAFETY: our own framebuffers and vertex array; bindings restored by the guard.
        unsafe {
            if self.vao == 0 {
                gl.GenVertexArrays(1, &mut self.vao);
            }
            gl.GenFramebuffers(2, self.fbos.as_mut_ptr());
            gl.BindFramebuffer(FRAMEBUFFER, self.fbos[0]);
            gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, self.textures[0], 0);
            gl.FramebufferTexture2D(FRAMEBUFFER, DEPTH_ATTACHMENT, TEXTURE_2D, self.textures[1], 0);
            let canvas = gl.CheckFramebufferStatus(FRAMEBUFFER);
            gl.BindFramebuffer(FRAMEBUFFER, self.fbos[1]);
            let point = depth_point(job.depth_format);
            gl.FramebufferTexture2D(FRAMEBUFFER, point, TEXTURE_2D, self.textures[2], 0);
            gl.DrawBuffer(NONE);
            gl.ReadBuffer(NONE);
            let copy = gl.CheckFramebufferStatus(FRAMEBUFFER);
            if canvas != FRAMEBUFFER_COMPLETE || copy != FRAMEBUFFER_COMPLETE {
                return Err(format!("reprojection framebuffers incomplete ({canvas:#x}, {copy:#x})"));
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
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbos[1]);
            gl.BlitFramebuffer(x, y, x + w, y + h, 0, 0, w, h, DEPTH_BUFFER_BIT, NEAREST);
        }
    }

    /// The canvas cleared (coverage 0, depth far) and every pixel of `v`'s kept render
    /// splatted where the camera sees it now.
    fn splat(&self, gl: &Gl, program: u32, job: &ReprojectJob, v: &MovedView, zero_to_one: i32) {
        let loc = |n| super::grid::loc(gl, program, n);
        let far = if job.reversed { 0.0f32 } else { 1.0 };
        let m = job.depth_model;
        let (motion, offset) = (v.motion.map(|x| x as f32), v.offset.map(|x| x as f32));
        // SAFETY: our framebuffer, program and textures; state restored by the guard.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbos[0]);
            gl.Viewport(0, 0, job.tile.0, job.tile.1);
            gl.DepthMask(TRUE);
            gl.ClearBufferfv(COLOR, 0, [0.0f32; 4].as_ptr());
            gl.ClearBufferfv(DEPTH, 0, &far);
            gl.Enable(DEPTH_TEST);
            gl.DepthFunc(if job.reversed { GREATER } else { LESS });
            gl.DepthRange(0.0, 1.0);
            gl.UseProgram(program);
            bind(gl, 0, job.color);
            bind(gl, 1, job.depth);
            gl.Uniform1i(loc("u_color"), 0);
            gl.Uniform1i(loc("u_depth"), 1);
            gl.Uniform2i(loc("u_origin"), v.origin.0, v.origin.1);
            gl.Uniform1i(loc("u_flip"), job.flipped as i32);
            gl.Uniform2i(loc("u_tile"), job.tile.0, job.tile.1);
            gl.UniformMatrix4fv(loc("u_motion"), 1, FALSE, motion.as_ptr());
            gl.Uniform4fv(loc("u_offset"), 1, offset.as_ptr());
            gl.Uniform2f(loc("u_model"), m.a as f32, m.b as f32);
            gl.Uniform1f(loc("u_far"), far);
            gl.Uniform1i(loc("u_zero_to_one"), zero_to_one);
            gl.DrawArrays(POINTS, 0, job.tile.0 * job.tile.1);
        }
    }

    /// The canvas over the tile where it agrees with the synthesised depth.
    fn merge(&self, gl: &Gl, program: u32, job: &ReprojectJob, v: &MovedView, zero_to_one: i32) {
        let [x, y, w, h] = v.rect;
        let loc = |n| super::grid::loc(gl, program, n);
        let m = job.depth_model;
        // SAFETY: our program and textures into the destination tile; state restored by the
        // guard. Alpha is left as the synthesis wrote it.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
            gl.Viewport(x, y, w, h);
            gl.DepthFunc(ALWAYS);
            gl.ColorMask(TRUE, TRUE, TRUE, FALSE);
            gl.UseProgram(program);
            for (unit, t) in self.textures.iter().enumerate() {
                bind(gl, unit as u32, *t);
            }
            gl.Uniform1i(loc("u_kept"), 0);
            gl.Uniform1i(loc("u_kept_depth"), 1);
            gl.Uniform1i(loc("u_synth_depth"), 2);
            gl.Uniform2i(loc("u_rect_origin"), x, y);
            gl.Uniform2f(loc("u_model"), m.a as f32, m.b as f32);
            gl.Uniform1i(loc("u_zero_to_one"), zero_to_one);
            gl.Uniform1f(loc("u_tolerance"), job.tolerance as f32);
            gl.BindBufferBase(SHADER_STORAGE_BUFFER, 4, job.marks);
            gl.Uniform1i(loc("u_layer"), v.layer);
            gl.Uniform2i(loc("u_tile"), job.tile.0, job.tile.1);
            gl.DrawArrays(TRIANGLES, 0, 3);
            gl.ColorMask(TRUE, TRUE, TRUE, TRUE);
        }
    }

    fn delete_images(&mut self, gl: &Gl) {
        // SAFETY: deleting our own objects; zero names are ignored.
        unsafe {
            gl.DeleteTextures(3, self.textures.as_ptr());
            gl.DeleteFramebuffers(2, self.fbos.as_ptr());
        }
        self.textures = [0; 3];
        self.fbos = [0; 2];
        self.made_for = None;
    }

    pub fn delete(&mut self, gl: &Gl) {
        self.delete_images(gl);
        if let Some(Ok(p)) = self.programs.take() {
            // SAFETY: our own programs and vertex array.
            unsafe {
                p.iter().for_each(|&p| gl.DeleteProgram(p));
                gl.DeleteVertexArrays(1, &self.vao);
            }
        }
        self.vao = 0;
    }

    /// Per-context objects: (framebuffers, vertex arrays).
    pub fn context_objects(&self) -> (usize, usize) {
        (self.fbos.iter().filter(|&&f| f != 0).count(), usize::from(self.vao != 0))
    }

    /// Shared with the share group: (textures, programs).
    pub fn shared_objects(&self) -> (Vec<u32>, Vec<u32>) {
        let programs = match &self.programs {
            Some(Ok(p)) => p.to_vec(),
            _ => vec![],
        };
        (self.textures.iter().copied().filter(|&t| t != 0).collect(), programs)
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
