//! Which shadowed framebuffers get scaled layers (`--fbo-scale`, see `scale`), and the
//! fall-backs to the app's size.
//!
//! One factor per context, the same for every framebuffer, so that a pass reading one
//! scaled target and writing another maps both alike (a same-size blit stays same-size).
//! A framebuffer keeps the app's size when:
//! - something attached has a size of its own, not the window's or a halving or doubling of it
//!   (`LayerScale::follows_window`): a reduction target, a shadow map, a lookup table;
//! - something attached is multisampled: a multisampled image cannot be copied to or from
//!   the app's object at another size;
//! - a program addresses texels in pixels (`texelFetch`, image load/store, `gl_FragCoord`
//!   divided by `textureSize`, or `gl_FragCoord` the layer could not map) while drawing into
//!   it or sampling what it holds; decided at that draw, logged once per framebuffer;
//! - a multisampled framebuffer of the app's size is resolved into it by a blit.
//!
//! Such an image is remembered (`Multiview::full_size`) and made again at full size; every
//! framebuffer holding it follows, so that the layers of one framebuffer share one scale. The
//! frame in which it is decided loses what earlier passes of that frame drew into those
//! layers.

use super::layered::{AppImage, Storage};
use super::scale::LayerScale;
use super::substitute::Substitutions;
use crate::gl::*;
use crate::multiview::Multiview;

/// The factors `--fbo-scale` gives in this context now (1 before the quilt exists).
pub fn context_scale(mv: &Multiview) -> LayerScale {
    match mv.layout() {
        Some(l) => LayerScale::new(mv.settings.fbo_scale, (l.window_w, l.window_h), (l.tile_w, l.tile_h)),
        None => LayerScale::ONE,
    }
}

/// The scale of a shadow over `attached`. When one of them must stay at the app's size, all
/// of them are remembered so: an image shared with another framebuffer then has one scale
/// there too, instead of being made again at each framebuffer's scale in turn.
pub fn for_framebuffer(mv: &mut Multiview, fbo: u32, attached: &[(GLenum, AppImage, Storage)]) -> LayerScale {
    let scale = context_scale(mv);
    let full = attached
        .iter()
        .any(|(_, app, s)| s.samples > 0 || mv.full_size.contains(app));
    let window = mv.layout().map_or((0, 0), |l| (l.window_w, l.window_h));
    let own = attached
        .iter()
        .find(|(_, _, s)| !LayerScale::follows_window((s.width, s.height), window));
    if !full && (own.is_none() || scale.is_one()) {
        return scale;
    }
    let multisampled = attached.iter().find(|(_, _, s)| s.samples > 0);
    if !scale.is_one() {
        let why = match (multisampled, own) {
            (Some((_, _, s)), _) => format!(
                "{}x{} with {} samples: a multisampled image cannot be copied at another size",
                s.width, s.height, s.samples
            ),
            (None, Some((_, _, s))) => format!(
                "{}x{} does not follow the {}x{} window: a size of its own",
                s.width, s.height, window.0, window.1
            ),
            // Remembered full-size through another framebuffer, which said why.
            (None, None) => String::new(),
        };
        if !why.is_empty() {
            crate::log::once_for(
                ("fbo-scale", u64::from(fbo)),
                crate::log::Level::Info,
                format_args!("framebuffer {fbo}: layers at the program's size ({why})"),
            );
        }
    }
    mv.full_size.extend(attached.iter().map(|(_, app, _)| *app));
    LayerScale::ONE
}

/// ", scaled by SXxSY" for the shadow log line, or nothing at the app's size.
pub fn describe(scale: LayerScale) -> String {
    if scale.is_one() {
        String::new()
    } else {
        format!(", scaled by {:.3}x{:.3}", scale.sx, scale.sy)
    }
}

/// `fbo`'s layers go back to the app's size: what it has attached is remembered as
/// full-size and its scaled images dropped (its shadow and any other holding them are rebuilt
/// before their next use). `true` when something was dropped. Asks GL nothing and allocates
/// nothing once `fbo` is full-size.
pub fn unscale_framebuffer(gl: &Gl, mv: &mut Multiview, fbo: u32, why: (&str, &str)) -> bool {
    let facts = super::shadow::facts(gl, &mut mv.fbo_facts, fbo);
    if facts.objects.iter().all(|a| mv.full_size.contains(a)) {
        return false;
    }
    let apps = facts.objects.clone();
    crate::log::once_for(
        ("fbo-scale", u64::from(fbo)),
        crate::log::Level::Info,
        format_args!("framebuffer {fbo}: layers at the program's size ({}{})", why.0, why.1),
    );
    unscale_images(gl, mv, &apps)
}

fn unscale_images(gl: &Gl, mv: &mut Multiview, apps: &[AppImage]) -> bool {
    let mut dropped = false;
    for &app in apps {
        mv.full_size.insert(app);
        if mv.images.get(&app).is_some_and(|i| !i.scale.is_one()) {
            super::lifetime::drop_image(gl, mv, app);
            dropped = true;
        }
    }
    dropped
}

/// Before a draw with a program that addresses texels in pixels (`pixel_addressing`): the
/// framebuffer it draws into and those holding the scaled textures it samples go back to the
/// app's size. `true` when the draw's substitutions must be found again.
pub fn before_pixel_addressing(
    gl: &Gl,
    mv: &mut Multiview,
    draw_fbo: u32,
    subs: &Substitutions,
    pixel_addressing: &str,
) -> bool {
    let why = ("a program drawing into it or sampling it reads ", pixel_addressing);
    let mut dropped = draw_fbo != 0 && unscale_framebuffer(gl, mv, draw_fbo, why);
    for &(_, tex, _) in subs.iter() {
        let app = AppImage::texture(tex);
        if mv.images.get(&app).is_none_or(|i| i.scale.is_one()) {
            continue;
        }
        let holders: Vec<u32> = mv
            .shadows
            .iter()
            .filter(|(_, s)| s.attached.iter().any(|a| a.app == app))
            .map(|(&f, _)| f)
            .collect();
        for fbo in holders {
            dropped |= unscale_framebuffer(gl, mv, fbo, why);
        }
        dropped |= unscale_images(gl, mv, &[app]);
    }
    dropped
}

/// A blit from `read`'s layers to `draw`'s at another scale, from a multisampled image: GL
/// cannot scale a multisample resolve, so `draw` must be at the app's size.
pub fn resolve_needs_full_size(mv: &Multiview, read: u32, draw: u32) -> bool {
    let (Some(src), Some(dst)) = (mv.shadows.get(&read), mv.shadows.get(&draw)) else {
        return false;
    };
    src.scale != dst.scale
        && src
            .attached
            .iter()
            .any(|a| mv.images.get(&a.app).is_some_and(|i| i.storage.samples > 0))
}
