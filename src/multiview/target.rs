//! The quilt render target that stands in for the app's default framebuffer: one colour
//! texture holding every view's tile and a depth/stencil renderbuffer, both sized to the
//! whole quilt. The colour format follows the real default framebuffer (alpha or not), so
//! blending with destination alpha behaves as it would on screen.

use super::layout::QuiltLayout;
use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::*;

pub struct QuiltTarget {
    pub fbo: u32,
    pub color: u32,
    pub depth: u32,
    pub layout: QuiltLayout,
}

/// One size query on the real default framebuffer (bound for draw by the caller's guard);
/// `None` when the window has no such buffer, whose sizes are not queryable
/// (GL_INVALID_OPERATION: most windows have no stencil, single-buffered ones no back buffer).
fn default_size(gl: &Gl, attachment: GLenum, pname: GLenum) -> Option<i32> {
    let (mut kind, mut bits) = (0, 0);
    // SAFETY: one integer out per query.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0);
        gl.GetFramebufferAttachmentParameteriv(
            DRAW_FRAMEBUFFER,
            attachment,
            FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
            &mut kind,
        );
        if kind as GLenum == NONE {
            return None;
        }
        gl.GetFramebufferAttachmentParameteriv(DRAW_FRAMEBUFFER, attachment, pname, &mut bits);
    }
    Some(bits)
}

/// Depth/stencil storage like the window's: a 32-bit window depth buffer resolves close
/// surfaces differently from a 24-bit one, so the quilt must not be coarser.
fn depth_format(gl: &Gl, info: GlInfo) -> (GLenum, GLenum) {
    let d = default_size(gl, DEPTH, FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE).unwrap_or(0);
    let s = default_size(gl, STENCIL, FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE).unwrap_or(0);
    match (d, s > 0) {
        // ES has no 32-bit normalised depth renderbuffers.
        (32, false) if info.es => (DEPTH_COMPONENT32F, DEPTH_ATTACHMENT),
        (32, false) => (DEPTH_COMPONENT32, DEPTH_ATTACHMENT),
        (32, true) => (DEPTH32F_STENCIL8, DEPTH_STENCIL_ATTACHMENT),
        (16, false) => (DEPTH_COMPONENT16, DEPTH_ATTACHMENT),
        _ => (DEPTH24_STENCIL8, DEPTH_STENCIL_ATTACHMENT),
    }
}

/// Alpha bits of the real default framebuffer's colour buffer (the front one of a
/// single-buffered window; ES names only the back one).
fn default_has_alpha(gl: &Gl, info: GlInfo) -> bool {
    let alpha = |buffer| default_size(gl, buffer, FRAMEBUFFER_ATTACHMENT_ALPHA_SIZE);
    let bits = if info.es {
        alpha(BACK)
    } else {
        alpha(BACK_LEFT).or_else(|| alpha(FRONT_LEFT))
    };
    bits.unwrap_or(8) > 0
}

impl QuiltTarget {
    /// The quilt with depth as precise as the window's, or the universal 24/8 format when the
    /// driver cannot render to that one.
    pub fn create(gl: &Gl, info: GlInfo, layout: QuiltLayout) -> Result<QuiltTarget, String> {
        let preferred = {
            let _guard = StateGuard::new(gl, info).framebuffers();
            depth_format(gl, info)
        };
        let fallback = (DEPTH24_STENCIL8, DEPTH_STENCIL_ATTACHMENT);
        match QuiltTarget::create_with(gl, info, layout, preferred) {
            Err(_) if preferred != fallback => QuiltTarget::create_with(gl, info, layout, fallback),
            result => result,
        }
    }

    fn create_with(
        gl: &Gl,
        info: GlInfo,
        layout: QuiltLayout,
        (depth_format, depth_point): (GLenum, GLenum),
    ) -> Result<QuiltTarget, String> {
        let _guard = StateGuard::new(gl, info).framebuffers().for_pass();
        let alpha = default_has_alpha(gl, info);
        let (mut fbo, mut color, mut depth) = (0, 0, 0);
        let (w, h) = (layout.width() as i32, layout.height() as i32);
        // SAFETY: creating and configuring our own objects; bindings are restored by the guard.
        let status = unsafe {
            gl.GenTextures(1, &mut color);
            gl.BindTexture(TEXTURE_2D, color);
            gl.TexStorage2D(TEXTURE_2D, 1, if alpha { RGBA8 } else { RGB8 }, w, h);
            for (p, v) in [
                (TEXTURE_MIN_FILTER, LINEAR),
                (TEXTURE_MAG_FILTER, LINEAR),
                (TEXTURE_WRAP_S, CLAMP_TO_EDGE),
                (TEXTURE_WRAP_T, CLAMP_TO_EDGE),
            ] {
                gl.TexParameteri(TEXTURE_2D, p, v as i32);
            }
            gl.GenRenderbuffers(1, &mut depth);
            gl.BindRenderbuffer(RENDERBUFFER, depth);
            gl.RenderbufferStorage(RENDERBUFFER, depth_format, w, h);
            gl.GenFramebuffers(1, &mut fbo);
            gl.BindFramebuffer(FRAMEBUFFER, fbo);
            gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, color, 0);
            gl.FramebufferRenderbuffer(FRAMEBUFFER, depth_point, RENDERBUFFER, depth);
            gl.CheckFramebufferStatus(FRAMEBUFFER)
        };
        let target = QuiltTarget {
            fbo,
            color,
            depth,
            layout,
        };
        if status != FRAMEBUFFER_COMPLETE {
            target.delete(gl);
            return Err(format!("quilt framebuffer {w}x{h} incomplete (status {status:#x})"));
        }
        Ok(target)
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting objects we created; zero names are ignored by GL.
        unsafe {
            gl.DeleteFramebuffers(1, &self.fbo);
            gl.DeleteTextures(1, &self.color);
            gl.DeleteRenderbuffers(1, &self.depth);
        }
    }
}
