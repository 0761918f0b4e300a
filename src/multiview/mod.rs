//! Per-view replay.
//!
//! The app's default framebuffer is replaced by a quilt ([`target::QuiltTarget`]): whenever
//! the app binds framebuffer 0 we bind the quilt instead, and every draw issued while it is
//! bound is replayed once per view, with the viewport and scissor mapped into that view's
//! tile and the injected `holoinject_view` uniform (or, for fixed-function draws, the
//! projection matrix) set to that view's shift. The app keeps seeing its own state: its
//! viewport and scissor stay in GL between draws, `glGet*` answers report framebuffer 0 and
//! its draw/read buffers, and `glReadPixels` from framebuffer 0 reads the centre view.
//!
//! Draws into the app's own framebuffers are drawn once, as the centre view (multi-pass
//! renderers get layered shadows in a later issue).

pub mod framebuffer;
pub mod immediate;
pub mod layers;
pub mod layout;
pub mod link;
pub mod raster;
pub mod replay;
pub mod screen_space;
pub mod shadow;
pub mod target;
pub mod ubo;

use crate::camera::ViewRig;
use crate::config::{Convergence, ViewSettings};
use crate::gl::GLenum;
use crate::gl::guard::get_i4;
use crate::state::{Current, GlInfo};
use layout::QuiltLayout;
use target::QuiltTarget;

/// The app's view of its default-framebuffer-related state.
#[derive(Clone, Copy, Debug)]
pub struct AppFramebuffer {
    pub draw_fbo: u32,
    pub read_fbo: u32,
    pub viewport: [i32; 4],
    pub scissor: [i32; 4],
    /// The app's `glDrawBuffer`/`glReadBuffer` choice for framebuffer 0 (e.g. GL_BACK).
    pub draw_buffer: GLenum,
    pub read_buffer: GLenum,
}

pub struct Multiview {
    pub info: GlInfo,
    pub settings: ViewSettings,
    pub target: Option<QuiltTarget>,
    pub app: AppFramebuffer,
    pub rig: ViewRig,
    pub program: u32,
    /// Smoothed auto-convergence estimate (w units), once the scene has been seen.
    pub auto_convergence: Option<f64>,
    /// Depth model of the last perspective projection seen (for auto-convergence).
    pub last_depth: Option<crate::camera::projection::DepthRange>,
    /// The main camera's bare projection (row3 = (0,0,-s,0)), for screen-space passes.
    pub camera_projection: Option<[f32; 16]>,
    /// Horizontal focal scale of that projection (for `--view-cone`).
    pub last_fx: Option<f64>,
    pub failed: bool,
    /// The app is compiling a display list: its calls must not be replayed.
    pub compiling_list: bool,
    pub immediate_list: u32,
    pub recording_immediate: bool,
    /// Transform feedback is active: draws run once (each replay would be captured).
    pub transform_feedback: bool,
    /// `glRenderMode` is GL_SELECT or GL_FEEDBACK: picking must see each draw once.
    pub selecting: bool,
    /// Layered shadows of the app's framebuffers, by app name; those that cannot be.
    pub shadows: std::collections::HashMap<u32, shadow::ShadowFbo>,
    pub unshadowable: std::collections::HashSet<u32>,
    /// Whether each of the app's framebuffers has a colour attachment (asked of GL once per
    /// attachment change, not per draw: shadow-map passes draw a lot).
    pub has_color: std::collections::HashMap<u32, bool>,
    /// Framebuffers already logged as drawn once (not view-dependent).
    pub drawn_once: std::collections::HashSet<u32>,
    pub units: layers::TextureUnits,
    /// Our full-screen passes and the native-resolution weave target.
    pub passes: crate::output::pass::Passes,
    pub native: Option<crate::output::native::NativeTarget>,
}

impl Multiview {
    /// Multiview state for a context just made current on a surface of `window` pixels.
    pub fn new(gl: &crate::gl::Gl, info: GlInfo, settings: ViewSettings, window: (u32, u32)) -> Multiview {
        let (draw, read) = (info.es || info.at_least(3, 0)).then_some(()).map_or((0, 0), |_| {
            (
                crate::gl::guard::get_i(gl, crate::gl::DRAW_FRAMEBUFFER_BINDING) as u32,
                crate::gl::guard::get_i(gl, crate::gl::READ_FRAMEBUFFER_BINDING) as u32,
            )
        });
        let app = AppFramebuffer {
            draw_fbo: draw,
            read_fbo: read,
            viewport: get_i4(gl, crate::gl::VIEWPORT),
            scissor: get_i4(gl, crate::gl::SCISSOR_BOX),
            draw_buffer: crate::gl::BACK,
            read_buffer: crate::gl::BACK,
        };
        let layout = QuiltLayout::new(settings.quilt, settings.tile, window);
        let rig = ViewRig {
            views: layout.views(),
            depthiness: 0.0,
            convergence: 1.0,
            focus: settings.focus,
        };
        let mut mv = Multiview {
            info,
            settings,
            target: None,
            app,
            rig,
            program: crate::gl::guard::get_i(gl, crate::gl::CURRENT_PROGRAM) as u32,
            auto_convergence: None,
            last_depth: None,
            last_fx: None,
            camera_projection: None,
            failed: false,
            compiling_list: false,
            immediate_list: 0,
            recording_immediate: false,
            transform_feedback: false,
            selecting: false,
            shadows: Default::default(),
            unshadowable: Default::default(),
            drawn_once: Default::default(),
            has_color: Default::default(),
            units: Default::default(),
            passes: Default::default(),
            native: None,
        };
        mv.update_rig(layout);
        mv
    }

    /// Depthiness and convergence for the current layout and scene (DESIGN §3 defaults).
    pub fn update_rig(&mut self, layout: QuiltLayout) {
        let views = layout.views();
        self.rig.views = views;
        self.rig.depthiness = self.depthiness(layout);
        self.rig.convergence = match self.settings.convergence {
            Convergence::Fixed(c) => c,
            Convergence::Auto => self.auto_convergence.unwrap_or_else(|| self.fallback_convergence()),
        };
    }

    /// `--depthiness` as given; else from `--view-cone` (s = Fx·tan(cone/2), DESIGN §3) once
    /// the projection is known; else 4 px between neighbouring views at infinity.
    fn depthiness(&self, layout: QuiltLayout) -> f64 {
        depthiness(self.settings.depthiness, self.settings.view_cone, self.last_fx, layout)
    }

    /// Before the scene's depth has been seen: the geometric mean of near and far when the
    /// projection is known, else one unit.
    fn fallback_convergence(&self) -> f64 {
        self.last_depth
            .map(|d| {
                let far = if d.far().is_finite() { d.far() } else { d.near() * 1e4 };
                (d.near().max(1e-6) * far).sqrt()
            })
            .filter(|c| c.is_finite() && *c > 0.0)
            .unwrap_or(1.0)
    }

    /// Multiview applies to what is drawn to framebuffer 0 right now.
    pub fn on_default_draw(&self) -> bool {
        self.target.is_some() && self.app.draw_fbo == 0 && !self.failed && !self.compiling_list
    }

    pub fn layout(&self) -> Option<QuiltLayout> {
        self.target.as_ref().map(|t| t.layout)
    }

    /// What of ours outlives this context in its share group: every texture, renderbuffer,
    /// program and display list (framebuffers and vertex arrays are per context).
    pub fn shared_objects(&self) -> crate::state::orphans::LayerObjects {
        let mut o = crate::state::orphans::LayerObjects::default();
        if let Some(t) = &self.target {
            o.textures.push(t.color);
            o.renderbuffers.push(t.depth);
        }
        for a in self.shadows.values().flat_map(|s| &s.attachments) {
            o.textures.push(a.array);
            o.textures.extend(&a.layer_views);
        }
        o.textures.extend(self.native.as_ref().map(|n| n.color));
        o.programs.extend(self.passes.programs());
        o.lists.push(self.immediate_list);
        o.without_zeros()
    }

    /// The quilt's framebuffer name while it stands in for framebuffer 0.
    pub fn quilt_fbo(&self) -> Option<u32> {
        self.target.as_ref().filter(|_| !self.failed).map(|t| t.fbo)
    }
}

/// `--depthiness` as given; else from `--view-cone` (s = Fx·tan(cone/2), DESIGN §3) once
/// the projection's `Fx` is known; else 4 px between neighbouring views at infinity.
pub fn depthiness(given: Option<f64>, cone_deg: Option<f64>, fx: Option<f64>, layout: QuiltLayout) -> f64 {
    match (given, cone_deg, fx) {
        (Some(s), _, _) => s,
        (None, Some(cone), Some(fx)) => fx * (cone.to_radians() / 2.0).tan(),
        _ => ViewRig::depthiness_for_disparity(4.0, layout.views(), layout.tile_w),
    }
}

/// Runs `f` with the current context's multiview state and GL table, when multiview is on and
/// this thread is not inside `f` already (a hook re-entered from the app's synchronous debug
/// callback, which GL runs inside a real call made here: see `state::lock`). `None`: the hook
/// passes the call through.
pub fn with_active<R>(f: impl FnOnce(&Current, &mut Multiview, &crate::gl::Gl) -> R) -> Option<R> {
    // Pass-through (`--output mono`) pays one load per hooked call, nothing more.
    if !crate::config::settings().multiview() {
        return None;
    }
    crate::state::with_current(|cur| {
        let cur = cur?;
        let (gl, _) = cur.ctx.gl()?;
        // None on re-entry from a callback inside one of our GL calls: pass through.
        let mut guard = cur.ctx.mv()?;
        let mv = guard.as_mut()?;
        Some(f(cur, mv, gl))
    })
}

/// Sets up multiview for a context at make-current (first time, or on a new surface size).
pub fn on_make_current(cur: &Current) {
    let settings = crate::config::settings();
    if !settings.multiview() {
        return;
    }
    let Some((gl, info)) = cur.ctx.gl() else { return };
    if !(info.es && info.at_least(3, 0) || !info.es && info.at_least(3, 0)) {
        crate::log::warn(format_args!(
            "context {:#x}: GL {info:?} has no framebuffer objects; multiview off",
            cur.ctx.handle
        ));
        return;
    }
    if cur.binding.draw == 0 {
        crate::log::info(format_args!(
            "context {:#x}: current without a surface; no multiview until it has one",
            cur.ctx.handle
        ));
        return;
    }
    let Some(window) = crate::output::surface_size(cur) else {
        crate::log::warn(format_args!(
            "context {:#x}: surface size unknown; multiview off",
            cur.ctx.handle
        ));
        return;
    };
    let Some(mut guard) = cur.ctx.mv() else { return };
    let mv = guard.get_or_insert_with(|| Multiview::new(gl, *info, settings.view.clone(), window));
    framebuffer::ensure_target(gl, mv, window);
}

/// Auto-convergence from the centre view's depth of the frame just finished.
pub fn update_convergence(gl: &crate::gl::Gl, mv: &mut Multiview) {
    let Some(layout) = mv.layout() else { return };
    // ES cannot read depth back: there the projection's near/far give the estimate.
    if mv.settings.convergence == Convergence::Auto
        && !mv.info.es
        && let (Some(target), Some(range)) = (mv.target.as_ref(), mv.last_depth)
    {
        let tile = target.layout.tile_rect(mv.rig.centre());
        let depths = crate::gl::readback::read_depth(gl, mv.info, target.fbo, tile);
        if let Some(c) = crate::camera::convergence::estimate(&depths, range) {
            if mv.auto_convergence.is_none() {
                crate::log::info(format_args!(
                    "auto-convergence: scene at {c:.4} (near {:.4}, far {:.4})",
                    range.near(),
                    range.far()
                ));
            }
            mv.auto_convergence = Some(crate::camera::convergence::smooth(mv.auto_convergence, c));
        }
    }
    mv.update_rig(layout);
}

/// After an internal failure the layer turns into pass-through: give the app back the real
/// framebuffer 0 and unshifted programs, so what it draws from now on reaches the window.
pub fn abandon() {
    with_active(|cur, mv, gl| {
        framebuffer::hand_back(gl, mv);
        mv.failed = true;
        framebuffer::rebind(gl, mv);
        let views: Vec<(u32, i32)> = cur
            .ctx
            .group
            .lock()
            .programs
            .iter()
            .filter(|(_, p)| p.view_loc >= 0)
            .map(|(&id, p)| (id, p.view_loc))
            .collect();
        for (program, loc) in views {
            // SAFETY: our own uniform in programs of this share group; zero shift.
            unsafe {
                if gl.ProgramUniform4f.is_loaded() {
                    gl.ProgramUniform4f(program, loc, 0.0, 1.0, 0.0, 2.0);
                }
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depthiness_from_option_cone_or_default() {
        let l = QuiltLayout::new((8, 6), Some((420, 560)), (420, 560));
        assert_eq!(depthiness(Some(0.3), Some(40.0), Some(2.0), l), 0.3);
        let s = depthiness(None, Some(40.0), Some(2.0), l);
        assert!((s - 2.0 * 20f64.to_radians().tan()).abs() < 1e-12);
        // Cone without a known projection: the pixel default, not garbage.
        assert!((depthiness(None, Some(40.0), None, l) - 4.0 * 47.0 / 420.0).abs() < 1e-12);
    }
}
