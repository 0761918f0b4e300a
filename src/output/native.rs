//! The lenticular weave (`--output native`, DESIGN §4) on the GPU: the quilt woven into a
//! framebuffer of the display's native resolution by `glsl-patches/lenticular.frag` (the GPU
//! twin of `weave::weave_cpu`), then shown in the window — 1:1 when the window is the
//! display, fitted otherwise.

use super::pass::{self, Passes};
use super::weave::Filter;
use crate::config::device::Device;
use crate::gl::GlInfo;
use crate::gl::*;
use crate::multiview::quilt::layout::QuiltLayout;

/// The native-resolution target, created on first use per context.
pub struct NativeTarget {
    pub fbo: u32,
    pub color: u32,
    pub size: (u32, u32),
}

impl NativeTarget {
    fn create(gl: &Gl, size: (u32, u32)) -> NativeTarget {
        let (fbo, color) = pass::color_target(gl, RGBA8, size);
        NativeTarget { fbo, color, size }
    }
}

fn set_uniforms(
    gl: &Gl,
    program: u32,
    device: &Device,
    views: u32,
    grid: (u32, u32),
    filter: Filter,
    size: (u32, u32),
) {
    let p = device.calibration.weave_params(views);
    let u = |name: &str| pass::uniform(gl, program, name);
    let (mode, sigma) = match filter {
        Filter::Gaussian { sigma } => (2, sigma),
        f => (f.mode(), 1.0),
    };
    let cells: Vec<f32> = p.cells.iter().flat_map(|c| c.iter().copied()).collect();
    // SAFETY: uniforms of our own bound program; array length matches the cell count.
    unsafe {
        gl.Uniform1i(u("u_quilt"), 0);
        gl.Uniform1f(u("u_pitch"), p.pitch);
        gl.Uniform1f(u("u_tilt"), p.tilt);
        gl.Uniform1f(u("u_subp"), p.subp);
        gl.Uniform1f(u("u_center"), p.center);
        gl.Uniform1i(u("u_inv_view"), p.inv_view as i32);
        gl.Uniform1i(u("u_flip_subp"), p.flip_subp as i32);
        gl.Uniform1i(u("u_view_count"), views as i32);
        gl.Uniform1i(u("u_cols"), grid.0 as i32);
        gl.Uniform1i(u("u_rows"), grid.1 as i32);
        gl.Uniform1i(u("u_filter"), mode);
        gl.Uniform1f(u("u_sigma"), sigma);
        gl.Uniform1i(u("u_cell_pattern"), p.cell_pattern as i32);
        gl.Uniform1i(u("u_cell_count"), p.cells.len().min(16) as i32);
        if !cells.is_empty() {
            gl.Uniform2fv(u("u_cells"), (cells.len() / 2).min(48) as i32, cells.as_ptr());
        }
        gl.Uniform2i(u("u_out_size"), size.0 as i32, size.1 as i32);
    }
}

pub struct WeaveInput<'a> {
    pub device: &'a Device,
    pub quilt_texture: u32,
    /// Where the views are drawn in the texture.
    pub layout: QuiltLayout,
    pub views: u32,
    pub grid: (u32, u32),
    pub filter: Filter,
}

/// Weaves the quilt into the native target (created or resized as needed); returns it.
pub fn weave<'t>(
    gl: &Gl,
    info: GlInfo,
    passes: &mut Passes,
    target: &'t mut Option<NativeTarget>,
    input: &WeaveInput,
) -> Result<&'t NativeTarget, String> {
    let size = (input.device.calibration.screen_w, input.device.calibration.screen_h);
    if target.as_ref().is_some_and(|t| t.size != size) {
        let t = target.take().unwrap();
        // SAFETY: deleting our own objects.
        unsafe {
            gl.DeleteFramebuffers(1, &t.fbo);
            gl.DeleteTextures(1, &t.color);
        }
    }
    let program = passes.program(gl, info, "lenticular", pass::LENTICULAR_FRAG)?;
    let t = target.get_or_insert_with(|| NativeTarget::create(gl, size));
    // SAFETY: drawing our pass into our target; the caller's guard restores state.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, t.fbo);
        gl.Viewport(0, 0, size.0 as i32, size.1 as i32);
        gl.UseProgram(program);
        gl.ActiveTexture(TEXTURE0);
        gl.BindTexture(TEXTURE_2D, input.quilt_texture);
    }
    set_uniforms(gl, program, input.device, input.views, input.grid, input.filter, size);
    let (a, b) = input.layout.swapped().map_or((-1, -1), |(a, b)| (a as i32, b as i32));
    // SAFETY: uniforms of our own bound program.
    unsafe {
        gl.Uniform1i(pass::uniform(gl, program, "u_flipped"), input.layout.flipped as i32);
        gl.Uniform2i(pass::uniform(gl, program, "u_swap"), a, b);
        let l = input.layout;
        gl.Uniform2i(pass::uniform(gl, program, "u_tile"), l.tile_w as i32, l.tile_h as i32);
    }
    passes.draw(gl);
    Ok(t)
}
