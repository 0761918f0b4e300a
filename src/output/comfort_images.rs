//! The images the comfort pass (`comfort.rs`) keeps between frames, remade when the quilt
//! changes: two copies of the quilt's depth (one sampled, one attached with the quilt's
//! colour so the pass may overwrite its stencil) and the pre-blurred half-size image.

use crate::gl::*;
use crate::multiview::quilt::target::QuiltTarget;

#[derive(Default)]
pub struct ComfortCopies {
    /// The quilt's depth, sampled by the shaders.
    pub depth: u32,
    /// The quilt's depth again, with its colour (`t.sampled`: stored values, never sRGB,
    /// blended raw), in `fbo`: tested against, its stencil ours.
    cull: u32,
    pub fbo: u32,
    /// The pre-blurred image (rows as the quilt stores them) in `half_fbo`, unflipped.
    pub half: u32,
    pub half_fbo: u32,
    /// The depth format has a stencil: the blur can skip pixels where nothing was drawn.
    pub stencil: bool,
    made_for: Option<(u32, (i32, i32), GLenum)>,
}

impl ComfortCopies {
    pub fn delete(&mut self, gl: &Gl) {
        // SAFETY: our own objects (zero names are ignored).
        unsafe {
            gl.DeleteTextures(2, [self.depth, self.half].as_ptr());
            gl.DeleteRenderbuffers(1, &self.cull);
            gl.DeleteFramebuffers(2, [self.fbo, self.half_fbo].as_ptr());
        }
        *self = ComfortCopies::default();
    }

    /// Framebuffers (per context).
    pub fn framebuffers(&self) -> usize {
        [self.fbo, self.half_fbo].iter().filter(|&&f| f != 0).count()
    }

    /// Textures and renderbuffers (shared by the share group).
    /// The depth copy the stages test against (a renderbuffer of the quilt's depth format).
    pub fn cull(&self) -> u32 {
        self.cull
    }

    pub fn textures(&self) -> [u32; 2] {
        [self.depth, self.half]
    }

    pub fn renderbuffers(&self) -> [u32; 1] {
        [self.cull]
    }

    /// Makes the images for quilt `t` with depth format `format`, unless they exist.
    pub fn ensure(&mut self, gl: &Gl, t: &QuiltTarget, format: GLenum) -> Result<(), String> {
        let size = (t.layout.width() as i32, t.layout.height() as i32);
        if self.made_for == Some((t.sampled, size, format)) {
            return Ok(());
        }
        self.delete(gl);
        self.stencil = matches!(format, DEPTH24_STENCIL8 | DEPTH32F_STENCIL8);
        let point = if self.stencil {
            DEPTH_STENCIL_ATTACHMENT
        } else {
            DEPTH_ATTACHMENT
        };
        let half = ((size.0 / 2).max(1), (size.1 / 2).max(1));
        self.depth = texture(gl, format, size, NEAREST);
        self.half = texture(gl, half_format(t.color_format), half, NEAREST);
        self.cull = renderbuffer(gl, format, size);
        let flip = t.window.flip_y;
        let (cull, color, half) = (self.cull, t.sampled, self.half);
        // SAFETY: attaching our images (and the quilt's colour) to framebuffers of ours; the
        // caller's guard restores the bindings.
        self.fbo = framebuffer(gl, flip, || unsafe {
            gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, color, 0);
            gl.FramebufferRenderbuffer(FRAMEBUFFER, point, RENDERBUFFER, cull);
        })?;
        // SAFETY: as above.
        self.half_fbo = framebuffer(gl, false, || unsafe {
            gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, half, 0);
        })?;
        self.made_for = Some((t.sampled, size, format));
        Ok(())
    }

    /// Copies the quilt's depth (and stencil) into `depth` and, `for_blur`, into `cull`; a
    /// multisampled quilt's depth is resolved first (into its resolved depth, which the fade
    /// then tests against).
    pub fn copy(&self, gl: &Gl, t: &QuiltTarget, for_blur: bool) {
        let (w, h) = (t.layout.width() as i32, t.layout.height() as i32);
        // SAFETY: copies between images of the quilt and ours, of the same format and size;
        // bindings restored by the caller's guard (the scissor test is off).
        unsafe {
            if t.fbo != t.resolved_fbo {
                gl.BindFramebuffer(READ_FRAMEBUFFER, t.fbo);
                gl.BindFramebuffer(DRAW_FRAMEBUFFER, t.resolved_fbo);
                gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, DEPTH_BUFFER_BIT, NEAREST);
            }
            let from = t.resolved_depth;
            gl.CopyImageSubData(
                from,
                RENDERBUFFER,
                0,
                0,
                0,
                0,
                self.depth,
                TEXTURE_2D,
                0,
                0,
                0,
                0,
                w,
                h,
                1,
            );
            if !for_blur {
                return;
            }
            gl.CopyImageSubData(
                from,
                RENDERBUFFER,
                0,
                0,
                0,
                0,
                self.cull,
                RENDERBUFFER,
                0,
                0,
                0,
                0,
                w,
                h,
                1,
            );
        }
    }
}

/// The pre-blurred image's format: 8 bits a channel (its alpha holds the circle of
/// confusion over the largest radius), or half floats for a float quilt, whose colours may
/// exceed 1.
fn half_format(quilt: GLenum) -> GLenum {
    match quilt {
        RGBA16F | RGBA32F | RGB16F | RGB32F | R11F_G11F_B10F => RGBA16F,
        _ => RGBA8,
    }
}

fn texture(gl: &Gl, format: GLenum, (w, h): (i32, i32), filter: GLenum) -> u32 {
    let mut t = 0;
    // SAFETY: our own texture; the caller's guard restores the binding.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(TEXTURE_2D, t);
        gl.TexStorage2D(TEXTURE_2D, 1, format, w.max(1), h.max(1));
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, filter as i32);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, filter as i32);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_WRAP_S, CLAMP_TO_EDGE as i32);
        gl.TexParameteri(TEXTURE_2D, TEXTURE_WRAP_T, CLAMP_TO_EDGE as i32);
    }
    t
}

fn renderbuffer(gl: &Gl, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut r = 0;
    // SAFETY: our own renderbuffer; the caller's guard restores the binding.
    unsafe {
        gl.GenRenderbuffers(1, &mut r);
        gl.BindRenderbuffer(RENDERBUFFER, r);
        gl.RenderbufferStorage(RENDERBUFFER, format, w.max(1), h.max(1));
    }
    r
}

/// A complete framebuffer of ours with `attach` done on it, stored top-down when `flip`.
fn framebuffer(gl: &Gl, flip: bool, attach: impl FnOnce()) -> Result<u32, String> {
    let fbo = crate::multiview::quilt::target::framebuffer(gl, flip, attach);
    if !crate::multiview::quilt::target::complete(gl) {
        // SAFETY: our own framebuffer.
        unsafe { gl.DeleteFramebuffers(1, &fbo) };
        return Err("a comfort pass framebuffer is incomplete".into());
    }
    Ok(fbo)
}
