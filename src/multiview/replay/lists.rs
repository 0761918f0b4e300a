//! Display lists replayed once per view. A list may move the current matrix outside any
//! push/pop of its own (xscreensaver's `engine` starts a list with `glRotatef`): called once
//! per view, view k would see k extra rotations. The model-view and texture matrices (and
//! their stack depths, and the matrix mode) are therefore put back before every call after
//! the first, so each view starts from the state the app called the list in, and the state
//! after the last view is the state after one call, as the app expects.
//!
//! The projection is not put back: each view loads its own before the call (`draw`).

use crate::gl::guard::get_i;
use crate::gl::*;
use crate::state::app::ListEffect;
use std::cell::Cell;

/// One matrix stack at the list's call: its depth and top.
#[derive(Clone, Copy)]
struct Stack {
    mode: GLenum,
    depth_query: GLenum,
    depth: i32,
    top: [f32; 16],
}

#[derive(Clone, Copy)]
struct Saved {
    mode: GLenum,
    stacks: [Stack; 2],
}

/// The matrices before a list's first call (taken at that call, when the list may move them).
pub struct ListMatrices {
    wanted: bool,
    saved: Cell<Option<Saved>>,
}

impl ListMatrices {
    /// `effect`: what the list does to shadowed state (`Anything` for lists not seen compiled).
    pub fn new(effect: ListEffect) -> ListMatrices {
        ListMatrices {
            wanted: effect != ListEffect::Nothing,
            saved: Cell::new(None),
        }
    }

    /// `call` (the app's `glCallList`) for one view: the matrices as they were before the
    /// first view's call.
    pub fn around(&self, gl: &Gl, call: impl FnOnce()) {
        if self.wanted {
            match self.saved.get() {
                None => self.saved.set(Some(save(gl))),
                Some(s) => restore(gl, &s),
            }
        }
        call()
    }
}

fn save(gl: &Gl) -> Saved {
    let stack = |mode: GLenum, depth: GLenum, matrix: GLenum| {
        let mut top = [0f32; 16];
        // SAFETY: a 16-float query of a matrix of the compatibility profile.
        unsafe { gl.GetFloatv(matrix, top.as_mut_ptr()) };
        Stack {
            mode,
            depth_query: depth,
            depth: get_i(gl, depth),
            top,
        }
    };
    Saved {
        mode: get_i(gl, MATRIX_MODE) as GLenum,
        stacks: [
            stack(MODELVIEW, MODELVIEW_STACK_DEPTH, MODELVIEW_MATRIX),
            stack(TEXTURE, TEXTURE_STACK_DEPTH, TEXTURE_MATRIX),
        ],
    }
}

fn restore(gl: &Gl, s: &Saved) {
    // SAFETY: matrix-stack calls of the compatibility profile, outside glBegin/glEnd (a list
    // is being called); pops stop at the depth saved, never below it.
    unsafe {
        for st in &s.stacks {
            gl.MatrixMode(st.mode);
            let mut depth = get_i(gl, st.depth_query);
            while depth > st.depth {
                gl.PopMatrix();
                depth -= 1;
            }
            gl.LoadMatrixf(st.top.as_ptr());
        }
        gl.MatrixMode(s.mode);
    }
}
