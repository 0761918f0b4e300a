//! Depth copies a blit cannot make.
//!
//! `glBlitFramebuffer` of depth (or stencil) is `GL_INVALID_OPERATION` unless both ends have
//! the same depth bits and type, and the same stencil bits where both have stencil. The
//! layer's own images take the app's formats exactly (`format`), but the quilt cannot always
//! have the window's: OpenGL ES has no 32-bit normalised depth renderbuffer to match a
//! 32-bit window (glmark2-es2's), and a format the driver refuses falls back to 24/8. Such
//! copies go through a pass instead: the source's depth is first blitted into a texture of
//! its own format (`depth_copy`), then drawn into the destination with `gl_FragDepth`.
//! Stencil has no such path without `ARB_shader_stencil_export`: it is left out. Measured
//! against a blit between equal 24-bit formats (the pass forced, `cubes` handed back after
//! its last draw): 40% of the pixels one unit of 2^-24 off, the rest identical.

use super::GlInfo;
use super::guard::{StateGuard, neutral_pass_state};
use super::*;

const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const DEPTH_WRITE_FRAG: &str = include_str!("../../glsl-patches/depth_write.frag");

/// What a depth or stencil blit compares at its two ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthFormat {
    pub bits: i32,
    pub float: bool,
    pub stencil: i32,
}

/// Whether a depth (and stencil) blit from `a` to `b` is valid.
pub fn blittable(a: DepthFormat, b: DepthFormat) -> bool {
    a.bits == b.bits && a.float == b.float && (a.stencil == 0 || b.stencil == 0 || a.stencil == b.stencil)
}

fn attachment_iv(gl: &Gl, point: GLenum, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: a single-integer query on the bound read framebuffer.
    unsafe { gl.GetFramebufferAttachmentParameteriv(READ_FRAMEBUFFER, point, pname, &mut v) };
    v
}

/// The depth and stencil of framebuffer `fbo` (0: the window); `None` without depth. Only
/// buffers that exist are asked their sizes (asking others is an error). State restored.
pub fn depth_format(gl: &Gl, info: GlInfo, fbo: u32) -> Option<DepthFormat> {
    let _guard = StateGuard::new(gl, info).framebuffers();
    // SAFETY: binding an existing framebuffer for the queries; the guard restores bindings.
    unsafe { gl.BindFramebuffer(READ_FRAMEBUFFER, fbo) };
    let (depth, stencil) = if fbo == 0 {
        (DEPTH, STENCIL)
    } else {
        (DEPTH_ATTACHMENT, STENCIL_ATTACHMENT)
    };
    let exists = |p| attachment_iv(gl, p, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum != NONE;
    if !exists(depth) {
        return None;
    }
    Some(DepthFormat {
        bits: attachment_iv(gl, depth, FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE),
        float: attachment_iv(gl, depth, FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE) as GLenum == FLOAT,
        stencil: if exists(stencil) {
            attachment_iv(gl, stencil, FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE)
        } else {
            0
        },
    })
}

/// Writes rectangle `src` (x, y, w, h in texels) of our depth texture `texture` into
/// rectangle `dst` of framebuffer `fbo`'s depth, nearest texel; colour and stencil untouched,
/// state restored. For rare copies (a program is made and deleted each time).
pub fn draw(gl: &Gl, info: GlInfo, texture: u32, src: [i32; 4], fbo: u32, dst: [i32; 4]) -> Result<(), String> {
    let _guard = StateGuard::new(gl, info).framebuffers().for_pass().depth_func();
    let program = super::program::link(gl, info, FULLSCREEN_VERT, DEPTH_WRITE_FRAG)
        .map_err(|e| format!("depth write pass: {e}"))?;
    neutral_pass_state(gl, info);
    let [src, dst] = [src, dst].map(|r| r.map(|v| v as f32));
    let mut vao = 0;
    // SAFETY: our program, vertex array and texture; every binding, mask and toggle changed
    // here is put back by the guard; our objects are deleted at the end.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
        gl.ColorMask(FALSE, FALSE, FALSE, FALSE);
        gl.DepthMask(TRUE);
        gl.Enable(DEPTH_TEST);
        gl.DepthFunc(ALWAYS);
        gl.Viewport(dst[0] as i32, dst[1] as i32, dst[2] as i32, dst[3] as i32);
        gl.UseProgram(program);
        gl.Uniform1i(gl.GetUniformLocation(program, c"depth".as_ptr()), 0);
        gl.Uniform4fv(gl.GetUniformLocation(program, c"src".as_ptr()), 1, src.as_ptr());
        gl.Uniform4fv(gl.GetUniformLocation(program, c"dst".as_ptr()), 1, dst.as_ptr());
        gl.ActiveTexture(TEXTURE0);
        gl.BindTexture(TEXTURE_2D, texture);
        gl.GenVertexArrays(1, &mut vao);
        gl.BindVertexArray(vao);
        gl.DrawArrays(TRIANGLES, 0, 3);
        gl.BindVertexArray(0);
        gl.DeleteVertexArrays(1, &vao);
        gl.UseProgram(0);
        gl.DeleteProgram(program);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const fn f(bits: i32, float: bool, stencil: i32) -> DepthFormat {
        DepthFormat { bits, float, stencil }
    }

    /// Mesa's rule (`validate_depth_buffer`): same depth bits and type; stencil bits compared
    /// only when both ends have stencil.
    #[test]
    fn blits_need_the_same_depth_and_stencil_bits() {
        assert!(blittable(f(24, false, 8), f(24, false, 0)));
        assert!(blittable(f(24, false, 8), f(24, false, 8)));
        assert!(
            !blittable(f(32, true, 0), f(32, false, 0)),
            "glmark2-es2's window and quilt"
        );
        assert!(!blittable(f(24, false, 8), f(32, false, 0)));
        assert!(!blittable(f(24, false, 8), f(24, false, 16)));
    }
}
