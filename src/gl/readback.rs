//! Reading back the default framebuffer without the app noticing: every piece of state the
//! read depends on is saved by [`PixelStateGuard`] and restored on drop, and only entry points
//! valid for the context's version are called (so no GL error is left for the app to find).

use super::GlInfo;
use super::{Gl, types::GLenum};

/// Saved read-side state; restored on drop.
pub(super) struct PixelStateGuard<'a> {
    gl: &'a Gl,
    info: GlInfo,
    read_fbo: i32,
    draw_fbo: i32,
    read_buffer: i32,
    pack_buffer: i32,
    pack: Vec<(GLenum, i32)>,
}

fn pack_params(info: GlInfo) -> &'static [GLenum] {
    use super::*;
    if !info.es {
        &[
            PACK_ALIGNMENT,
            PACK_ROW_LENGTH,
            PACK_SKIP_ROWS,
            PACK_SKIP_PIXELS,
            PACK_SWAP_BYTES,
            PACK_LSB_FIRST,
        ]
    } else if info.at_least(3, 0) {
        &[PACK_ALIGNMENT, PACK_ROW_LENGTH, PACK_SKIP_ROWS, PACK_SKIP_PIXELS]
    } else {
        &[PACK_ALIGNMENT]
    }
}

fn get(gl: &Gl, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: a single-integer query into a local.
    unsafe { gl.GetIntegerv(pname, &mut v) };
    v
}

impl<'a> PixelStateGuard<'a> {
    /// Rows packed with `alignment` and no row length or skips: a read fills exactly
    /// `w*h` pixels of its destination. The saved values come back on drop.
    pub(super) fn pack_tightly(&self, gl: &Gl, alignment: i32) {
        for &(p, _) in &self.pack {
            // SAFETY: plain pixel-store parameters of the current context.
            unsafe { gl.PixelStorei(p, if p == super::PACK_ALIGNMENT { alignment } else { 0 }) };
        }
    }

    pub(super) fn save(gl: &'a Gl, info: GlInfo) -> Self {
        use super::*;
        let fbo = info.has_framebuffers();
        let split = fbo && info.has_gl3_features();
        let read_fbo = if split {
            get(gl, READ_FRAMEBUFFER_BINDING)
        } else if fbo {
            get(gl, FRAMEBUFFER_BINDING)
        } else {
            0
        };
        let draw_fbo = if split {
            get(gl, DRAW_FRAMEBUFFER_BINDING)
        } else {
            read_fbo
        };
        let read_buffer = if info.has_read_buffer() {
            get(gl, READ_BUFFER)
        } else {
            0
        };
        let pack_buffer = if info.has_pack_buffer() {
            get(gl, PIXEL_PACK_BUFFER_BINDING)
        } else {
            0
        };
        let pack = pack_params(info).iter().map(|&p| (p, get(gl, p))).collect();
        PixelStateGuard {
            gl,
            info,
            read_fbo,
            draw_fbo,
            read_buffer,
            pack_buffer,
            pack,
        }
    }
}

impl Drop for PixelStateGuard<'_> {
    fn drop(&mut self) {
        use super::*;
        let (gl, info) = (self.gl, self.info);
        // SAFETY: restoring values this guard read from the same current context.
        unsafe {
            if info.has_framebuffers() {
                if info.has_gl3_features() {
                    gl.BindFramebuffer(READ_FRAMEBUFFER, self.read_fbo as u32);
                    gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.draw_fbo as u32);
                } else {
                    gl.BindFramebuffer(FRAMEBUFFER, self.read_fbo as u32);
                }
            }
            if info.has_read_buffer() {
                gl.ReadBuffer(self.read_buffer as u32);
            }
            if info.has_pack_buffer() {
                gl.BindBuffer(PIXEL_PACK_BUFFER, self.pack_buffer as u32);
            }
            for &(p, v) in &self.pack {
                gl.PixelStorei(p, v);
            }
        }
    }
}

/// Which colour buffer of the default framebuffer the app draws (and so presents).
fn presented_buffer(gl: &Gl, info: GlInfo) -> Option<GLenum> {
    use super::*;
    if !info.has_read_buffer() {
        return None;
    }
    if info.es {
        return Some(BACK);
    }
    if info.has_framebuffers() {
        // SAFETY: binding the default framebuffer for draw only to ask for its draw buffer;
        // the guard restores the app's binding.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, 0) };
    }
    Some(match get(gl, DRAW_BUFFER) as GLenum {
        FRONT | FRONT_LEFT | FRONT_RIGHT => FRONT,
        _ => BACK,
    })
}

/// Where a read comes from.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    /// The real default framebuffer, the buffer the app presents.
    Presented,
    /// Colour attachment 0 of one of our framebuffers.
    Fbo(u32),
}

/// RGBA8 rows, bottom-up, of the buffer the app is about to present.
pub fn read_presented(gl: &Gl, info: GlInfo, w: u32, h: u32) -> Result<Vec<u8>, String> {
    read_rgba(gl, info, Source::Presented, [0, 0, w as i32, h as i32])
}

/// RGBA8 rows, bottom-up, of `rect` (x, y, w, h) of `source`, all read state restored.
pub fn read_rgba(gl: &Gl, info: GlInfo, source: Source, rect: [i32; 4]) -> Result<Vec<u8>, String> {
    use super::*;
    if !gl.ReadPixels.is_loaded() {
        return Err("glReadPixels is not available".into());
    }
    let mut pixels = vec![0u8; rect[2].max(0) as usize * rect[3].max(0) as usize * 4];
    let guard = PixelStateGuard::save(gl, info);
    let mut default_read = None;
    let mut resolved = None;
    // SAFETY: the buffer holds w*h RGBA8 pixels with alignment 1 and no row length/skips, and
    // no pack buffer is bound, so ReadPixels writes exactly into it.
    unsafe {
        let fbo = match source {
            Source::Presented => 0,
            Source::Fbo(f) => f,
        };
        if info.has_framebuffers() {
            let target = if !info.has_gl3_features() {
                FRAMEBUFFER
            } else {
                READ_FRAMEBUFFER
            };
            gl.BindFramebuffer(target, fbo);
        }
        match source {
            Source::Presented => {
                if let Some(buffer) = presented_buffer(gl, info) {
                    // Framebuffer 0's own read buffer is app state too: put it back below.
                    default_read = Some(get(gl, READ_BUFFER) as u32);
                    gl.ReadBuffer(buffer);
                }
                resolved = Resolved::of_presented(gl, info, rect);
            }
            Source::Fbo(_) if info.has_read_buffer() => gl.ReadBuffer(COLOR_ATTACHMENT0),
            Source::Fbo(_) => {}
        }
        if info.has_pack_buffer() {
            gl.BindBuffer(PIXEL_PACK_BUFFER, 0);
        }
        guard.pack_tightly(gl, 1);
        gl.ReadPixels(
            rect[0],
            rect[1],
            rect[2],
            rect[3],
            RGBA,
            UNSIGNED_BYTE,
            pixels.as_mut_ptr().cast(),
        );
        if let Some(r) = &resolved {
            // Back to framebuffer 0, whose read buffer is put back next.
            r.delete(gl);
            gl.BindFramebuffer(READ_FRAMEBUFFER, 0);
        }
        if let Some(b) = default_read {
            gl.ReadBuffer(b);
        }
    }
    drop(guard);
    Ok(pixels)
}

/// A single-sampled copy of a multisampled window, resolved as the window resolves when it
/// is shown. Reading the window itself gives something else on Mesa: each pixel's first
/// sample (measured on llvmpipe: 13,822 of 307,200 edge pixels differ from what is shown).
struct Resolved {
    fbo: u32,
    renderbuffer: u32,
}

impl Resolved {
    /// For a read of `rect` of framebuffer 0 (bound for reading, its read buffer chosen, and
    /// for drawing): `None` unless it is multisampled; else the copy, bound for reading.
    fn of_presented(gl: &Gl, info: GlInfo, rect: [i32; 4]) -> Option<Resolved> {
        use super::*;
        if !info.has_gl3_features() || get(gl, SAMPLE_BUFFERS) == 0 {
            return None;
        }
        let mut caps = vec![SCISSOR_TEST];
        if !info.es {
            caps.push(FRAMEBUFFER_SRGB);
        }
        let _guard = super::guard::StateGuard::new(gl, info).caps(&caps);
        let (mut fbo, mut renderbuffer) = (0, 0);
        let [x, y, w, h] = rect;
        // SAFETY: our own renderbuffer and framebuffer; the caller's pixel guard restores the
        // framebuffer bindings, this function's guard the scissor and sRGB writes, and the
        // renderbuffer binding is put back here.
        unsafe {
            let bound_rb = get(gl, RENDERBUFFER_BINDING) as u32;
            gl.GenRenderbuffers(1, &mut renderbuffer);
            gl.BindRenderbuffer(RENDERBUFFER, renderbuffer);
            gl.RenderbufferStorage(RENDERBUFFER, RGBA8, x + w, y + h);
            gl.BindRenderbuffer(RENDERBUFFER, bound_rb);
            gl.GenFramebuffers(1, &mut fbo);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
            gl.FramebufferRenderbuffer(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, RENDERBUFFER, renderbuffer);
            caps.iter().for_each(|&c| gl.Disable(c));
            gl.BlitFramebuffer(x, y, x + w, y + h, x, y, x + w, y + h, COLOR_BUFFER_BIT, NEAREST);
            gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
        }
        Some(Resolved { fbo, renderbuffer })
    }

    fn delete(&self, gl: &Gl) {
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteFramebuffers(1, &self.fbo);
            gl.DeleteRenderbuffers(1, &self.renderbuffer);
        }
    }
}

/// Window depth values (0..1) of `rect` of framebuffer `fbo`, read state restored.
pub fn read_depth(gl: &Gl, info: GlInfo, fbo: u32, rect: [i32; 4]) -> Vec<f32> {
    read_floats(gl, info, fbo, rect, (super::DEPTH_COMPONENT, 1))
}

/// The `RG32F` pairs of `rect` of framebuffer `fbo`'s read buffer (a disparity record), rows
/// bottom-up; read state restored.
pub fn read_rg(gl: &Gl, info: GlInfo, fbo: u32, rect: [i32; 4]) -> Vec<f32> {
    read_floats(gl, info, fbo, rect, (super::RG, 2))
}

/// `rect` of `fbo` as floats, `format` with `n` components a pixel.
fn read_floats(gl: &Gl, info: GlInfo, fbo: u32, rect: [i32; 4], (format, n): (GLenum, usize)) -> Vec<f32> {
    use super::*;
    let mut out = vec![0f32; n * rect[2].max(0) as usize * rect[3].max(0) as usize];
    let guard = PixelStateGuard::save(gl, info);
    // SAFETY: as in `read_rgba`, with `n` floats per pixel into a buffer of that size.
    unsafe {
        gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
        if info.has_pack_buffer() {
            gl.BindBuffer(PIXEL_PACK_BUFFER, 0);
        }
        guard.pack_tightly(gl, 4);
        gl.ReadPixels(
            rect[0],
            rect[1],
            rect[2],
            rect[3],
            format,
            FLOAT,
            out.as_mut_ptr().cast(),
        );
    }
    drop(guard);
    out
}
