//! Which draws go to layered shadows, and the per-view texture substitution (see `shadow`).

use super::Multiview;
use super::shadow::{self, ShadowFbo};
use crate::gl::*;
use crate::state::AppState;
use std::sync::Arc;

/// Units whose bound texture has layer views: (unit, app texture, views).
pub type Substitutions = Vec<(u32, u32, Arc<[u32]>)>;

/// Fills `subs` (emptied first; a vector kept from draw to draw, so that no draw allocates).
pub fn substitutions(app: &AppState, mv: &Multiview, subs: &mut Substitutions) {
    subs.clear();
    if mv.shadows.is_empty() {
        return;
    }
    for (unit, &tex) in app.units.bound_2d.iter().enumerate().filter(|(_, t)| **t != 0) {
        if let Some(views) = mv.shadows.values().find_map(|s| s.layer_views_of(tex)) {
            subs.push((unit as u32, tex, views.clone()));
        }
    }
}

/// Binds view `i`'s layers (`None`: the app's own textures back) on the substituted units.
pub fn bind_layers(gl: &Gl, app: &AppState, subs: &Substitutions, i: Option<usize>) {
    if subs.is_empty() {
        return;
    }
    // SAFETY: texture bindings of this context; the app's active unit is put back.
    unsafe {
        for (unit, texture, views) in subs {
            gl.ActiveTexture(TEXTURE0 + unit);
            gl.BindTexture(TEXTURE_2D, i.map_or(*texture, |i| views[i.min(views.len() - 1)]));
        }
        gl.ActiveTexture(TEXTURE0 + app.units.active);
    }
}

/// Why a draw into the app's framebuffer `fbo` is view-dependent, if it is.
pub fn dependence(
    gl: &Gl,
    mv: &mut Multiview,
    fbo: u32,
    camera_draw: bool,
    subs: &Substitutions,
) -> Option<&'static str> {
    use crate::config::FboViews;
    match mv.settings.fbo_views {
        FboViews::None => return None,
        FboViews::All => return Some("--fbo-views all"),
        FboViews::Auto => {}
    }
    if !subs.is_empty() {
        Some("it samples a view-dependent texture")
    } else if camera_draw
        && *mv
            .has_color
            .entry(fbo)
            .or_insert_with(|| shadow::has_color_attachment(gl, fbo))
    {
        Some("the main camera draws into it")
    } else {
        None
    }
}

/// The per-view framebuffers for a draw into the app's `fbo`, creating its shadow when the
/// draw makes it view-dependent.
pub fn target_views(
    gl: &Gl,
    mv: &mut Multiview,
    fbo: u32,
    camera_draw: bool,
    subs: &Substitutions,
) -> Option<Arc<[u32]>> {
    if let Some(s) = mv.shadows.get(&fbo) {
        return Some(s.views.clone());
    }
    if mv.unshadowable.contains(&fbo) || !shadow::supported(gl, mv.info) {
        return None;
    }
    let Some(why) = dependence(gl, mv, fbo, camera_draw, subs) else {
        if mv.drawn_once.insert(fbo) {
            crate::log::info(format_args!(
                "framebuffer {fbo}: pass drawn once for all views (not view-dependent)"
            ));
        }
        return None;
    };
    ensure_shadow(gl, mv, fbo, why)
}

/// Creates the shadow of `fbo` (logged once, with the reason).
pub fn ensure_shadow(gl: &Gl, mv: &mut Multiview, fbo: u32, why: &str) -> Option<Arc<[u32]>> {
    if let Some(s) = mv.shadows.get(&fbo) {
        return Some(s.views.clone());
    }
    if mv.unshadowable.contains(&fbo)
        || !shadow::supported(gl, mv.info)
        || mv.settings.fbo_views == crate::config::FboViews::None
    {
        return None;
    }
    let n = mv.camera.rig.views;
    // Texture targets are the share group's: the attachments may come from another context.
    let group = crate::state::with_current(|cur| cur.map(|cur| cur.ctx.group.clone()));
    let target_of = |t| group.as_ref().map_or(0, |g| g.textures.target_of(t));
    match ShadowFbo::create(gl, mv.info, fbo, n, target_of) {
        Ok(s) => {
            crate::log::info(format_args!(
                "framebuffer {fbo} shadowed with {n} layers ({}x{}): {why}",
                s.size.0, s.size.1
            ));
            let views = s.views.clone();
            mv.shadows.insert(fbo, s);
            Some(views)
        }
        Err(e) => {
            crate::log::info(format_args!("framebuffer {fbo} stays single-view: {e}"));
            mv.unshadowable.insert(fbo);
            None
        }
    }
}

/// Drops shadows that no longer match the app's objects (re-attached, resized, deleted).
pub fn forget(gl: &Gl, mv: &mut Multiview, pred: impl Fn(u32, &ShadowFbo) -> bool) {
    let stale: Vec<u32> = mv
        .shadows
        .iter()
        .filter(|(f, s)| pred(**f, s))
        .map(|(f, _)| *f)
        .collect();
    for fbo in stale {
        if let Some(s) = mv.shadows.remove(&fbo) {
            crate::log::debug(format_args!("framebuffer {fbo}: shadow dropped"));
            s.delete(gl);
        }
    }
}
