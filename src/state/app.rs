//! The app's GL state as the app set it, per context, tracked whether multiview is on or not.
//!
//! Multiview changes GL behind the app's back (the quilt stands in for framebuffer 0, the
//! viewport is mapped into each tile, layer views stand in for the app's textures); what the
//! app asked for is kept here, so the layer can put it back after every replay and answer the
//! app's `glGet*` queries with it. It is tracked from the first make-current on, so that
//! multiview can also be turned on later in a context's life.

use super::program::ProgramSnapshot;
use crate::gl::{BACK, GLenum, Gl, GlInfo};
use std::collections::HashMap;

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
    /// The two capabilities every replay asks about, shadowed from `glEnable`/`glDisable`;
    /// None: unknown (after `glPopAttrib` or a display list), asked of GL at the next draw.
    pub scissor_test: Option<bool>,
    pub rasterizer_discard: Option<bool>,
    /// The fixed-function matrix mode and projection, shadowed from the matrix calls; None:
    /// unknown until the next fixed-function draw asks GL.
    pub matrix_mode: Option<GLenum>,
    pub projection: Option<[f32; 16]>,
    /// The fixed-function model-view, asked of GL by a perspective draw after it changed
    /// (whether the draw is attached to the camera: `camera::attached`).
    pub modelview: Option<[f32; 16]>,
    /// What the layer knows of the current program (not app-visible: see `program`).
    pub current: ProgramSnapshot,
    /// The display list being compiled: its name, mode, and what its calls do to shadowed
    /// state so far.
    pub list: Option<(u32, GLenum, ListEffect)>,
    /// What the lists compiled in this context do to shadowed state when called (a list not
    /// compiled here may do anything).
    pub lists: HashMap<u32, ListEffect>,
}

/// What a call, or a display list of calls, does to the state the layer shadows; ordered, a
/// list does the most of what its calls do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ListEffect {
    Nothing,
    /// Changes the matrix of the current mode (`glRotate`, `glLoadIdentity`…): the projection
    /// only if the mode is GL_PROJECTION when the list is called.
    CurrentMatrix,
    /// Changes the projection or the model-view whatever the mode (direct-state-access calls
    /// naming one of them).
    NamedMatrix,
    /// Anything (the matrix mode, the shadowed enables, `glPopAttrib`, other lists).
    Anything,
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
            scissor_test: None,
            rasterizer_discard: None,
            matrix_mode: None,
            projection: None,
            modelview: None,
            current: ProgramSnapshot::default(),
            list: None,
            lists: HashMap::new(),
        }
    }

    /// A call that changes shadowed state (by `effect`): applied by `apply` unless it is only
    /// being compiled into a display list (`GL_COMPILE`), and noted against the list.
    pub fn shadowed_call(&mut self, effect: ListEffect, apply: impl FnOnce(&mut AppState)) {
        if let Some((_, mode, list_effect)) = &mut self.list {
            *list_effect = (*list_effect).max(effect);
            if *mode == crate::gl::COMPILE {
                return;
            }
        }
        apply(self)
    }

    /// `glNewList(name, mode)`.
    pub fn list_begun(&mut self, name: u32, mode: GLenum) {
        self.compiling_list = true;
        self.list = Some((name, mode, ListEffect::Nothing));
    }

    /// `glEndList()`.
    pub fn list_ended(&mut self) {
        self.compiling_list = false;
        if let Some((name, _, effect)) = self.list.take() {
            self.lists.insert(name, effect);
        }
    }

    /// `glCallList(name)` just ran (`None`: lists the layer cannot name, `glCallLists`).
    pub fn list_called(&mut self, name: Option<u32>) {
        let effect = name
            .and_then(|n| self.lists.get(&n).copied())
            .unwrap_or(ListEffect::Anything);
        self.shadowed_call(effect, |app| match effect {
            ListEffect::Nothing => {}
            ListEffect::CurrentMatrix => app.matrix_changed(None),
            ListEffect::NamedMatrix => {
                app.projection = None;
                app.modelview = None;
            }
            ListEffect::Anything => app.forget_shadowed(),
        });
    }

    /// `glBindFramebuffer(target, fbo)`.
    pub fn bind_framebuffer(&mut self, target: GLenum, fbo: u32) {
        match target {
            crate::gl::DRAW_FRAMEBUFFER => self.draw_fbo = fbo,
            crate::gl::READ_FRAMEBUFFER => self.read_fbo = fbo,
            _ => {
                self.draw_fbo = fbo;
                self.read_fbo = fbo;
            }
        }
    }

    /// `glDrawBuffer(buf)`; true when it is framebuffer 0's choice.
    pub fn set_draw_buffer(&mut self, buf: GLenum) -> bool {
        let fb0 = self.draw_fbo == 0;
        if fb0 {
            self.draw_buffer = buf;
        }
        fb0
    }

    /// `glReadBuffer(buf)`; true when it is framebuffer 0's choice.
    pub fn set_read_buffer(&mut self, buf: GLenum) -> bool {
        let fb0 = self.read_fbo == 0;
        if fb0 {
            self.read_buffer = buf;
        }
        fb0
    }

    /// `glIsEnabled(cap)` for the shadowed caps, asked of GL only when unknown.
    pub fn enabled(&mut self, gl: &Gl, cap: GLenum) -> bool {
        let slot = match cap {
            crate::gl::SCISSOR_TEST => &mut self.scissor_test,
            crate::gl::RASTERIZER_DISCARD => &mut self.rasterizer_discard,
            _ => return is_enabled(gl, cap),
        };
        *slot.get_or_insert_with(|| is_enabled(gl, cap))
    }

    /// `glEnable`/`glDisable` of `cap` by the app.
    pub fn set_enabled(&mut self, cap: GLenum, on: bool) {
        match cap {
            crate::gl::SCISSOR_TEST => self.scissor_test = Some(on),
            crate::gl::RASTERIZER_DISCARD => self.rasterizer_discard = Some(on),
            _ => {}
        }
    }

    /// The app's `GL_MATRIX_MODE`, asked of GL only when unknown.
    pub fn matrix_mode(&mut self, gl: &Gl) -> GLenum {
        *self
            .matrix_mode
            .get_or_insert_with(|| crate::gl::guard::get_i(gl, crate::gl::MATRIX_MODE) as GLenum)
    }

    /// The fixed-function projection matrix, asked of GL only when unknown.
    pub fn fixed_projection(&mut self, gl: &Gl) -> [f32; 16] {
        *self.projection.get_or_insert_with(|| {
            crate::log::costs::gl_query();
            let mut p = [0f32; 16];
            // SAFETY: a 16-float query into a local array (compatibility contexts).
            unsafe { gl.GetFloatv(crate::gl::PROJECTION_MATRIX, p.as_mut_ptr()) };
            p
        })
    }

    /// The fixed-function model-view matrix, asked of GL only when unknown.
    pub fn fixed_modelview(&mut self, gl: &Gl) -> [f32; 16] {
        *self.modelview.get_or_insert_with(|| {
            crate::log::costs::gl_query();
            let mut m = [0f32; 16];
            // SAFETY: a 16-float query into a local array (compatibility contexts).
            unsafe { gl.GetFloatv(crate::gl::MODELVIEW_MATRIX, m.as_mut_ptr()) };
            m
        })
    }

    /// Whether depth writes are on, asked of GL (only for the rare draw that needs it).
    pub fn depth_writes(&self, gl: &Gl) -> bool {
        crate::log::costs::gl_query();
        let mut b = 0u8;
        // SAFETY: a one-boolean query into a local.
        unsafe { gl.GetBooleanv(crate::gl::DEPTH_WRITEMASK, &mut b) };
        b != 0
    }

    /// A matrix call in mode `mode` (None: the current one): the projection or the
    /// model-view may have changed.
    pub fn matrix_changed(&mut self, mode: Option<GLenum>) {
        let mode = mode.or(self.matrix_mode);
        if mode.is_none_or(|m| m == crate::gl::PROJECTION) {
            self.projection = None;
        }
        if mode.is_none_or(|m| m == crate::gl::MODELVIEW) {
            self.modelview = None;
        }
    }

    /// Something restored or replayed state the layer did not see call by call (`glPopAttrib`,
    /// a display list): ask GL again.
    pub fn forget_shadowed(&mut self) {
        self.scissor_test = None;
        self.rasterizer_discard = None;
        self.matrix_mode = None;
        self.projection = None;
        self.modelview = None;
    }
}

fn is_enabled(gl: &Gl, cap: GLenum) -> bool {
    crate::log::costs::gl_query();
    // SAFETY: an enable query of a capability valid in the contexts the layer replays in.
    unsafe { gl.IsEnabled(cap) != 0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gl::{COMPILE, COMPILE_AND_EXECUTE, MODELVIEW, PROJECTION, SCISSOR_TEST};

    fn known() -> AppState {
        AppState {
            draw_fbo: 0,
            read_fbo: 0,
            viewport: [0; 4],
            scissor: [0; 4],
            draw_buffer: BACK,
            read_buffer: BACK,
            program: 0,
            units: TextureUnits::default(),
            compiling_list: false,
            transform_feedback: false,
            selecting: false,
            scissor_test: Some(false),
            rasterizer_discard: Some(false),
            matrix_mode: Some(MODELVIEW),
            projection: Some([1.0; 16]),
            modelview: Some([1.0; 16]),
            current: ProgramSnapshot::default(),
            list: None,
            lists: HashMap::new(),
        }
    }

    #[test]
    fn modelview_calls_keep_the_projection_and_projection_calls_drop_it() {
        let mut a = known();
        a.matrix_changed(None);
        assert!(a.projection.is_some());
        a.matrix_changed(Some(PROJECTION));
        assert!(a.projection.is_none());
        a.projection = Some([1.0; 16]);
        a.matrix_mode = None;
        a.matrix_changed(None);
        assert!(a.projection.is_none(), "unknown mode: the projection may have changed");
    }

    /// Regression guard: `glMatrixMode`/`glEnable` compiled into a list with GL_COMPILE do
    /// not run, so they must not change the shadow.
    #[test]
    fn compiled_calls_change_no_shadow_but_mark_the_list() {
        let mut a = known();
        a.list_begun(7, COMPILE);
        a.shadowed_call(ListEffect::Anything, |a| a.matrix_mode = Some(PROJECTION));
        a.shadowed_call(ListEffect::Anything, |a| a.set_enabled(SCISSOR_TEST, true));
        a.list_ended();
        assert_eq!((a.matrix_mode, a.scissor_test), (Some(MODELVIEW), Some(false)));
        a.list_called(Some(7));
        assert_eq!((a.matrix_mode, a.scissor_test, a.projection), (None, None, None));
    }

    #[test]
    fn lists_without_shadowed_calls_keep_the_shadow_when_called() {
        let mut a = known();
        a.list_begun(8, COMPILE_AND_EXECUTE);
        a.list_ended();
        a.list_called(Some(8));
        assert_eq!(a.matrix_mode, Some(MODELVIEW));
        a.list_called(Some(9)); // never seen compiled
        assert_eq!(a.matrix_mode, None);
        // Recompiled with a shadowed call: no longer plain.
        let mut a = known();
        a.list_begun(8, COMPILE_AND_EXECUTE);
        a.list_ended();
        a.list_begun(8, COMPILE_AND_EXECUTE);
        a.shadowed_call(ListEffect::Anything, |a| a.set_enabled(SCISSOR_TEST, true));
        a.list_ended();
        assert_eq!(a.scissor_test, Some(true), "executed while compiled");
        a.list_called(Some(8));
        assert_eq!(a.scissor_test, None);
    }

    /// A list of modelview transforms (the common case: an object's placement) keeps the
    /// projection when called in modelview mode, and drops it in projection mode.
    #[test]
    fn lists_of_current_matrix_calls_drop_the_projection_only_in_projection_mode() {
        let mut a = known();
        a.list_begun(4, COMPILE);
        a.shadowed_call(ListEffect::CurrentMatrix, |a| a.matrix_changed(None));
        a.list_ended();
        a.list_called(Some(4));
        assert!(a.projection.is_some() && a.matrix_mode == Some(MODELVIEW));
        a.matrix_mode = Some(PROJECTION);
        a.list_called(Some(4));
        assert!(a.projection.is_none());
    }
}
