//! The textures and buffers a warp works in, sized for one tile and K rendered views, kept
//! from frame to frame and rebuilt only when the tile, K or the depth format changes.

use crate::gl::*;

/// Pyramid levels: cells of 2, 4, 8, 16 and 32 pixels.
pub const LEVELS: usize = 5;
/// Bytes per leaf (`uvec4 rect; vec4 corners; vec4 depths` in std430).
pub const LEAF_BYTES: isize = 48;
/// Bytes between the per-source draw commands (any storage-buffer offset alignment a driver
/// asks for is at most this).
pub const COMMAND_STRIDE: isize = 256;

#[derive(Debug, PartialEq)]
pub struct Resources {
    pub tile: (i32, i32),
    pub sources: usize,
    pub depth_format: GLenum,
    /// 2D arrays with one layer per rendered view.
    pub color: u32,
    pub depth: u32,
    pub parallax: u32,
    pub levels: [u32; LEVELS],
    pub leaves: u32,
    /// A buffer texture over `leaves`, which the warp's vertex shader reads.
    pub leaf_view: u32,
    pub commands: u32,
    /// Bytes of the leaf list of one source (room for one leaf per pixel).
    pub leaf_stride: isize,
}

fn array(gl: &Gl, format: GLenum, (w, h): (i32, i32), layers: usize, filter: GLenum) -> u32 {
    let mut t = 0;
    // SAFETY: creating our own texture; the caller's guard restores the binding.
    unsafe {
        gl.GenTextures(1, &mut t);
        gl.BindTexture(TEXTURE_2D_ARRAY, t);
        gl.TexStorage3D(TEXTURE_2D_ARRAY, 1, format, w.max(1), h.max(1), layers as i32);
    }
    sample_plainly(gl, TEXTURE_2D_ARRAY, filter);
    t
}

/// `filter` both ways, clamped to the edge, no depth comparison: the bound `target` texture
/// of ours read as plain values by our passes.
pub fn sample_plainly(gl: &Gl, target: GLenum, filter: GLenum) {
    // SAFETY: parameters of our own texture, bound by the caller.
    unsafe {
        for (p, v) in [
            (TEXTURE_MIN_FILTER, filter),
            (TEXTURE_MAG_FILTER, filter),
            (TEXTURE_WRAP_S, CLAMP_TO_EDGE),
            (TEXTURE_WRAP_T, CLAMP_TO_EDGE),
            (TEXTURE_COMPARE_MODE, NONE),
        ] {
            gl.TexParameteri(target, p, v as i32);
        }
    }
}

/// A buffer of ours with `bytes` of uninitialised storage (written by our passes).
fn buffer(gl: &Gl, bytes: isize) -> u32 {
    let mut b = 0;
    // SAFETY: our own buffer; the caller's guard restores ARRAY_BUFFER.
    unsafe {
        gl.GenBuffers(1, &mut b);
        gl.BindBuffer(ARRAY_BUFFER, b);
        gl.BufferData(ARRAY_BUFFER, bytes, core::ptr::null(), DYNAMIC_COPY);
    }
    b
}

/// Cells of level `l` (0 = 2x2 pixels) covering a tile.
pub fn level_size(tile: (i32, i32), l: usize) -> (i32, i32) {
    let cell = 2 << l;
    ((tile.0 + cell - 1) / cell, (tile.1 + cell - 1) / cell)
}

impl Resources {
    pub fn create(gl: &Gl, tile: (i32, i32), sources: usize, depth_format: GLenum) -> Resources {
        let leaf_stride = ((tile.0 as isize * tile.1 as isize * LEAF_BYTES) + 255) / 256 * 256;
        let mut levels = [0; LEVELS];
        for (l, t) in levels.iter_mut().enumerate() {
            *t = array(gl, RGBA32F, level_size(tile, l), sources, NEAREST);
        }
        let leaves = buffer(gl, leaf_stride * sources as isize);
        let commands = buffer(gl, COMMAND_STRIDE * sources as isize);
        let mut leaf_view = 0;
        // SAFETY: a name for our buffer texture (its storage is pointed at per source).
        unsafe { gl.GenTextures(1, &mut leaf_view) };
        Resources {
            tile,
            sources,
            depth_format,
            color: array(gl, RGBA8, tile, sources, LINEAR),
            depth: array(gl, depth_format, tile, sources, NEAREST),
            parallax: array(gl, R32F, tile, sources, NEAREST),
            levels,
            leaves,
            leaf_view,
            commands,
            leaf_stride,
        }
    }

    pub fn fits(&self, tile: (i32, i32), sources: usize, depth_format: GLenum) -> bool {
        self.tile == tile && self.sources == sources && self.depth_format == depth_format
    }

    pub fn textures(&self) -> Vec<u32> {
        let mut t = vec![self.color, self.depth, self.parallax, self.leaf_view];
        t.extend(self.levels);
        t
    }

    pub fn buffers(&self) -> [u32; 2] {
        [self.leaves, self.commands]
    }

    pub fn delete(&self, gl: &Gl) {
        let t = self.textures();
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteTextures(t.len() as i32, t.as_ptr());
            gl.DeleteBuffers(2, self.buffers().as_ptr());
        }
    }
}
