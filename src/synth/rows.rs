//! The row warp (`glsl-patches/synth_rows.comp`): the adaptive grid in one dimension. Views
//! move sideways only, so each target row is warped from the same source row, by a compute
//! pass with one invocation per row and target, into arrays of ours; a fragment pass then
//! puts each target's colour and depth into its tile.
//!
//! It draws no triangles: on a software rasterizer, where every small triangle costs a setup,
//! a bin and a 4x4 block of shading, the quad grid's thousands of edge cells cost more than
//! rendering the view (measured on llvmpipe: README "Choosing a mode").

use super::Job;
use super::pass::{Pass, loc};
use super::programs::FULLSCREEN_VERT;
use super::rows_host;
use crate::gl::GlInfo;
use crate::gl::guard::get_i;
use crate::gl::*;

const ROWS_COMP: &str = include_str!("../../glsl-patches/synth_rows.comp");
const PACK_COMP: &str = include_str!("../../glsl-patches/synth_pack.comp");
const RESOLVE_FRAG: &str = include_str!("../../glsl-patches/synth_resolve.frag");
/// Rows per work group (`local_size_x` of synth_rows.comp).
const ROWS_PER_GROUP: u32 = 32;
/// Window depth between a disocclusion fill and the surface it stretches.
const FILL_BIAS: f32 = 1.0 / 16384.0;

#[derive(Clone, Copy, Debug)]
pub struct RowPrograms {
    pack: u32,
    rows: u32,
    resolve: u32,
}

impl RowPrograms {
    pub fn link(gl: &Gl, info: GlInfo) -> Result<RowPrograms, String> {
        Ok(RowPrograms {
            pack: crate::gl::program::link_compute(gl, PACK_COMP)
                .map_err(|e| format!("synthesis packing pass: {e}"))?,
            rows: crate::gl::program::link_compute(gl, ROWS_COMP).map_err(|e| format!("synthesis row pass: {e}"))?,
            resolve: crate::gl::program::link(gl, info, FULLSCREEN_VERT, RESOLVE_FRAG)
                .map_err(|e| format!("synthesis resolve pass: {e}"))?,
        })
    }

    pub fn names(&self) -> [u32; 3] {
        [self.pack, self.rows, self.resolve]
    }
}

/// Storage of the row warp: the sources packed per pixel (12 bytes), the warped targets
/// (8 bytes per pixel) and the targets' parameters.
#[derive(Debug, PartialEq)]
pub struct RowTargets {
    tile: (i32, i32),
    /// The sources' guard band, columns each side (`Job::guard`).
    guard: i32,
    sources: usize,
    count: usize,
    packed: u32,
    warped: u32,
    params: u32,
    /// One counter: the pixels of the last warp's targets filled over holes.
    holes: u32,
    /// A buffer texture (RG32UI) over `warped`, which the resolve pass reads.
    warped_view: u32,
}

/// Per target, as `Target` in synth_rows.comp (std430: vec4 then ivec4).
#[repr(C)]
#[derive(Clone, Copy)]
struct Params {
    du: [f32; 4],
    src: [i32; 4],
}

fn storage(gl: &Gl, bytes: usize) -> u32 {
    let mut b = 0;
    // SAFETY: our own buffer; the caller's guard restores ARRAY_BUFFER.
    unsafe {
        gl.GenBuffers(1, &mut b);
        gl.BindBuffer(ARRAY_BUFFER, b);
        gl.BufferData(ARRAY_BUFFER, bytes.max(16) as isize, core::ptr::null(), DYNAMIC_COPY);
    }
    b
}

impl RowTargets {
    /// The storage as the CPU's scan sees it.
    fn storage(&self) -> rows_host::Storage {
        rows_host::Storage {
            tile: self.tile,
            guard: self.guard,
            sources: self.sources,
            count: self.count,
            packed: self.packed,
            warped: self.warped,
            holes: self.holes,
            fill_bias: FILL_BIAS,
        }
    }

    /// `guard`: the sources' band, columns each side of the tile.
    pub fn create(gl: &Gl, (tile, guard): ((i32, i32), i32), sources: usize, count: usize) -> RowTargets {
        let pixels = tile.0.max(1) as usize * tile.1.max(1) as usize;
        let source_pixels = (tile.0.max(1) + 2 * guard.max(0)) as usize * tile.1.max(1) as usize;
        RowTargets {
            tile,
            guard,
            sources,
            count,
            packed: storage(gl, source_pixels * sources * 12),
            warped: storage(gl, pixels * count * 8),
            params: storage(gl, count * std::mem::size_of::<Params>()),
            holes: storage(gl, 4),
            warped_view: {
                let mut t = 0;
                // SAFETY: a name for our buffer texture (pointed at `warped` when resolving).
                unsafe { gl.GenTextures(1, &mut t) };
                t
            },
        }
    }

    pub fn textures(&self) -> [u32; 1] {
        [self.warped_view]
    }

    pub fn fits(&self, (tile, guard): ((i32, i32), i32), sources: usize, count: usize) -> bool {
        self.tile == tile && self.guard == guard && self.sources == sources && self.count == count
    }

    pub fn buffers(&self) -> [u32; 4] {
        [self.packed, self.warped, self.params, self.holes]
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting our own objects; zero names are ignored.
        unsafe {
            gl.DeleteBuffers(4, self.buffers().as_ptr());
            gl.DeleteTextures(1, &self.warped_view);
        }
    }

    /// The last warp's output, one (colour, depth) per target pixel, targets in the job's
    /// order, rows bottom-up; a depth with its sign bit set was filled over a hole.
    pub fn warped(&self) -> u32 {
        self.warped
    }

    /// The share of the last warp's target pixels filled over holes (waits for the warp).
    pub fn hole_fraction(&self, gl: &Gl) -> f64 {
        let mut n = 0u32;
        // SAFETY: four bytes of our own buffer into a local; the binding is put back.
        unsafe {
            gl.MemoryBarrier(BUFFER_UPDATE_BARRIER_BIT);
            let old = crate::gl::guard::get_i(gl, COPY_READ_BUFFER_BINDING) as u32;
            gl.BindBuffer(COPY_READ_BUFFER, self.holes);
            gl.GetBufferSubData(COPY_READ_BUFFER, 0, 4, (&mut n as *mut u32).cast());
            gl.BindBuffer(COPY_READ_BUFFER, old);
        }
        let pixels = self.tile.0.max(1) as f64 * self.tile.1.max(1) as f64 * self.count.max(1) as f64;
        f64::from(n) / pixels
    }
}

/// Warps every target of `job` row by row; the sources are copied by `pass`.
/// `on_cpu`: the scan by this process's threads (`rows_host`, `colour` its scratch, `band`
/// what it saw of the guard band), else by a compute pass.
pub fn run(
    pass: &Pass,
    programs: &RowPrograms,
    out: &RowTargets,
    job: &Job,
    (on_cpu, colour, band): (bool, &mut Vec<u32>, &mut Option<(u64, u64)>),
) -> Result<(), String> {
    let mut profile = super::profile::Profile::new(pass.gl);
    for (j, source) in job.sources.iter().enumerate() {
        pass.copy_source(j, source, job)?;
        profile.lap("copy");
        pass.parallax(j, job);
        pack(pass, programs, out, j, job);
        profile.lap("parallax");
    }
    if on_cpu {
        match rows_host::warp(pass, &out.storage(), job, (colour, band), &mut profile) {
            Ok(rows_host::Done::InTiles) => return Ok(()),
            Ok(rows_host::Done::Warped) => {}
            Err(e) => {
                crate::log::once_for(
                    ("rows-on-cpu", 0),
                    crate::log::Level::Warn,
                    format_args!("synthesis: the row warp runs on the GPU this frame: {e}"),
                );
                warp_rows(pass, programs, out, job);
                profile.lap("rows");
            }
        }
    } else {
        warp_rows(pass, programs, out, job);
        profile.lap("rows");
    }
    resolve(pass, programs, out, job)?;
    profile.lap("resolve");
    Ok(())
}

/// Source `j`'s colour, depth and parallax into the packed storage. Where the source
/// recorded its disparity, the depth the warp orders pixels by is the one the scene's model
/// gives that parallax (DESIGN §5: one disparity per pixel, for what is in front too): a HUD
/// that wrote no depth is in front of the sky behind it, as its record says.
fn pack(pass: &Pass, programs: &RowPrograms, out: &RowTargets, j: usize, job: &Job) {
    let (gl, res, p) = (pass.gl, pass.res, programs.pack);
    pass.bind_array(0, res.color);
    pass.bind_array(1, res.depth);
    pass.bind_array(2, res.parallax);
    pass.bind_array(3, res.record);
    let m = job.model;
    // SAFETY: uniforms of our own program.
    unsafe {
        gl.UseProgram(p);
        gl.Uniform1i(loc(gl, p, "u_record"), 3);
        gl.Uniform1i(loc(gl, p, "u_recorded"), (pass.recorded >> j & 1) as i32);
        gl.Uniform4f(
            loc(gl, p, "u_model"),
            m.a_hi,
            m.a_lo,
            m.scale,
            f32::from(u8::from(m.reversed)),
        );
    }
    // SAFETY: our program and buffer; bindings are restored by the caller's guard.
    unsafe {
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 1, out.packed);
        gl.UseProgram(p);
        gl.Uniform1i(loc(gl, p, "u_color"), 0);
        gl.Uniform1i(loc(gl, p, "u_depth"), 1);
        gl.Uniform1i(loc(gl, p, "u_parallax"), 2);
        gl.Uniform1i(loc(gl, p, "u_layer"), j as i32);
        gl.Uniform2i(loc(gl, p, "u_tile"), res.tile.0, res.tile.1);
        gl.DispatchCompute((res.tile.0 as u32).div_ceil(8), (res.tile.1 as u32).div_ceil(8), 1);
    }
}

fn warp_rows(pass: &Pass, programs: &RowPrograms, out: &RowTargets, job: &Job) {
    let (gl, p) = (pass.gl, programs.rows);
    let params: Vec<Params> = job
        .targets
        .iter()
        .map(|t| {
            let [preferred, second] = t.sources;
            let du = |j: usize| (t.u - job.sources[j].u) as f32;
            Params {
                du: [du(second), du(preferred), 0.0, 0.0],
                src: [
                    second as i32,
                    preferred as i32,
                    if second != preferred { 2 } else { 1 },
                    0,
                ],
            }
        })
        .collect();
    let px = job.tile.0 as f64 / 2.0;
    let bias = if job.model.reversed { -FILL_BIAS } else { FILL_BIAS };
    // SAFETY: our program and buffers; bindings are restored by the caller's guard.
    unsafe {
        gl.BindBuffer(ARRAY_BUFFER, out.params);
        let bytes = (params.len() * std::mem::size_of::<Params>()) as isize;
        gl.BufferSubData(ARRAY_BUFFER, 0, bytes, params.as_ptr().cast());
        gl.BindBuffer(ARRAY_BUFFER, out.holes);
        gl.BufferSubData(ARRAY_BUFFER, 0, 4, [0u32].as_ptr().cast());
        gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 0, out.params);
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 1, out.packed);
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 2, out.warped);
        gl.BindBufferBase(SHADER_STORAGE_BUFFER, 3, out.holes);
        gl.UseProgram(p);
        gl.Uniform2i(loc(gl, p, "u_tile"), job.tile.0, job.tile.1);
        gl.Uniform1i(loc(gl, p, "u_guard"), job.guard);
        gl.Uniform1i(loc(gl, p, "u_targets"), params.len() as i32);
        gl.Uniform1i(loc(gl, p, "u_count_holes"), job.count_holes as i32);
        gl.Uniform1i(loc(gl, p, "u_second_fills_holes"), job.second_fills_holes as i32);
        gl.Uniform2f(
            loc(gl, p, "u_px"),
            (job.depthiness * px) as f32,
            (job.focus * px) as f32,
        );
        gl.Uniform1f(loc(gl, p, "u_threshold"), job.threshold as f32);
        gl.Uniform1i(loc(gl, p, "u_reversed"), job.model.reversed as i32);
        gl.Uniform1f(loc(gl, p, "u_far_bias"), bias);
        gl.DispatchCompute((job.tile.1 as u32).div_ceil(ROWS_PER_GROUP), params.len() as u32, 1);
        gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
    }
}

/// Each target's colour and depth into its tile (depth written whatever was there), read
/// through a buffer texture over the warped pixels: all targets at once where this GL's
/// buffer textures are that large, else one target at a time (where the offsets allow).
fn resolve(pass: &Pass, programs: &RowPrograms, out: &RowTargets, job: &Job) -> Result<(), String> {
    let (gl, p) = (pass.gl, programs.resolve);
    let pixels = job.tile.0 as i64 * job.tile.1 as i64;
    let whole = pixels * job.targets.len() as i64 <= get_i(gl, MAX_TEXTURE_BUFFER_SIZE) as i64;
    let align = get_i(gl, TEXTURE_BUFFER_OFFSET_ALIGNMENT).max(1) as i64;
    if !whole && ((pixels * 8) % align != 0 || pixels > get_i(gl, MAX_TEXTURE_BUFFER_SIZE) as i64) {
        return Err(format!(
            "a {}x{} tile's warped pixels do not fit this GL's buffer textures",
            job.tile.0, job.tile.1
        ));
    }
    // SAFETY: our program and textures, into the layer's own framebuffer; all of it is
    // restored by the caller's guard (unit 4's buffer texture included).
    unsafe {
        gl.ActiveTexture(TEXTURE4);
        gl.BindTexture(TEXTURE_BUFFER, out.warped_view);
        if whole {
            gl.TexBuffer(TEXTURE_BUFFER, RG32UI, out.warped);
        }
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
        gl.Enable(DEPTH_TEST);
        gl.DepthFunc(ALWAYS);
        gl.DepthMask(TRUE);
        gl.Enable(SCISSOR_TEST);
        gl.UseProgram(p);
        gl.Uniform2i(loc(gl, p, "u_tile"), job.tile.0, job.tile.1);
        gl.Uniform1i(loc(gl, p, "u_warped"), 4);
        gl.BindVertexArray(pass.vao);
        let (u_layer, u_origin) = (loc(gl, p, "u_layer"), loc(gl, p, "u_origin"));
        for (i, t) in job.targets.iter().enumerate() {
            let r = t.rect;
            gl.Viewport(r[0], r[1], r[2], r[3]);
            gl.Scissor(r[0], r[1], r[2], r[3]);
            if whole {
                gl.Uniform1i(u_layer, i as i32);
            } else {
                let bytes = pixels * 8;
                gl.TexBufferRange(
                    TEXTURE_BUFFER,
                    RG32UI,
                    out.warped,
                    (i as i64 * bytes) as isize,
                    bytes as isize,
                );
                gl.Uniform1i(u_layer, 0);
            }
            gl.Uniform2i(u_origin, r[0], r[1]);
            gl.DrawArrays(TRIANGLES, 0, 3);
        }
    }
    Ok(())
}
