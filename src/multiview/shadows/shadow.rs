//! Layered shadows of the app's framebuffer objects.
//!
//! Multi-pass renderers draw the scene into their own framebuffers (post-processing,
//! G-buffers, HDR) and only then to framebuffer 0. For those passes to differ per view, each
//! such framebuffer gets a shadow: one framebuffer per view, with layer i of each attached
//! object's layered image (`layered`) in the app's attachment points and draw buffers. A draw
//! into the app's framebuffer is replayed once per view into the view's framebuffer; a
//! texture sampled during view i's replay is replaced by a texture view of layer i (created
//! once, never per draw). The app keeps its own names and answers: its attachments just stop
//! being written while their images live.
//!
//! The images belong to the app's objects, not to the shadow: when the app attaches other
//! objects (or detaches them after a pass, as VTK does), the shadow is marked stale and its
//! view framebuffers are pointed at the new set before the next use, while every image keeps
//! what the frame has drawn into it.
//!
//! Built with GL 4.5 direct state access and texture views (4.3): no binding of ours is ever
//! visible to the app. Older contexts keep the centre view in off-screen passes.

use super::layered::AppImage;
use super::scale::LayerScale;
use crate::gl::GlInfo;
use crate::gl::*;
use std::collections::HashMap;
use std::sync::Arc;

/// An image attached to the view framebuffers: the app's object and our array.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Attached {
    pub point: GLenum,
    pub app: AppImage,
    pub array: u32,
}

pub struct ShadowFbo {
    /// One framebuffer per view (layer i of every attached image), shared with the replays.
    pub views: Arc<[u32]>,
    pub attached: Vec<Attached>,
    /// The layers' size (the smallest attached), and the factors from the app's pixels to
    /// theirs (`scale`), the same for every attached image.
    pub size: (i32, i32),
    pub scale: LayerScale,
    /// The app changed an attachment since `attached` was set: rebuilt before the next use.
    pub stale: bool,
    /// The app's last blit of it to the window turned it upside down (wined3d draws with
    /// `gl_Position.y` negated and flips at Present): what reads its depth or disparity
    /// record alongside the window's colour reads them flipped (`scene_rect`).
    pub presented_flipped: bool,
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

pub fn is_color(point: GLenum) -> bool {
    (COLOR_ATTACHMENT0..=COLOR_ATTACHMENT7).contains(&point)
}

fn attachment_iv(gl: &Gl, fbo: u32, point: GLenum, pname: GLenum) -> i32 {
    let mut v = 0;
    // SAFETY: a single-integer query on a framebuffer name.
    unsafe { gl.GetNamedFramebufferAttachmentParameteriv(fbo, point, pname, &mut v) };
    v
}

/// An attachment of the app's framebuffer as GL reports it: (point, object, mip level).
pub type Found = (GLenum, AppImage, i32);

/// What the app's framebuffer has attached where. An object in both the depth and the
/// stencil point is one depth-stencil attachment.
pub fn attachments(gl: &Gl, fbo: u32) -> Vec<Found> {
    let mut found: Vec<Found> = Vec::new();
    for point in POINTS {
        let ty = attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE) as GLenum;
        if ty == NONE {
            continue;
        }
        let app = AppImage {
            name: attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_OBJECT_NAME) as u32,
            renderbuffer: ty == RENDERBUFFER,
        };
        let level = match ty {
            TEXTURE => attachment_iv(gl, fbo, point, FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL),
            _ => 0,
        };
        match found
            .iter_mut()
            .find(|(p, a, _)| *p == DEPTH_ATTACHMENT && *a == app && point == STENCIL_ATTACHMENT)
        {
            Some(depth) => depth.0 = DEPTH_STENCIL_ATTACHMENT,
            None => found.push((point, app, level)),
        }
    }
    found
}

/// What `attachments` lists at `point` (depth and stencil both match a depth-stencil
/// attachment): the object and its mip level.
pub fn attached_at(found: &[Found], point: GLenum) -> Option<(AppImage, i32)> {
    found
        .iter()
        .find(|(p, _, _)| *p == point || *p == DEPTH_STENCIL_ATTACHMENT && is_depth_or_stencil(point))
        .map(|&(_, app, level)| (app, level))
}

fn is_depth_or_stencil(point: GLenum) -> bool {
    point == DEPTH_ATTACHMENT || point == STENCIL_ATTACHMENT
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

/// Detaches `point` (both depth and stencil for a depth-stencil attachment) from `view`.
fn detach(gl: &Gl, view: u32, point: GLenum) {
    // SAFETY: our own view framebuffer, named.
    unsafe { gl.NamedFramebufferTexture(view, point, 0, 0) };
}

impl ShadowFbo {
    /// `n` view framebuffers, nothing attached yet (see `attach`).
    pub fn new(gl: &Gl, n: u32) -> ShadowFbo {
        let mut views = vec![0; n as usize];
        // SAFETY: creating our own framebuffers.
        unsafe { gl.CreateFramebuffers(n as i32, views.as_mut_ptr()) };
        ShadowFbo {
            views: Arc::from(views),
            attached: Vec::new(),
            size: (0, 0),
            scale: LayerScale::ONE,
            stale: true,
            presented_flipped: false,
        }
    }

    /// Its layers' rectangle in the window's orientation: bottom-up, negative height, when
    /// the app presents it flipped (a blit with these corners turns it the window's way).
    pub fn scene_rect(&self) -> [i32; 4] {
        let (w, h) = self.size;
        if self.presented_flipped {
            [0, h, w, -h]
        } else {
            [0, 0, w, h]
        }
    }

    /// Points the view framebuffers at `wanted` (layer i in view i), touching only what
    /// changed, with the draw and read buffers of the app's `fbo`.
    pub fn attach(
        &mut self,
        gl: &Gl,
        info: GlInfo,
        fbo: u32,
        wanted: Vec<Attached>,
        (size, scale): ((i32, i32), LayerScale),
    ) -> Result<(), String> {
        let gone: Vec<GLenum> = self
            .attached
            .iter()
            .filter(|a| !wanted.contains(a))
            .map(|a| a.point)
            .collect();
        let new: Vec<Attached> = wanted.iter().filter(|a| !self.attached.contains(a)).copied().collect();
        let (draw, read) = buffers(gl, info, fbo);
        // SAFETY: our own view framebuffers and arrays, named.
        unsafe {
            for (i, &view) in self.views.iter().enumerate() {
                gone.iter().for_each(|&p| detach(gl, view, p));
                for a in &new {
                    gl.NamedFramebufferTextureLayer(view, a.point, a.array, 0, i as i32);
                }
                gl.NamedFramebufferDrawBuffers(view, draw.len() as i32, draw.as_ptr());
                gl.NamedFramebufferReadBuffer(view, read);
            }
        }
        self.attached = wanted;
        self.size = size;
        self.scale = scale;
        self.stale = false;
        // SAFETY: a status query on our own framebuffer.
        let status = unsafe { gl.CheckNamedFramebufferStatus(self.views[0], DRAW_FRAMEBUFFER) };
        if status != FRAMEBUFFER_COMPLETE {
            return Err(format!("shadow of framebuffer {fbo} incomplete ({status:#x})"));
        }
        Ok(())
    }

    /// Our array `array` is going away: detached now (the shadow is rebuilt before its next
    /// use), so that the view framebuffers do not keep its storage alive.
    pub fn forget_array(&mut self, gl: &Gl, array: u32) {
        let points: Vec<GLenum> = self
            .attached
            .iter()
            .filter(|a| a.array == array)
            .map(|a| a.point)
            .collect();
        for &view in self.views.iter() {
            points.iter().for_each(|&p| detach(gl, view, p));
        }
        if !points.is_empty() {
            self.attached.retain(|a| a.array != array);
            self.stale = true;
        }
    }

    pub fn delete(&self, gl: &Gl) {
        // SAFETY: deleting only the framebuffers this shadow created (the images are not
        // its own).
        unsafe { gl.DeleteFramebuffers(self.views.len() as i32, self.views.as_ptr()) };
    }

    /// What the shadow has attached at `point` (depth and stencil both match a depth-stencil
    /// attachment).
    pub fn attached_at(&self, point: GLenum) -> Option<AppImage> {
        self.attached
            .iter()
            .find(|a| a.point == point || a.point == DEPTH_STENCIL_ATTACHMENT && is_depth_or_stencil(point))
            .map(|a| a.app)
    }
}

/// What the layer knows of one of the app's framebuffers, asked of GL once per attachment
/// change, not per draw (shadow-map passes draw a lot).
pub struct FboFacts {
    pub has_color: bool,
    pub objects: Vec<AppImage>,
}

pub fn facts<'a>(gl: &Gl, all: &'a mut HashMap<u32, FboFacts>, fbo: u32) -> &'a FboFacts {
    all.entry(fbo).or_insert_with(|| {
        let found = attachments(gl, fbo);
        FboFacts {
            has_color: found.iter().any(|(p, _, _)| is_color(*p)),
            objects: found.iter().map(|(_, a, _)| *a).collect(),
        }
    })
}
