//! The comfort post-pass (README "Comfort"): edge fade and background depth of field, drawn
//! over each view's tile of the finished quilt, before it is composed or dumped.
//!
//! Both effects need each pixel's disparity, so they need the quilt's depth: the pass copies
//! colour and depth (a blit, which also resolves a multisampled quilt's depth), makes a
//! half-size copy of the colour with a linear blit (the pre-blurred image of Agus et al.'s
//! depth of field: a 2x2 box, widened further by bilinear taps), and draws each tile back
//! into the quilt with `glsl-patches/comfort_post.frag`. Every copy is made like the quilt
//! (rows stored top-down when it is), so the shader addresses all of them alike.
//!
//! The disparity is the outermost view's, the same for every view, so a pixel fades or blurs
//! alike in all views and nothing flickers from view to view. The fade goes to the app's
//! clear colour (`GL_COLOR_CLEAR_VALUE` at the swap): that is what the app shows where
//! nothing is drawn, so a faded object looks as if it stood behind the frame.
//! Settings are read every frame (`ComfortSettings`); nothing is compiled in.

use crate::camera::comfort;
use crate::gl::guard::StateGuard;
use crate::gl::*;
use crate::multiview::Multiview;
use crate::synth::disparity::ParallaxModel;

const POST_FRAG: &str = include_str!("../../glsl-patches/comfort_post.frag");

/// Largest blur radius, in tile pixels, at `--dof 1`.
pub const RADIUS_PER_STRENGTH: f64 = 6.0;

/// The copies the pass reads: colour, half-size colour, depth, each with its framebuffer.
#[derive(Default)]
pub struct ComfortCopies {
    pub textures: [u32; 3],
    pub fbos: [u32; 3],
    size: (i32, i32),
    formats: (GLenum, GLenum),
    /// Stored top-down, as the quilt.
    flip: bool,
}

impl ComfortCopies {
    pub fn delete(&mut self, gl: &Gl) {
        // SAFETY: our own objects (zero names are ignored).
        unsafe {
            gl.DeleteTextures(3, self.textures.as_ptr());
            gl.DeleteFramebuffers(3, self.fbos.as_ptr());
        }
        *self = ComfortCopies::default();
    }

    fn ensure(&mut self, gl: &Gl, size: (i32, i32), formats: (GLenum, GLenum), flip: bool) {
        if self.size == size && self.formats == formats && self.flip == flip && self.fbos[0] != 0 {
            return;
        }
        self.delete(gl);
        let half = ((size.0 / 2).max(1), (size.1 / 2).max(1));
        let specs = [
            (formats.0, size, COLOR_ATTACHMENT0),
            (formats.0, half, COLOR_ATTACHMENT0),
            (formats.1, size, DEPTH_ATTACHMENT),
        ];
        for (k, (format, (w, h), point)) in specs.into_iter().enumerate() {
            // SAFETY: our own texture and framebuffer; the caller's guard restores bindings.
            unsafe {
                gl.GenTextures(1, &mut self.textures[k]);
                gl.BindTexture(TEXTURE_2D, self.textures[k]);
                gl.TexStorage2D(TEXTURE_2D, 1, format, w, h);
                let filter = if k == 1 { LINEAR } else { NEAREST };
                gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, filter as i32);
                gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, filter as i32);
                gl.TexParameteri(TEXTURE_2D, TEXTURE_WRAP_S, CLAMP_TO_EDGE as i32);
                gl.TexParameteri(TEXTURE_2D, TEXTURE_WRAP_T, CLAMP_TO_EDGE as i32);
                gl.GenFramebuffers(1, &mut self.fbos[k]);
                gl.BindFramebuffer(FRAMEBUFFER, self.fbos[k]);
                if flip {
                    gl.FramebufferParameteri(FRAMEBUFFER, crate::multiview::window_format::FRAMEBUFFER_FLIP_Y_MESA, 1);
                }
                gl.FramebufferTexture2D(FRAMEBUFFER, point, TEXTURE_2D, self.textures[k], 0);
            }
        }
        self.size = size;
        self.formats = formats;
        self.flip = flip;
    }
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
    let Some(model) = ParallaxModel::new(depth, mv.camera.rig.convergence) else {
        return Ok(());
    };
    let depth_format = crate::gl::depth_copy::describe(gl, mv.info, t.fbo)?.format;
    let dof = c.dof.is_some();
    let program = if dof {
        let frag = comfort::with_glsl(&POST_FRAG.replacen('\n', "\n#define HOLOINJECT_DOF\n", 1));
        passes.program(gl, mv.info, "comfort-dof", &frag)?
    } else {
        passes.program(gl, mv.info, "comfort-fade", &comfort::with_glsl(POST_FRAG))?
    };
    let layout = t.layout;
    let size = (layout.width() as i32, layout.height() as i32);
    if !mv.info.has_samplers() || !gl.CopyImageSubData.is_loaded() {
        return Err("the comfort pass needs GL 4.3 or ES 3.2 (glCopyImageSubData)".into());
    }
    let _guard = StateGuard::new(gl, mv.info)
        .framebuffers()
        .for_pass()
        .textures(TEXTURE_2D, TEXTURE_BINDING_2D, 1..3)
        .samplers(1..3);
    super::pass::neutral_state(gl, mv.info);
    copies.ensure(gl, size, (stored_format(t.color_format), depth_format), t.window.flip_y);
    // The fade alone changes the border bands only: copy and draw those.
    let rects: Vec<[i32; 4]> = if dof {
        vec![[0, 0, size.0, size.1]]
    } else {
        let band = (c.edge_fade.unwrap_or(0.0).ceil() as i32).min(layout.tile_w as i32 / 2);
        (0..layout.views())
            .flat_map(|i| bands(layout.tile_rect(i), band))
            .collect()
    };
    copy(gl, copies, (t.color, t.fbo), size, &rects, dof);
    // SAFETY: our program and copies, drawing into the quilt; state restored by the guard.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, t.resolved_fbo);
        gl.UseProgram(program);
        for (unit, tex) in copies.textures.iter().enumerate() {
            gl.ActiveTexture(TEXTURE0 + unit as u32);
            gl.BindTexture(TEXTURE_2D, *tex);
            gl.BindSampler(unit as u32, 0);
        }
    }
    set_uniforms(gl, program, mv, model, layout.flipped);
    let u = |n: &str| super::pass::uniform(gl, program, n);
    for i in 0..layout.views() {
        let r = layout.tile_rect(i);
        let y = if layout.flipped { size.1 - r[1] - r[3] } else { r[1] };
        // SAFETY: our uniform; restored by the guard.
        unsafe { gl.Uniform4i(u("u_tile"), r[0], y, r[2], r[3]) };
        let band = (c.edge_fade.unwrap_or(0.0).ceil() as i32).min(r[2] / 2);
        let draw = if dof { vec![r] } else { bands(r, band).to_vec() };
        for v in draw {
            // SAFETY: the viewport; restored by the guard.
            unsafe { gl.Viewport(v[0], v[1], v[2], v[3]) };
            passes.draw(gl);
        }
    }
    Ok(())
}

/// The left and right bands, `band` pixels wide, of tile rectangle `r` (GL coordinates).
fn bands(r: [i32; 4], band: i32) -> [[i32; 4]; 2] {
    [[r[0], r[1], band, r[3]], [r[0] + r[2] - band, r[1], band, r[3]]]
}

/// The colour copy's format: an sRGB quilt is copied as the plain format of the same size,
/// so the pass reads and writes back the stored values (sampling sRGB would decode them, and
/// the quilt is written with `FRAMEBUFFER_SRGB` off).
fn stored_format(format: GLenum) -> GLenum {
    match format {
        SRGB8_ALPHA8 => RGBA8,
        SRGB8 => RGB8,
        f => f,
    }
}

/// Colour (a raw copy of the resolved quilt texture) and depth (from the drawn quilt,
/// resolving it) of `rects` (GL coordinates of the quilt), then, for the blur, the half-size
/// colour.
fn copy(
    gl: &Gl,
    copies: &ComfortCopies,
    (resolved, drawn): (u32, u32),
    (w, h): (i32, i32),
    rects: &[[i32; 4]],
    dof: bool,
) {
    let [colour, half, depth] = copies.fbos;
    // SAFETY: copies between textures and framebuffers of ours and the quilt's; bindings
    // restored by the caller's guard (the scissor test is off: `neutral_state`).
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, drawn);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, depth);
        for r in rects {
            // Texture rows are stored as the quilt stores them: the same rectangle, flipped.
            let y = if copies.flip { h - r[1] - r[3] } else { r[1] };
            let t = copies.textures[0];
            gl.CopyImageSubData(
                resolved, TEXTURE_2D, 0, r[0], y, 0, t, TEXTURE_2D, 0, r[0], y, 0, r[2], r[3], 1,
            );
            let (x1, y1) = (r[0] + r[2], r[1] + r[3]);
            gl.BlitFramebuffer(r[0], r[1], x1, y1, r[0], r[1], x1, y1, DEPTH_BUFFER_BIT, NEAREST);
        }
        if !dof {
            return;
        }
        gl.BindFramebuffer(READ_FRAMEBUFFER, colour);
        gl.ReadBuffer(COLOR_ATTACHMENT0);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, half);
        let (hw, hh) = ((w / 2).max(1), (h / 2).max(1));
        gl.BlitFramebuffer(0, 0, w, h, 0, 0, hw, hh, COLOR_BUFFER_BIT, LINEAR);
    }
}

fn set_uniforms(gl: &Gl, program: u32, mv: &Multiview, m: ParallaxModel, flipped: bool) {
    let c = mv.settings.comfort;
    let u = |n: &str| super::pass::uniform(gl, program, n);
    let s = crate::multiview::comfort::pixels_per_parallax(mv) as f32;
    let remap = crate::multiview::comfort::remap_pixels(mv);
    let range = c.range().uniform();
    let mut background = [0f32; 4];
    // SAFETY: a four-float query into a local, then uniforms of our bound program.
    unsafe {
        gl.GetFloatv(COLOR_CLEAR_VALUE, background.as_mut_ptr());
        for (unit, name) in ["u_color", "u_half", "u_depth"].iter().enumerate() {
            gl.Uniform1i(u(name), unit as i32);
        }
        gl.Uniform1i(u("u_flipped"), i32::from(flipped));
        gl.Uniform4f(u("u_model"), m.a_hi, m.a_lo, m.scale, s);
        gl.Uniform4f(u("u_remap"), remap[0], remap[1], remap[2], remap[3]);
        gl.Uniform4f(u("u_range"), range[0], range[1], range[2], range[3]);
        gl.Uniform1f(u("u_fade"), c.edge_fade.unwrap_or(0.0) as f32);
        gl.Uniform1f(u("u_far_depth"), m.far_depth());
        gl.Uniform1f(u("u_radius"), (c.dof.unwrap_or(0.0) * RADIUS_PER_STRENGTH) as f32);
        let b = background;
        gl.Uniform4f(u("u_background"), b[0], b[1], b[2], b[3]);
    }
}
