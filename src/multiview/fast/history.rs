//! The history quilt of `--reuse` (`reuse`): a copy of the quilt's layout and formats
//! holding, per view, its last exact render (colour, depth and stencil), and the GPU
//! comparison of this frame's renders with it.
//!
//! Same formats and the same storage order as the quilt (top-down when the quilt is, with
//! `MESA_framebuffer_flip_y`), so tile copies are plain same-rectangle blits in either
//! direction, and a texel address means the same pixel in both. Single-sampled quilts only:
//! a blit cannot write a multisampled framebuffer from a single-sampled one.
//!
//! The comparison draws one full-tile triangle per compared view into a scratch target
//! (colour writes off), whose fragments fetch the two texels and discard equal ones; a
//! `GL_SAMPLES_PASSED` query around the draws counts the pixels that differ. Its result is
//! waited for right away: the kept views are shown this frame or not at all.

use crate::gl::GlInfo;
use crate::gl::guard::{StateGuard, get_i};
use crate::gl::types::GLbitfield;
use crate::gl::*;
use crate::multiview::quilt::layout::QuiltLayout;
use crate::multiview::quilt::target::QuiltTarget;

const FULLSCREEN_VERT: &str = include_str!("../../../glsl-patches/fullscreen.vert");
const COMPARE_FRAG: &str = include_str!("../../../glsl-patches/reuse_compare.frag");

pub struct History {
    /// Colour (the quilt's format) and depth/stencil (the quilt's) textures, on `fbo`.
    fbo: u32,
    color: u32,
    /// `color` as the reprojection samples it: undecoded when sRGB (`target::linear_view`).
    sampled: u32,
    depth: u32,
    /// What the quilt it mirrors was: its colour texture, layout, formats.
    quilt_color: u32,
    layout: QuiltLayout,
    depth_format: GLenum,
    depth_bits: GLbitfield,
    /// The comparison: program, its origin uniform, a tile-sized scratch target, a query.
    program: u32,
    origin_loc: i32,
    scratch_fbo: u32,
    scratch: u32,
    vao: u32,
    query: u32,
}

/// The quilt's depth/stencil renderbuffer's format, and the buffers a blit of it copies.
fn depth_of(gl: &Gl, quilt: &QuiltTarget) -> (GLenum, GLenum, GLbitfield) {
    let mut format = 0;
    // SAFETY: a query of our own renderbuffer; the caller's guard restores the binding.
    unsafe {
        gl.BindRenderbuffer(RENDERBUFFER, quilt.depth);
        gl.GetRenderbufferParameteriv(RENDERBUFFER, RENDERBUFFER_INTERNAL_FORMAT, &mut format);
    }
    let format = format as GLenum;
    match format {
        DEPTH24_STENCIL8 | DEPTH32F_STENCIL8 => {
            (format, DEPTH_STENCIL_ATTACHMENT, DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT)
        }
        _ => (format, DEPTH_ATTACHMENT, DEPTH_BUFFER_BIT),
    }
}

fn renderbuffer(gl: &Gl, format: GLenum, (w, h): (i32, i32)) -> u32 {
    let mut rb = 0;
    // SAFETY: our own renderbuffer; the caller's guard restores the binding.
    unsafe {
        gl.GenRenderbuffers(1, &mut rb);
        gl.BindRenderbuffer(RENDERBUFFER, rb);
        gl.RenderbufferStorage(RENDERBUFFER, format, w, h);
    }
    rb
}

/// A framebuffer of ours (`target::framebuffer`) with `color` (a texture when `.1`) and
/// optionally a depth texture; an error if it is incomplete.
fn framebuffer(gl: &Gl, flip: bool, color: (u32, bool), depth: Option<(GLenum, u32)>) -> Result<u32, String> {
    // SAFETY: attaching our own images to the framebuffer just made and bound.
    let fbo = crate::multiview::quilt::target::framebuffer(gl, flip, || unsafe {
        match color {
            (t, true) => gl.FramebufferTexture2D(FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, t, 0),
            (rb, false) => gl.FramebufferRenderbuffer(FRAMEBUFFER, COLOR_ATTACHMENT0, RENDERBUFFER, rb),
        }
        if let Some((point, t)) = depth {
            gl.FramebufferTexture2D(FRAMEBUFFER, point, TEXTURE_2D, t, 0);
        }
    });
    // SAFETY: a status query on the bound framebuffer, and deleting our own.
    unsafe {
        if gl.CheckFramebufferStatus(FRAMEBUFFER) != FRAMEBUFFER_COMPLETE {
            gl.DeleteFramebuffers(1, &fbo);
            return Err("framebuffer incomplete".into());
        }
    }
    Ok(fbo)
}

impl History {
    pub fn create(gl: &Gl, info: GlInfo, quilt: &QuiltTarget) -> Result<History, String> {
        let _guard = StateGuard::new(gl, info).framebuffers().for_pass();
        let l = quilt.layout;
        let size = (l.width() as i32, l.height() as i32);
        let (depth_format, point, depth_bits) = depth_of(gl, quilt);
        let mut h = History {
            fbo: 0,
            color: 0,
            sampled: 0,
            // Sampled when kept views are reprojected (`synth::reproject`).
            depth: crate::gl::depth_copy::storage(gl, depth_format, size),
            quilt_color: quilt.color,
            layout: l,
            depth_format,
            depth_bits,
            program: 0,
            origin_loc: -1,
            scratch_fbo: 0,
            scratch: renderbuffer(gl, R8, (l.tile_w as i32, l.tile_h as i32)),
            vao: 0,
            query: 0,
        };
        // SAFETY: our own texture, vertex array and query; bindings restored by the guard.
        unsafe {
            gl.GenTextures(1, &mut h.color);
            gl.BindTexture(TEXTURE_2D, h.color);
            gl.TexStorage2D(TEXTURE_2D, 1, quilt.color_format, size.0, size.1);
            gl.TexParameteri(TEXTURE_2D, TEXTURE_MIN_FILTER, NEAREST as i32);
            gl.TexParameteri(TEXTURE_2D, TEXTURE_MAG_FILTER, NEAREST as i32);
            h.sampled = crate::multiview::quilt::target::linear_view(gl, info, h.color, quilt.color_format);
            gl.GenVertexArrays(1, &mut h.vao);
            gl.GenQueries(1, &mut h.query);
        }
        let made = (|| {
            h.fbo = framebuffer(gl, l.flipped, (h.color, true), Some((point, h.depth)))?;
            h.scratch_fbo = framebuffer(gl, false, (h.scratch, false), None)?;
            h.program = crate::gl::program::link(gl, info, FULLSCREEN_VERT, COMPARE_FRAG)?;
            // SAFETY: our own linked program; the guard restores the current program.
            unsafe {
                gl.UseProgram(h.program);
                gl.Uniform1i(crate::gl::program::uniform(gl, h.program, "u_now"), 0);
                gl.Uniform1i(crate::gl::program::uniform(gl, h.program, "u_kept"), 1);
                h.origin_loc = crate::gl::program::uniform(gl, h.program, "u_origin");
            }
            Ok::<(), String>(())
        })();
        match made {
            Ok(()) => Ok(h),
            Err(e) => {
                h.delete(gl);
                Err(e)
            }
        }
    }

    /// Still the mirror of `quilt` (not re-created since, same layout).
    pub fn fits(&self, quilt: &QuiltTarget) -> bool {
        self.quilt_color == quilt.color && self.layout == quilt.layout
    }

    /// Copies `views`' tiles from the quilt into the history.
    pub fn store(&self, gl: &Gl, info: GlInfo, quilt: &QuiltTarget, views: &[u32]) {
        self.blit(gl, info, (quilt.fbo, self.fbo), views);
    }

    /// Copies `views`' tiles from the history into the quilt.
    pub fn restore(&self, gl: &Gl, info: GlInfo, quilt: &QuiltTarget, views: &[u32]) {
        self.blit(gl, info, (self.fbo, quilt.fbo), views);
    }

    fn blit(&self, gl: &Gl, info: GlInfo, (from, to): (u32, u32), views: &[u32]) {
        if views.is_empty() {
            return;
        }
        let _guard = StateGuard::new(gl, info)
            .framebuffers()
            .caps(&[SCISSOR_TEST, FRAMEBUFFER_SRGB]);
        // SAFETY: same-rectangle blits between two framebuffers of ours with the same formats;
        // bindings, scissor, sRGB and the quilt's read and draw buffers (the app's choice for
        // framebuffer 0) are restored.
        unsafe {
            gl.Disable(SCISSOR_TEST);
            gl.Disable(FRAMEBUFFER_SRGB);
            gl.BindFramebuffer(READ_FRAMEBUFFER, from);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, to);
            let (read, draw) = (get_i(gl, READ_BUFFER) as GLenum, get_i(gl, DRAW_BUFFER0) as GLenum);
            gl.ReadBuffer(COLOR_ATTACHMENT0);
            gl.DrawBuffer(COLOR_ATTACHMENT0);
            for &v in views {
                let [x, y, w, h] = self.layout.tile_rect(v);
                let mask = COLOR_BUFFER_BIT | self.depth_bits;
                gl.BlitFramebuffer(x, y, x + w, y + h, x, y, x + w, y + h, mask, NEAREST);
            }
            gl.ReadBuffer(read);
            gl.DrawBuffer(draw);
        }
    }

    /// Pixels of `views` in which the quilt differs from the history, summed over the views
    /// (0 for no views); `None` when it cannot be counted now (the app has an occlusion query
    /// running).
    pub fn differing(&self, gl: &Gl, info: GlInfo, quilt: &QuiltTarget, views: &[u32]) -> Option<u64> {
        if views.is_empty() {
            return Some(0);
        }
        if app_query_active(gl) {
            return None;
        }
        let _guard = StateGuard::new(gl, info)
            .framebuffers()
            .for_pass()
            .textures(TEXTURE_2D, TEXTURE_BINDING_2D, 0..2)
            .samplers(0..2);
        crate::gl::guard::neutral_pass_state(gl, info);
        let l = self.layout;
        let mut count = 0u64;
        // SAFETY: our program, textures, framebuffer and query; everything changed is put back
        // by the guard. The query's result is waited for (a few tile-sized fragment passes).
        unsafe {
            gl.ColorMask(FALSE, FALSE, FALSE, FALSE);
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.scratch_fbo);
            gl.Viewport(0, 0, l.tile_w as i32, l.tile_h as i32);
            gl.UseProgram(self.program);
            gl.BindVertexArray(self.vao);
            for (unit, texture) in [(0, quilt.color), (1, self.color)] {
                gl.ActiveTexture(TEXTURE0 + unit);
                gl.BindTexture(TEXTURE_2D, texture);
                gl.BindSampler(unit, 0);
            }
            gl.BeginQuery(SAMPLES_PASSED, self.query);
            for &v in views {
                let (x, y) = storage_origin(l, v);
                gl.Uniform2i(self.origin_loc, x, y);
                gl.DrawArrays(TRIANGLES, 0, 3);
            }
            gl.EndQuery(SAMPLES_PASSED);
            gl.GetQueryObjectui64v(self.query, QUERY_RESULT, &mut count);
        }
        Some(count)
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting objects we created; zero names are ignored.
        unsafe {
            gl.DeleteFramebuffers(1, &self.fbo);
            gl.DeleteFramebuffers(1, &self.scratch_fbo);
            if self.sampled != self.color {
                gl.DeleteTextures(1, &self.sampled);
            }
            gl.DeleteTextures(1, &self.color);
            gl.DeleteTextures(1, &self.depth);
            gl.DeleteRenderbuffers(1, &self.scratch);
            gl.DeleteProgram(self.program);
            gl.DeleteVertexArrays(1, &self.vao);
            gl.DeleteQueries(1, &self.query);
        }
    }

    /// Shared with the share group: (textures, renderbuffers, programs).
    pub fn shared_objects(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let mut textures = vec![self.color, self.depth];
        if self.sampled != self.color {
            textures.push(self.sampled);
        }
        (textures, vec![self.scratch], vec![self.program])
    }

    /// The colour and depth textures, stored in `layout()`'s order.
    pub fn textures(&self) -> (u32, u32) {
        (self.sampled, self.depth)
    }

    pub fn depth_format(&self) -> GLenum {
        self.depth_format
    }

    pub fn layout(&self) -> QuiltLayout {
        self.layout
    }

    /// Where view `v`'s tile starts in texel addresses.
    pub fn origin(&self, v: u32) -> (i32, i32) {
        storage_origin(self.layout, v)
    }
}

/// Where view `v`'s tile starts in texel addresses (rows flipped when stored top-down).
fn storage_origin(l: QuiltLayout, v: u32) -> (i32, i32) {
    let [x, y, _, h] = l.tile_rect(v);
    if l.flipped {
        (x, l.height() as i32 - y - h)
    } else {
        (x, y)
    }
}

/// One of the app's occlusion queries is running: ours cannot begin.
fn app_query_active(gl: &Gl) -> bool {
    [SAMPLES_PASSED, ANY_SAMPLES_PASSED, ANY_SAMPLES_PASSED_CONSERVATIVE]
        .iter()
        .any(|&target| {
            let mut q = 0;
            // SAFETY: a query of the current query name of a target valid in GL 4.3.
            unsafe { gl.GetQueryiv(target, CURRENT_QUERY, &mut q) };
            q != 0
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_origin_follows_the_stored_order() {
        let l = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100));
        // View 3 (the centre) is drawn at the origin cell (module notes of `layout`).
        assert_eq!(storage_origin(l, 3), (0, 0));
        assert_eq!(storage_origin(l, 4), (100, 50));
        let top_down = l.stored(true);
        assert_eq!(storage_origin(top_down, 3), (0, 0), "the top-left tile is stored first");
        assert_eq!(storage_origin(top_down, 0), (0, 50));
    }
}
