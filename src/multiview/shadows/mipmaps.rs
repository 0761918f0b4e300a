//! The app regenerated a shadowed texture's mipmaps: its layers' too, but only those drawn
//! this frame. A fast mode renders few views; the others' layers are never sampled before
//! they are drawn again (a synthesised view samples its nearest rendered view's layer), and
//! a whole array's chain is dear: glmark2 terrain mipmaps its 400x300 scene five times a
//! frame, 37 ms a call for 48 layers on llvmpipe, most of what a synthesised view cost.
//!
//! A layer's view cannot do it alone: Mesa 22.3 generates a view's mipmaps for every layer
//! of the texture it views (`st_generate_mipmap` takes its layer range from the resource).
//! So each wanted layer is filtered level by level by blits, the way Mesa's own generation
//! does it (`util_gen_mipmap`: a linear blit per level, sRGB decoded and encoded).

use super::layered::LayeredImage;
use crate::gl::guard::StateGuard;
use crate::gl::{GlInfo, *};

/// Mipmaps of `image`'s layers `wanted`: of the whole array when every layer is wanted, or
/// when its format cannot be filtered by a blit (depth, stencil, integers).
pub fn generate(gl: &Gl, info: GlInfo, image: &LayeredImage, wanted: impl Fn(u32) -> bool) {
    let n = image.layer_views.len() as u32;
    if n == 0 || !image.filterable || (0..n).all(&wanted) {
        // SAFETY: our own array texture.
        unsafe { gl.GenerateTextureMipmap(image.array) };
        return;
    }
    let levels = level_range(gl, image);
    let _guard = StateGuard::new(gl, info).caps(&[SCISSOR_TEST, FRAMEBUFFER_SRGB]);
    let mut fbos = [0u32; 2];
    let (w, h) = image.size;
    let size = |l: i32| ((w >> l).max(1), (h >> l).max(1));
    // SAFETY: our own framebuffers, named (no binding changes), deleted at the end; only our
    // array is attached to them. Scissor and sRGB encoding are restored by the guard.
    unsafe {
        gl.Disable(SCISSOR_TEST);
        gl.Enable(FRAMEBUFFER_SRGB);
        gl.CreateFramebuffers(2, fbos.as_mut_ptr());
        let [src, dst] = fbos;
        for layer in (0..n).filter(|&i| wanted(i)) {
            for l in levels.clone() {
                gl.NamedFramebufferTextureLayer(src, COLOR_ATTACHMENT0, image.array, l, layer as i32);
                gl.NamedFramebufferTextureLayer(dst, COLOR_ATTACHMENT0, image.array, l + 1, layer as i32);
                let ((sw, sh), (dw, dh)) = (size(l), size(l + 1));
                gl.BlitNamedFramebuffer(src, dst, 0, 0, sw, sh, 0, 0, dw, dh, COLOR_BUFFER_BIT, LINEAR);
            }
        }
        gl.DeleteFramebuffers(2, fbos.as_ptr());
    }
}

/// The levels each blit reads, as glGenerateMipmap would fill them: from the base level up
/// to the maximum (the layer views carry the app's), within the array's storage.
fn level_range(gl: &Gl, image: &LayeredImage) -> std::ops::Range<i32> {
    let (mut base, mut max, mut stored) = (0, 1000, 1);
    // SAFETY: single-integer queries on our own textures.
    unsafe {
        gl.GetTextureParameteriv(image.layer_views[0], TEXTURE_BASE_LEVEL, &mut base);
        gl.GetTextureParameteriv(image.layer_views[0], TEXTURE_MAX_LEVEL, &mut max);
        gl.GetTextureParameteriv(image.array, TEXTURE_IMMUTABLE_LEVELS, &mut stored);
    }
    let (w, h) = image.size;
    let full = 32 - (w.max(h).max(1) as u32).leading_zeros() as i32;
    let last = max.min(stored - 1).min(base + full - 1);
    base.max(0)..last.max(base.max(0))
}
