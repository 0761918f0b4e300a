//! The textures and buffers a warp works in, sized for one tile and K rendered views, kept
//! from frame to frame and rebuilt only when the tile, K or the depth format changes. The
//! quad grid's pyramid and leaf lists (about 53 bytes per pixel and source: 12 MB per
//! source at 420x560) exist only when the grid warp runs.

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
    /// The sources' disparity records (`shader::record`): (parallax, recorded?).
    pub record: u32,
    /// The grid's storage from here on (all 0 when the grid is not used).
    pub levels: [u32; LEVELS],
    pub leaves: u32,
    /// A buffer texture over `leaves`, which the warp's vertex shader reads.
    pub leaf_view: u32,
    pub commands: u32,
    /// Bytes of the leaf list of one source (room for one leaf per pixel).
    pub leaf_stride: isize,
}

pub(super) fn array(gl: &Gl, format: GLenum, (w, h): (i32, i32), layers: usize, filter: GLenum) -> u32 {
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
pub(super) fn buffer(gl: &Gl, bytes: isize) -> u32 {
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
    /// Storage for `sources` views of `tile`; the grid's own only with `grid`.
    pub fn create(gl: &Gl, tile: (i32, i32), sources: usize, depth_format: GLenum, grid: bool) -> Resources {
        let mut r = Resources {
            tile,
            sources,
            depth_format,
            color: array(gl, RGBA8, tile, sources, LINEAR),
            depth: array(gl, depth_format, tile, sources, NEAREST),
            parallax: array(gl, R32F, tile, sources, NEAREST),
            record: array(gl, RG32F, tile, sources, NEAREST),
            levels: [0; LEVELS],
            leaves: 0,
            leaf_view: 0,
            commands: 0,
            leaf_stride: 0,
        };
        if grid {
            r.leaf_stride = ((tile.0 as isize * tile.1 as isize * LEAF_BYTES) + 255) / 256 * 256;
            for (l, t) in r.levels.iter_mut().enumerate() {
                *t = array(gl, RGBA32F, level_size(tile, l), sources, NEAREST);
            }
            r.leaves = buffer(gl, r.leaf_stride * sources as isize);
            r.commands = buffer(gl, COMMAND_STRIDE * sources as isize);
            // SAFETY: a name for our buffer texture (its storage is pointed at per source).
            unsafe { gl.GenTextures(1, &mut r.leaf_view) };
        }
        r
    }

    pub fn has_grid(&self) -> bool {
        self.leaves != 0
    }

    pub fn fits(&self, tile: (i32, i32), sources: usize, depth_format: GLenum, grid: bool) -> bool {
        self.tile == tile && self.sources == sources && self.depth_format == depth_format && (self.has_grid() || !grid)
    }

    pub fn textures(&self) -> Vec<u32> {
        let mut t = vec![self.color, self.depth, self.parallax, self.record, self.leaf_view];
        t.extend(self.levels);
        t.retain(|&t| t != 0);
        t
    }

    pub fn buffers(&self) -> Vec<u32> {
        [self.leaves, self.commands].into_iter().filter(|&b| b != 0).collect()
    }

    pub fn delete(&self, gl: &Gl) {
        let (t, b) = (self.textures(), self.buffers());
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteTextures(t.len() as i32, t.as_ptr());
            gl.DeleteBuffers(b.len() as i32, b.as_ptr());
        }
    }
}
