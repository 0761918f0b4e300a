//! `synth:pixel`, the per-pixel baseline the grid warp is measured against (DESIGN §5).
//!
//! Per target view: every pixel of each of its sources is forward-splatted as a one-pixel
//! point, moved by its own disparity and depth-tested (nearer wins), into a canvas of ours
//! whose alpha marks the covered pixels; then the holes (disocclusions, and cracks where a
//! surface stretches) are filled by pull-push (`pull_push`) and the result is written into
//! the target tile.
//!
//! Points rather than one-pixel quads: a quad one pixel wide covers exactly the one pixel
//! centre a point of size 1 covers, so both leave the same cracks, and a point is one vertex
//! instead of six (measured in the README). Points bring their own state (size, and
//! smoothing in compatibility contexts), which the guard saves and this pass neutralises.
//!
//! The sources are the copies every warp makes (`pass::Pass::copy_source`); the parallax is
//! computed in the splat's vertex shader with the same arithmetic as the parallax pass.

use super::pass;
use super::pull_push::Canvas;
use super::{Job, Target};
use crate::gl::GlInfo;
use crate::gl::guard::{StateGuard, get_i};
use crate::gl::*;

const SPLAT_VERT: &str = include_str!("../../glsl-patches/synth_splat.vert");
const SPLAT_FRAG: &str = include_str!("../../glsl-patches/synth_splat.frag");

/// Per-context state of the per-pixel mode: its programs, canvas and framebuffers.
#[derive(Default)]
pub struct PixelSynth {
    programs: Option<Result<Programs, String>>,
    canvas: Option<Canvas>,
    /// The canvas's level-0 framebuffer (colour and depth), and one re-attached per level.
    fbos: [u32; 2],
}

#[derive(Clone, Copy, Debug)]
pub struct Programs {
    splat: u32,
    pull: u32,
    push: u32,
}

impl Programs {
    fn link(gl: &Gl, info: GlInfo) -> Result<Programs, String> {
        let link = |v, f| crate::gl::program::link(gl, info, v, f);
        let (pull, push) = super::pull_push::link(gl, info)?;
        Ok(Programs {
            splat: link(&crate::camera::comfort::with_glsl(SPLAT_VERT), SPLAT_FRAG)
                .map_err(|e| format!("per-pixel splat pass: {e}"))?,
            pull,
            push,
        })
    }

    fn names(&self) -> [u32; 3] {
        [self.splat, self.pull, self.push]
    }
}

/// GL_POINT_SMOOTH exists (and would turn coverage into partial alpha) in compatibility
/// contexts only; touching it in a core context is an error the app could see. (Every
/// context that gets here is GL 4.3, which has the profile mask.)
fn compatibility(gl: &Gl) -> bool {
    get_i(gl, CONTEXT_PROFILE_MASK) as u32 & CONTEXT_COMPATIBILITY_PROFILE_BIT != 0
}

/// One-pixel points whatever the app left set; no sampler object of the app's overriding our
/// textures' filtering (`pass::guard` restores units 0..5).
fn neutral_point_state(gl: &Gl, compatibility: bool) {
    // SAFETY: state the guards restore; POINT_SMOOTH only where it exists.
    unsafe {
        gl.Enable(PROGRAM_POINT_SIZE);
        if compatibility {
            gl.Disable(POINT_SMOOTH);
        }
        for unit in 0..5 {
            gl.BindSampler(unit, 0);
        }
    }
}

/// What the per-pixel passes change beyond `pass::guard`: the 2D texture units of the
/// pyramid and the point state.
fn guard(gl: &Gl, info: GlInfo, compatibility: bool) -> StateGuard<'_> {
    let g = StateGuard::new(gl, info)
        .textures(TEXTURE_2D, TEXTURE_BINDING_2D, 2..5)
        .caps(&[PROGRAM_POINT_SIZE]);
    if compatibility { g.caps(&[POINT_SMOOTH]) } else { g }
}

impl PixelSynth {
    /// Splats and fills every target of `job`, using the shared source copies. The caller
    /// holds `pass::guard` and has set the neutral pass state.
    pub fn run(&mut self, gl: &Gl, info: GlInfo, pass: &pass::Pass, job: &Job) -> Result<(), String> {
        let programs = self.programs(gl, info)?;
        self.make_canvas(gl, job.tile);
        let canvas = self.canvas.as_ref().ok_or("no canvas")?;
        for (j, source) in job.sources.iter().enumerate() {
            pass.copy_source(j, source, job)?;
        }
        let compatibility = compatibility(gl);
        let _guard = guard(gl, info, compatibility);
        neutral_point_state(gl, compatibility);
        let splat = Splat {
            gl,
            program: programs.splat,
            fbo: self.fbos[0],
            vao: pass.vao,
            res: pass.res,
            recorded: pass.recorded,
        };
        splat.prepare(job);
        let fill = super::pull_push::Fill {
            gl,
            pull: programs.pull,
            push: programs.push,
            fbo: self.fbos[1],
            vao: pass.vao,
            canvas,
        };
        fill.prepare();
        for t in job.targets {
            splat.target(t, job);
            fill.run(job.dest_fbo, t.rect);
        }
        Ok(())
    }

    /// Linked once per context; a failure is kept and answered again.
    fn programs(&mut self, gl: &Gl, info: GlInfo) -> Result<Programs, String> {
        match &self.programs {
            Some(p) => p.clone(),
            None => {
                let p = Programs::link(gl, info);
                self.programs = Some(p.clone());
                p
            }
        }
    }

    /// The canvas for tiles of `tile`, (re)made when the tile changes, with its framebuffers.
    fn make_canvas(&mut self, gl: &Gl, tile: (i32, i32)) {
        if self.fbos[0] == 0 {
            // SAFETY: our own framebuffers (per context).
            unsafe { gl.GenFramebuffers(2, self.fbos.as_mut_ptr()) };
        }
        if !self.canvas.as_ref().is_some_and(|c| c.fits(tile)) {
            if let Some(old) = self.canvas.take() {
                old.delete(gl);
            }
            let canvas = Canvas::create(gl, tile);
            canvas.attach_level0(gl, self.fbos[0]);
            self.canvas = Some(canvas);
        }
    }

    /// What of ours is shared with the context's share group.
    pub fn shared_objects(&self, o: &mut crate::state::orphans::LayerObjects) {
        if let Some(Ok(p)) = &self.programs {
            o.programs.extend(p.names());
        }
        if let Some(c) = &self.canvas {
            o.textures.extend(c.textures());
        }
    }
}

/// The splat pass into the canvas's level 0.
struct Splat<'a> {
    gl: &'a Gl,
    program: u32,
    fbo: u32,
    vao: u32,
    res: &'a super::resources::Resources,
    recorded: u64,
}

impl Splat<'_> {
    /// Uniforms and bindings shared by every target.
    fn prepare(&self, job: &Job) {
        let (gl, p) = (self.gl, self.program);
        let loc = |name| pass::loc(gl, p, name);
        let m = job.model;
        let px = job.tile.0 as f64 / 2.0;
        // SAFETY: our program and textures; the guards restore bindings and uniforms are ours.
        unsafe {
            gl.UseProgram(p);
            gl.Uniform1i(loc("u_color"), 0);
            gl.Uniform1i(loc("u_depth"), 1);
            gl.Uniform1i(loc("u_record"), 2);
            gl.Uniform2i(loc("u_tile"), job.tile.0, job.tile.1);
            gl.Uniform2f(loc("u_px"), (job.depthiness * px) as f32, (job.focus * px) as f32);
            gl.Uniform3f(loc("u_model"), m.a_hi, m.a_lo, m.scale);
            let r = job.remap;
            gl.Uniform4f(loc("u_remap"), r[0], r[1], r[2], r[3]);
            gl.Uniform1i(loc("u_zero_to_one"), pass::zero_to_one(gl) as i32);
            gl.ActiveTexture(TEXTURE0);
            gl.BindTexture(TEXTURE_2D_ARRAY, self.res.color);
            gl.ActiveTexture(TEXTURE1);
            gl.BindTexture(TEXTURE_2D_ARRAY, self.res.depth);
            gl.ActiveTexture(TEXTURE2);
            gl.BindTexture(TEXTURE_2D_ARRAY, self.res.record);
        }
    }

    /// The canvas cleared (colour and coverage 0, depth far), then each of `t`'s sources
    /// splatted, the preferred one last (it wins depth ties).
    fn target(&self, t: &Target, job: &Job) {
        let gl = self.gl;
        let (tw, th) = job.tile;
        let clear = [0.0f32; 4];
        let far = [job.model.far_depth()];
        // SAFETY: our framebuffer, program and vertex array; state restored by the guards.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            gl.Viewport(0, 0, tw, th);
            gl.DepthMask(TRUE);
            gl.ClearBufferfv(COLOR, 0, clear.as_ptr());
            gl.ClearBufferfv(DEPTH, 0, far.as_ptr());
            gl.Enable(DEPTH_TEST);
            // Or-equal: the background at the far value itself must be drawn over the clear.
            gl.DepthFunc(if job.model.reversed { GEQUAL } else { LEQUAL });
            gl.DepthRange(0.0, 1.0);
            gl.UseProgram(self.program);
            gl.BindVertexArray(self.vao);
        }
        let (u_du, u_layer, u_recorded) = (
            pass::loc(gl, self.program, "u_du"),
            pass::loc(gl, self.program, "u_layer"),
            pass::loc(gl, self.program, "u_recorded"),
        );
        let second = (t.sources[1] != t.sources[0]).then_some(t.sources[1]);
        for j in second.into_iter().chain(std::iter::once(t.sources[0])) {
            // SAFETY: as above; vertex j·w·h.. of nothing: the shader reads only gl_VertexID.
            unsafe {
                gl.Uniform1f(u_du, (t.u - job.sources[j].u) as f32);
                gl.Uniform1i(u_layer, j as i32);
                gl.Uniform1i(u_recorded, (self.recorded >> j & 1) as i32);
                gl.DrawArrays(POINTS, 0, tw * th);
            }
        }
        // SAFETY: as above.
        unsafe { gl.Disable(DEPTH_TEST) };
    }
}
