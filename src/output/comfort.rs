//! The comfort post-pass (README "Comfort"): background depth of field and edge fade, drawn
//! over each view's tile of the finished quilt, before it is composed or dumped.
//!
//! Both effects need each pixel's disparity, so they need the quilt's depth: the pass copies
//! it into a texture (a raw copy of the renderbuffer; a multisampled quilt's is resolved
//! first), and where the scene recorded its disparity, the record's depth overwrites it
//! (`comfort_record`: one disparity per pixel, DESIGN §5). Neither effect touches most pixels, and the pass is built so that the pixels it
//! leaves alone cost next to nothing (`scripts/comfort-figures.py` measures it):
//!
//! - Depth of field (Agus et al.'s downsampled pre-blurred image blended by a variable
//!   kernel): a half-size image of the quilt holds each texel's circle of confusion in its
//!   alpha; 12 Poisson taps of it are gathered around each background pixel and blended over
//!   it. It tests against a second copy of the depth whose stencil is ours, marked where
//!   something was drawn, so the empty (cleared) pixels are never shaded.
//! - Edge fade: the app's clear colour blended over the border bands' foreground pixels.
//!
//! Both are drawn at the depth of their disparity threshold (B behind, the screen plane in
//! front) with the depth test on and depth writes off, so the rasteriser drops the pixels on
//! the other side before shading (a software rasteriser runs the whole shader for every pixel
//! that reaches it, whatever it discards); the threshold is conservative (the remap only
//! compresses: `R(x) > B` needs `x > B`), and each pixel's weight comes from its exact
//! disparity in the shader. No colour is copied: both blend premultiplied colour.
//!
//! The disparity is the outermost view's, the same for every view, so a pixel fades or blurs
//! alike in all views and nothing flickers from view to view. The fade goes to the app's
//! clear colour (`GL_COLOR_CLEAR_VALUE` at the swap): that is what the app shows where
//! nothing is drawn, so a faded object looks as if it stood behind the frame.
//! Settings are read every frame (`ComfortSettings`); nothing is compiled in.

use crate::camera::comfort;
use crate::camera::projection::DepthRange;
use crate::gl::guard::StateGuard;
use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::quilt::target::QuiltTarget;
use crate::synth::disparity::ParallaxModel;

const POST_FRAG: &str = include_str!("../../glsl-patches/comfort_post.frag");

/// Largest blur radius, in tile pixels, at `--dof 1`.
pub const RADIUS_PER_STRENGTH: f64 = 6.0;

pub use super::comfort_images::ComfortCopies;

/// The NDC depth where the outermost view's disparity, before the remap, is `x` tile px (`s`
/// px per unit of parallax, convergence `c`), and whether disparity grows with depth. `None`
/// when the disparity does not depend on depth (depthiness 0).
fn threshold(depth: DepthRange, c: f64, s: f64, x: f64) -> Option<(f64, bool)> {
    // D = s·(1 − (c/b)·(z + a)) (synth::disparity).
    let k = c / depth.b;
    let z = (1.0 - x / s) / k - depth.a;
    (s != 0.0 && k != 0.0 && z.is_finite()).then_some((z, s * k < 0.0))
}

/// Applies the fade and the depth of field to `mv`'s quilt, if either is on; all GL state
/// is restored. `Ok` without drawing when no depth model is known yet.
pub fn apply(
    gl: &Gl,
    passes: &mut super::pass::Passes,
    copies: &mut ComfortCopies,
    mv: &Multiview,
) -> Result<(), String> {
    let c = mv.settings.comfort;
    if !c.post_pass() {
        return Ok(());
    }
    let (Some(t), Some(depth)) = (mv.target.as_ref(), mv.camera.last_depth) else {
        return Ok(());
    };
    let convergence = mv.camera.rig.convergence;
    let Some(model) = ParallaxModel::new(depth, convergence) else {
        return Ok(());
    };
    let s = crate::multiview::quilt::comfort::pixels_per_parallax(mv);
    let range = crate::multiview::quilt::comfort::range_pixels(mv);
    let (Some(behind), Some(front)) = (
        threshold(depth, convergence, s, range.back),
        threshold(depth, convergence, s, 0.0),
    ) else {
        return Ok(());
    };
    if !mv.info.has_samplers() || !gl.CopyImageSubData.is_loaded() {
        return Err("the comfort pass needs GL 4.3 or ES 3.2 (glCopyImageSubData)".into());
    }
    let depth_format = crate::gl::depth_copy::describe(gl, mv.info, t.fbo)?.format;
    let program = |passes: &mut super::pass::Passes, name, stage: &str| {
        let frag = comfort::with_glsl(&POST_FRAG.replacen('\n', &format!("\n#define {stage}\n"), 1));
        passes.program(gl, mv.info, name, &frag)
    };
    let dof = match c.dof {
        Some(_) => Some([
            program(passes, "comfort-half", "COMFORT_HALF")?,
            program(passes, "comfort-mark", "COMFORT_MARK")?,
            program(passes, "comfort-dof", "COMFORT_DOF")?,
        ]),
        None => None,
    };
    let fade = match c.edge_fade {
        Some(_) => Some(program(passes, "comfort-fade", "COMFORT_FADE")?),
        None => None,
    };
    let layout = t.layout;
    let size = (layout.width() as i32, layout.height() as i32);
    let _guard = StateGuard::new(gl, mv.info)
        .framebuffers()
        .for_pass()
        .textures(TEXTURE_2D, TEXTURE_BINDING_2D, 1..3)
        .textures(TEXTURE_2D_ARRAY, TEXTURE_BINDING_2D_ARRAY, 1..3)
        .samplers(1..3)
        .depth_range()
        .depth_func()
        .blend_func()
        .stencil()
        .caps(&[POLYGON_OFFSET_FILL]);
    super::pass::neutral_state(gl, mv.info);
    copies.ensure(gl, t, depth_format)?;
    // The record, where there is one, overwrites the tested copy's depth (`comfort_record`).
    let recorded = super::comfort_record::source(mv).is_some() && model.scale != 0.0;
    copies.copy(gl, t, dof.is_some() || recorded);
    // Window depth is NDC depth under `glClipControl(.., GL_ZERO_TO_ONE)`, else (z + 1)/2.
    let zero_to_one = crate::synth::zero_to_one(gl);
    if recorded {
        super::comfort_record::overlay(gl, passes, copies, mv, model, zero_to_one)?;
    }
    let near_ndc = if zero_to_one { 0.0 } else { -1.0 };
    let quad_z = |z: f64| z.clamp(near_ndc, 1.0) as f32;
    // SAFETY: the depth test against our copies, never writing them; restored by the guard.
    unsafe {
        gl.Disable(POLYGON_OFFSET_FILL);
        gl.Enable(DEPTH_TEST);
        gl.DepthMask(FALSE);
    }
    crate::gl::guard::set_depth_range(gl, mv.info, [0.0, 1.0]);
    let uniforms = Uniforms::new(gl, mv, model, s, zero_to_one);
    // Drawn pixels: nearer than the far clear.
    let far = if model.reversed { near_ndc } else { 1.0 };
    let drawn = (quad_z(far), if model.reversed { LESS } else { GREATER });
    // Disparity beyond B: depth past the threshold's; below 0: in front of the screen.
    let (d, grows) = behind;
    let behind = (quad_z(d), if grows { LEQUAL } else { GEQUAL });
    let (d, grows) = front;
    let front = (quad_z(d), if grows { GEQUAL } else { LEQUAL });
    let stages = Stages {
        gl,
        passes,
        uniforms: &uniforms,
        stencil: copies.stencil,
    };
    // SAFETY: the depth copy the stages sample, on a unit the guard restores.
    unsafe {
        gl.ActiveTexture(TEXTURE2);
        gl.BindTexture(TEXTURE_2D, copies.depth);
        gl.BindSampler(2, 0);
    }
    if let Some([half_program, mark_program, dof_program]) = dof {
        // SAFETY: our framebuffer and the quilt's colour on unit 1; restored by the guard.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, copies.half_fbo);
            gl.ActiveTexture(TEXTURE1);
            gl.BindTexture(TEXTURE_2D, t.sampled);
            gl.BindSampler(1, 0);
        }
        uniforms.set(gl, half_program, (0.0, ALWAYS));
        let half = [0, 0, (size.0 / 2).max(1), (size.1 / 2).max(1)];
        stages.draw(half_program, [([0, 0, size.0, size.1], vec![half])]);
        // SAFETY: the quilt's framebuffer of ours and the half-size image on unit 1.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, copies.fbo);
            gl.ActiveTexture(TEXTURE1);
            gl.BindTexture(TEXTURE_2D, copies.half);
            gl.BindSampler(1, 0);
        }
        stages.mark(mark_program, drawn, &[[0, 0, size.0, size.1]]);
        stages.blend();
        uniforms.set(gl, dof_program, behind);
        stages.stencil_test();
        stages.draw(
            dof_program,
            (0..layout.views()).map(|i| (stored_rect(t, i), vec![layout.tile_rect(i)])),
        );
    }
    if let (Some(fade_program), Some(band)) = (fade, c.edge_fade) {
        // Without a record the quilt's own depth is as good to test against as our copy.
        // SAFETY: binding the quilt's framebuffer or ours; restored by the guard.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, if recorded { copies.fbo } else { t.resolved_fbo });
            gl.Disable(STENCIL_TEST);
        }
        stages.blend();
        uniforms.set(gl, fade_program, front);
        let bands = |i| {
            let r = layout.tile_rect(i);
            let b = (band.ceil() as i32).min(r[2] / 2);
            (
                stored_rect(t, i),
                vec![[r[0], r[1], b, r[3]], [r[0] + r[2] - b, r[1], b, r[3]]],
            )
        };
        stages.draw(fade_program, (0..layout.views()).map(bands));
    }
    Ok(())
}

/// What the stages share: the context, the full-screen triangle and the uniforms.
struct Stages<'a> {
    gl: &'a Gl,
    passes: &'a super::pass::Passes,
    uniforms: &'a Uniforms,
    stencil: bool,
}

impl Stages<'_> {
    /// Marks the drawn pixels of `rects` in the bound framebuffer's stencil (cleared first),
    /// with `program` (COMFORT_MARK) at `drawn`; nothing when there is no stencil.
    fn mark(&self, program: u32, drawn: (f32, GLenum), rects: &[[i32; 4]]) {
        if !self.stencil {
            return;
        }
        let gl = self.gl;
        // SAFETY: our framebuffer's stencil; state restored by the caller's guard.
        unsafe {
            gl.Disable(BLEND);
            gl.StencilMask(0xff);
            gl.ClearBufferiv(STENCIL, 0, &0);
            gl.Enable(STENCIL_TEST);
            gl.StencilFunc(ALWAYS, 1, 0xff);
            gl.StencilOp(KEEP, KEEP, REPLACE);
            gl.ColorMask(FALSE, FALSE, FALSE, FALSE);
        }
        self.uniforms.set(gl, program, drawn);
        self.draw(program, rects.iter().map(|&r| (r, vec![r])));
        // SAFETY: as above.
        unsafe { gl.ColorMask(TRUE, TRUE, TRUE, TRUE) };
    }

    /// Only the marked pixels from here on (all of them without a stencil).
    fn stencil_test(&self) {
        // SAFETY: state restored by the caller's guard.
        unsafe {
            if self.stencil {
                self.gl.Enable(STENCIL_TEST);
                self.gl.StencilFunc(EQUAL, 1, 0xff);
                self.gl.StencilMask(0);
            } else {
                self.gl.Disable(STENCIL_TEST);
            }
        }
    }

    /// out = src + (1 − a)·dst: the blending stages write premultiplied colour; alpha kept.
    fn blend(&self) {
        let gl = self.gl;
        // SAFETY: state restored by the caller's guard.
        unsafe {
            gl.Enable(BLEND);
            gl.BlendFuncSeparate(ONE, ONE_MINUS_SRC_ALPHA, ZERO, ONE);
            gl.BlendEquationSeparate(FUNC_ADD, FUNC_ADD);
        }
    }

    /// Draws `program` (bound) over each `(tile, viewports)`: the tile at stored texels
    /// (`u_tile`) and the viewports (GL coordinates of the bound framebuffer) to cover.
    fn draw(&self, program: u32, tiles: impl IntoIterator<Item = ([i32; 4], Vec<[i32; 4]>)>) {
        let gl = self.gl;
        let location = super::pass::uniform(gl, program, "u_tile");
        for (t, viewports) in tiles {
            // SAFETY: our uniform and the viewport; restored by the guard.
            unsafe { gl.Uniform4i(location, t[0], t[1], t[2], t[3]) };
            for v in viewports {
                // SAFETY: as above.
                unsafe { gl.Viewport(v[0], v[1], v[2], v[3]) };
                self.passes.draw(gl);
            }
        }
    }
}

/// View `i`'s tile in stored texels (rows top-down when the quilt stores them so).
fn stored_rect(t: &QuiltTarget, i: u32) -> [i32; 4] {
    let r = t.layout.tile_rect(i);
    let h = t.layout.height() as i32;
    let y = if t.layout.flipped { h - r[1] - r[3] } else { r[1] };
    [r[0], y, r[2], r[3]]
}

/// The values every stage of the pass reads, computed once a frame.
struct Uniforms {
    model: ParallaxModel,
    s: f32,
    remap: [f32; 4],
    range: [f32; 4],
    fade: f32,
    radius: f32,
    background: [f32; 4],
    flipped: bool,
    zero_to_one: bool,
}

impl Uniforms {
    fn new(gl: &Gl, mv: &Multiview, model: ParallaxModel, s: f64, zero_to_one: bool) -> Uniforms {
        let c = mv.settings.comfort;
        let mut background = [0f32; 4];
        // SAFETY: a four-float query into a local.
        unsafe { gl.GetFloatv(COLOR_CLEAR_VALUE, background.as_mut_ptr()) };
        Uniforms {
            model,
            s: s as f32,
            remap: crate::multiview::quilt::comfort::remap_pixels(mv),
            range: crate::multiview::quilt::comfort::range_pixels(mv).uniform(),
            fade: c.edge_fade.unwrap_or(0.0) as f32,
            radius: (c.dof.unwrap_or(0.0) * RADIUS_PER_STRENGTH) as f32,
            background,
            flipped: mv.target.as_ref().is_some_and(|t| t.layout.flipped),
            zero_to_one,
        }
    }

    /// Binds `program` with its uniforms: the quad at NDC depth `z`, tested with `func`; the
    /// stage's image (`u_color` or `u_half`) on texture unit 1, the depth copy on unit 2.
    fn set(&self, gl: &Gl, program: u32, (z, func): (f32, GLenum)) {
        let u = |n: &str| super::pass::uniform(gl, program, n);
        let (m, r, g, b) = (self.model, self.remap, self.range, self.background);
        // SAFETY: uniforms of our program, bound here; state restored by the caller's guard.
        unsafe {
            gl.UseProgram(program);
            gl.DepthFunc(func);
            for (name, unit) in [("u_color", 1), ("u_half", 1), ("u_depth", 2)] {
                gl.Uniform1i(u(name), unit);
            }
            gl.Uniform1f(u("u_quad_z"), z);
            gl.Uniform1i(u("u_flipped"), i32::from(self.flipped));
            gl.Uniform1i(u("u_zero_to_one"), i32::from(self.zero_to_one));
            gl.Uniform4f(u("u_model"), m.a_hi, m.a_lo, m.scale, self.s);
            gl.Uniform4f(u("u_remap"), r[0], r[1], r[2], r[3]);
            gl.Uniform4f(u("u_range"), g[0], g[1], g[2], g[3]);
            gl.Uniform1f(u("u_fade"), self.fade);
            gl.Uniform1f(u("u_far_depth"), m.far_depth());
            gl.Uniform1f(u("u_radius"), self.radius);
            gl.Uniform4f(u("u_background"), b[0], b[1], b[2], b[3]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The threshold's depth gives back disparity x, and its side is the right one, for the
    /// usual projection and reversed-Z.
    #[test]
    fn threshold_depth_has_the_asked_disparity() {
        let (near, far, c, s) = (0.1, 100.0, 24.0, 240.0);
        let usual = DepthRange {
            a: -(far + near) / (far - near),
            b: -2.0 * far * near / (far - near),
        };
        let reversed = DepthRange {
            a: -usual.a,
            b: -usual.b,
        };
        for depth in [usual, reversed] {
            let disparity = |z: f64| s * (1.0 - c / depth.w_of_ndc(z));
            for x in [-60.0, 0.0, 43.0, 129.0] {
                let (z, grows) = threshold(depth, c, s, x).unwrap();
                assert!((disparity(z) - x).abs() < 1e-6, "{x}: {}", disparity(z));
                assert_eq!(disparity(z + 1e-4) > x, grows, "{x} {depth:?}");
            }
        }
        assert!(threshold(usual, c, 0.0, 10.0).is_none());
    }
}
