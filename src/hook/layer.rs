//! The layer's per-context data — replay state ([`Multiview`]) and presenter — kept in the
//! context's slot in `state` (which does not know these types), and what happens to it at
//! make-current and on an internal failure.

use crate::gl::Gl;
use crate::multiview::Multiview;
use crate::output::Presenter;
use crate::state::orphans::LayerObjects;
use crate::state::{AppState, ContextLayer, Current};
use std::any::Any;

pub struct Layer {
    pub views: Multiview,
    pub presenter: Presenter,
    /// The generation of live values (`config::live`) applied to `views.settings`.
    pub live_generation: u64,
    /// `--gpu-counts`: the frame's statistics queries (`None` until the first frame; then
    /// `Some(None)` where the driver has none).
    pub gpu_stats: Option<Option<crate::gl::stats_query::FrameStats<crate::log::counts::FrameCounts>>>,
}

impl ContextLayer for Layer {
    fn shared_objects(&self) -> LayerObjects {
        let mut o = self.views.shared_objects();
        o.append(self.presenter.shared_objects());
        o
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// Runs `f` with the current context's app state, layer data and GL table, when multiview is
/// on in it.
pub fn with_layer<R>(f: impl FnOnce(&Current, &mut AppState, &mut Layer, &Gl) -> R) -> Option<R> {
    // Pass-through (`--output mono`) pays one load per hooked call, nothing more.
    if !crate::config::settings().multiview() {
        return None;
    }
    crate::state::with_current(|cur| {
        let cur = cur?;
        let (gl, _) = cur.ctx.gl()?;
        let mut tracked = cur.ctx.tracked()?;
        let tracked = &mut *tracked;
        let app = tracked.app.as_mut()?;
        let layer = tracked.layer.as_mut()?.as_any_mut().downcast_mut::<Layer>()?;
        Some(f(cur, app, layer, gl))
    })
}

/// `with_layer` for handlers, which need the replay state only.
pub fn with_active<R>(f: impl FnOnce(&Current, &mut AppState, &mut Multiview, &Gl) -> R) -> Option<R> {
    with_layer(|cur, app, layer, gl| f(cur, app, &mut layer.views, gl))
}

/// At make-current: the context's state is tracked (`state::make_current`); multiview is
/// set up the first time it has a surface, and its quilt follows the surface's size.
pub fn on_make_current() {
    let settings = crate::config::settings();
    if !settings.multiview() {
        return;
    }
    crate::state::with_current(|cur| {
        let Some(cur) = cur else { return };
        let Some((gl, info)) = cur.ctx.gl() else { return };
        if !info.has_gl3_features() {
            crate::log::warn(format_args!(
                "context {:#x}: GL {info:?} has no layered framebuffers; multiview off",
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
        let Some(window) = crate::state::surface_size(cur) else {
            crate::log::warn(format_args!(
                "context {:#x}: surface size unknown; multiview off",
                cur.ctx.handle
            ));
            return;
        };
        let Some(mut tracked) = cur.ctx.tracked() else { return };
        let tracked = &mut *tracked;
        let Some(app) = tracked.app.as_ref() else { return };
        let slot = tracked.layer.get_or_insert_with(|| {
            super::heap::tune_once();
            Box::new(Layer {
                views: Multiview::new(*info, settings.view.clone(), window),
                presenter: Presenter::default(),
                live_generation: 0,
                gpu_stats: None,
            })
        });
        if let Some(layer) = slot.as_any_mut().downcast_mut::<Layer>() {
            crate::multiview::replay::framebuffer::ensure_target(gl, app, &mut layer.views, window);
        }
    });
}

/// After an internal failure the layer turns into pass-through: give the app back the real
/// framebuffer 0 and unshifted programs, so what it draws from now on reaches the window.
pub fn abandon() {
    with_active(|cur, app, mv, gl| {
        crate::multiview::replay::framebuffer::hand_back(gl, mv);
        mv.failed = true;
        crate::multiview::replay::framebuffer::rebind(gl, app, mv);
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
