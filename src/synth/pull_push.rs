//! Pull-push hole filling (Gortler et al. 1996, Grossman & Dally 1998) of the per-pixel
//! splat: pull halves the canvas level by level, each texel the mean of the covered pixels
//! under it with a coverage weight; push goes back down, each level's uncovered part filled
//! from the level above. Every hole gets the mean colour of the nearest covered pixels at the
//! scale of the hole; nothing is left empty while anything was splatted.
//!
//! Levels are separate textures (not mip levels of one), so no pass reads the texture it
//! renders into and no base/max level juggling is needed.

use crate::gl::GlInfo;
use crate::gl::*;

const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const PULL_FRAG: &str = include_str!("../../glsl-patches/synth_pull.frag");
const PUSH_FRAG: &str = include_str!("../../glsl-patches/synth_push.frag");

/// The pull and push programs.
pub fn link(gl: &Gl, info: GlInfo) -> Result<(u32, u32), String> {
    let link = |frag| crate::gl::program::link(gl, info, FULLSCREEN_VERT, frag);
    let pull = link(PULL_FRAG).map_err(|e| format!("pull-push hole filling: {e}"))?;
    let push = link(PUSH_FRAG).map_err(|e| format!("pull-push hole filling: {e}"))?;
    Ok((pull, push))
}

/// Size of level `l` of a canvas of `size` (level 0).
fn level_size(size: (i32, i32), l: usize) -> (i32, i32) {
    let d = 1 << l;
    ((size.0 + d - 1) / d, (size.1 + d - 1) / d)
}

/// Levels down to 1x1, level 0 included.
fn level_count(size: (i32, i32)) -> usize {
    (0..).find(|&l| level_size(size, l) == (1, 1)).unwrap_or(0) + 1
}

/// The splat's target and the pyramid, one tile large, reused by every target view.
#[derive(Debug, PartialEq)]
pub struct Canvas {
    size: (i32, i32),
    /// Level 0: splatted colour, alpha 1 where covered (RGBA8), and its depth.
    color: u32,
    depth: u32,
    /// Levels 1.. after pull (premultiplied colour, weight).
    pulled: Vec<u32>,
    /// Levels 1..top after push (the top level is the pulled one).
    filled: Vec<u32>,
}

fn texture(gl: &Gl, format: GLenum, (w, h): (i32, i32), filter: GLenum) -> u32 {
    let mut t = 0;
    // SAFETY: creating our own texture; the caller's guard restores the binding of unit 0.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.ActiveTexture(TEXTURE0);
        gl.BindTexture(TEXTURE_2D, t);
        gl.TexStorage2D(TEXTURE_2D, 1, format, w.max(1), h.max(1));
    }
    super::resources::sample_plainly(gl, TEXTURE_2D, filter);
    t
}

impl Canvas {
    pub fn create(gl: &Gl, size: (i32, i32)) -> Canvas {
        let levels = level_count(size);
        // Half floats: sums of up to four weights and premultiplied colours keep 8-bit
        // precision after the division.
        let level = |l| texture(gl, RGBA16F, level_size(size, l), LINEAR);
        Canvas {
            size,
            color: texture(gl, RGBA8, size, NEAREST),
            depth: texture(gl, DEPTH_COMPONENT32F, size, NEAREST),
            pulled: (1..levels).map(level).collect(),
            filled: (1..levels.saturating_sub(1)).map(level).collect(),
        }
    }

    pub fn fits(&self, size: (i32, i32)) -> bool {
        self.size == size
    }

    /// Attaches level 0 (colour and depth) to `fbo`, the splat's framebuffer.
    pub fn attach_level0(&self, gl: &Gl, fbo: u32) {
        // SAFETY: our framebuffer and textures; the caller's guard restores the binding.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
            gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, self.color, 0);
            gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, DEPTH_ATTACHMENT, TEXTURE_2D, self.depth, 0);
        }
    }

    fn levels(&self) -> usize {
        self.pulled.len() + 1
    }

    fn pulled(&self, l: usize) -> u32 {
        if l == 0 { self.color } else { self.pulled[l - 1] }
    }

    fn filled(&self, l: usize) -> u32 {
        if l + 1 >= self.levels() {
            self.pulled(l)
        } else {
            self.filled[l - 1]
        }
    }

    pub fn textures(&self) -> Vec<u32> {
        let mut t = vec![self.color, self.depth];
        t.extend(&self.pulled);
        t.extend(&self.filled);
        t
    }

    pub fn delete(&self, gl: &Gl) {
        let t = self.textures();
        // SAFETY: deleting our own textures.
        unsafe { gl.DeleteTextures(t.len() as i32, t.as_ptr()) };
    }
}

/// The pull-push passes over a splatted canvas, resolved into a target tile.
pub struct Fill<'a> {
    pub gl: &'a Gl,
    pub pull: u32,
    pub push: u32,
    /// Our framebuffer, re-attached to each level drawn.
    pub fbo: u32,
    pub vao: u32,
    pub canvas: &'a Canvas,
}

impl Fill<'_> {
    /// Uniforms that stay for every target (units 2, 3, 4: source, coarse level, depth).
    pub fn prepare(&self) {
        let gl = self.gl;
        // SAFETY: uniforms of our own programs; the guard restores the current program.
        unsafe {
            gl.UseProgram(self.pull);
            gl.Uniform1i(super::pass::loc(gl, self.pull, "u_src"), 2);
            gl.UseProgram(self.push);
            gl.Uniform1i(super::pass::loc(gl, self.push, "u_own"), 2);
            gl.Uniform1i(super::pass::loc(gl, self.push, "u_coarse"), 3);
            gl.Uniform1i(super::pass::loc(gl, self.push, "u_depth"), 4);
        }
    }

    /// Fills the canvas's holes and writes it into `rect` of `dest` (colour and depth).
    pub fn run(&self, dest: u32, rect: [i32; 4]) {
        let (gl, c) = (self.gl, self.canvas);
        let top = c.levels() - 1;
        for l in 1..=top {
            self.bind(2, c.pulled(l - 1));
            self.pass(self.pull, c.pulled(l), l);
        }
        self.push_uniforms([0, 0], false);
        for l in (1..top).rev() {
            self.bind(2, c.pulled(l));
            self.bind(3, c.filled(l + 1));
            self.pass(self.push, c.filled(l), l);
        }
        self.bind(2, c.color);
        self.bind(3, c.filled(1.min(top)));
        self.bind(4, c.depth);
        self.push_uniforms([rect[0], rect[1]], true);
        // SAFETY: the layer's destination framebuffer; depth test and function are restored
        // by the guards. The test must be on for the depth to be written.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, dest);
            gl.Viewport(rect[0], rect[1], rect[2], rect[3]);
            gl.Enable(DEPTH_TEST);
            gl.DepthFunc(ALWAYS);
            gl.DrawArrays(TRIANGLES, 0, 3);
            gl.Disable(DEPTH_TEST);
        }
    }

    fn push_uniforms(&self, origin: [i32; 2], resolve: bool) {
        let (gl, p) = (self.gl, self.push);
        // SAFETY: uniforms of our own program.
        unsafe {
            gl.UseProgram(p);
            gl.Uniform2i(super::pass::loc(gl, p, "u_origin"), origin[0], origin[1]);
            gl.Uniform1i(super::pass::loc(gl, p, "u_resolve"), resolve as i32);
        }
    }

    fn bind(&self, unit: u32, texture: u32) {
        // SAFETY: our texture on a unit the guard restores.
        unsafe {
            self.gl.ActiveTexture(TEXTURE0 + unit);
            self.gl.BindTexture(TEXTURE_2D, texture);
        }
    }

    /// A full-screen pass of `program` into `texture`, level `l` of the canvas.
    fn pass(&self, program: u32, texture: u32, l: usize) {
        let gl = self.gl;
        let (w, h) = level_size(self.canvas.size, l);
        // SAFETY: our framebuffer, texture, program and empty vertex array.
        unsafe {
            gl.BindFramebuffer(DRAW_FRAMEBUFFER, self.fbo);
            gl.FramebufferTexture2D(DRAW_FRAMEBUFFER, COLOR_ATTACHMENT0, TEXTURE_2D, texture, 0);
            gl.Viewport(0, 0, w, h);
            gl.UseProgram(program);
            gl.BindVertexArray(self.vao);
            gl.DrawArrays(TRIANGLES, 0, 3);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_halve_down_to_one_pixel() {
        assert_eq!(level_count((1, 1)), 1);
        assert_eq!(level_count((2, 1)), 2);
        assert_eq!(level_count((420, 560)), 11);
        assert_eq!(level_size((420, 560), 10), (1, 1));
        assert_eq!(level_size((5, 3), 1), (3, 2));
    }
}
