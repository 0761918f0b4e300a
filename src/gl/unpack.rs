//! Uploads from client memory without the app noticing: the app's pixel-unpack state (buffer
//! binding, row length, skips, alignment) set to tight rows for the upload and put back.

use super::Gl;
use super::guard::get_i;
use super::*;

/// The app's pixel-unpack state, set to tight rows from client memory until `restore`.
pub struct UnpackState {
    buffer: u32,
    store: Vec<(GLenum, i32)>,
}

const UNPACK: [GLenum; 6] = [
    UNPACK_ALIGNMENT,
    UNPACK_ROW_LENGTH,
    UNPACK_SKIP_ROWS,
    UNPACK_SKIP_PIXELS,
    UNPACK_IMAGE_HEIGHT,
    UNPACK_SKIP_IMAGES,
];

impl UnpackState {
    pub fn neutral(gl: &Gl) -> UnpackState {
        let s = UnpackState {
            buffer: get_i(gl, PIXEL_UNPACK_BUFFER_BINDING) as u32,
            store: UNPACK.iter().map(|&p| (p, get_i(gl, p))).collect(),
        };
        // SAFETY: unpack parameters and binding valid in a GL 3 context (multiview needs one).
        unsafe {
            gl.BindBuffer(PIXEL_UNPACK_BUFFER, 0);
            for p in UNPACK {
                gl.PixelStorei(p, if p == UNPACK_ALIGNMENT { 1 } else { 0 });
            }
        }
        s
    }

    pub fn restore(self, gl: &Gl) {
        // SAFETY: putting back values read from this context.
        unsafe {
            gl.BindBuffer(PIXEL_UNPACK_BUFFER, self.buffer);
            for (p, v) in self.store {
                gl.PixelStorei(p, v);
            }
        }
    }
}
