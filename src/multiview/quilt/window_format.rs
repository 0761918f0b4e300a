//! What the real default framebuffer is made of, asked of GL before the quilt stands in for
//! it, so that the quilt can be made of the same: what a draw to framebuffer 0 computes
//! depends on the target's sample count (coverage, the resolve), its colour encoding (what
//! `GL_FRAMEBUFFER_SRGB` does), its alpha bits (whether destination alpha reads as 1), its
//! depth precision, and, on Mesa, its orientation: Mesa stores window framebuffers top-down
//! and framebuffer objects bottom-up, and rasterises, rounds interpolants and covers smooth
//! lines in storage coordinates, so the same draw lands on different pixels in the two
//! (xscreensaver's `winduprobot`, thin smooth lines: 28,858 of 307,200 pixels off by more
//! than one level). Mesa's
//! `GL_MESA_framebuffer_flip_y` makes a framebuffer object stored like a window; Mesa then
//! maps viewports, scissors, reads, blits, copies, raster positions and `gl_FragCoord` itself.

use crate::gl::GlInfo;
use crate::gl::guard::{StateGuard, get_i};
use crate::gl::*;
use std::ffi::CStr;

/// `GL_MESA_framebuffer_flip_y` (not in the generated bindings).
pub const FRAMEBUFFER_FLIP_Y_MESA: GLenum = 0x8BBB;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowFormat {
    /// Bits of red, green, blue and alpha.
    pub bits: [i32; 4],
    pub srgb: bool,
    /// Samples per pixel, 0 for a single-sampled window.
    pub samples: i32,
    /// Depth/stencil storage and where it attaches.
    pub depth: (GLenum, GLenum),
    /// Framebuffer objects can be stored top-down like the window (Mesa only; other drivers
    /// do not say how they store windows).
    pub flip_y: bool,
}

/// One attachment query on the real default framebuffer (bound for draw by the caller);
/// `default` when the window has no such buffer, whose sizes are not queryable
/// (GL_INVALID_OPERATION: most windows have no stencil, single-buffered ones no back buffer).
fn default_iv(gl: &Gl, attachment: GLenum, pname: GLenum, default: i32) -> i32 {
    let (mut kind, mut v) = (0, default);
    // SAFETY: one integer out per query; framebuffer 0 is bound for draw.
    unsafe {
        gl.GetFramebufferAttachmentParameteriv(
            DRAW_FRAMEBUFFER,
            attachment,
            FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
            &mut kind,
        );
        if kind as GLenum == NONE {
            return default;
        }
        gl.GetFramebufferAttachmentParameteriv(DRAW_FRAMEBUFFER, attachment, pname, &mut v);
    }
    v
}

/// Depth/stencil storage like the window's: a 32-bit window depth buffer resolves close
/// surfaces differently from a 24-bit one, so the quilt must not be coarser.
fn depth_format(gl: &Gl, info: GlInfo) -> (GLenum, GLenum) {
    let d = default_iv(gl, DEPTH, FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, 0);
    let s = default_iv(gl, STENCIL, FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE, 0);
    match (d, s > 0) {
        // ES has no 32-bit normalised depth renderbuffers.
        (32, false) if info.es => (DEPTH_COMPONENT32F, DEPTH_ATTACHMENT),
        (32, false) => (DEPTH_COMPONENT32, DEPTH_ATTACHMENT),
        (32, true) => (DEPTH32F_STENCIL8, DEPTH_STENCIL_ATTACHMENT),
        (16, false) => (DEPTH_COMPONENT16, DEPTH_ATTACHMENT),
        _ => (DEPTH24_STENCIL8, DEPTH_STENCIL_ATTACHMENT),
    }
}

/// Whether the context lists each of `names`.
fn extensions<const N: usize>(gl: &Gl, names: [&str; N]) -> [bool; N] {
    let mut found = [false; N];
    if !gl.GetStringi.is_loaded() {
        return found;
    }
    for i in 0..get_i(gl, NUM_EXTENSIONS).max(0) as u32 {
        // SAFETY: an index below GL_NUM_EXTENSIONS; GL returns a static string or null.
        let p = unsafe { gl.GetStringi(EXTENSIONS, i) };
        if p.is_null() {
            continue;
        }
        // SAFETY: GL's extension names are NUL-terminated static strings.
        let name = unsafe { CStr::from_ptr(p.cast()) }.to_bytes();
        for (k, n) in names.iter().enumerate() {
            found[k] |= name == n.as_bytes();
        }
    }
    found
}

impl WindowFormat {
    /// The real default framebuffer's format; bindings restored.
    pub fn query(gl: &Gl, info: GlInfo) -> WindowFormat {
        let _guard = StateGuard::new(gl, info).framebuffers();
        // SAFETY: binding the real default framebuffer for the queries; restored by the guard.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0) };
        // A single-buffered window has only its front buffer (ES names only the back one).
        let has = |b| default_iv(gl, b, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, NONE as i32) as GLenum != NONE;
        let color = if info.es {
            BACK
        } else if has(BACK_LEFT) {
            BACK_LEFT
        } else {
            FRONT_LEFT
        };
        let bits = [
            FRAMEBUFFER_ATTACHMENT_RED_SIZE,
            FRAMEBUFFER_ATTACHMENT_GREEN_SIZE,
            FRAMEBUFFER_ATTACHMENT_BLUE_SIZE,
            FRAMEBUFFER_ATTACHMENT_ALPHA_SIZE,
        ]
        .map(|pname| default_iv(gl, color, pname, 8));
        let encoding = default_iv(gl, color, FRAMEBUFFER_ATTACHMENT_COLOR_ENCODING, LINEAR as i32);
        let [flip_y] = extensions(gl, ["GL_MESA_framebuffer_flip_y"]);
        WindowFormat {
            bits,
            srgb: encoding as GLenum == SRGB,
            samples: get_i(gl, SAMPLES).max(0),
            depth: depth_format(gl, info),
            flip_y: flip_y && gl.FramebufferParameteri.is_loaded(),
        }
    }

    /// The colour format of a quilt behaving like the window: as many bits per channel
    /// (blending and dithering round to them), no alpha where the window has none
    /// (destination alpha then reads as 1), sRGB where the window is sRGB-capable.
    pub fn color_format(&self, info: GlInfo) -> GLenum {
        let alpha = self.bits[3] > 0;
        match (self.bits, self.srgb, alpha) {
            (_, true, true) => SRGB8_ALPHA8,
            // ES cannot render to SRGB8.
            (_, true, false) if info.es => SRGB8_ALPHA8,
            (_, true, false) => SRGB8,
            ([5, 6, 5, 0], _, _) => RGB565,
            ([10, 10, 10, 2], _, _) => RGB10_A2,
            ([10, 10, 10, 0], _, _) if info.es => RGB10_A2,
            ([10, 10, 10, 0], _, _) => RGB10,
            ([16, 16, 16, _], _, true) if !info.es => RGBA16,
            ([16, 16, 16, _], _, false) if !info.es => RGB16,
            (_, _, true) => RGBA8,
            (_, _, false) => RGB8,
        }
    }

    /// The closest format with alpha, should the driver not render to `color_format`.
    pub fn with_alpha(&self) -> GLenum {
        match (self.srgb, self.bits[0]) {
            (true, _) => SRGB8_ALPHA8,
            (false, 10) => RGB10_A2,
            (false, _) => RGBA8,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(bits: [i32; 4], srgb: bool) -> WindowFormat {
        WindowFormat {
            bits,
            srgb,
            samples: 0,
            depth: (DEPTH24_STENCIL8, DEPTH_STENCIL_ATTACHMENT),
            flip_y: true,
        }
    }

    #[test]
    fn quilt_colour_follows_the_window() {
        let gl = GlInfo::parse("4.5 (Compatibility Profile) Mesa 22.3.6");
        let es = GlInfo::parse("OpenGL ES 3.2 Mesa 22.3.6");
        assert_eq!(window([8, 8, 8, 8], false).color_format(gl), RGBA8);
        assert_eq!(window([8, 8, 8, 0], false).color_format(gl), RGB8);
        assert_eq!(window([8, 8, 8, 8], true).color_format(gl), SRGB8_ALPHA8);
        assert_eq!(window([8, 8, 8, 0], true).color_format(gl), SRGB8);
        assert_eq!(window([8, 8, 8, 0], true).color_format(es), SRGB8_ALPHA8);
        assert_eq!(window([10, 10, 10, 0], false).color_format(gl), RGB10);
        assert_eq!(window([10, 10, 10, 2], false).color_format(gl), RGB10_A2);
        assert_eq!(window([5, 6, 5, 0], false).color_format(gl), RGB565);
        assert_eq!(window([10, 10, 10, 0], false).with_alpha(), RGB10_A2);
    }
}
