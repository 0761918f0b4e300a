//! Pixel-rectangle drawing of the fixed-function pipeline (`glBitmap`, `glDrawPixels`,
//! `glCopyPixels`): they draw at the current raster position, which GL computed in window
//! coordinates under the app's own viewport. Per view, the raster position is moved into
//! that view's tile with `glWindowPos` (keeping the raster colour and depth), and afterwards
//! put back where the app's call left it (a bitmap advances it).

use crate::gl::*;
use crate::multiview::quilt::layout::QuiltLayout;

/// The app's raster position (window x, y, z) and colour before the replay.
pub struct RasterState {
    pos: [f32; 4],
    color: [f32; 4],
    valid: bool,
}

pub fn save(gl: &Gl) -> RasterState {
    let (mut pos, mut color, mut valid) = ([0f32; 4], [0f32; 4], 0u8);
    // SAFETY: compatibility-profile queries into locals.
    unsafe {
        gl.GetFloatv(CURRENT_RASTER_POSITION, pos.as_mut_ptr());
        gl.GetFloatv(CURRENT_RASTER_COLOR, color.as_mut_ptr());
        gl.GetBooleanv(CURRENT_RASTER_POSITION_VALID, &mut valid);
    }
    RasterState {
        pos,
        color,
        valid: valid != 0,
    }
}

/// `glWindowPos3f` sets the raster colour from the current colour, so the current colour is
/// swapped for the raster one around it.
fn window_pos(gl: &Gl, r: &RasterState, x: f32, y: f32) {
    let mut current = [0f32; 4];
    // SAFETY: compatibility-profile state, restored right after.
    unsafe {
        gl.GetFloatv(CURRENT_COLOR, current.as_mut_ptr());
        gl.Color4fv(r.color.as_ptr());
        gl.WindowPos3f(x, y, r.pos[2]);
        gl.Color4fv(current.as_ptr());
    }
}

/// Moves the raster position into view `i`'s tile (same place in the tile as in the window).
pub fn place(gl: &Gl, r: &RasterState, layout: &QuiltLayout, i: u32) {
    if !r.valid {
        return;
    }
    let (ox, oy) = layout.origin(i);
    let sx = layout.tile_w as f32 / layout.window_w as f32;
    let sy = layout.tile_h as f32 / layout.window_h as f32;
    window_pos(gl, r, ox as f32 + r.pos[0] * sx, oy as f32 + r.pos[1] * sy);
}

/// Puts the raster position where the app's single call would have left it.
pub fn finish(gl: &Gl, r: &RasterState, advance: (f32, f32)) {
    if r.valid {
        window_pos(gl, r, r.pos[0] + advance.0, r.pos[1] + advance.1);
    }
}
