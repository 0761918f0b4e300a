//! The N-layer stand-in for one of the app's textures or renderbuffers.
//!
//! A layered image belongs to the app's object, not to a framebuffer: renderers built on
//! render passes (VTK: f3d, ParaView) attach a texture for one pass, detach it once the pass
//! is drawn, sample it in the next pass, and attach it again next frame, possibly to another
//! framebuffer. The per-view content lives as long as the object and its storage do, so
//! framebuffer shadows (`shadow`) are only sets of view framebuffers pointing at images, and
//! can be rebuilt at any time without losing what the frame has drawn. An image is made from
//! the app's own content (a shadow made mid-frame, or of a target rendered once, must not
//! start empty) and gives the centre layer back when the layer gives up.
//!
//! Sampling goes through one `GL_TEXTURE_2D` view per layer, which has sampling parameters
//! of its own: they are copied from the app's texture when the views are made, and the
//! app's later changes are mirrored (`mirror`).
//!
//! Layers may be smaller than the app's object (`scale`, `--fbo-scale`): the copies to and
//! from the app's object then scale too, linearly for colour.

use super::scale::LayerScale;
use crate::gl::GlInfo;
use crate::gl::format;
use crate::gl::types::GLbitfield;
use crate::gl::*;
use std::sync::Arc;

/// One of the app's textures or renderbuffers (separate name spaces).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct AppImage {
    pub name: u32,
    pub renderbuffer: bool,
}

impl AppImage {
    pub fn texture(name: u32) -> AppImage {
        AppImage {
            name,
            renderbuffer: false,
        }
    }
}

/// The storage of an object's level 0 (`format` sized, as GL chose it): an image is kept
/// while it stays the same.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Storage {
    pub format: GLenum,
    pub width: i32,
    pub height: i32,
    pub samples: i32,
}

pub struct LayeredImage {
    pub app: AppImage,
    pub storage: Storage,
    /// Which buffers it holds (colour, or depth and/or stencil), for the copies.
    pub buffers: GLbitfield,
    pub array: u32,
    /// Each layer's size, and the factors from the app's object to it.
    pub size: (i32, i32),
    pub scale: LayerScale,
    /// A blit may filter it linearly: colour that is not integer (scaled copies, mipmaps).
    pub filterable: bool,
    /// Per-layer `GL_TEXTURE_2D` views for sampling (single-sample textures only); shared
    /// with the draws that substitute them, without copying.
    pub layer_views: Arc<[u32]>,
}

/// The storage of `app` now, its format sized as GL chose it (`gl::format`; immutable
/// storage needs a sized one, and a guess can differ from the app's). GL_TEXTURE_TARGET is
/// not queryable on every driver (Mesa 22.3 raises an error), so a texture's target comes
/// from the app's own binds (`target`).
pub fn storage(gl: &Gl, app: AppImage, target: GLenum) -> Result<Storage, String> {
    let name = app.name;
    let mut v = [0i32; 4];
    // SAFETY: existence checks, then single-integer queries on the app's object names.
    let components = unsafe {
        if app.renderbuffer {
            if gl.IsRenderbuffer(name) == 0 {
                return Err(format!("renderbuffer {name} does not exist"));
            }
            let pnames = [
                RENDERBUFFER_INTERNAL_FORMAT,
                RENDERBUFFER_WIDTH,
                RENDERBUFFER_HEIGHT,
                RENDERBUFFER_SAMPLES,
            ];
            for (v, p) in v.iter_mut().zip(pnames) {
                gl.GetNamedRenderbufferParameteriv(name, p, v);
            }
            format::renderbuffer_components(gl, name)
        } else {
            if target != TEXTURE_2D && target != TEXTURE_2D_MULTISAMPLE {
                return Err(format!("texture {name}: target {target:#x} is not shadowed (2D only)"));
            }
            if gl.IsTexture(name) == 0 {
                return Err(format!("texture {name} does not exist"));
            }
            let pnames = [TEXTURE_INTERNAL_FORMAT, TEXTURE_WIDTH, TEXTURE_HEIGHT, TEXTURE_SAMPLES];
            for (v, p) in v.iter_mut().zip(pnames) {
                gl.GetTextureLevelParameteriv(name, 0, p, v);
            }
            format::texture_components(gl, name)
        }
    };
    Ok(Storage {
        format: format::sized(v[0] as GLenum, components)?,
        width: v[1],
        height: v[2],
        samples: v[3],
    })
}

/// Mip levels the layers need: the app's, or the full chain when a mipmapping filter on a
/// single level says glGenerateMipmap comes later (immutable storage cannot grow).
fn levels(gl: &Gl, app: AppImage, s: Storage, (w, h): (i32, i32)) -> i32 {
    if app.renderbuffer || s.samples > 0 {
        return 1;
    }
    let (mut levels, mut filter) = (1, 0);
    // SAFETY: single-integer queries on the app's texture.
    unsafe {
        while levels < 16 {
            let mut w = 0;
            gl.GetTextureLevelParameteriv(app.name, levels, TEXTURE_WIDTH, &mut w);
            if w == 0 {
                break;
            }
            levels += 1;
        }
        gl.GetTextureParameteriv(app.name, TEXTURE_MIN_FILTER, &mut filter);
    }
    // A scaled layer has a shorter chain than the app's object.
    let chain = 32 - (w.max(h).max(1) as u32).leading_zeros() as i32;
    if matches!(filter as GLenum, NEAREST | LINEAR) {
        levels.min(chain)
    } else {
        chain
    }
}

/// Depth and stencil copies between the app's object and our array are blits, which need
/// the same depth and stencil bits at both ends (colour blits convert). The array has the
/// app's sized format, so they match; should a driver store the two differently anyway, the
/// framebuffer stays single-view instead of every copy being an error.
fn same_depth_stencil(gl: &Gl, app: AppImage, array: u32, buffers: GLbitfield) -> Result<(), String> {
    if buffers == COLOR_BUFFER_BIT {
        return Ok(());
    }
    let theirs = if app.renderbuffer {
        format::renderbuffer_components(gl, app.name)
    } else {
        format::texture_components(gl, app.name)
    };
    let [theirs, ours] = [theirs, format::texture_components(gl, array)].map(format::depth_stencil);
    if theirs != ours {
        return Err(format!(
            "{app:?}: layers stored with (depth bits, float, stencil bits) {ours:?}, the app's object {theirs:?}"
        ));
    }
    Ok(())
}

/// The framebuffer attachment point for an image holding `buffers`.
fn point(buffers: GLbitfield) -> GLenum {
    match buffers {
        COLOR_BUFFER_BIT => COLOR_ATTACHMENT0,
        DEPTH_BUFFER_BIT => DEPTH_ATTACHMENT,
        STENCIL_BUFFER_BIT => STENCIL_ATTACHMENT,
        _ => DEPTH_STENCIL_ATTACHMENT,
    }
}

/// The buffers an attachment at `point` holds.
pub fn buffers_at(point: GLenum) -> GLbitfield {
    match point {
        DEPTH_ATTACHMENT => DEPTH_BUFFER_BIT,
        STENCIL_ATTACHMENT => STENCIL_BUFFER_BIT,
        DEPTH_STENCIL_ATTACHMENT => DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT,
        _ => COLOR_BUFFER_BIT,
    }
}

impl LayeredImage {
    /// A new image of `n` layers for `app`, attached at `point`, each layer a copy of the
    /// app's content.
    pub fn create(
        gl: &Gl,
        info: GlInfo,
        app: AppImage,
        (s, scale): (Storage, LayerScale),
        point: GLenum,
        n: u32,
    ) -> Result<Self, String> {
        let format = s.format;
        let (w, h) = scale.size((s.width, s.height));
        let levels = levels(gl, app, s, (w, h));
        let mut array = 0;
        // SAFETY: creating our own immutable array.
        unsafe {
            if s.samples > 0 {
                gl.CreateTextures(TEXTURE_2D_MULTISAMPLE_ARRAY, 1, &mut array);
                gl.TextureStorage3DMultisample(array, s.samples, format, w, h, n as i32, TRUE);
            } else {
                gl.CreateTextures(TEXTURE_2D_ARRAY, 1, &mut array);
                gl.TextureStorage3D(array, levels, format, w, h, n as i32);
            }
        }
        if let Err(e) = same_depth_stencil(gl, app, array, buffers_at(point)) {
            // SAFETY: our own array, not yet shared with anything.
            unsafe { gl.DeleteTextures(1, &array) };
            return Err(e);
        }
        let layer_views = if app.renderbuffer || s.samples > 0 {
            Arc::from([])
        } else {
            Arc::from(super::sampling::layer_views(gl, app.name, array, format, levels, n))
        };
        let buffers = buffers_at(point);
        let image = LayeredImage {
            app,
            storage: s,
            buffers,
            array,
            size: (w, h),
            scale,
            filterable: filterable(gl, array, buffers),
            layer_views,
        };
        image.copy(gl, info, Direction::FromApp, 0..n);
        Ok(image)
    }

    /// The reverse of the filling at creation for one layer: the app's object gets view
    /// `layer`'s content (when the layer gives up mid-frame).
    pub fn copy_back(&self, gl: &Gl, info: GlInfo, layer: u32) {
        self.copy(gl, info, Direction::ToApp, layer..layer + 1);
    }

    /// Blits between the app's object and `layers` through two framebuffers of our own, so
    /// that neither the app's framebuffers (their completeness, buffer selections) nor its
    /// bindings are involved. Blits obey the scissor test and sRGB encoding: both are off
    /// meanwhile. A scaled image's copies scale (a multisampled one cannot be blitted at
    /// another size: it is not scaled, see `layers`).
    fn copy(&self, gl: &Gl, info: GlInfo, direction: Direction, layers: std::ops::Range<u32>) {
        let _guard = crate::gl::guard::StateGuard::new(gl, info).caps(&[SCISSOR_TEST, FRAMEBUFFER_SRGB]);
        let point = point(self.buffers);
        let (w, h) = (self.storage.width, self.storage.height);
        let (lw, lh) = self.size;
        let mut fbos = [0u32; 2];
        // SAFETY: our own framebuffers, named (no binding changes), deleted at the end; the
        // app's object is only attached to them.
        unsafe {
            gl.Disable(SCISSOR_TEST);
            gl.Disable(FRAMEBUFFER_SRGB);
            gl.CreateFramebuffers(2, fbos.as_mut_ptr());
            let [app_fbo, layer_fbo] = fbos;
            if self.app.renderbuffer {
                gl.NamedFramebufferRenderbuffer(app_fbo, point, RENDERBUFFER, self.app.name);
            } else {
                gl.NamedFramebufferTexture(app_fbo, point, self.app.name, 0);
            }
            let (src, dst, from, to) = match direction {
                Direction::FromApp => (app_fbo, layer_fbo, (w, h), (lw, lh)),
                Direction::ToApp => (layer_fbo, app_fbo, (lw, lh), (w, h)),
            };
            for layer in layers {
                gl.NamedFramebufferTextureLayer(layer_fbo, point, self.array, 0, layer as i32);
                gl.BlitNamedFramebuffer(
                    src,
                    dst,
                    0,
                    0,
                    from.0,
                    from.1,
                    0,
                    0,
                    to.0,
                    to.1,
                    self.buffers,
                    self.copy_filter(),
                );
            }
            gl.DeleteFramebuffers(2, fbos.as_ptr());
        }
    }

    /// The filter of the copies between the app's object and the layers: linear for scaled
    /// colour that may be filtered, else NEAREST.
    fn copy_filter(&self) -> GLenum {
        if self.scale.is_one() || !self.filterable {
            NEAREST
        } else {
            LINEAR
        }
    }

    /// Our texture names: the array and the layer views.
    pub fn textures(&self) -> impl Iterator<Item = u32> + '_ {
        std::iter::once(self.array).chain(self.layer_views.iter().copied())
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting only objects this image created.
        unsafe {
            gl.DeleteTextures(self.layer_views.len() as i32, self.layer_views.as_ptr());
            gl.DeleteTextures(1, &self.array);
        }
    }
}

/// A blit may filter `array` linearly: colour that is not integer (only NEAREST may blit
/// integers, depth and stencil). Asked once, when the layers are made.
fn filterable(gl: &Gl, array: u32, buffers: GLbitfield) -> bool {
    buffers == COLOR_BUFFER_BIT && !matches!(format::texture_components(gl, array).color_type, INT | UNSIGNED_INT)
}

#[derive(Clone, Copy)]
enum Direction {
    FromApp,
    ToApp,
}
