//! The per-view texture substitution: wherever the app samples one of its textures that has
//! per-view layers, view i's replay binds layer i's view in its place, so a post-processing
//! pass reads the scene of its own view. Listed once per draw, into a vector kept from draw
//! to draw, so that no draw allocates.

use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::shadows::layered::AppImage;
use crate::state::AppState;
use std::sync::Arc;

/// Units whose bound texture has layer views: (unit, app texture, views).
pub type Substitutions = Vec<(u32, u32, Arc<[u32]>)>;

/// Fills `subs` (emptied first; a vector kept from draw to draw, so that no draw allocates).
pub fn substitutions(app: &AppState, mv: &Multiview, subs: &mut Substitutions) {
    subs.clear();
    if mv.images.is_empty() {
        return;
    }
    for (unit, &tex) in app.units.bound_2d.iter().enumerate().filter(|(_, t)| **t != 0) {
        if let Some(image) = mv
            .images
            .get(&AppImage::texture(tex))
            .filter(|i| !i.layer_views.is_empty())
        {
            subs.push((unit as u32, tex, image.layer_views.clone()));
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
