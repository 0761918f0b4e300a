//! The quilt render target that stands in for the app's default framebuffer: colour holding
//! every view's tile and depth/stencil, both sized to the whole quilt, made like the real
//! default framebuffer (`window_format`): the same samples, colour encoding, alpha and depth
//! bits, and, where the driver allows it, stored top-down as the window is.
//!
//! A multisampled quilt is drawn into renderbuffers and resolved, as the window resolves at
//! its swap, into a single-sampled texture: what is presented, dumped and read back.

use super::layout::QuiltLayout;
use super::window_format::{FRAMEBUFFER_FLIP_Y_MESA, WindowFormat};
use crate::gl::GlInfo;
use crate::gl::guard::StateGuard;
use crate::gl::types::GLbitfield;
use crate::gl::*;

pub struct QuiltTarget {
    /// What the app's draws to framebuffer 0 land in.
    pub fbo: u32,
    /// The quilt as presented: a single-sampled texture, attached to `resolved_fbo`.
    pub color: u32,
    /// What our passes sample: `color`, or, when it is sRGB, a linear view of it, so that
    /// `texelFetch` (which decodes sRGB whatever `TEXTURE_SRGB_DECODE_EXT` says, on Mesa)
    /// reads the stored values, as the window shows them.
    pub sampled: u32,
    pub resolved_fbo: u32,
    /// The multisampled colour renderbuffer `fbo` draws into (0 when single-sampled: `fbo`
    /// is then `resolved_fbo`).
    pub msaa_color: u32,
    pub depth: u32,
    /// Multisampled only: depth/stencil resolved for the app's reads of framebuffer 0.
    pub resolved_depth: u32,
    pub samples: i32,
    pub layout: QuiltLayout,
    /// What the quilt was made like, and its colour format.
    pub window: WindowFormat,
    pub color_format: GLenum,
}

/// One attempt at the quilt: samples, colour, depth/stencil and its attachment point.
type Formats = (i32, GLenum, (GLenum, GLenum));

/// Samples (pixels times samples per pixel) a multisampled quilt may have: 2^26, so colour
/// and depth take at most 512 MB (4 samples of an 8x6 quilt of 640x480 tiles take 470 MB).
const MAX_QUILT_SAMPLES: u64 = 1 << 26;

/// A framebuffer of ours with `attach` done on it, stored as the window is when `flip`.
pub(crate) fn framebuffer(gl: &Gl, flip: bool, attach: impl FnOnce()) -> u32 {
    let mut fbo = 0;
    // SAFETY: our own framebuffer; bindings are restored by the caller's guard.
    unsafe {
        gl.GenFramebuffers(1, &mut fbo);
        gl.BindFramebuffer(FRAMEBUFFER, fbo);
        if flip {
            gl.FramebufferParameteri(FRAMEBUFFER, FRAMEBUFFER_FLIP_Y_MESA, TRUE as i32);
        }
    }
    attach();
    fbo
}

fn renderbuffer(gl: &Gl, samples: i32, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut rb = 0;
    // SAFETY: our own renderbuffer; the binding is restored by the caller's guard.
    unsafe {
        gl.GenRenderbuffers(1, &mut rb);
        gl.BindRenderbuffer(RENDERBUFFER, rb);
        if samples > 0 {
            gl.RenderbufferStorageMultisample(RENDERBUFFER, samples, format, w, h);
        } else {
            gl.RenderbufferStorage(RENDERBUFFER, format, w, h);
        }
    }
    rb
}

fn texture(gl: &Gl, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut t = 0;
    // SAFETY: our own texture; the binding is restored by the caller's guard.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(TEXTURE_2D, t);
        gl.TexStorage2D(TEXTURE_2D, 1, format, w, h);
        for (p, v) in [
            (TEXTURE_MIN_FILTER, LINEAR),
            (TEXTURE_MAG_FILTER, LINEAR),
            (TEXTURE_WRAP_S, CLAMP_TO_EDGE),
            (TEXTURE_WRAP_T, CLAMP_TO_EDGE),
        ] {
            gl.TexParameteri(TEXTURE_2D, p, v as i32);
        }
    }
    t
}

/// A view of `color` (immutable storage in `format`) in the linear format of the same size
/// (desktop GL 4.3; elsewhere our passes read an sRGB quilt decoded).
pub(in crate::multiview) fn linear_view(gl: &Gl, info: GlInfo, color: u32, format: GLenum) -> u32 {
    let linear = match format {
        SRGB8_ALPHA8 => RGBA8,
        SRGB8 => RGB8,
        _ => return color,
    };
    // Loaders hand out entry points whatever the context (libglvnd): ask the version.
    if info.es || !info.at_least(4, 3) || !gl.TextureView.is_loaded() {
        return color;
    }
    let mut view = 0;
    // SAFETY: a view of our own immutable texture in a format of its view class.
    unsafe {
        gl.GenTextures(1, &mut view);
        gl.TextureView(view, TEXTURE_2D, color, linear, 0, 1, 0, 1);
    }
    view
}

pub(crate) fn complete(gl: &Gl) -> bool {
    // SAFETY: a status query on the bound framebuffer.
    unsafe { gl.CheckFramebufferStatus(FRAMEBUFFER) == FRAMEBUFFER_COMPLETE }
}

impl QuiltTarget {
    /// The quilt made like the window, or, when the driver cannot render to that, with
    /// alpha, then in plain RGBA8 with 24/8 depth, then single-sampled (each fallback
    /// logged). A multisampled quilt past `MAX_QUILT_SAMPLES` is single-sampled.
    pub fn create(gl: &Gl, info: GlInfo, layout: QuiltLayout) -> Result<QuiltTarget, String> {
        let window = WindowFormat::query(gl, info);
        let pixels = layout.storage_width() as u64 * layout.height() as u64;
        let samples = if window.samples as u64 * pixels > MAX_QUILT_SAMPLES {
            crate::log::warn(format_args!(
                "a {}x{} quilt with {} samples per pixel would take more than {} MB: single-sampled \
                 (the centre view's edges then differ from the window's)",
                layout.width(),
                layout.height(),
                window.samples,
                (MAX_QUILT_SAMPLES * 8) >> 20,
            ));
            0
        } else {
            window.samples
        };
        let plain = (RGBA8, (DEPTH24_STENCIL8, DEPTH_STENCIL_ATTACHMENT));
        let mut tries: Vec<Formats> = vec![
            (samples, window.color_format(info), window.depth),
            (samples, window.with_alpha(), window.depth),
            (samples, plain.0, plain.1),
            (0, plain.0, plain.1),
        ];
        tries.dedup();
        let mut error = String::new();
        for (n, formats) in tries.iter().enumerate() {
            match QuiltTarget::create_with(gl, info, window, layout, *formats) {
                Ok(t) if n == 0 => return Ok(t),
                Ok(t) => {
                    crate::log::warn(format_args!(
                        "the quilt cannot be made like the window ({window:?}): {} samples, colour {:#x}, \
                         depth {:#x} instead",
                        formats.0, formats.1, formats.2.0
                    ));
                    return Ok(t);
                }
                Err(e) => error = e,
            }
        }
        Err(error)
    }

    fn create_with(
        gl: &Gl,
        info: GlInfo,
        window: WindowFormat,
        layout: QuiltLayout,
        (samples, color_format, (depth_format, depth_point)): Formats,
    ) -> Result<QuiltTarget, String> {
        let _guard = StateGuard::new(gl, info).framebuffers().for_pass();
        let layout = layout.stored(window.flip_y);
        let size = (layout.storage_width() as i32, layout.height() as i32);
        let color = texture(gl, color_format, size);
        let sampled = linear_view(gl, info, color, color_format);
        let depth = renderbuffer(gl, samples, depth_format, size);
        let (msaa_color, resolved_depth) = if samples > 0 {
            (
                renderbuffer(gl, samples, color_format, size),
                renderbuffer(gl, 0, depth_format, size),
            )
        } else {
            (0, depth)
        };
        let mut ok = true;
        // SAFETY: attaching our own images to our own framebuffers.
        let resolved_fbo = framebuffer(gl, window.flip_y, || unsafe {
            gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, color, 0);
            gl.FramebufferRenderbuffer(FRAMEBUFFER, depth_point, RENDERBUFFER, resolved_depth);
            ok &= complete(gl);
        });
        let fbo = if samples > 0 {
            // SAFETY: as above.
            framebuffer(gl, window.flip_y, || unsafe {
                gl.FramebufferRenderbuffer(FRAMEBUFFER, COLOR_ATTACHMENT0, RENDERBUFFER, msaa_color);
                gl.FramebufferRenderbuffer(FRAMEBUFFER, depth_point, RENDERBUFFER, depth);
                ok &= complete(gl);
            })
        } else {
            resolved_fbo
        };
        let target = QuiltTarget {
            fbo,
            color,
            sampled,
            resolved_fbo,
            msaa_color,
            depth,
            resolved_depth,
            samples,
            layout,
            window,
            color_format,
        };
        if !ok {
            target.delete(gl);
            let (w, h) = size;
            return Err(format!(
                "quilt framebuffer {w}x{h} ({samples} samples, colour {color_format:#x}) incomplete"
            ));
        }
        Ok(target)
    }

    /// Resolves `mask`'s buffers in `rect` of the multisampled quilt into `resolved_fbo`, as
    /// the window's own resolve does: sample values averaged as stored, whatever the app's
    /// `GL_FRAMEBUFFER_SRGB`. Nothing to do when single-sampled.
    pub fn resolve(&self, gl: &Gl, info: GlInfo, rect: [i32; 4], mask: GLbitfield) {
        if self.samples == 0 {
            return;
        }
        let mut caps = vec![SCISSOR_TEST];
        if !info.es {
            caps.push(FRAMEBUFFER_SRGB);
        }
        let _guard = StateGuard::new(gl, info).framebuffers().caps(&caps);
        let [x, y, w, h] = rect;
        // SAFETY: a same-rectangle blit between our framebuffers; bindings, scissor and sRGB
        // are restored by the guard, the quilt's read buffer (the app's choice for
        // framebuffer 0) here.
        unsafe {
            caps.iter().for_each(|&c| gl.Disable(c));
            gl.BindFramebuffer(READ_FRAMEBUFFER, self.fbo);
            let app_read = crate::gl::guard::get_i(gl, READ_BUFFER) as GLenum;
            gl.ReadBuffer(COLOR_ATTACHMENT0);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.resolved_fbo);
            gl.BlitFramebuffer(x, y, x + w, y + h, x, y, x + w, y + h, mask, NEAREST);
            gl.ReadBuffer(app_read);
        }
    }

    /// `mask`'s buffers of the whole quilt, resolved.
    pub fn resolve_all(&self, gl: &Gl, info: GlInfo, mask: GLbitfield) {
        let l = self.layout;
        self.resolve(gl, info, [0, 0, l.width() as i32, l.height() as i32], mask);
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting objects we created; zero names are ignored by GL.
        unsafe {
            if self.fbo != self.resolved_fbo {
                gl.DeleteFramebuffers(1, &self.fbo);
            }
            gl.DeleteFramebuffers(1, &self.resolved_fbo);
            gl.DeleteTextures(1, &self.color);
            if self.sampled != self.color {
                gl.DeleteTextures(1, &self.sampled);
            }
            gl.DeleteRenderbuffers(1, &self.depth);
            gl.DeleteRenderbuffers(1, &self.msaa_color);
            if self.resolved_depth != self.depth {
                gl.DeleteRenderbuffers(1, &self.resolved_depth);
            }
        }
    }
}
