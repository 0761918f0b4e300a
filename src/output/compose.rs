//! At the frame boundary, the quilt becomes what the window shows: the centre view (`mono`),
//! the quilt letterboxed (`quilt`), two views side by side (`sbs`), a red/cyan anaglyph or
//! the lenticular weave (`native`). All GL state touched is restored, so the app's next frame
//! starts from exactly where it left off.

use crate::config::Output;
use crate::gl::guard::StateGuard;
use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::layout::QuiltLayout;

/// Letterboxed rectangle (x0, y0, x1, y1) of a `w`×`h` image fitted into the window.
fn fit(w: u32, h: u32, win_w: u32, win_h: u32) -> [i32; 4] {
    let scale = (win_w as f64 / w as f64).min(win_h as f64 / h as f64);
    let (fw, fh) = ((w as f64 * scale).round() as i32, (h as f64 * scale).round() as i32);
    let (x0, y0) = ((win_w as i32 - fw) / 2, (win_h as i32 - fh) / 2);
    [x0, y0, x0 + fw, y0 + fh]
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

/// Draws the quilt into the real default framebuffer (`window` pixels) as `output` asks.
pub fn present(gl: &Gl, mv: &Multiview, window: (u32, u32), output: Output) -> Result<(), String> {
    let target = mv.target.as_ref().ok_or("no quilt")?;
    let layout: QuiltLayout = target.layout;
    let _guard = StateGuard::new(gl, mv.info).framebuffers().for_pass();
    // SAFETY: our quilt as the read source, the real default framebuffer as destination.
    unsafe {
        gl.Disable(SCISSOR_TEST);
        gl.BindFramebuffer(READ_FRAMEBUFFER, target.fbo);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0);
        gl.ReadBuffer(COLOR_ATTACHMENT0);
    }
    let win = [0, 0, window.0 as i32, window.1 as i32];
    match output {
        Output::Mono => blit(gl, corners(layout.tile_rect(mv.rig.centre())), win, LINEAR),
        Output::Quilt => {
            clear_window(gl);
            blit(
                gl,
                [0, 0, layout.width() as i32, layout.height() as i32],
                fit(layout.width(), layout.height(), window.0, window.1),
                LINEAR,
            );
        }
        Output::SideBySide => {
            let (l, r) = stereo_pair(layout.views());
            let half = window.0 as i32 / 2;
            blit(gl, corners(layout.tile_rect(l)), [0, 0, half, win[3]], LINEAR);
            blit(gl, corners(layout.tile_rect(r)), [half, 0, win[2], win[3]], LINEAR);
        }
        Output::Anaglyph | Output::Native => {
            return Err(format!("--output {output:?} is not available in this build yet"));
        }
    }
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
    fn stereo_pair_is_symmetric() {
        assert_eq!(stereo_pair(9), (2, 6));
        assert_eq!(stereo_pair(48), (12, 35));
        assert_eq!(stereo_pair(1), (0, 0));
    }
}
