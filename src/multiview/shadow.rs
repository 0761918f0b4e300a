//! Layered shadows of the app's framebuffer objects.
//!
//! Multi-pass renderers draw the scene into their own framebuffers (post-processing,
//! G-buffers, HDR) and only then to framebuffer 0. For those passes to differ per view, each
//! such framebuffer gets a shadow: every attachment becomes an N-layer array texture (layer
//! i = view i), plus one framebuffer per view with layer i attached in the app's attachment
//! points and draw buffers. A draw into the app's framebuffer is replayed once per view into
//! the view's framebuffer; a texture sampled during view i's replay is replaced by a texture
//! view of layer i (created once, never per draw). The app keeps its own names and answers:
//! its attachments just stop being written while the shadow lives.
//!
//! Built with GL 4.5 direct state access and texture views (4.3): no binding of ours is ever
//! visible to the app. Older contexts keep the centre view in off-screen passes.

use crate::gl::GlInfo;
use crate::gl::*;
use std::sync::Arc;

pub struct ShadowAttachment {
    pub point: GLenum,
    /// The app's texture or renderbuffer.
    pub app_name: u32,
    pub renderbuffer: bool,
    pub array: u32,
    /// Per-layer `GL_TEXTURE_2D` views for sampling (single-sample textures only); shared
    /// with the draws that substitute them, without copying.
    pub layer_views: Arc<[u32]>,
}

pub struct ShadowFbo {
    /// One framebuffer per view (layer i of every attachment), shared with the replays.
    pub views: Arc<[u32]>,
    pub attachments: Vec<ShadowAttachment>,
    pub size: (i32, i32),
}

/// Shadowing needs direct state access, texture views and image copies.
pub fn supported(gl: &Gl, info: GlInfo) -> bool {
    !info.es && info.at_least(4, 5) && gl.TextureView.is_loaded() && gl.CopyImageSubData.is_loaded()
}

const POINTS: [GLenum; 10] = [
    COLOR_ATTACHMENT0,
    COLOR_ATTACHMENT1,
    COLOR_ATTACHMENT2,
    COLOR_ATTACHMENT3,
    COLOR_ATTACHMENT4,
    COLOR_ATTACHMENT5,
    COLOR_ATTACHMENT6,
    COLOR_ATTACHMENT7,
    DEPTH_ATTACHMENT,
    STENCIL_ATTACHMENT,
];

fn attachment_iv(gl: &Gl, fbo: u32, point: GLenum, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: a single-integer query on a framebuffer name.
    unsafe { gl.GetNamedFramebufferAttachmentParameteriv(fbo, point, pname, &mut v) };
    v
}

/// What is attached where: (point, name, is renderbuffer). A texture or renderbuffer in both
/// depth and stencil points becomes one depth-stencil attachment.
fn attachments(gl: &Gl, fbo: u32) -> Result<Vec<(GLenum, u32, bool)>, String> {
    let mut found: Vec<(GLenum, u32, bool)> = Vec::new();
    for point in POINTS {
        let ty = attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum;
        if ty == NONE {
            continue;
        }
        let name = attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_OBJECT_NAME) as u32;
        if ty == TEXTURE && attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL) != 0 {
            return Err(format!("framebuffer {fbo}: attachment {point:#x} is not mip level 0"));
        }
        match found
            .iter_mut()
            .find(|(p, n, _)| *p == DEPTH_ATTACHMENT && *n == name && point == STENCIL_ATTACHMENT)
        {
            Some(depth) => depth.0 = DEPTH_STENCIL_ATTACHMENT,
            None => found.push((point, name, ty == RENDERBUFFER)),
        }
    }
    Ok(found)
}

/// (internal format, width, height, samples, levels) of an attachment; only 2D textures
/// (single- or multi-sample) and renderbuffers are shadowed.
fn describe(gl: &Gl, name: u32, renderbuffer: bool, target: GLenum) -> Result<(GLenum, i32, i32, i32, i32), String> {
    let mut v = [0i32; 4];
    // SAFETY: single-integer queries on the app's object names.
    unsafe {
        if renderbuffer {
            for (i, p) in [
                RENDERBUFFER_INTERNAL_FORMAT,
                RENDERBUFFER_WIDTH,
                RENDERBUFFER_HEIGHT,
                RENDERBUFFER_SAMPLES,
            ]
            .into_iter()
            .enumerate()
            {
                gl.GetNamedRenderbufferParameteriv(name, p, &mut v[i]);
            }
            return Ok((v[0] as GLenum, v[1], v[2], v[3], 1));
        }
        // GL_TEXTURE_TARGET is not queryable on every driver (Mesa 22.3 raises an error), so
        // the target comes from the app's own binds, tracked by the layer.
        if target != TEXTURE_2D && target != TEXTURE_2D_MULTISAMPLE {
            return Err(format!("texture {name}: target {target:#x} is not shadowed (2D only)"));
        }
        for (i, p) in [TEXTURE_INTERNAL_FORMAT, TEXTURE_WIDTH, TEXTURE_HEIGHT, TEXTURE_SAMPLES]
            .into_iter()
            .enumerate()
        {
            gl.GetTextureLevelParameteriv(name, 0, p, &mut v[i]);
        }
        let mut levels = 1;
        while levels < 16 {
            let mut w = 0;
            gl.GetTextureLevelParameteriv(name, levels, TEXTURE_WIDTH, &mut w);
            if w == 0 {
                break;
            }
            levels += 1;
        }
        Ok((v[0] as GLenum, v[1], v[2], v[3], levels))
    }
}

/// Immutable storage needs a sized format; `glTexImage2D` keeps the unsized one it was given.
fn sized(format: GLenum) -> Result<GLenum, String> {
    Ok(match format {
        RGBA => RGBA8,
        RGB => RGB8,
        RG => RG8,
        RED => R8,
        DEPTH_COMPONENT => DEPTH_COMPONENT24,
        DEPTH_STENCIL => DEPTH24_STENCIL8,
        ALPHA | LUMINANCE | LUMINANCE_ALPHA | INTENSITY => {
            return Err(format!("format {format:#x} has no sized equivalent"));
        }
        sized => sized,
    })
}

fn mipmapped(gl: &Gl, name: u32) -> bool {
    let mut filter = 0;
    // SAFETY: a single-integer texture parameter query.
    unsafe { gl.GetTextureParameteriv(name, TEXTURE_MIN_FILTER, &mut filter) };
    !matches!(filter as GLenum, NEAREST | LINEAR)
}

const SAMPLER_PARAMS: [GLenum; 6] = [
    TEXTURE_MIN_FILTER,
    TEXTURE_MAG_FILTER,
    TEXTURE_WRAP_S,
    TEXTURE_WRAP_T,
    TEXTURE_COMPARE_MODE,
    TEXTURE_COMPARE_FUNC,
];

/// One layer view per view, sampling like the app's texture does.
fn layer_views(gl: &Gl, app: u32, array: u32, format: GLenum, levels: i32, n: u32) -> Vec<u32> {
    (0..n)
        .map(|layer| {
            let mut view = 0;
            // SAFETY: a new view of our own immutable array; parameters copied from the app's.
            unsafe {
                gl.GenTextures(1, &mut view);
                gl.TextureView(view, TEXTURE_2D, array, format, 0, levels as u32, layer, 1);
                for p in SAMPLER_PARAMS {
                    let mut v = 0;
                    gl.GetTextureParameteriv(app, p, &mut v);
                    gl.TextureParameteri(view, p, v);
                }
            }
            view
        })
        .collect()
}

fn shadow_attachment(
    gl: &Gl,
    point: GLenum,
    name: u32,
    renderbuffer: bool,
    target: GLenum,
    n: u32,
) -> Result<(ShadowAttachment, (i32, i32)), String> {
    let (format, w, h, samples, levels) = describe(gl, name, renderbuffer, target)?;
    // A mipmapping filter on a single level means glGenerateMipmap comes later: the layers
    // get the full chain now (immutable storage cannot grow).
    let levels = if renderbuffer || samples > 0 || !mipmapped(gl, name) {
        levels
    } else {
        levels.max(32 - (w.max(h).max(1) as u32).leading_zeros() as i32)
    };
    let format = sized(format)?;
    let mut array = 0;
    let multisample = samples > 0;
    // SAFETY: creating our own immutable array (filled from the app's content once the view
    // framebuffers exist, see `fill_from_app`).
    unsafe {
        if multisample {
            gl.CreateTextures(TEXTURE_2D_MULTISAMPLE_ARRAY, 1, &mut array);
            gl.TextureStorage3DMultisample(array, samples, format, w, h, n as i32, TRUE);
        } else {
            gl.CreateTextures(TEXTURE_2D_ARRAY, 1, &mut array);
            gl.TextureStorage3D(array, levels, format, w, h, n as i32);
        }
    }
    let views = if renderbuffer || multisample {
        Arc::from([])
    } else {
        Arc::from(layer_views(gl, name, array, format, levels, n))
    };
    Ok((
        ShadowAttachment {
            point,
            app_name: name,
            renderbuffer,
            array,
            layer_views: views,
        },
        (w, h),
    ))
}

/// The app framebuffer's draw buffers and read buffer, to give every view framebuffer the
/// same. They are only queryable on the bound framebuffer, so it is bound briefly.
fn buffers(gl: &Gl, info: GlInfo, fbo: u32) -> (Vec<GLenum>, GLenum) {
    let _guard = crate::gl::guard::StateGuard::new(gl, info).framebuffers();
    // SAFETY: binding the app's own framebuffer for the queries; the guard restores bindings.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo);
        gl.BindFramebuffer(READ_FRAMEBUFFER, fbo);
    }
    let draw = (0..8)
        .map(|i| crate::gl::guard::get_i(gl, DRAW_BUFFER0 + i) as GLenum)
        .collect();
    (draw, crate::gl::guard::get_i(gl, READ_BUFFER) as GLenum)
}

impl ShadowFbo {
    /// `target_of`: the texture target the app bound each texture name to (0 if unknown).
    pub fn create(
        gl: &Gl,
        info: GlInfo,
        fbo: u32,
        n: u32,
        target_of: impl Fn(u32) -> GLenum,
    ) -> Result<ShadowFbo, String> {
        let mut shadow = ShadowFbo {
            views: Arc::from([]),
            attachments: Vec::new(),
            size: (0, 0),
        };
        for (point, name, rb) in attachments(gl, fbo)? {
            let target = if rb { RENDERBUFFER } else { target_of(name) };
            match shadow_attachment(gl, point, name, rb, target, n) {
                Ok((a, size)) => {
                    shadow.size = size;
                    shadow.attachments.push(a);
                }
                Err(e) => {
                    shadow.delete(gl);
                    return Err(e);
                }
            }
        }
        if shadow.attachments.is_empty() {
            return Err(format!("framebuffer {fbo} has no attachments"));
        }
        let (buffers, read) = self::buffers(gl, info, fbo);
        // SAFETY: our own framebuffers, one per view, with layer i of each array attached.
        unsafe {
            let mut views = vec![0; n as usize];
            gl.CreateFramebuffers(n as i32, views.as_mut_ptr());
            shadow.views = Arc::from(views);
            for (i, &view) in shadow.views.iter().enumerate() {
                for a in &shadow.attachments {
                    gl.NamedFramebufferTextureLayer(view, a.point, a.array, 0, i as i32);
                }
                gl.NamedFramebufferDrawBuffers(view, buffers.len() as i32, buffers.as_ptr());
                gl.NamedFramebufferReadBuffer(view, read as GLenum);
            }
            let status = gl.CheckNamedFramebufferStatus(shadow.views[0], DRAW_FRAMEBUFFER);
            if status != FRAMEBUFFER_COMPLETE {
                shadow.delete(gl);
                return Err(format!("shadow of framebuffer {fbo} incomplete ({status:#x})"));
            }
        }
        shadow.fill_from_app(gl, fbo, &buffers, read as GLenum);
        Ok(shadow)
    }

    /// Every layer starts as a copy of what the app's framebuffer holds now: a shadow made
    /// mid-frame, or of a target rendered once (a precomputed map), must not start empty.
    /// Blits work for every attachment kind and completeness state, unlike image copies;
    /// colour attachments go one at a time through the read/draw buffer selection, which is
    /// put back afterwards (on the app's framebuffer too).
    fn fill_from_app(&self, gl: &Gl, fbo: u32, draw_buffers: &[GLenum], read: GLenum) {
        let (w, h) = self.size;
        let colors: Vec<GLenum> = self
            .attachments
            .iter()
            .map(|a| a.point)
            .filter(|p| (COLOR_ATTACHMENT0..=COLOR_ATTACHMENT7).contains(p))
            .collect();
        let depth_stencil = self.attachments.iter().fold(0, |bits, a| match a.point {
            DEPTH_ATTACHMENT => bits | DEPTH_BUFFER_BIT,
            STENCIL_ATTACHMENT => bits | STENCIL_BUFFER_BIT,
            DEPTH_STENCIL_ATTACHMENT => bits | DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT,
            _ => bits,
        });
        // SAFETY: a capability query, valid in every context.
        let scissored = unsafe { gl.IsEnabled(SCISSOR_TEST) } != 0;
        // SAFETY: named blits between the app's framebuffer and ours (blits obey the scissor
        // test, so it is off meanwhile); selections and the scissor test restored.
        unsafe {
            gl.Disable(SCISSOR_TEST);
            for &view in self.views.iter() {
                for &p in &colors {
                    gl.NamedFramebufferReadBuffer(fbo, p);
                    gl.NamedFramebufferDrawBuffer(view, p);
                    gl.BlitNamedFramebuffer(fbo, view, 0, 0, w, h, 0, 0, w, h, COLOR_BUFFER_BIT, NEAREST);
                }
                if depth_stencil != 0 {
                    gl.BlitNamedFramebuffer(fbo, view, 0, 0, w, h, 0, 0, w, h, depth_stencil, NEAREST);
                }
                gl.NamedFramebufferDrawBuffers(view, draw_buffers.len() as i32, draw_buffers.as_ptr());
            }
            gl.NamedFramebufferReadBuffer(fbo, read);
            if scissored {
                gl.Enable(SCISSOR_TEST);
            }
        }
    }

    /// The reverse of `fill_from_app` for one layer: the app's own attachments get view
    /// `layer`'s content (when the layer gives up mid-frame). Same care with selections and
    /// the scissor test; the caller has the scissor test off.
    pub fn copy_back(&self, gl: &Gl, info: GlInfo, fbo: u32, layer: usize) {
        let Some(&view) = self.views.get(layer.min(self.views.len().saturating_sub(1))) else {
            return;
        };
        let (w, h) = self.size;
        let (draw, read) = buffers(gl, info, fbo);
        // SAFETY: named blits and selections on the app's framebuffer and our view
        // framebuffer; the app's selections were read above and are put back.
        unsafe {
            let mut ds = 0;
            for a in &self.attachments {
                match a.point {
                    p @ COLOR_ATTACHMENT0..=COLOR_ATTACHMENT7 => {
                        gl.NamedFramebufferReadBuffer(view, p);
                        gl.NamedFramebufferDrawBuffer(fbo, p);
                        gl.BlitNamedFramebuffer(view, fbo, 0, 0, w, h, 0, 0, w, h, COLOR_BUFFER_BIT, NEAREST);
                    }
                    DEPTH_ATTACHMENT => ds |= DEPTH_BUFFER_BIT,
                    STENCIL_ATTACHMENT => ds |= STENCIL_BUFFER_BIT,
                    DEPTH_STENCIL_ATTACHMENT => ds |= DEPTH_BUFFER_BIT | STENCIL_BUFFER_BIT,
                    _ => {}
                }
            }
            if ds != 0 {
                gl.BlitNamedFramebuffer(view, fbo, 0, 0, w, h, 0, 0, w, h, ds, NEAREST);
            }
            gl.NamedFramebufferDrawBuffers(fbo, draw.len() as i32, draw.as_ptr());
            gl.NamedFramebufferReadBuffer(fbo, read as GLenum);
        }
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting only objects this shadow created.
        unsafe {
            gl.DeleteFramebuffers(self.views.len() as i32, self.views.as_ptr());
            for a in &self.attachments {
                gl.DeleteTextures(a.layer_views.len() as i32, a.layer_views.as_ptr());
                gl.DeleteTextures(1, &a.array);
            }
        }
    }

    /// Does this shadow stand in for texture `name` (for sampling)?
    pub fn layer_views_of(&self, name: u32) -> Option<&Arc<[u32]>> {
        self.attachments
            .iter()
            .find(|a| !a.renderbuffer && a.app_name == name && !a.layer_views.is_empty())
            .map(|a| &a.layer_views)
    }

    /// What is attached at `point` (depth and stencil both match a depth-stencil attachment).
    pub fn attached(&self, point: GLenum) -> Option<(u32, bool)> {
        let depth_or_stencil = point == DEPTH_ATTACHMENT || point == STENCIL_ATTACHMENT;
        self.attachments
            .iter()
            .find(|a| a.point == point || a.point == DEPTH_STENCIL_ATTACHMENT && depth_or_stencil)
            .map(|a| (a.app_name, a.renderbuffer))
    }

    pub fn owns(&self, name: u32, renderbuffer: bool) -> bool {
        self.attachments
            .iter()
            .any(|a| a.app_name == name && a.renderbuffer == renderbuffer)
    }

    /// Mipmaps of every layer, when the app regenerates its texture's.
    pub fn generate_mipmaps(&self, gl: &Gl, name: u32) {
        for a in self
            .attachments
            .iter()
            .filter(|a| a.app_name == name && !a.renderbuffer)
        {
            // SAFETY: our own array texture.
            unsafe { gl.GenerateTextureMipmap(a.array) };
        }
    }
}

/// Colour attachments of framebuffer `fbo` exist (a depth-only target is a shadow map: drawn
/// from a light, the same for every view).
pub fn has_color_attachment(gl: &Gl, fbo: u32) -> bool {
    POINTS[..8]
        .iter()
        .any(|&p| attachment_iv(gl, fbo, p, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum != NONE)
}
