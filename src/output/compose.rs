//! At the frame boundary, the quilt becomes what the window shows: the centre view (`mono`),
//! the quilt letterboxed (`quilt`), two views side by side (`sbs`), a red/cyan anaglyph or
//! the lenticular weave (`native`). All GL state touched is restored, so the app's next frame
//! starts from exactly where it left off.

use super::Presenter;
use super::staging::Staging;
use crate::config::Output;
use crate::gl::guard::StateGuard;
use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::QuiltLayout;

/// Letterboxed rectangle (x0, y0, x1, y1) of a `w`×`h` image fitted into the window.
fn fit(w: u32, h: u32, win_w: u32, win_h: u32) -> [i32; 4] {
    let scale = (win_w as f64 / w as f64).min(win_h as f64 / h as f64);
    let (fw, fh) = ((w as f64 * scale).round() as i32, (h as f64 * scale).round() as i32);
    let (x0, y0) = ((win_w as i32 - fw) / 2, (win_h as i32 - fh) / 2);
    [x0, y0, x0 + fw, y0 + fh]
}

/// Where a tile at quilt position `origin` lands when the whole quilt is drawn into `to`
/// (corners), rounded as the edges of the whole are.
fn tile_in(layout: QuiltLayout, origin: (i32, i32), to: [i32; 4]) -> [i32; 4] {
    let (qw, qh) = (layout.width() as f64, layout.height() as f64);
    let x = |q: i32| to[0] + (q as f64 * (to[2] - to[0]) as f64 / qw).round() as i32;
    let y = |q: i32| to[1] + (q as f64 * (to[3] - to[1]) as f64 / qh).round() as i32;
    let (w, h) = (layout.tile_w as i32, layout.tile_h as i32);
    [x(origin.0), y(origin.1), x(origin.0 + w), y(origin.1 + h)]
}

fn corners(r: [i32; 4]) -> [i32; 4] {
    [r[0], r[1], r[0] + r[2], r[1] + r[3]]
}

/// The two views shown by `sbs` and `anaglyph`: symmetric about the centre, a quarter of the
/// quilt apart on each side.
pub fn stereo_pair(views: u32) -> (u32, u32) {
    if views < 2 {
        return (0, 0);
    }
    let half = (views - 1) as f64 / 2.0;
    let d = ((views - 1) as f64 / 4.0).max(0.5);
    (
        (half - d).round() as u32,
        (half + d).round().min((views - 1) as f64) as u32,
    )
}

fn blit(gl: &Gl, src: [i32; 4], dst: [i32; 4], filter: GLenum) {
    // SAFETY: framebuffers are bound by the caller; rectangles are inside both.
    unsafe {
        gl.BlitFramebuffer(
            src[0],
            src[1],
            src[2],
            src[3],
            dst[0],
            dst[1],
            dst[2],
            dst[3],
            COLOR_BUFFER_BIT,
            filter,
        )
    };
}

fn clear_window(gl: &Gl) {
    let black = [0f32, 0.0, 0.0, 1.0];
    // SAFETY: clears the bound draw framebuffer's colour without touching the clear colour.
    unsafe { gl.ClearBufferfv(COLOR, 0, black.as_ptr()) };
}

/// Clears the real default framebuffer to black.
pub fn blank(gl: &Gl, info: crate::gl::GlInfo) -> Result<(), String> {
    let _guard = StateGuard::new(gl, info).framebuffers().for_pass();
    crate::output::pass::neutral_state(gl, info);
    // SAFETY: the real default framebuffer as destination; restored by the guard.
    unsafe {
        gl.Disable(SCISSOR_TEST);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0);
    }
    clear_window(gl);
    Ok(())
}

/// Draws the quilt into the real default framebuffer (`window` pixels) as `output` asks.
pub fn present(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    window: (u32, u32),
    output: Output,
) -> Result<(), String> {
    let target = mv.target.as_ref().ok_or("no quilt")?;
    let (layout, quilt_fbo, quilt_tex): (QuiltLayout, u32, u32) = (target.layout, target.resolved_fbo, target.sampled);
    let _guard = StateGuard::new(gl, mv.info).framebuffers().for_pass();
    crate::output::pass::neutral_state(gl, mv.info);
    let staged = target.window.samples > 0;
    let out_fbo = if staged {
        Staging::ensure(gl, &mut presenter.staging, window, target.color_format)
    } else {
        0
    };
    // SAFETY: our quilt as the read source, the real default framebuffer (or what stands in
    // for a multisampled one) as destination.
    unsafe {
        gl.Disable(SCISSOR_TEST);
        gl.BindFramebuffer(READ_FRAMEBUFFER, quilt_fbo);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, out_fbo);
        gl.ReadBuffer(COLOR_ATTACHMENT0);
    }
    let win = [0, 0, window.0 as i32, window.1 as i32];
    match output {
        Output::Mono => blit(gl, corners(layout.tile_rect(mv.camera.rig.centre())), win, LINEAR),
        Output::Quilt => {
            clear_window(gl);
            let to = fit(layout.width(), layout.height(), window.0, window.1);
            blit(gl, [0, 0, layout.width() as i32, layout.height() as i32], to, LINEAR);
            // The two views drawn in each other's place go back to their own.
            for view in layout.swapped().map_or(vec![], |(a, b)| vec![a, b]) {
                let cell = tile_in(layout, layout.cell_origin(view), to);
                blit(gl, corners(layout.tile_rect(view)), cell, LINEAR);
            }
        }
        Output::SideBySide => {
            let (l, r) = stereo_pair(layout.views());
            let half = window.0 as i32 / 2;
            blit(gl, corners(layout.tile_rect(l)), [0, 0, half, win[3]], LINEAR);
            blit(gl, corners(layout.tile_rect(r)), [half, 0, win[2], win[3]], LINEAR);
        }
        Output::Anaglyph => anaglyph(gl, presenter, mv, quilt_tex, layout, window)?,
        Output::Native => {
            let (fbo, size) = weave(gl, presenter, mv, quilt_tex, layout)?;
            // SAFETY: the woven image to the window, fitted.
            unsafe {
                gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
                gl.BindFramebuffer(DRAW_FRAMEBUFFER, out_fbo);
            }
            clear_window(gl);
            let filter = if size == window { NEAREST } else { LINEAR };
            blit(
                gl,
                [0, 0, size.0 as i32, size.1 as i32],
                fit(size.0, size.1, window.0, window.1),
                filter,
            );
        }
    }
    presenter.overlay.draw(gl, out_fbo, window)?;
    if let Some(s) = presenter.staging.as_ref().filter(|_| staged) {
        // SAFETY: the real default framebuffer as destination; restored by the guard.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0) };
        s.show(gl, mv.info, &mut presenter.passes)?;
    }
    Ok(())
}

/// The quilt woven into the presenter's native target; its framebuffer and size. The caller
/// restores state.
pub fn weave(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    quilt_tex: u32,
    layout: QuiltLayout,
) -> Result<(u32, (u32, u32)), String> {
    let device = mv.settings.device.clone().ok_or("--output native needs --device")?;
    let input = crate::output::native::WeaveInput {
        device: &device,
        quilt_texture: quilt_tex,
        layout,
        views: layout.views(),
        grid: (layout.cols, layout.rows),
        filter: mv.settings.weave_filter,
    };
    let t = crate::output::native::weave(gl, mv.info, &mut presenter.passes, &mut presenter.native, &input)?;
    Ok((t.fbo, t.size))
}

/// Weaves the quilt and reads the weave back: RGBA8 rows, bottom-up, and its size.
pub fn woven_pixels(gl: &Gl, presenter: &mut Presenter, mv: &Multiview) -> Result<(Vec<u8>, (u32, u32)), String> {
    let target = mv.target.as_ref().ok_or("no quilt")?;
    let (fbo, size) = {
        let _guard = StateGuard::new(gl, mv.info).framebuffers().for_pass();
        crate::output::pass::neutral_state(gl, mv.info);
        weave(gl, presenter, mv, target.sampled, target.layout)?
    };
    let rect = [0, 0, size.0 as i32, size.1 as i32];
    let rgba = crate::gl::readback::read_rgba(gl, mv.info, crate::gl::readback::Source::Fbo(fbo), rect)?;
    Ok((rgba, size))
}

fn anaglyph(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    quilt_tex: u32,
    layout: QuiltLayout,
    window: (u32, u32),
) -> Result<(), String> {
    let program = presenter
        .passes
        .program(gl, mv.info, "anaglyph", crate::output::pass::ANAGLYPH_FRAG)?;
    let (l, r) = stereo_pair(layout.views());
    let u = |n: &str| crate::output::pass::uniform(gl, program, n);
    let (tl, tr) = (layout.tile_rect(l), layout.tile_rect(r));
    // SAFETY: our program drawing into the real default framebuffer; state restored by the guard.
    unsafe {
        gl.Viewport(0, 0, window.0 as i32, window.1 as i32);
        gl.UseProgram(program);
        gl.ActiveTexture(TEXTURE0);
        gl.BindTexture(TEXTURE_2D, quilt_tex);
        gl.Uniform1i(u("u_quilt"), 0);
        gl.Uniform4i(u("u_left"), tl[0], tl[1], tl[2], tl[3]);
        gl.Uniform4i(u("u_right"), tr[0], tr[1], tr[2], tr[3]);
        gl.Uniform2i(u("u_out_size"), window.0 as i32, window.1 as i32);
        gl.Uniform1i(u("u_flipped"), layout.flipped as i32);
    }
    presenter.passes.draw(gl);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letterbox_keeps_aspect() {
        assert_eq!(fit(200, 100, 100, 100), [0, 25, 100, 75]);
        assert_eq!(fit(100, 100, 200, 100), [50, 0, 150, 100]);
    }

    #[test]
    fn tiles_land_inside_the_fitted_quilt() {
        let l = QuiltLayout::new((5, 1), None, (64, 48));
        assert_eq!(tile_in(l, l.cell_origin(2), [0, 0, 160, 24]), [64, 0, 96, 24]);
        assert_eq!(tile_in(l, l.cell_origin(4), [10, 5, 170, 29]), [138, 5, 170, 29]);
    }

    #[test]
    fn stereo_pair_is_symmetric() {
        assert_eq!(stereo_pair(9), (2, 6));
        assert_eq!(stereo_pair(48), (12, 35));
        assert_eq!(stereo_pair(1), (0, 0));
    }
}
