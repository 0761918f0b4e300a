//! Which draws go to layered shadows, and building and rebuilding the shadows (see `shadow`
//! and `layered`; what the app's calls do to shadows and images is in `lifetime`, the
//! per-view texture binding in `substitute`).

use super::layered::{AppImage, LayeredImage, Storage};
use super::lifetime;
use super::scale::LayerScale;
use super::shadow::{self, Attached, ShadowFbo, facts};
use super::substitute::Substitutions;
use crate::gl::*;
use crate::multiview::Multiview;
use std::sync::Arc;

/// Why a draw into the app's framebuffer `fbo` is view-dependent, if it is. A framebuffer
/// holding an object that has per-view content must be drawn per view, whatever the draw:
/// drawn once, it would write the app's object, which nothing samples any more.
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
        return Some("it samples a view-dependent texture");
    }
    let facts = facts(gl, &mut mv.fbo_facts, fbo);
    if facts.objects.iter().any(|o| mv.images.contains_key(o)) {
        Some("it holds view-dependent images")
    } else if camera_draw && facts.has_color {
        Some("the main camera draws into it")
    } else {
        None
    }
}

/// The per-view framebuffers for a draw into the app's `fbo`, creating (or bringing up to
/// date) its shadow when the draw makes it view-dependent.
pub fn target_views(
    gl: &Gl,
    mv: &mut Multiview,
    fbo: u32,
    camera_draw: bool,
    subs: &Substitutions,
) -> Option<Arc<[u32]>> {
    if let Some(s) = mv.shadows.get(&fbo).filter(|s| !s.stale) {
        return Some(s.views.clone());
    }
    if mv.unshadowable.contains_key(&fbo) || !shadow::supported(gl, mv.info) {
        return None;
    }
    let Some(why) = dependence(gl, mv, fbo, camera_draw, subs) else {
        lifetime::drop_shadow(gl, mv, fbo);
        if mv.drawn_once.insert(fbo) {
            crate::log::info(format_args!(
                "framebuffer {fbo}: pass drawn once for all views (not view-dependent)"
            ));
        }
        return None;
    };
    ensure_shadow(gl, mv, fbo, why)
}

/// The per-view framebuffers of `fbo` for a clear, a blit or a read: its shadow, brought up
/// to date, or a new one if it holds view-dependent images; `None` for framebuffers drawn
/// once.
pub fn current_views(gl: &Gl, mv: &mut Multiview, fbo: u32) -> Option<Arc<[u32]>> {
    if fbo == 0 || !mv.shadows.contains_key(&fbo) && mv.images.is_empty() {
        return None;
    }
    if let Some(s) = mv.shadows.get(&fbo).filter(|s| !s.stale) {
        return Some(s.views.clone());
    }
    if mv.unshadowable.contains_key(&fbo) || !shadow::supported(gl, mv.info) {
        return None;
    }
    match dependence(gl, mv, fbo, false, &Vec::new()) {
        Some(why) => ensure_shadow(gl, mv, fbo, why),
        None => {
            lifetime::drop_shadow(gl, mv, fbo);
            None
        }
    }
}

/// Creates the shadow of `fbo`, or points a stale one at the app's current attachments.
/// Logged once per framebuffer at `info`; rebuilds at `debug`.
pub fn ensure_shadow(gl: &Gl, mv: &mut Multiview, fbo: u32, why: &str) -> Option<Arc<[u32]>> {
    if let Some(s) = mv.shadows.get(&fbo).filter(|s| !s.stale) {
        return Some(s.views.clone());
    }
    if mv.unshadowable.contains_key(&fbo)
        || !shadow::supported(gl, mv.info)
        || mv.settings.fbo_views == crate::config::FboViews::None
    {
        return None;
    }
    match build(gl, mv, fbo) {
        Ok(views) => {
            let (n, (w, h)) = (views.len(), mv.shadows[&fbo].size);
            if mv.announced.insert((fbo, true)) {
                let scaled = super::downscale::describe(mv.shadows[&fbo].scale);
                crate::log::info(format_args!(
                    "framebuffer {fbo} shadowed with {n} layers ({w}x{h}{scaled}): {why}"
                ));
            } else {
                crate::log::debug(format_args!("framebuffer {fbo}: shadow re-attached ({w}x{h}): {why}"));
            }
            Some(views)
        }
        Err(e) => {
            if mv.announced.insert((fbo, false)) {
                crate::log::info(format_args!("framebuffer {fbo} stays single-view: {e}"));
            } else {
                crate::log::debug(format_args!("framebuffer {fbo} stays single-view: {e}"));
            }
            lifetime::give_up(gl, mv, fbo);
            None
        }
    }
}

/// The shadow of `fbo` over the images of what it has attached now (kept when they exist,
/// made from the app's content when not); its views. Every attachment is checked
/// before any image is made, so that a framebuffer that cannot be shadowed costs no layers.
fn build(gl: &Gl, mv: &mut Multiview, fbo: u32) -> Result<Arc<[u32]>, String> {
    let n = mv.camera.rig.views;
    let found = shadow::attachments(gl, fbo);
    if found.is_empty() {
        return Err(format!("framebuffer {fbo} has no attachments"));
    }
    // Texture targets are the share group's: the attachments may come from another context.
    let group = crate::state::with_current(|cur| cur.map(|cur| cur.ctx.group.clone()));
    let target_of = |t| group.as_ref().map_or(0, |g| g.textures.target_of(t));
    let mut checked = Vec::new();
    for (point, app, level) in found {
        if level != 0 {
            return Err(format!("framebuffer {fbo}: attachment {point:#x} is not mip level 0"));
        }
        let target = if app.renderbuffer {
            RENDERBUFFER
        } else {
            target_of(app.name)
        };
        checked.push((point, app, super::layered::storage(gl, app, target)?));
    }
    let scale = super::downscale::for_framebuffer(mv, fbo, &checked);
    let (mut wanted, mut size) = (Vec::new(), (i32::MAX, i32::MAX));
    for (point, app, storage) in checked {
        let image = obtain(gl, mv, app, (storage, scale), point, n)?;
        size = (size.0.min(image.size.0), size.1.min(image.size.1));
        wanted.push(Attached {
            point,
            app,
            array: image.array,
        });
    }
    let info = mv.info;
    let shadow = mv.shadows.entry(fbo).or_insert_with(|| ShadowFbo::new(gl, n));
    shadow.attach(gl, info, fbo, wanted, (size, scale))?;
    Ok(shadow.views.clone())
}

/// The image of `app`: the one it has if its storage is still `storage` and its scale
/// `scale`, else a new one made from the app's content (`point`: where it is attached). The storage may have changed
/// behind the hooks (in another context of the share group, or through a call the layer does
/// not wrap): the image follows what GL says.
fn obtain<'a>(
    gl: &Gl,
    mv: &'a mut Multiview,
    app: AppImage,
    (storage, scale): (Storage, LayerScale),
    point: GLenum,
    n: u32,
) -> Result<&'a LayeredImage, String> {
    if mv
        .images
        .get(&app)
        .is_some_and(|i| i.storage != storage || i.scale != scale)
    {
        lifetime::drop_image(gl, mv, app);
    }
    if !mv.images.contains_key(&app) {
        let image = LayeredImage::create(gl, mv.info, app, (storage, scale), point, n)?;
        mv.images.insert(app, image);
    }
    Ok(&mv.images[&app])
}
