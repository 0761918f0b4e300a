//! The passes of the adaptive quad-grid warp (see the module comment of `synth`).

use super::Job;
use super::pass::{Pass, loc, zero_to_one};
use super::resources::{COMMAND_STRIDE, LEVELS, level_size};
use crate::gl::*;

/// Rows of a column segment (`SEGMENT` in synth_columns.comp).
const COLUMN_SEGMENT: u32 = 32;

/// Window depth between a stretched (disocclusion) quad and the surface it lies on.
const STRETCHED_BIAS: f32 = 1.0 / 16384.0;

/// The quad-grid warp of `job`: steps 1 to 3 of the module comment of `synth`, per source
/// and then per target.
pub fn run(pass: &Pass, job: &Job) -> Result<(), String> {
    if !(pass.programs.has_grid() && pass.res.has_grid()) {
        return Err("the grid's programs or storage are missing".into());
    }
    let mut profile = super::profile::Profile::new(pass.gl);
    for (j, source) in job.sources.iter().enumerate() {
        pass.copy_source(j, source, job)?;
        profile.lap("copy");
        pass.parallax(j, job);
        pyramid(pass, j);
        profile.lap("pyramid");
        list_leaves(pass, j, job);
        profile.lap("grid");
        if profile.on() {
            profile.leaves += leaf_count(pass, j);
        }
    }
    // SAFETY: the leaf lists are read as vertex attributes and draw commands next.
    unsafe {
        pass.gl
            .MemoryBarrier(VERTEX_ATTRIB_ARRAY_BARRIER_BIT | COMMAND_BARRIER_BIT)
    };
    draw_targets(pass, job);
    profile.lap("warp");
    Ok(())
}

/// Leaves listed for source `j` (a read-back: for the trace profile only).
fn leaf_count(pass: &Pass, j: usize) -> u64 {
    let mut command = [0u32; 4];
    // SAFETY: 16 bytes of our own command buffer into a local of that size.
    unsafe {
        pass.gl.BindBuffer(DRAW_INDIRECT_BUFFER, pass.res.commands);
        pass.gl.GetBufferSubData(
            DRAW_INDIRECT_BUFFER,
            j as isize * COMMAND_STRIDE,
            16,
            command.as_mut_ptr().cast(),
        );
    }
    u64::from(command[0] / 6)
}

/// The min/max pyramid of source `j`'s parallax.
fn pyramid(pass: &Pass, j: usize) {
    let (gl, p, res) = (pass.gl, pass.programs, pass.res);
    for l in 0..LEVELS {
        let src = if l == 0 { res.parallax } else { res.levels[l - 1] };
        pass.bind_array(0, src);
        // SAFETY: as above.
        unsafe {
            gl.UseProgram(p.minmax);
            gl.Uniform1i(loc(gl, p.minmax, "u_src"), 0);
            gl.Uniform1i(loc(gl, p.minmax, "u_layer"), j as i32);
            gl.Uniform1i(loc(gl, p.minmax, "u_first"), (l == 0) as i32);
        }
        pass.fullscreen(p.minmax, res.levels[l], j, level_size(res.tile, l));
    }
    pass.attach(COLOR_ATTACHMENT0, 0, 0);
}

/// Source `j`'s leaf cells, appended to its list by one dispatch per level, then its
/// columns of single pixels.
fn list_leaves(pass: &Pass, j: usize, job: &Job) {
    let (gl, res) = (pass.gl, pass.res);
    let reach = job
        .targets
        .iter()
        .filter(|t| t.sources.contains(&j))
        .map(|t| (t.u - job.sources[j].u).abs())
        .fold(0.0, f64::max);
    let scale = job.depthiness.abs() * job.tile.0 as f64 / 2.0 * reach;
    let command: [u32; 4] = [0, 1, 0, 0];
    // SAFETY: our buffers; bindings are restored by the guard.
    unsafe {
        gl.BindBuffer(DRAW_INDIRECT_BUFFER, res.commands);
        gl.BufferSubData(
            DRAW_INDIRECT_BUFFER,
            j as isize * COMMAND_STRIDE,
            16,
            command.as_ptr().cast(),
        );
        gl.BindBufferRange(
            SHADER_STORAGE_BUFFER,
            0,
            res.leaves,
            j as isize * res.leaf_stride,
            res.leaf_stride,
        );
        gl.BindBufferRange(SHADER_STORAGE_BUFFER, 1, res.commands, j as isize * COMMAND_STRIDE, 16);
    }
    let common = |p: u32| {
        // SAFETY: uniforms of our own program.
        unsafe {
            gl.UseProgram(p);
            gl.Uniform1i(loc(gl, p, "u_parallax"), 0);
            gl.Uniform1i(loc(gl, p, "u_level"), 1);
            gl.Uniform1i(loc(gl, p, "u_depth"), 3);
            gl.Uniform1i(loc(gl, p, "u_layer"), j as i32);
            gl.Uniform1f(loc(gl, p, "u_scale"), scale as f32);
            gl.Uniform1f(loc(gl, p, "u_threshold"), job.threshold as f32);
            gl.Uniform2i(loc(gl, p, "u_tile"), res.tile.0, res.tile.1);
        }
    };
    let p = pass.programs.leaves;
    common(p);
    // SAFETY: as above.
    unsafe { gl.Uniform1i(loc(gl, p, "u_parent"), 2) };
    pass.bind_array(0, res.parallax);
    pass.bind_array(3, res.depth);
    for l in (0..LEVELS).rev() {
        pass.bind_array(1, res.levels[l]);
        pass.bind_array(2, res.levels[(l + 1).min(LEVELS - 1)]);
        let (cw, ch) = level_size(res.tile, l);
        // SAFETY: as above; the barrier orders the appends of consecutive levels.
        unsafe {
            gl.Uniform1i(loc(gl, p, "u_cell"), 2 << l);
            gl.Uniform1i(loc(gl, p, "u_top"), (l == LEVELS - 1) as i32);
            gl.DispatchCompute((cw as u32).div_ceil(8), (ch as u32).div_ceil(8), 1);
            gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
        }
    }
    common(pass.programs.columns);
    pass.bind_array(1, res.levels[0]);
    let (w, h) = (res.tile.0 as u32, res.tile.1 as u32);
    // SAFETY: as above.
    unsafe {
        gl.DispatchCompute(w.div_ceil(64), h.div_ceil(COLUMN_SEGMENT), 1);
        gl.MemoryBarrier(SHADER_STORAGE_BARRIER_BIT);
    }
}

/// Every target tile: depth cleared to the far value, then each of its sources' leaves
/// drawn, the preferred source last (it wins depth ties).
fn draw_targets(pass: &Pass, job: &Job) {
    let (gl, p, res) = (pass.gl, pass.programs.warp, pass.res);
    let far = [job.model.far_depth()];
    let (tw, th) = job.tile;
    // Well inside any viewport size and bounds GL 4.3 guarantees.
    let overhang = tw.min(4096);
    // SAFETY: our program, vertex array and buffers; the destination is the layer's own
    // framebuffer. All of it is restored by the guard.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, job.dest_fbo);
        gl.Enable(DEPTH_TEST);
        // Or-equal: the background at the far value itself must be drawn over the clear.
        gl.DepthFunc(if job.model.reversed { GEQUAL } else { LEQUAL });
        gl.DepthMask(TRUE);
        gl.Enable(SCISSOR_TEST);
        gl.UseProgram(p);
        gl.Uniform1i(loc(gl, p, "u_color"), 0);
        gl.Uniform1i(loc(gl, p, "u_depth"), 1);
        gl.Uniform1i(loc(gl, p, "u_parallax"), 2);
        gl.DepthRange(0.0, 1.0);
        gl.Uniform1i(loc(gl, p, "u_zero_to_one"), zero_to_one(gl) as i32);
        gl.Uniform2f(loc(gl, p, "u_tile"), tw as f32, th as f32);
        let px = job.tile.0 as f64 / 2.0;
        gl.Uniform2f(
            loc(gl, p, "u_px"),
            (job.depthiness * px) as f32,
            (job.focus * px) as f32,
        );
        gl.Uniform1f(loc(gl, p, "u_margin"), 0.5);
        gl.Uniform1f(loc(gl, p, "u_overhang"), overhang as f32);
        let bias = if job.model.reversed {
            -STRETCHED_BIAS
        } else {
            STRETCHED_BIAS
        };
        gl.Uniform1f(loc(gl, p, "u_far_bias"), bias);
        gl.BindVertexArray(pass.vao);
        gl.Uniform1i(loc(gl, p, "u_leaves"), 4);
        gl.ActiveTexture(TEXTURE4);
        gl.BindTexture(TEXTURE_BUFFER, res.leaf_view);
        gl.BindBuffer(DRAW_INDIRECT_BUFFER, res.commands);
    }
    pass.bind_array(0, res.color);
    pass.bind_array(1, res.depth);
    pass.bind_array(2, res.parallax);
    let (u_du, u_layer) = (loc(gl, p, "u_du"), loc(gl, p, "u_layer"));
    for t in job.targets {
        let r = t.rect;
        // SAFETY: as above.
        unsafe {
            gl.Viewport(r[0] - overhang, r[1], r[2] + 2 * overhang, r[3]);
            gl.Scissor(r[0], r[1], r[2], r[3]);
            gl.ClearBufferfv(DEPTH, 0, far.as_ptr());
        }
        let second = (t.sources[1] != t.sources[0]).then_some(t.sources[1]);
        for j in second.into_iter().chain(std::iter::once(t.sources[0])) {
            let base = j as isize * res.leaf_stride;
            // SAFETY: as above; the buffer texture views source j's leaf list.
            unsafe {
                gl.ActiveTexture(TEXTURE4);
                gl.TexBufferRange(TEXTURE_BUFFER, RGBA32UI, res.leaves, base, res.leaf_stride);
                gl.Uniform1f(u_du, (t.u - job.sources[j].u) as f32);
                gl.Uniform1i(u_layer, j as i32);
                gl.DrawArraysIndirect(TRIANGLES, (j as isize * COMMAND_STRIDE) as *const _);
            }
        }
    }
}
