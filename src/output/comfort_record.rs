//! The disparity record in the comfort pass (DESIGN §5: the depth of field reads the same
//! parallax as every other consumer).
//!
//! The depth of field and the edge fade test and shade against a copy of the quilt's depth,
//! through the scene's depth model. On a renderer that draws its scene off-screen and composites it, that
//! depth is the composite's full-screen quad (or nothing), the blur found no background and the fade no foreground.
//! The record knows each rendered pixel's parallax wherever the scene was drawn, so before
//! the stages run, every recorded pixel's depth in the copy is replaced by the window depth
//! the scene's model gives that parallax (`comfort_record.frag`, one full-screen pass per
//! tile, depth writes only): the stages, their early depth rejection and their stencil marks
//! then work on it unchanged. Unrecorded pixels (fixed-function draws, views the fast modes
//! synthesised, whose depth the warp wrote) keep the quilt's depth, or, when the scene is
//! drawn off-screen, take its framebuffer's (the quilt's is the composite's there).

use super::comfort_images::ComfortCopies;
use crate::gl::*;
use crate::multiview::Multiview;
use crate::synth::disparity::ParallaxModel;

const FRAG: &str = include_str!("../../glsl-patches/comfort_record.frag");

/// The scene target's record, if it has one: the quilt's (`true`) or its shadow's.
pub fn source(mv: &Multiview) -> Option<(crate::multiview::quilt::record::RecordImage, bool)> {
    match mv.scene.tracker.target? {
        0 => mv.record.quilt.map(|r| (r, true)),
        f => mv.record.shadow.filter(|(g, _)| *g == f).map(|(_, r)| (r, false)),
    }
}

/// Writes the record's depth into `copies`' depth (its cull renderbuffer, then the sampled
/// texture). Runs inside the comfort pass's state guard; leaves colour writes on.
pub fn overlay(
    gl: &Gl,
    passes: &mut super::pass::Passes,
    copies: &ComfortCopies,
    mv: &Multiview,
    model: ParallaxModel,
    zero_to_one: bool,
) -> Result<(), String> {
    let Some(t) = mv.target.as_ref() else { return Ok(()) };
    let Some((img, quilt)) = source(mv).filter(|_| model.scale != 0.0) else {
        return Ok(());
    };
    // A scene drawn off-screen: its depth where nothing recorded, not the composite's.
    let shadow_depth = mv.scene.tracker.target.and_then(|f| mv.shadows.get(&f)).and_then(|s| {
        s.attached
            .iter()
            .find(|a| matches!(a.point, DEPTH_ATTACHMENT | DEPTH_STENCIL_ATTACHMENT))
            .map(|a| a.array)
    });
    let shadow_flipped = mv.scene_shadow().is_some_and(|s| s.presented_flipped);
    if !quilt && shadow_depth.is_none() {
        return Ok(());
    }
    let program = passes.program(gl, mv.info, "comfort-record", FRAG)?;
    let layout = t.layout;
    let loc = |name| super::pass::uniform(gl, program, name);
    // SAFETY: our framebuffer, program and textures; the comfort pass's guard restores them.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, copies.fbo);
        gl.ColorMask(FALSE, FALSE, FALSE, FALSE);
        gl.Enable(DEPTH_TEST);
        gl.DepthFunc(ALWAYS);
        gl.DepthMask(TRUE);
        gl.Disable(STENCIL_TEST);
        gl.UseProgram(program);
        gl.ActiveTexture(TEXTURE1);
        if quilt {
            gl.BindTexture(TEXTURE_2D, img.texture);
        } else {
            gl.BindTexture(TEXTURE_2D_ARRAY, img.texture);
        }
        gl.BindSampler(1, 0);
        gl.Uniform1i(loc("u_quilt_record"), if quilt { 1 } else { 3 });
        gl.Uniform1i(loc("u_shadow_record"), if quilt { 3 } else { 1 });
        gl.ActiveTexture(TEXTURE2);
        gl.BindTexture(TEXTURE_2D_ARRAY, shadow_depth.unwrap_or(0));
        gl.BindSampler(2, 0);
        gl.Uniform1i(loc("u_shadow_depth"), 2);
        gl.Uniform2i(loc("u_src_size"), img.size.0, img.size.1);
        let rows = if quilt && layout.flipped {
            layout.height() as i32
        } else {
            0
        };
        gl.Uniform1i(loc("u_quilt_rows"), rows);
        gl.Uniform1i(loc("u_shadow_flipped"), i32::from(!quilt && shadow_flipped));
        let m = model;
        gl.Uniform4f(loc("u_model"), m.a_hi, m.a_lo, m.scale, zero_to_one as i32 as f32);
        gl.Uniform1f(loc("u_quad_z"), 0.0);
    }
    for i in 0..layout.views() {
        let r = layout.tile_rect(i);
        // SAFETY: viewport and our uniforms, as above.
        unsafe {
            gl.Viewport(r[0], r[1], r[2], r[3]);
            gl.Uniform4i(loc("u_tile"), r[0], r[1], r[2], r[3]);
            gl.Uniform1i(loc("u_layer"), if quilt { -1 } else { i as i32 });
        }
        passes.draw(gl);
    }
    let (w, h) = (layout.width() as i32, layout.height() as i32);
    // SAFETY: our renderbuffer into our texture, same format and size; colour writes back on
    // for the stages (the guard restores the app's).
    unsafe {
        gl.CopyImageSubData(
            copies.cull(),
            RENDERBUFFER,
            0,
            0,
            0,
            0,
            copies.depth,
            TEXTURE_2D,
            0,
            0,
            0,
            0,
            w,
            h,
            1,
        );
        gl.ColorMask(TRUE, TRUE, TRUE, TRUE);
    }
    Ok(())
}
