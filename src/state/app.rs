//! The app's GL state as the app set it, per context, tracked whether multiview is on or not.
//!
//! Multiview changes GL behind the app's back (the quilt stands in for framebuffer 0, the
//! viewport is mapped into each tile, layer views stand in for the app's textures); what the
//! app asked for is kept here, so the layer can put it back after every replay and answer the
//! app's `glGet*` queries with it. It is tracked from the first make-current on, so that
//! multiview can also be turned on later in a context's life.

use crate::gl::{BACK, GLenum, Gl, GlInfo};

/// Texture bindings of `GL_TEXTURE_2D` per unit, as the app made them.
#[derive(Clone, Debug, Default)]
pub struct TextureUnits {
    pub active: u32,
    pub bound_2d: Vec<u32>,
}

impl TextureUnits {
    pub fn bind(&mut self, unit: u32, texture: u32) {
        let unit = unit as usize;
        if unit >= 192 {
            return;
        }
        if self.bound_2d.len() <= unit {
            self.bound_2d.resize(unit + 1, 0);
        }
        self.bound_2d[unit] = texture;
    }
}

#[derive(Clone, Debug)]
pub struct AppState {
    pub draw_fbo: u32,
    pub read_fbo: u32,
    pub viewport: [i32; 4],
    pub scissor: [i32; 4],
    /// The app's `glDrawBuffer`/`glReadBuffer` choice for framebuffer 0 (e.g. GL_BACK).
    pub draw_buffer: GLenum,
    pub read_buffer: GLenum,
    pub program: u32,
    pub units: TextureUnits,
    /// The app is compiling a display list: its calls must not be replayed.
    pub compiling_list: bool,
    /// Transform feedback is active: draws run once (each replay would be captured).
    pub transform_feedback: bool,
    /// `glRenderMode` is GL_SELECT or GL_FEEDBACK: picking must see each draw once.
    pub selecting: bool,
}

impl AppState {
    /// The state of a context at its first make-current (read from GL once).
    pub fn read(gl: &Gl, info: GlInfo) -> AppState {
        use crate::gl::guard::{get_i, get_i4};
        let (draw_fbo, read_fbo) = if info.has_gl3_features() {
            (
                get_i(gl, crate::gl::DRAW_FRAMEBUFFER_BINDING) as u32,
                get_i(gl, crate::gl::READ_FRAMEBUFFER_BINDING) as u32,
            )
        } else {
            (0, 0)
        };
        AppState {
            draw_fbo,
            read_fbo,
            viewport: get_i4(gl, crate::gl::VIEWPORT),
            scissor: get_i4(gl, crate::gl::SCISSOR_BOX),
            draw_buffer: BACK,
            read_buffer: BACK,
            program: get_i(gl, crate::gl::CURRENT_PROGRAM) as u32,
            units: TextureUnits::default(),
            compiling_list: false,
            transform_feedback: false,
            selecting: false,
        }
    }
}
