//! `--measure-error`: on the chosen frames every view is rendered exactly as well, and each
//! synthesised view is compared with its exact render, in the same process and frame.
//!
//! A measured frame renders all views up to the warp point; there the quilt (exact so far) is
//! copied aside, and the warp overwrites the synthesised tiles as on any other frame, so
//! what is presented is the fast mode's image. Both are compared at the swap: per-tile PSNR
//! over RGB (DESIGN §6), logged as one line. What is drawn after the warp point (HUDs) is
//! drawn alike in both and not part of the comparison.

use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::readback::{self, Source};
use crate::gl::*;
use crate::multiview::quilt::layout::QuiltLayout;
use crate::multiview::quilt::target::QuiltTarget;

#[derive(Default)]
pub struct ErrorMeasure {
    fbo: u32,
    texture: u32,
    size: (i32, i32),
    /// A reference was kept this frame.
    pending: bool,
}

/// Per-view PSNR of the synthesised views of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameError {
    /// (view, PSNR dB) of each synthesised view; identical views give infinity.
    pub views: Vec<(u32, f64)>,
}

impl FrameError {
    pub fn mean(&self) -> f64 {
        // A mean over PSNRs with infinities would be infinite: identical views count as the
        // 8-bit ceiling, 100 dB.
        let n = self.views.len().max(1) as f64;
        self.views.iter().map(|v| v.1.min(100.0)).sum::<f64>() / n
    }

    pub fn worst(&self) -> Option<(u32, f64)> {
        self.views.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// PSNR (dB) over RGB between two RGBA8 images of equal size.
pub fn psnr(a: &[u8], b: &[u8]) -> f64 {
    let mut sum = 0u64;
    let mut n = 0u64;
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for c in 0..3 {
            let d = pa[c] as i64 - pb[c] as i64;
            sum += (d * d) as u64;
        }
        n += 3;
    }
    if sum == 0 || n == 0 {
        return f64::INFINITY;
    }
    let mse = sum as f64 / n as f64;
    10.0 * (255.0 * 255.0 / mse).log10()
}

impl ErrorMeasure {
    /// Copies the quilt as it is now (every view exact) aside.
    pub fn keep_reference(&mut self, gl: &Gl, info: GlInfo, quilt: &QuiltTarget) {
        let (w, h) = (quilt.layout.width() as i32, quilt.layout.height() as i32);
        let _guard = StateGuard::new(gl, info).framebuffers().scissor();
        // SAFETY: our own texture and framebuffer; bindings restored by the guard.
        unsafe {
            if self.size != (w, h) {
                gl.DeleteTextures(1, &self.texture);
                gl.GenTextures(1, &mut self.texture);
                gl.BindTexture(TEXTURE_2D, self.texture);
                gl.TexStorage2D(TEXTURE_2D, 1, RGBA8, w, h);
                gl.BindTexture(TEXTURE_2D, 0);
                if self.fbo == 0 {
                    gl.GenFramebuffers(1, &mut self.fbo);
                }
                gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
                gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, self.texture, 0);
                self.size = (w, h);
            }
            gl.Disable(SCISSOR_TEST);
            gl.BindFramebuffer(READ_FRAMEBUFFER, quilt.fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, COLOR_BUFFER_BIT, NEAREST);
        }
        self.pending = true;
    }

    /// At the swap: the synthesised views (all but `rendered`) against the reference kept.
    pub fn compare(&mut self, gl: &Gl, info: GlInfo, quilt: &QuiltTarget, rendered: &[u32]) -> Option<FrameError> {
        if !std::mem::take(&mut self.pending) {
            return None;
        }
        let layout: QuiltLayout = quilt.layout;
        let mut views = Vec::new();
        for i in (0..layout.views()).filter(|i| !rendered.contains(i)) {
            let r = layout.tile_rect(i);
            let exact = readback::read_rgba(gl, info, Source::Fbo(self.fbo), r).ok()?;
            let synth = readback::read_rgba(gl, info, Source::Fbo(quilt.fbo), r).ok()?;
            views.push((i, psnr(&exact, &synth)));
        }
        Some(FrameError { views })
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: our own objects (zero names are ignored).
        unsafe {
            gl.DeleteFramebuffers(1, &self.fbo);
            gl.DeleteTextures(1, &self.texture);
        }
    }

    pub fn texture(&self) -> u32 {
        self.texture
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psnr_of_identical_and_off_by_one() {
        let a = vec![10u8, 20, 30, 255, 40, 50, 60, 0];
        assert_eq!(psnr(&a, &a), f64::INFINITY);
        let b: Vec<u8> = a.iter().map(|v| v.saturating_add(1)).collect();
        assert!((psnr(&a, &b) - 48.13).abs() < 0.01);
        let e = FrameError {
            views: vec![(0, f64::INFINITY), (1, 30.0)],
        };
        assert_eq!(e.mean(), 65.0);
        assert_eq!(e.worst(), Some((1, 30.0)));
    }
}
