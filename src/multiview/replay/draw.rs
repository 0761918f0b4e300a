//! One draw call, replayed once per view into its tile (or into its layer of a shadowed
//! framebuffer).
//!
//! Per view only three things change: the viewport (the app's, mapped into the tile), the
//! scissor (clamped to the tile so wide lines, points and clears never bleed into a
//! neighbour), and the view shift — the injected uniform for shader programs, or the
//! projection matrix for fixed-function draws (see `shift`). Everything is put back
//! afterwards.
//!
//! This runs for every draw the app makes, so in the common cases (a shader or
//! fixed-function draw to framebuffer 0, a draw into a shadowed framebuffer) it takes no
//! share-group lock, asks GL nothing and allocates nothing: what it needs is shadowed in
//! `state::AppState` or kept in `Multiview` from draw to draw.

use super::screen_space;
use super::shift::{self, Shift};
use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::fast::guard;
use crate::multiview::quilt::layout::{QuiltLayout, intersect};
use crate::multiview::quilt::record::DisparityRecord;
use crate::multiview::shadows::layers;
use crate::multiview::shadows::scale::LayerScale;
use crate::multiview::shadows::substitute::{self, Substitutions};
use crate::shader::ViewMode;
use crate::state::share::ProgramInfo;
use crate::state::{AppState, ShareGroup};
use std::sync::atomic::Ordering;

/// Replays `f` (the real draw) once per view when framebuffer 0 is the target.
pub fn draw(gl: &Gl, app: &mut AppState, mv: &mut Multiview, group: &ShareGroup, f: impl Fn()) {
    draw_views(gl, app, mv, group, |_| f())
}

/// View index passed to `draw_views`' callback when the draw is not replayed.
pub const SINGLE: u32 = u32::MAX;

/// `draw`, with the view index (or `SINGLE`) given to the callback, for draws that need
/// per-view work of their own (raster positions).
pub fn draw_views(gl: &Gl, app: &mut AppState, mv: &mut Multiview, group: &ShareGroup, f: impl Fn(u32)) {
    let _costs = crate::log::costs::draw();
    crate::log::counts::app_draw();
    let f = |i| crate::log::counts::replay(|| f(i));
    let replayed = !mv.failed && !app.compiling_list && !captures_once(gl, app);
    let Some(layout) = mv.layout().filter(|_| replayed) else {
        return draw_single(gl, app, mv, group, || f(SINGLE));
    };
    let mut scratch = Scratch {
        subs: std::mem::take(&mut mv.substitutions),
        camera_uniforms: std::mem::take(&mut mv.camera_uniforms),
    };
    substitute::substitutions(app, mv, &mut scratch.subs);
    replay(gl, app, mv, group, layout, &mut scratch, &f);
    mv.substitutions = scratch.subs;
    mv.camera_uniforms = scratch.camera_uniforms;
}

/// Vectors a replay fills, kept in `Multiview` between draws so that no draw allocates.
struct Scratch {
    subs: Substitutions,
    camera_uniforms: Vec<screen_space::CameraUniform>,
}

fn replay(
    gl: &Gl,
    app: &mut AppState,
    mv: &mut Multiview,
    group: &ShareGroup,
    layout: QuiltLayout,
    scratch: &mut Scratch,
    f: &impl Fn(u32),
) {
    let shift = shift::of(gl, app, mv, group);
    unscale_for_program(gl, app, mv, &mut scratch.subs);
    if app.draw_fbo == 0 && mv.plan.before_default_draw(shift.camera() || !scratch.subs.is_empty()) {
        // The views are complete up to here; what follows (a HUD) is drawn in every view.
        if mv.record.quilt.is_some() {
            DisparityRecord::release_bound(gl);
        }
        crate::multiview::fast::synthesis::warp(gl, mv);
    }
    if mv.scene.tracker.draw(app.draw_fbo, shift.scene(), app.viewport) {
        // The scene's depth is about to be drawn over: auto-convergence copies it first.
        crate::multiview::scene::convergence::take_depth(gl, app, mv);
    }
    if matches!(shift, Shift::Uniform { .. }) {
        set_remap_uniform(gl, app, mv);
    } else if fixed_remap_skipped(&shift, mv) {
        crate::log::once_for(
            ("remap-fixed-function", 0),
            crate::log::Level::Info,
            format_args!(
                "--depth-remap: fixed-function draws keep the plain shift (a projection matrix cannot bend disparity)"
            ),
        );
    }
    let fixed = matches!(shift, Shift::Projection { .. });
    let app_matrix_mode = fixed.then(|| app.matrix_mode(gl));
    let scissored = app.enabled(gl, SCISSOR_TEST);
    let records = if shift.camera() {
        super::record::wanted(app, mv)
    } else if overlay(&shift, app, mv) && !app.enabled(gl, BLEND) {
        // An opaque draw through an orthographic matrix into the scene's own framebuffer is
        // an overlay (wined3d draws a game's HUD there, not into the window): recorded as
        // on the screen plane, so the warps keep it in place. Not for auto-convergence
        // alone, which should not count a HUD as scene; a blended one (a tint, fog) leaves
        // the scene's record under it.
        super::record::wanted(app, mv).filter(|v| matches!(v, super::record::Views::All))
    } else {
        None
    };
    let blending = records.is_some() && app.enabled(gl, BLEND);
    // A fixed-function draw is recorded by drawing it again (`record_fixed`).
    let fixed = match (&shift, records) {
        (Shift::Projection { infinity, .. }, Some(_)) => {
            let c = if *infinity {
                0.0
            } else {
                mv.camera.rig.convergence as f32
            };
            super::record_fixed::plan(gl, mv.info, app, &mut mv.record_fixed, c)
        }
        _ => None,
    };
    let app: &AppState = app;
    let identity = matches!(shift, Shift::Uniform { camera: false, .. });
    screen_space::camera_uniforms(app, mv, identity, &mut scratch.camera_uniforms);
    let (subs, camera_uniforms) = (&scratch.subs, &scratch.camera_uniforms);
    // `(dh, geometry)`: the view's image moved by `dh` more (NDC), for a guard band's strip:
    // the camera matrices a pass un-projects with, and with `geometry` the draw's positions.
    let set_view = |mv: &Multiview, i: u32, (dh, geometry): (f32, bool)| {
        // After the warp point a synthesised view samples its nearest rendered view's layer.
        let layer = if mv.plan.renders(i) { i } else { mv.plan.nearest(i) };
        substitute::bind_layers(gl, app, subs, Some(layer as usize));
        screen_space::set_moved(gl, app, mv, camera_uniforms, Some((i, dh)));
        let dh = if geometry { dh } else { 0.0 };
        match shift {
            Shift::Uniform {
                loc, mode, infinity, ..
            } => set_view_uniform(gl, app.program, mv, loc, (i, dh), mode, infinity),
            Shift::Projection { p, infinity } => {
                let sheared = if infinity { &mv.sheared_far } else { &mv.sheared };
                load_projection(gl, &sheared.moved(&mv.camera.rig, &p, i, dh).0, app_matrix_mode)
            }
            Shift::None => {}
        }
    };
    if app.draw_fbo == 0 {
        let fragcoord = current_info(app).map_or(-1, |p| p.fragcoord_loc);
        let recorded = match records {
            Some(v) => super::record::quilt(gl, app, mv, v, blending).map(|writes| (writes, v)),
            // Nothing else may reach the record (`quilt::record`).
            None => {
                if mv.record.quilt.is_some() {
                    DisparityRecord::release_bound(gl);
                }
                None
            }
        };
        // `strip`: a guard band's strip of view i (its image shift and origin) instead of
        // its tile.
        let set_tile = |mv: &Multiview, i, strip: Option<&guard::StripDraw>| {
            set_view(mv, i, strip.map_or((0.0, false), |s| (s.dh, s.shifted)));
            let origin = strip.map_or_else(|| layout.origin(i), |s| s.origin);
            set_fragcoord(gl, app.program, fragcoord, Some((layout, origin)));
            if let Some((writes, views)) = recorded {
                super::record::tile(gl, views, writes, i);
            }
        };
        let fixed = fixed.zip(recorded.map(|r| r.1));
        let draw_and_record = |i: u32| {
            f(i);
            if let Some((fx, _)) = fixed.filter(|(_, v)| v.includes(i)) {
                fx.redraw(gl, || f(i));
            }
        };
        // A view that records alone is drawn last: its record's mask is set once.
        let last = recorded.and_then(|(_, v)| v.only());
        draw_tiles(
            gl,
            app,
            mv,
            (layout, last, shift.camera()),
            scissored,
            set_tile,
            &draw_and_record,
        );
        if let Some((writes, _)) = recorded {
            super::record::done(gl, mv, writes);
        }
        set_fragcoord(gl, app.program, fragcoord, None);
    } else if let Some(views) = layers::target_views(gl, mv, app.draw_fbo, shift.camera(), subs) {
        let record = records.and_then(|v| Some((super::record::shadow(gl, app, mv, v, blending)?, v)));
        let scale = mv.shadows.get(&app.draw_fbo).map_or(LayerScale::ONE, |s| s.scale);
        let fragcoord = current_info(app).map_or(-1, |p| p.fragcoord_loc);
        let scaled = (!scale.is_one()).then(|| scale_pass(gl, app, scale, scissored, fragcoord));
        for (i, &fbo) in views.iter().enumerate() {
            // Off-screen passes run for the rendered views only; the others are warped.
            if !mv.plan.renders(i as u32) {
                continue;
            }
            // SAFETY: our view framebuffer in place of the app's; rebound below.
            unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo) };
            let recording = record.filter(|(_, v)| v.includes(i as u32));
            if let Some((img, _)) = recording {
                DisparityRecord::attach_bound(gl, img, i as i32);
            }
            set_view(mv, i as u32, (0.0, false));
            f(i as u32);
            if let Some(fx) = fixed.filter(|_| recording.is_some()) {
                fx.redraw(gl, || f(i as u32));
            }
            if recording.is_some() {
                DisparityRecord::release_bound(gl);
            }
        }
        if record.is_some() {
            mv.record.after_draw(gl);
        }
        // SAFETY: the app's own framebuffer back.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, app.draw_fbo) };
        if scaled.is_some() {
            unscale_pass(gl, app, scissored, fragcoord);
        }
    } else {
        // An unshadowed target sampling layered textures sees the centre view's layer.
        substitute::bind_layers(gl, app, subs, Some(mv.camera.rig.centre() as usize));
        centre_uniform(gl, app, mv);
        f(SINGLE);
        substitute::bind_layers(gl, app, subs, None);
        return;
    }
    substitute::bind_layers(gl, app, subs, None);
    screen_space::set(gl, app, mv, camera_uniforms, None);
    if let Shift::Projection { p, .. } = shift {
        load_projection(gl, &p, app_matrix_mode);
    }
    if let (Shift::Uniform { .. }, Some(info)) = (shift, current_info(app)) {
        // The program's view uniform now holds the last view's shift, not the centre's.
        info.centre_set.store(false, Ordering::Relaxed);
    }
}

/// A program that addresses texels in pixels gets its target and the textures it samples at
/// the app's size (`downscale`); the substitutions are found again when layers went.
fn unscale_for_program(gl: &Gl, app: &AppState, mv: &mut Multiview, subs: &mut Substitutions) {
    let Some(why) = current_info(app).and_then(|p| p.pixel_addressing) else {
        return;
    };
    if crate::multiview::shadows::downscale::context_scale(mv).is_one() {
        return;
    }
    if crate::multiview::shadows::downscale::before_pixel_addressing(gl, mv, app.draw_fbo, subs, why) {
        substitute::substitutions(app, mv, subs);
    }
}

/// Viewport, scissor and `gl_FragCoord` mapped from the app's pixels into layers of `scale`
/// for one draw (`unscale_pass` puts the app's back). The viewport keeps its fractions
/// (`glViewportIndexedf`, GL 4.1, which shadows need anyway).
fn scale_pass(gl: &Gl, app: &AppState, scale: LayerScale, scissored: bool, fragcoord: i32) {
    let v = scale.rect_f(app.viewport);
    let s = scale.rect_out(app.scissor);
    let f = scale.fragcoord();
    // SAFETY: viewport, scissor box and our own uniform; restored by `unscale_pass`.
    unsafe {
        gl.ViewportIndexedf(0, v[0], v[1], v[2], v[3]);
        if scissored {
            gl.Scissor(s[0], s[1], s[2], s[3]);
        }
        if fragcoord >= 0 {
            gl.ProgramUniform4f(app.program, fragcoord, f[0], f[1], f[2], f[3]);
        }
    }
}

fn unscale_pass(gl: &Gl, app: &AppState, scissored: bool, fragcoord: i32) {
    let (v, s) = (app.viewport, app.scissor);
    // SAFETY: the app's viewport and scissor back, our uniform to window coordinates.
    unsafe {
        gl.Viewport(v[0], v[1], v[2], v[3]);
        if scissored {
            gl.Scissor(s[0], s[1], s[2], s[3]);
        }
    }
    set_fragcoord(gl, app.program, fragcoord, None);
}

/// The link-time facts of the app's current program, as the last draw refreshed them.
fn current_info(app: &AppState) -> Option<&ProgramInfo> {
    (app.program != 0 && app.current.program == app.program)
        .then_some(app.current.info.as_deref())
        .flatten()
}

/// View `i`'s shift, its image moved by `dh` more (NDC: a guard band's strip, else 0).
fn set_view_uniform(
    gl: &Gl,
    program: u32,
    mv: &Multiview,
    loc: i32,
    (i, dh): (u32, f32),
    mode: ViewMode,
    infinity: bool,
) {
    let mut v = mv.camera.rig.params(i);
    v.h += dh;
    if infinity {
        // No convergence term: `x += k w` (view_shift.glsl reads c == 0 as parallax 1).
        v.c = 0.0;
    }
    // SAFETY: `loc` belongs to the program current in this context (ProgramUniform when
    // available, so separable pipelines work too).
    unsafe {
        if gl.ProgramUniform4f.is_loaded() {
            gl.ProgramUniform4f(program, loc, v.k, v.c, v.h, mode.as_uniform());
        } else {
            gl.Uniform4f(loc, v.k, v.c, v.h, mode.as_uniform());
        }
    }
}

/// The comfort remap in the current program, in its units of parallax (`camera::comfort`),
/// set only when it differs from what the program holds.
fn set_remap_uniform(gl: &Gl, app: &AppState, mv: &Multiview) {
    let Some(info) = current_info(app).filter(|p| p.remap_loc >= 0) else {
        return;
    };
    let value = crate::multiview::quilt::comfort::remap_uniform(mv);
    let held = info.remap_set.each_ref().map(|a| a.load(Ordering::Relaxed));
    if held == value.map(f32::to_bits) {
        return;
    }
    for (a, v) in info.remap_set.iter().zip(value) {
        a.store(v.to_bits(), Ordering::Relaxed);
    }
    // SAFETY: our own uniform in the program current in this context.
    unsafe {
        if gl.ProgramUniform4f.is_loaded() {
            gl.ProgramUniform4f(app.program, info.remap_loc, value[0], value[1], value[2], value[3]);
        } else {
            gl.Uniform4f(info.remap_loc, value[0], value[1], value[2], value[3]);
        }
    }
}

fn fixed_remap_skipped(shift: &Shift, mv: &Multiview) -> bool {
    matches!(shift, Shift::Projection { .. }) && mv.settings.comfort.remap.is_some()
}

/// Puts the centre view into the current program's view uniform, unless it holds it already.
fn centre_uniform(gl: &Gl, app: &AppState, mv: &Multiview) {
    let Some(info) = current_info(app).filter(|p| p.view_loc >= 0) else {
        return;
    };
    if !info.centre_set.swap(true, Ordering::Relaxed) {
        set_view_uniform(
            gl,
            app.program,
            mv,
            info.view_loc,
            (mv.camera.rig.centre(), 0.0),
            ViewMode::Unknown,
            false,
        );
    }
}

/// A draw that is not replayed (into one of the app's own framebuffers, or one whose side
/// effects must happen once): the centre view only.
fn draw_single(gl: &Gl, app: &mut AppState, mv: &Multiview, group: &ShareGroup, f: impl Fn()) {
    if app.program != 0 {
        app.current.current(group, app.program);
        centre_uniform(gl, app, mv);
    }
    f()
}

/// Draws whose side effects must happen once: transform feedback captures every replay,
/// selection/feedback modes (picking) count every replay, and with rasterisation discarded
/// there is nothing per view to draw.
fn captures_once(gl: &Gl, app: &mut AppState) -> bool {
    app.transform_feedback || app.selecting || app.enabled(gl, RASTERIZER_DISCARD)
}

/// `holoinject_fragcoord` of the current program: where window pixel (0, 0) of the view is
/// (its tile's origin, or a guard strip's) and the window/tile scale, or (0, 0, 1, 1)
/// outside tiles.
fn set_fragcoord(gl: &Gl, program: u32, loc: i32, tile: Option<(QuiltLayout, (i32, i32))>) {
    if loc < 0 {
        return;
    }
    let v = tile.map_or([0.0, 0.0, 1.0, 1.0], |(l, (ox, oy))| {
        [
            ox as f32,
            oy as f32,
            l.window_w as f32 / l.tile_w as f32,
            l.window_h as f32 / l.tile_h as f32,
        ]
    });
    // SAFETY: our own uniform in the current program.
    unsafe { gl.ProgramUniform4f(program, loc, v[0], v[1], v[2], v[3]) };
}

/// The tile loop: viewport and scissor mapped into each view's tile; then, while the scene
/// is drawn, the guard band's strips (`fast::guard`), `shifted` when the draw is seen
/// through the camera.
fn draw_tiles(
    gl: &Gl,
    app: &AppState,
    mv: &Multiview,
    (layout, last, shifted): (QuiltLayout, Option<u32>, bool),
    scissored: bool,
    set_view: impl Fn(&Multiview, u32, Option<&guard::StripDraw>),
    f: &impl Fn(u32),
) {
    // SAFETY: viewport and scissor changes below are restored after the loop.
    unsafe { gl.Enable(SCISSOR_TEST) };
    let views = (0..layout.views()).filter(|&i| Some(i) != last).chain(last);
    for i in views.filter(|&i| mv.plan.draws(i)) {
        let vp = layout.map_rect(i, app.viewport);
        let tile = layout.tile_rect(i);
        let sc = if scissored {
            intersect(layout.map_rect(i, app.scissor), tile)
        } else {
            tile
        };
        // SAFETY: as above.
        unsafe {
            gl.Viewport(vp[0], vp[1], vp[2], vp[3]);
            gl.Scissor(sc[0], sc[1], sc[2], sc[3]);
        }
        set_view(mv, i, None);
        f(i);
    }
    let band = guard::drawn_now(mv);
    if band > 0 {
        let rects = (app.viewport, scissored.then_some(app.scissor));
        guard::strip_draws(mv, layout, band, rects, shifted, |strip| {
            let (vp, sc) = (strip.viewport, strip.scissor);
            // SAFETY: as above.
            unsafe {
                gl.Viewport(vp[0], vp[1], vp[2], vp[3]);
                gl.Scissor(sc[0], sc[1], sc[2], sc[3]);
            }
            set_view(mv, strip.view, Some(&strip));
            mv.guard_meter.time(|| f(strip.view));
        });
    }
    let (v, s) = (app.viewport, app.scissor);
    // SAFETY: the app's viewport, scissor and scissor test back.
    unsafe {
        gl.Viewport(v[0], v[1], v[2], v[3]);
        gl.Scissor(s[0], s[1], s[2], s[3]);
        if !scissored {
            gl.Disable(SCISSOR_TEST);
        }
    }
}

/// Loads `m` as the projection and returns to the app's matrix mode: the draw itself (a
/// display list, say) may push and multiply whatever matrix the app had selected.
fn load_projection(gl: &Gl, m: &[f32; 16], app_mode: Option<u32>) {
    // SAFETY: compatibility-context matrix calls; the app's mode is put back.
    unsafe {
        gl.MatrixMode(PROJECTION);
        gl.LoadMatrixf(m.as_ptr());
        gl.MatrixMode(app_mode.unwrap_or(MODELVIEW));
    }
}

/// A draw over the scene (a HUD): through an orthographic projection of the program's, or
/// with its positions given in clip space (a pass-through vertex shader: a Direct3D 10/11
/// HUD under wined3d) into the scene's framebuffer after the camera drew there this frame.
/// Exact mode leaves a clip-space draw unshifted, so the screen plane is the disparity exact
/// gives it; before the camera's draws (a full-screen pass that fills the target, a sky quad)
/// it is not taken for one.
fn overlay(shift: &Shift, app: &AppState, mv: &Multiview) -> bool {
    match shift {
        Shift::Uniform {
            mode: ViewMode::Orthographic,
            ..
        } => true,
        Shift::Uniform { camera: false, .. } => {
            mv.scene.tracker.target == Some(app.draw_fbo)
                && mv.scene.tracker.phase != crate::multiview::scene::tracker::Phase::Waiting
        }
        _ => false,
    }
}
