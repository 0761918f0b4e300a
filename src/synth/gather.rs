//! The gather warp (`glsl-patches/synth_gather.frag`): every synthesised view is one pass
//! over its tile that writes each pixel's colour and depth once, the floor's shape (issue 23:
//! `../shared/tools/fill-floor.c`). Each target pixel finds what lands on it by walking its
//! source row in visibility order, skipping blocks with a per-row min/max parallax hierarchy;
//! all targets are one instanced draw. Per source, once per frame: the pixels packed for
//! one fetch each, the hierarchy, and per pixel how far a view may move before another
//! pixel can cover it, which lets most target pixels take the piece they aim at directly.
//!
//! Same rule as the row warp (pieces, depth edges, disocclusions filled from the far side),
//! without its storage, its resolve pass or its hole count: holes are not marked, so
//! `--reuse-motion` and the hole share of `--measure-error` need the row warp.

use super::Job;
use super::pass::{Pass, loc};
use crate::gl::GlInfo;
use crate::gl::*;

const PACK_COMP: &str = include_str!("../../glsl-patches/synth_gather_pack.comp");
const BOUNDS_COMP: &str = include_str!("../../glsl-patches/synth_gather_bounds.comp");
const REACH_COMP: &str = include_str!("../../glsl-patches/synth_gather_reach.comp");
const GATHER_VERT: &str = include_str!("../../glsl-patches/synth_gather.vert");
const GATHER_FRAG: &str = include_str!("../../glsl-patches/synth_gather.frag");
/// Window depth between a disocclusion fill and the surface it stretches (as the row warp).
const FILL_BIAS: f32 = 1.0 / 16384.0;
/// Levels the fragment shader's offset table holds (tiles up to 2^15 pixels wide).
const MAX_LEVELS: usize = 15;

#[derive(Clone, Copy, Debug)]
pub struct GatherPrograms {
    pack: u32,
    bounds: u32,
    reach: u32,
    warp: u32,
}

impl GatherPrograms {
    pub fn link(gl: &Gl, info: GlInfo) -> Result<GatherPrograms, String> {
        Ok(GatherPrograms {
            pack: crate::gl::program::link_compute(gl, PACK_COMP)
                .map_err(|e| format!("synthesis gather packing pass: {e}"))?,
            bounds: crate::gl::program::link_compute(gl, BOUNDS_COMP)
                .map_err(|e| format!("synthesis gather bounds pass: {e}"))?,
            reach: crate::gl::program::link_compute(gl, REACH_COMP)
                .map_err(|e| format!("synthesis gather reach pass: {e}"))?,
            warp: crate::gl::program::link(gl, info, GATHER_VERT, GATHER_FRAG)
                .map_err(|e| format!("synthesis gather pass: {e}"))?,
        })
    }

    pub fn names(&self) -> [u32; 4] {
        [self.pack, self.bounds, self.reach, self.warp]
    }
}

/// Levels of the row hierarchy of a row `width` pixels wide: (x offset, texels) of levels
/// 1..=L, level l holding blocks of 2^l pixels, the last a single texel.
pub fn levels(width: i32) -> Vec<(i32, i32)> {
    let mut out = Vec::new();
    let (mut offset, mut l) = (0, 1);
    loop {
        let n = (width.max(1) + (1 << l) - 1) >> l;
        out.push((offset, n));
        offset += n;
        if n <= 1 || out.len() == MAX_LEVELS {
            return out;
        }
        l += 1;
    }
}

/// The gather warp's storage: the packed sources, their row bounds and the targets'
/// parameters.
#[derive(Debug, PartialEq)]
pub struct GatherStorage {
    tile: (i32, i32),
    sources: usize,
    count: usize,
    /// The packed pixels without their reach, which the bounds are made from.
    staged: u32,
    packed: u32,
    bounds: u32,
    params: u32,
}

/// Per target, as `Target` in synth_gather.vert (std430: vec4, ivec4, ivec4).
#[repr(C)]
#[derive(Clone, Copy)]
struct Params {
    ab: [f32; 4],
    src: [i32; 4],
    rect: [i32; 4],
}

impl GatherStorage {
    pub fn create(gl: &Gl, tile: (i32, i32), sources: usize, count: usize) -> GatherStorage {
        use super::resources::{array, buffer};
        let width: i32 = levels(tile.0).iter().map(|l| l.1).sum();
        GatherStorage {
            tile,
            sources,
            count,
            staged: array(gl, RGBA32UI, tile, sources, NEAREST),
            packed: array(gl, RGBA32UI, tile, sources, NEAREST),
            bounds: array(gl, RG32F, (width, tile.1), sources, NEAREST),
            params: buffer(gl, (count.max(1) * std::mem::size_of::<Params>()) as isize),
        }
    }

    pub fn fits(&self, tile: (i32, i32), sources: usize, count: usize) -> bool {
        self.tile == tile && self.sources == sources && self.count == count
    }

    pub fn textures(&self) -> [u32; 3] {
        [self.staged, self.packed, self.bounds]
    }

    pub fn buffers(&self) -> [u32; 1] {
        [self.params]
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteTextures(3, self.textures().as_ptr());
            gl.DeleteBuffers(1, &self.params);
        }
    }
}

/// Warps every target of `job` by gathering; the sources are copied by `pass`.
pub fn run(pass: &Pass, programs: &GatherPrograms, out: &GatherStorage, job: &Job) -> Result<(), String> {
    let mut profile = super::profile::Profile::new(pass.gl);
    for (j, source) in job.sources.iter().enumerate() {
        pass.copy_source(j, source, job)?;
        profile.lap("copy");
        pass.parallax(j, job);
        profile.lap("parallax");
        pack(pass, programs, out, j);
        profile.lap("pack+bounds");
        reach(pass, programs, out, j, largest_move(job, j));
        profile.lap("reach");
    }
    gather(pass, programs, out, job);
    profile.lap("gather");
    Ok(())
}

/// Source `j` packed, and its row bounds level by level (image units 0 and 1 are put back).
fn pack(pass: &Pass, programs: &GatherPrograms, out: &GatherStorage, j: usize) {
    let (gl, res) = (pass.gl, pass.res);
    let _images = crate::gl::guard::StateGuard::new(gl, pass.info).images(0..2);
    let (tw, th) = res.tile;
    pass.bind_array(0, res.color);
    pass.bind_array(1, res.depth);
    pass.bind_array(2, res.parallax);
    let p = programs.pack;
    // SAFETY: our programs and textures; bindings are restored by the caller's guard.
    unsafe {
        gl.UseProgram(p);
        gl.Uniform1i(loc(gl, p, "u_color"), 0);
        gl.Uniform1i(loc(gl, p, "u_depth"), 1);
        gl.Uniform1i(loc(gl, p, "u_parallax"), 2);
        gl.Uniform1i(loc(gl, p, "u_layer"), j as i32);
        gl.Uniform2i(loc(gl, p, "u_tile"), tw, th);
        gl.BindImageTexture(0, out.staged, 0, TRUE, 0, WRITE_ONLY, RGBA32UI);
        gl.Uniform1i(loc(gl, p, "u_packed"), 0);
        gl.DispatchCompute((tw as u32).div_ceil(8), (th as u32).div_ceil(8), 1);
        gl.MemoryBarrier(TEXTURE_FETCH_BARRIER_BIT | SHADER_IMAGE_ACCESS_BARRIER_BIT);
        let b = programs.bounds;
        gl.UseProgram(b);
        pass.bind_array(3, out.staged);
        gl.Uniform1i(loc(gl, b, "u_packed"), 3);
        gl.BindImageTexture(1, out.bounds, 0, TRUE, 0, READ_WRITE, RG32F);
        gl.Uniform1i(loc(gl, b, "u_bounds"), 1);
        gl.Uniform1i(loc(gl, b, "u_layer"), j as i32);
        gl.Uniform1i(loc(gl, b, "u_width"), tw);
        gl.Uniform1i(loc(gl, b, "u_rows"), th);
        let (u_this, u_below) = (loc(gl, b, "u_this"), loc(gl, b, "u_below"));
        let mut below = (-1, tw);
        for (offset, n) in levels(tw) {
            gl.Uniform2i(u_this, offset, n);
            gl.Uniform2i(u_below, below.0, below.1);
            gl.DispatchCompute((n as u32).div_ceil(64), th as u32, 1);
            gl.MemoryBarrier(SHADER_IMAGE_ACCESS_BARRIER_BIT | TEXTURE_FETCH_BARRIER_BIT);
            below = (offset, n);
        }
    }
}

/// The largest |a| (pixels of move per unit of parallax) of the views warped from source `j`
/// first.
fn largest_move(job: &Job, j: usize) -> f32 {
    let px = job.tile.0 as f64 / 2.0;
    job.targets
        .iter()
        .filter(|t| t.sources[0] == j)
        .map(|t| ((t.u - job.sources[j].u) * job.depthiness * px).abs() as f32)
        .fold(0.0, f32::max)
}

/// Source `j`'s packed pixels with their reach (synth_gather_reach.comp), for views moving at
/// most `largest` pixels per unit of parallax.
fn reach(pass: &Pass, programs: &GatherPrograms, out: &GatherStorage, j: usize, largest: f32) {
    let gl = pass.gl;
    let _images = crate::gl::guard::StateGuard::new(gl, pass.info).images(0..1);
    let (tw, th) = pass.res.tile;
    let top = levels(tw).last().map_or(0, |l| l.0);
    let p = programs.reach;
    // SAFETY: our program and textures; bindings are restored by the caller's guard.
    unsafe {
        gl.UseProgram(p);
        pass.bind_array(3, out.staged);
        pass.bind_array(0, out.bounds);
        gl.Uniform1i(loc(gl, p, "u_staged"), 3);
        gl.Uniform1i(loc(gl, p, "u_bounds"), 0);
        gl.Uniform1i(loc(gl, p, "u_layer"), j as i32);
        gl.Uniform2i(loc(gl, p, "u_tile"), tw, th);
        gl.Uniform1i(loc(gl, p, "u_top"), top);
        gl.Uniform1f(loc(gl, p, "u_reach"), largest);
        gl.BindImageTexture(0, out.packed, 0, TRUE, 0, WRITE_ONLY, RGBA32UI);
        gl.Uniform1i(loc(gl, p, "u_packed"), 0);
        gl.DispatchCompute((tw as u32).div_ceil(64), th as u32, 1);
        gl.MemoryBarrier(TEXTURE_FETCH_BARRIER_BIT | SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
}

/// Every target in one instanced draw into the destination.
fn gather(pass: &Pass, programs: &GatherPrograms, out: &GatherStorage, job: &Job) {
    let (gl, p) = (pass.gl, programs.warp);
    let px = job.tile.0 as f64 / 2.0;
    let params: Vec<Params> = job
        .targets
        .iter()
        .map(|t| {
            let [preferred, second] = t.sources;
            let ab = |j: usize| {
                let du = t.u - job.sources[j].u;
                ((du * job.depthiness * px) as f32, (du * job.focus * px) as f32)
            };
            let (a0, b0) = ab(preferred);
            let (a1, b1) = ab(second);
            Params {
                ab: [a0, b0, a1, b1],
                src: [
                    preferred as i32,
                    second as i32,
                    if second != preferred { 2 } else { 1 },
                    0,
                ],
                rect: t.rect,
            }
        })
        .collect();
    let dest = params.iter().fold((1, 1), |(w, h), t| {
        (w.max(t.rect[0] + t.rect[2]), h.max(t.rect[1] + t.rect[3]))
    });
    let levels = levels(job.tile.0);
    let bias = if job.model.reversed { -FILL_BIAS } else { FILL_BIAS };
    // SAFETY: our program, buffer and textures, into the layer's own framebuffer; all of it
    // is restored by the caller's guard.
    unsafe {
        gl.BindBuffer(ARRAY_BUFFER, out.params);
        let bytes = (params.len() * std::mem::size_of::<Params>()) as isize;
        gl.BufferSubData(ARRAY_BUFFER, 0, bytes, params.as_ptr().cast());
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 0, out.params);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
        gl.Viewport(0, 0, dest.0, dest.1);
        gl.Disable(SCISSOR_TEST);
        gl.Enable(DEPTH_TEST);
        gl.DepthFunc(ALWAYS);
        gl.DepthMask(TRUE);
        gl.UseProgram(p);
        pass.bind_array(3, out.packed);
        pass.bind_array(0, out.bounds);
        gl.Uniform1i(loc(gl, p, "u_packed"), 3);
        gl.Uniform1i(loc(gl, p, "u_bounds"), 0);
        gl.Uniform1i(loc(gl, p, "u_levels"), levels.len() as i32);
        let offsets: Vec<i32> = std::iter::once(0).chain(levels.iter().map(|l| l.0)).collect();
        gl.Uniform1iv(loc(gl, p, "u_offset"), offsets.len() as i32, offsets.as_ptr());
        gl.Uniform1i(loc(gl, p, "u_width"), job.tile.0);
        gl.Uniform1f(loc(gl, p, "u_threshold"), job.threshold as f32);
        gl.Uniform1f(loc(gl, p, "u_far_bias"), bias);
        gl.Uniform2f(loc(gl, p, "u_dest"), dest.0 as f32, dest.1 as f32);
        gl.BindVertexArray(pass.vao);
        gl.DrawArraysInstanced(TRIANGLES, 0, 6, params.len() as i32);
    }
}

#[cfg(test)]
mod tests {
    use super::levels;

    #[test]
    fn levels_halve_down_to_one_texel_per_row() {
        assert_eq!(
            levels(420),
            vec![
                (0, 210),
                (210, 105),
                (315, 53),
                (368, 27),
                (395, 14),
                (409, 7),
                (416, 4),
                (420, 2),
                (422, 1)
            ]
        );
        assert_eq!(levels(1), vec![(0, 1)]);
        assert_eq!(levels(2), vec![(0, 1)]);
        assert_eq!(levels(3), vec![(0, 2), (2, 1)]);
    }
}
