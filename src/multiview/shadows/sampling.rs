//! Layer views sample like the app's texture they stand in for.
//!
//! A texture view has sampling parameters of its own. They are copied from the app's texture
//! when the views are made, and every later change the app makes to its texture
//! (`glTexParameter*`, `glTextureParameter*`: renderers re-send filters, wrap and compare
//! modes whenever they like) is made on the views too, so that view i samples layer i
//! exactly as the app samples its texture. Only parameters valid on a view of an immutable
//! array are mirrored; the others (image format, storage) cannot change under a view.

use crate::gl::*;

/// Parameters copied when the views are made: (name, values, read as floats).
/// `GL_TEXTURE_MAX_ANISOTROPY` is not among them (querying it is an error without the
/// extension); it is mirrored when the app sets it, which proves the extension is there.
const COPIED: [(GLenum, usize, bool); 15] = [
    (TEXTURE_MIN_FILTER, 1, false),
    (TEXTURE_MAG_FILTER, 1, false),
    (TEXTURE_WRAP_S, 1, false),
    (TEXTURE_WRAP_T, 1, false),
    (TEXTURE_WRAP_R, 1, false),
    (TEXTURE_COMPARE_MODE, 1, false),
    (TEXTURE_COMPARE_FUNC, 1, false),
    (TEXTURE_MIN_LOD, 1, true),
    (TEXTURE_MAX_LOD, 1, true),
    (TEXTURE_LOD_BIAS, 1, true),
    (TEXTURE_BASE_LEVEL, 1, false),
    (TEXTURE_MAX_LEVEL, 1, false),
    (TEXTURE_SWIZZLE_RGBA, 4, false),
    (TEXTURE_BORDER_COLOR, 4, true),
    (DEPTH_STENCIL_TEXTURE_MODE, 1, false),
];

/// Whether a change of `pname` on the app's texture is made on its layer views too.
pub fn mirrored(pname: GLenum) -> bool {
    COPIED.iter().any(|&(p, _, _)| p == pname)
        || matches!(
            pname,
            TEXTURE_SWIZZLE_R | TEXTURE_SWIZZLE_G | TEXTURE_SWIZZLE_B | TEXTURE_SWIZZLE_A | TEXTURE_MAX_ANISOTROPY
        )
}

/// How many values a `glTexParameter*v` call passes for `pname`.
pub fn values(pname: GLenum) -> i32 {
    match pname {
        TEXTURE_BORDER_COLOR | TEXTURE_SWIZZLE_RGBA => 4,
        _ => 1,
    }
}

/// Whether `pname` also matters to the array itself (mipmap generation reads the levels).
pub fn applies_to_array(pname: GLenum) -> bool {
    matches!(pname, TEXTURE_BASE_LEVEL | TEXTURE_MAX_LEVEL)
}

/// One `GL_TEXTURE_2D` view per layer of `array`, sampling like the app's texture `app`.
pub fn layer_views(gl: &Gl, app: u32, array: u32, format: GLenum, levels: i32, n: u32) -> Vec<u32> {
    let mut views = vec![0; n as usize];
    // SAFETY: new views of our own immutable array.
    unsafe {
        gl.GenTextures(n as i32, views.as_mut_ptr());
        for (layer, &view) in views.iter().enumerate() {
            gl.TextureView(view, TEXTURE_2D, array, format, 0, levels as u32, layer as u32, 1);
        }
    }
    copy_parameters(gl, app, &views);
    views
}

fn copy_parameters(gl: &Gl, app: u32, views: &[u32]) {
    for (pname, count, float) in COPIED {
        let (mut i, mut f) = ([0i32; 4], [0f32; 4]);
        // SAFETY: queries of parameters valid on any 2D texture, into arrays of four; the
        // same values set on our views.
        unsafe {
            if float {
                gl.GetTextureParameterfv(app, pname, f.as_mut_ptr());
            } else {
                gl.GetTextureParameteriv(app, pname, i.as_mut_ptr());
            }
            for &view in views {
                match (float, count) {
                    (true, 1) => gl.TextureParameterf(view, pname, f[0]),
                    (true, _) => gl.TextureParameterfv(view, pname, f.as_ptr()),
                    (false, 1) => gl.TextureParameteri(view, pname, i[0]),
                    (false, _) => gl.TextureParameteriv(view, pname, i.as_ptr()),
                }
            }
        }
    }
}
