//! Recording of immediate-mode blocks for per-view replay (see the GL handler's essay).

use crate::gl::*;
use crate::multiview::Multiview;
use crate::state::AppState;

/// Starts compiling the coming `glBegin`…`glEnd` block into our list, when it will need
/// replaying (drawn to framebuffer 0, compatibility context, app not compiling a list).
pub fn begin(gl: &Gl, app: &AppState, mv: &mut Multiview) {
    if !mv.on_default_draw(app) || app.compiling_list || mv.info.es || !gl.NewList.is_loaded() {
        return;
    }
    // SAFETY: list creation and compile mode in the current compatibility context.
    unsafe {
        if mv.immediate_list == 0 {
            mv.immediate_list = gl.GenLists(1);
        }
        if mv.immediate_list != 0 {
            gl.NewList(mv.immediate_list, COMPILE);
            mv.recording_immediate = true;
        }
    }
}

/// Ends the recording started by `begin`; the list to replay, if one was recorded.
pub fn end(gl: &Gl, mv: &mut Multiview) -> Option<u32> {
    if !mv.recording_immediate {
        return None;
    }
    mv.recording_immediate = false;
    // SAFETY: closes the list opened in `begin`.
    unsafe { gl.EndList() };
    Some(mv.immediate_list)
}

pub fn call(gl: &Gl, list: u32) {
    // SAFETY: `list` is our compiled immediate-mode block.
    unsafe { gl.CallList(list) };
}
