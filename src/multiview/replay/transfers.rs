//! Clears, reads and blits on framebuffer 0 and on shadowed framebuffers, per view: a clear
//! of framebuffer 0 clears every tile, a blit between view-dependent framebuffers copies
//! layer to layer, and the app's reads of framebuffer 0 see the centre view.

use super::framebuffer::{ALL_BUFFERS, rebind};
use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::intersect;
use crate::multiview::shadows::scale::LayerScale;
use crate::state::AppState;

/// Clears every rendered layer of a shadowed framebuffer of the app (the app's scissor box
/// mapped into scaled layers): the others are not drawn this frame, nor sampled before they
/// are (a synthesised view samples its nearest rendered view's layer).
fn clear_layers(gl: &Gl, app: &mut AppState, mv: &mut Multiview, f: &impl Fn()) -> bool {
    let Some(views) = crate::multiview::shadows::layers::current_views(gl, mv, app.draw_fbo) else {
        return false;
    };
    let scale = mv.shadows.get(&app.draw_fbo).map_or(LayerScale::ONE, |s| s.scale);
    let scissor = (!scale.is_one() && app.enabled(gl, SCISSOR_TEST)).then(|| scale.rect_out(app.scissor));
    if let Some(r) = scissor {
        // SAFETY: a scissor box; the app's is restored below.
        unsafe { gl.Scissor(r[0], r[1], r[2], r[3]) };
    }
    for (i, &view) in views.iter().enumerate() {
        if !mv.plan.renders(i as u32) {
            continue;
        }
        // SAFETY: our view framebuffer; the app's binding is restored below.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, view) };
        f();
    }
    let s = app.scissor;
    // SAFETY: the app's own framebuffer and scissor box back.
    unsafe {
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, app.draw_fbo);
        if scissor.is_some() {
            gl.Scissor(s[0], s[1], s[2], s[3]);
        }
    }
    true
}

/// Clears every tile (or the app's scissored part of each) while framebuffer 0 is bound, and
/// every rendered layer of a shadowed framebuffer. Before the warp point of a frame whose
/// warp overwrites every synthesised tile's colour and depth (`synthesis::overwrites_tiles`),
/// a clear of colour and depth reaches the rendered tiles only: clearing an 8x6 quilt of
/// 420x560 tiles cost llvmpipe 12 ms, most of it for tiles written again anyway. `stencil`:
/// the clear is of the stencil too, which the warp does not write: every tile then.
pub fn clear(gl: &Gl, app: &mut AppState, mv: &mut Multiview, stencil: bool, f: impl Fn()) {
    if clear_layers(gl, app, mv, &f) {
        return;
    }
    let Some(layout) = mv.layout().filter(|_| mv.on_default_draw(app)) else {
        return f();
    };
    // A clear never reaches the disparity record.
    if mv.record.quilt.is_some() {
        crate::multiview::quilt::record::DisparityRecord::release_bound(gl);
    }
    if mv.plan.before_default_draw(false) {
        crate::multiview::fast::synthesis::warp(gl, mv);
    }
    let scissored = app.enabled(gl, SCISSOR_TEST);
    let skip = !stencil && crate::multiview::fast::synthesis::overwrites_tiles(mv);
    if !scissored && !skip {
        return f();
    }
    // SAFETY: the scissor test, restored after the loop.
    unsafe { gl.Enable(SCISSOR_TEST) };
    for i in (0..layout.views()).filter(|&i| !skip || mv.plan.draws(i)) {
        let tile = layout.tile_rect(i);
        let r = if scissored {
            intersect(layout.map_rect(i, app.scissor), tile)
        } else {
            tile
        };
        // SAFETY: a scissor box; the app's is restored after the loop.
        unsafe { gl.Scissor(r[0], r[1], r[2], r[3]) };
        f();
    }
    // The guard band's strips are cleared as their views' tiles are.
    let band = crate::multiview::fast::guard::drawn_now(mv);
    if band > 0 {
        let rects = (app.viewport, scissored.then_some(app.scissor));
        crate::multiview::fast::guard::strip_draws(mv, layout, band, rects, false, |strip| {
            let r = strip.scissor;
            // SAFETY: as above.
            unsafe { gl.Scissor(r[0], r[1], r[2], r[3]) };
            f();
        });
    }
    let s = app.scissor;
    // SAFETY: the app's scissor box and test back.
    unsafe {
        gl.Scissor(s[0], s[1], s[2], s[3]);
        if !scissored {
            gl.Disable(SCISSOR_TEST);
        }
    }
}

/// Source rectangle of a read from framebuffer 0: the centre view's tile. A multisampled
/// quilt cannot be read (a multisampled window can: GL resolves it first), so that rectangle
/// is resolved and its resolved framebuffer bound for reading; `true` then in the answer:
/// the caller rebinds (`rebind`) after the read.
pub fn centre_rect(gl: &Gl, app: &AppState, mv: &Multiview, r: [i32; 4]) -> Option<([i32; 4], bool)> {
    let target = mv
        .target
        .as_ref()
        .filter(|_| app.read_fbo == 0 && mv.quilt_fbo().is_some())?;
    let rect = target.layout.map_rect(mv.camera.rig.centre(), r);
    if target.samples == 0 {
        return Some((rect, false));
    }
    target.resolve(gl, mv.info, rect, ALL_BUFFERS);
    // SAFETY: our resolved quilt for reading.
    unsafe { gl.BindFramebuffer(READ_FRAMEBUFFER, target.resolved_fbo) };
    Some((rect, true))
}

/// For a blit from framebuffer 0: a multisampled quilt is read resolved when its tiles are
/// scaled (blits from multisampled buffers cannot scale, and the window's would not have
/// to), and on ES, where they cannot move either (a tile is not where the window's pixels
/// are); the caller rebinds.
fn resolved_blit_source(gl: &Gl, app: &AppState, mv: &Multiview) {
    let Some(t) = mv.target.as_ref().filter(|t| app.read_fbo == 0 && t.samples > 0) else {
        return;
    };
    if !t.layout.unscaled() || mv.info.es {
        t.resolve_all(gl, mv.info, ALL_BUFFERS);
        // SAFETY: our resolved quilt for reading.
        unsafe { gl.BindFramebuffer(READ_FRAMEBUFFER, t.resolved_fbo) };
    }
}

/// `glBlitFramebuffer` between framebuffer 0 (tiles) and the app's framebuffers (layers when
/// shadowed): view i reads view i's tile or layer and writes view i's; a view-dependent
/// source makes its destination view-dependent too. A single-view end reads the centre.
pub fn blit(gl: &Gl, app: &AppState, mv: &mut Multiview, src: [i32; 4], dst: [i32; 4], f: impl Fn([i32; 4], [i32; 4])) {
    let Some(layout) = mv.layout().filter(|_| mv.quilt_fbo().is_some()) else {
        return f(src, dst);
    };
    if app.draw_fbo == 0 && mv.record.quilt.is_some() {
        // A blit writes every draw buffer, whatever the masks: never the disparity record.
        crate::multiview::quilt::record::DisparityRecord::release_bound(gl);
    }
    let corners = |r: [i32; 4]| [r[0], r[1], r[2] - r[0], r[3] - r[1]];
    let back = |r: [i32; 4]| [r[0], r[1], r[0] + r[2], r[1] + r[3]];
    let (read, draw) = (app.read_fbo, app.draw_fbo);
    let src_layers = crate::multiview::shadows::layers::current_views(gl, mv, read);
    let mut dst_layers = blit_destination(gl, mv, draw, src_layers.is_some());
    if src_layers.is_some()
        && dst_layers.is_some()
        && crate::multiview::shadows::downscale::resolve_needs_full_size(mv, read, draw)
    {
        let why = (
            "a multisampled framebuffer of the program's size is blitted into it",
            "",
        );
        crate::multiview::shadows::downscale::unscale_framebuffer(gl, mv, draw, why);
        dst_layers = blit_destination(gl, mv, draw, true);
    }
    let scale_of = |fbo: u32, layers: &Option<_>| match layers {
        Some(_) => mv.shadows.get(&fbo).map_or(LayerScale::ONE, |s| s.scale),
        None => LayerScale::ONE,
    };
    let (src_scale, dst_scale) = (scale_of(read, &src_layers), scale_of(draw, &dst_layers));
    if draw == 0 && src_layers.is_some() {
        note_orientation(mv, read, src, dst);
    }
    resolved_blit_source(gl, app, mv);
    let per_view = draw == 0 || src_layers.is_some() || dst_layers.is_some();
    if draw == 0 && mv.plan.before_default_draw(src_layers.is_some() || read == 0) {
        crate::multiview::fast::synthesis::warp(gl, mv);
    }
    if !per_view {
        let s = if read == 0 {
            back(layout.map_rect(mv.camera.rig.centre(), corners(src)))
        } else {
            src
        };
        f(s, dst);
        return rebind(gl, app, mv);
    }
    for i in 0..layout.views() {
        let drawn = if draw == 0 {
            mv.plan.draws(i)
        } else {
            mv.plan.renders(i)
        };
        if !drawn {
            continue;
        }
        let s = if read == 0 {
            back(layout.map_rect(i, corners(src)))
        } else {
            src_scale.corners(src)
        };
        let d = if draw == 0 {
            back(layout.map_rect(i, corners(dst)))
        } else {
            dst_scale.corners(dst)
        };
        // SAFETY: our view framebuffers in place of the app's; rebound below.
        unsafe {
            if let Some(v) = &src_layers {
                gl.BindFramebuffer(READ_FRAMEBUFFER, v[i as usize]);
            }
            if let Some(v) = &dst_layers {
                gl.BindFramebuffer(DRAW_FRAMEBUFFER, v[i as usize]);
            }
        }
        f(s, d);
    }
    rebind(gl, app, mv);
}

/// Whether the app's blit of shadowed `read` to the window (corners `src` to `dst`) turns it
/// upside down, remembered for those who read depth beside the window's colour
/// (`ShadowFbo::scene_rect`). Orientation belongs to the images: wined3d draws into one
/// framebuffer (colour and depth) and presents through another holding the same colour
/// texture, so every shadow sharing an image with `read` takes it.
fn note_orientation(mv: &mut Multiview, read: u32, src: [i32; 4], dst: [i32; 4]) {
    let flipped = (src[1] > src[3]) != (dst[1] > dst[3]);
    let Some(apps) = mv
        .shadows
        .get(&read)
        .map(|s| s.attached.iter().map(|a| a.app).collect::<Vec<_>>())
    else {
        return;
    };
    for (&fbo, s) in mv.shadows.iter_mut() {
        if s.presented_flipped == flipped || !s.attached.iter().any(|a| apps.contains(&a.app)) {
            continue;
        }
        s.presented_flipped = flipped;
        if flipped {
            crate::log::once_for(
                ("presented-flipped", u64::from(fbo)),
                crate::log::Level::Info,
                format_args!(
                    "framebuffer {fbo} is presented upside down ({} blitted flipped to the window): its depth \
                     and disparity record are read flipped",
                    if fbo == read {
                        "it is".to_string()
                    } else {
                        format!("its colour is, through framebuffer {read},")
                    }
                ),
            );
        }
    }
}

/// The layers a blit into the app's `fbo` writes: a view-dependent source makes it
/// view-dependent too.
fn blit_destination(gl: &Gl, mv: &mut Multiview, fbo: u32, layered_source: bool) -> Option<std::sync::Arc<[u32]>> {
    match (fbo, layered_source) {
        (0, _) => None,
        (_, true) => crate::multiview::shadows::layers::ensure_shadow(
            gl,
            mv,
            fbo,
            "a view-dependent framebuffer is blitted into it",
        ),
        (_, false) => crate::multiview::shadows::layers::current_views(gl, mv, fbo),
    }
}

/// Reads from a shadowed framebuffer of the app come from the centre view's layer (or the
/// rendered one nearest to it, when a fast mode does not render the centre): binds it
/// for reading (the caller rebinds with `rebind`). A scaled layer cannot answer in the app's
/// pixels: it is scaled back up into the app's own objects (which no pass of ours reads while
/// their layers live), and the read is the app's own, at the app's size: the centre view at
/// the layers' resolution.
pub fn read_centre_layer(gl: &Gl, app: &AppState, mv: &mut Multiview) -> bool {
    let Some(views) = crate::multiview::shadows::layers::current_views(gl, mv, app.read_fbo) else {
        return false;
    };
    let centre = mv.plan.nearest(mv.camera.rig.centre());
    if let Some(s) = mv.shadows.get(&app.read_fbo).filter(|s| !s.scale.is_one()) {
        for a in &s.attached {
            if let Some(image) = mv.images.get(&a.app) {
                image.copy_back(gl, mv.info, centre);
            }
        }
        return true;
    }
    let view = views[(centre as usize).min(views.len() - 1)];
    // SAFETY: our view framebuffer for reading.
    unsafe { gl.BindFramebuffer(READ_FRAMEBUFFER, view) };
    true
}
