//! One draw call, replayed once per view into its tile.
//!
//! Per view only three things change: the viewport (the app's, mapped into the tile), the
//! scissor (clamped to the tile so wide lines, points and clears never bleed into a
//! neighbour), and the view shift — the injected uniform for shader programs, or the
//! projection matrix for fixed-function draws. Everything is put back afterwards.

use super::Multiview;
use super::layout::{QuiltLayout, intersect};
use super::{layers, screen_space};
use crate::camera::projection::{self, ProjectionKind};
use crate::gl::*;
use crate::shader::ViewMode;
use crate::state::AppState;
use crate::state::ShareGroup;
use crate::state::share::ProgramInfo;

/// How a draw's views differ.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shift {
    /// `holoinject_view` at this location, with the shader-side projection mode (see
    /// `glsl-patches/view_shift.glsl`); `camera`: the draw is seen through the main camera
    /// (not a full-screen pass with positions given in NDC).
    Uniform { loc: i32, mode: ViewMode, camera: bool },
    /// Fixed function: the app's projection, sheared per view.
    Projection([f32; 16]),
    /// Nothing view-dependent (orthographic fixed function, or a program we left alone).
    None,
}

impl Shift {
    /// A draw that makes its target view-dependent.
    fn camera(&self) -> bool {
        match self {
            Shift::Uniform { mode, camera, .. } => *camera && *mode != ViewMode::Orthographic,
            Shift::Projection(_) => true,
            Shift::None => false,
        }
    }
}

fn fixed_function_projection(gl: &Gl) -> Option<[f32; 16]> {
    let mut p = [0f32; 16];
    // SAFETY: a 16-float query into a local array.
    unsafe { gl.GetFloatv(PROJECTION_MATRIX, p.as_mut_ptr()) };
    Some(p)
}

fn program_name(program: u32) -> String {
    match program {
        0 => "fixed function".to_string(),
        p => format!("program {p}"),
    }
}

fn mode_of(app: &AppState, matrix: Option<[f32; 16]>, mv: &mut Multiview) -> ViewMode {
    match matrix.and_then(|m| projection::classify(&m)) {
        Some(p) if p.kind == ProjectionKind::Orthographic => ViewMode::Orthographic,
        Some(p) => {
            let m = matrix.unwrap_or_default();
            if m[3] == 0.0 && m[7] == 0.0 && m[15] == 0.0 && m[11] < 0.0 {
                mv.camera.camera_projection = Some(m);
            }
            if let Some(d) = p.depth {
                if mv.camera.last_depth.is_none() {
                    let far = if d.far().is_finite() {
                        format!("{:.6}", d.far())
                    } else {
                        "infinite".into()
                    };
                    crate::log::info(format_args!(
                        "{}: perspective projection, near {:.6}, far {far}{}",
                        program_name(app.program),
                        d.near(),
                        if d.a > 0.0 { " (reversed-Z)" } else { "" }
                    ));
                }
                mv.camera.last_depth = p.depth;
                mv.camera.last_fx = p.fx.or(mv.camera.last_fx);
            }
            if let Some(issue) = p.issue {
                crate::log::once_for(
                    ("depth-issue", u64::from(app.program)),
                    crate::log::Level::Info,
                    format_args!(
                        "{}: its projection has a {issue} (the shift stays exact; what cannot be \
                         read from it comes from the last good projection)",
                        program_name(app.program)
                    ),
                );
            }
            ViewMode::of(Some(&p))
        }
        None => {
            crate::log::once_for(
                ("unknown-projection", u64::from(app.program)),
                crate::log::Level::Debug,
                format_args!(
                    "{}: projection unknown or not finite; w == 1 vertices are left unshifted",
                    program_name(app.program)
                ),
            );
            ViewMode::Unknown
        }
    }
}

fn shift_for(gl: &Gl, app: &AppState, mv: &mut Multiview, group: &ShareGroup) -> Shift {
    if app.program == 0 {
        if mv.info.es {
            return Shift::None;
        }
        return match fixed_function_projection(gl) {
            Some(p) if mode_of(app, Some(p), mv).is_perspective() => Shift::Projection(p),
            _ => Shift::None,
        };
    }
    let mut state = group.lock();
    let program = app.program;
    let tracked = |state: &crate::state::share::GroupState, loc: i32| state.matrices.get(&(program, loc)).copied();
    let Some(info) = state.programs.get(&program).filter(|p| p.view_loc >= 0) else {
        return Shift::None;
    };
    let (loc, builtin, plain, ubo, camera) = (
        info.view_loc,
        info.builtin_projection,
        info.projection_loc,
        info.projection_ubo,
        !info.identity,
    );
    let matrix = if builtin {
        fixed_function_projection(gl)
    } else if let Some(l) = plain {
        tracked(&state, l)
    } else {
        ubo.and_then(|m| ubo_projection(gl, state.programs.get_mut(&program)?, program, m))
    };
    drop(state);
    Shift::Uniform {
        loc,
        mode: mode_of(app, matrix, mv),
        camera,
    }
}

/// A block-held projection, read again only when buffers may have changed.
fn ubo_projection(
    gl: &Gl,
    info: &mut ProgramInfo,
    program: u32,
    m: crate::state::share::UboMember,
) -> Option<[f32; 16]> {
    let generation = super::ubo::generation();
    if let Some((_, value)) = info.ubo_cache.filter(|(g, _)| *g == generation) {
        return Some(value);
    }
    let value = super::ubo::read(gl, program, m)?;
    info.ubo_cache = Some((generation, value));
    Some(value)
}

fn set_view_uniform(gl: &Gl, app: &AppState, mv: &Multiview, loc: i32, i: u32, mode: ViewMode) {
    let v = mv.camera.rig.params(i);
    // SAFETY: `loc` belongs to the program current in this context (ProgramUniform when
    // available, so separable pipelines work too).
    unsafe {
        if gl.ProgramUniform4f.is_loaded() {
            gl.ProgramUniform4f(app.program, loc, v.k, v.c, v.h, mode.as_uniform());
        } else {
            gl.Uniform4f(loc, v.k, v.c, v.h, mode.as_uniform());
        }
    }
}

/// A draw into one of the app's own framebuffers: the centre view only.
fn draw_single(gl: &Gl, app: &AppState, mv: &Multiview, group: &ShareGroup, f: impl Fn()) {
    if app.program != 0 {
        let mut state = group.lock();
        if let Some(p) = state
            .programs
            .get_mut(&app.program)
            .filter(|p| p.view_loc >= 0 && !p.centre_set)
        {
            p.centre_set = true;
            let loc = p.view_loc;
            drop(state);
            set_view_uniform(gl, app, mv, loc, mv.camera.rig.centre(), ViewMode::Unknown);
        }
    }
    f()
}

/// Draws whose side effects must happen once: transform feedback captures every replay,
/// selection/feedback modes (picking) count every replay, and with rasterisation discarded
/// there is nothing per view to draw.
fn captures_once(gl: &Gl, app: &AppState) -> bool {
    // SAFETY: an enable query valid in GL 3.0+ / ES 3.0+, the only contexts with a quilt.
    app.transform_feedback || app.selecting || unsafe { gl.IsEnabled(RASTERIZER_DISCARD) } != 0
}

/// Replays `f` (the real draw) once per view when framebuffer 0 is the target.
pub fn draw(gl: &Gl, app: &AppState, mv: &mut Multiview, group: &ShareGroup, f: impl Fn()) {
    draw_views(gl, app, mv, group, |_| f())
}

/// View index passed to `draw_views`' callback when the draw is not replayed.
pub const SINGLE: u32 = u32::MAX;

/// `draw`, with the view index (or `SINGLE`) given to the callback, for draws that need
/// per-view work of their own (raster positions).
pub fn draw_views(gl: &Gl, app: &AppState, mv: &mut Multiview, group: &ShareGroup, f: impl Fn(u32)) {
    let Some(layout) = mv
        .layout()
        .filter(|_| !mv.failed && !app.compiling_list && !captures_once(gl, app))
    else {
        return draw_single(gl, app, mv, group, || f(SINGLE));
    };
    let subs = layers::substitutions(app, mv);
    let shift = shift_for(gl, app, mv, group);
    let identity = matches!(shift, Shift::Uniform { camera: false, .. });
    let camera_uniforms = screen_space::camera_uniforms(app, mv, group, identity);
    let app_matrix_mode =
        matches!(shift, Shift::Projection(_)).then(|| crate::gl::guard::get_i(gl, MATRIX_MODE) as u32);
    let set_view = |mv: &Multiview, i: u32| {
        layers::bind_layers(gl, app, &subs, Some(i as usize));
        screen_space::set(gl, app, mv, &camera_uniforms, Some(i));
        match shift {
            Shift::Uniform { loc, mode, .. } => set_view_uniform(gl, app, mv, loc, i, mode),
            Shift::Projection(p) => load_projection(gl, &sheared(mv, i, &p), app_matrix_mode),
            Shift::None => {}
        }
    };
    if app.draw_fbo == 0 {
        let fragcoord = fragcoord_loc(app, group);
        draw_tiles(
            gl,
            app,
            mv,
            layout,
            |mv, i| {
                set_view(mv, i);
                set_fragcoord(gl, app, fragcoord, Some((layout, i)));
            },
            &f,
        );
        set_fragcoord(gl, app, fragcoord, None);
    } else if let Some(views) = layers::target_views(gl, mv, app.draw_fbo, shift.camera(), &subs) {
        for (i, &fbo) in views.iter().enumerate() {
            // SAFETY: our view framebuffer in place of the app's; rebound below.
            unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo) };
            set_view(mv, i as u32);
            f(i as u32);
        }
        // SAFETY: the app's own framebuffer back.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, app.draw_fbo) };
    } else {
        // An unshadowed target sampling layered textures sees the centre view's layer.
        layers::bind_layers(gl, app, &subs, Some(mv.camera.rig.centre() as usize));
        draw_single(gl, app, mv, group, || f(SINGLE));
        layers::bind_layers(gl, app, &subs, None);
        return;
    }
    layers::bind_layers(gl, app, &subs, None);
    screen_space::set(gl, app, mv, &camera_uniforms, None);
    if let Shift::Projection(p) = shift {
        load_projection(gl, &p, app_matrix_mode);
    }
    finish_shift(app, &shift, group);
}

fn fragcoord_loc(app: &AppState, group: &ShareGroup) -> i32 {
    if app.program == 0 {
        return -1;
    }
    group.lock().programs.get(&app.program).map_or(-1, |p| p.fragcoord_loc)
}

/// `holoinject_fragcoord` of the current program: view i's tile origin and the window/tile
/// scale, or (0, 0, 1, 1) outside tiles.
fn set_fragcoord(gl: &Gl, app: &AppState, loc: i32, tile: Option<(QuiltLayout, u32)>) {
    if loc < 0 {
        return;
    }
    let v = tile.map_or([0.0, 0.0, 1.0, 1.0], |(l, i)| {
        let (ox, oy) = l.origin(i);
        [
            ox as f32,
            oy as f32,
            l.window_w as f32 / l.tile_w as f32,
            l.window_h as f32 / l.tile_h as f32,
        ]
    });
    // SAFETY: our own uniform in the current program.
    unsafe { gl.ProgramUniform4f(app.program, loc, v[0], v[1], v[2], v[3]) };
}

/// The tile loop: viewport and scissor mapped into each view's tile.
fn draw_tiles(
    gl: &Gl,
    app: &AppState,
    mv: &Multiview,
    layout: QuiltLayout,
    set_view: impl Fn(&Multiview, u32),
    f: &impl Fn(u32),
) {
    // SAFETY: viewport and scissor changes below are restored after the loop.
    let scissored = unsafe { gl.IsEnabled(SCISSOR_TEST) } != 0;
    unsafe { gl.Enable(SCISSOR_TEST) };
    for i in 0..layout.views() {
        let vp = layout.map_rect(i, app.viewport);
        let tile = layout.tile_rect(i);
        let sc = if scissored {
            intersect(layout.map_rect(i, app.scissor), tile)
        } else {
            tile
        };
        unsafe {
            gl.Viewport(vp[0], vp[1], vp[2], vp[3]);
            gl.Scissor(sc[0], sc[1], sc[2], sc[3]);
        }
        set_view(mv, i);
        f(i);
    }
    let (v, s) = (app.viewport, app.scissor);
    unsafe {
        gl.Viewport(v[0], v[1], v[2], v[3]);
        gl.Scissor(s[0], s[1], s[2], s[3]);
        if !scissored {
            gl.Disable(SCISSOR_TEST);
        }
    }
}

fn sheared(mv: &Multiview, i: u32, p: &[f32; 16]) -> [f32; 16] {
    mv.camera.rig.shear(i, &p.map(f64::from)).map(|v| v as f32)
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

/// The program's view uniform now holds the last view's shift, not the centre's.
fn finish_shift(app: &AppState, shift: &Shift, group: &ShareGroup) {
    if let Shift::Uniform { .. } = shift {
        if let Some(p) = group.lock().programs.get_mut(&app.program) {
            p.centre_set = false;
        }
    }
}

/// Link-time facts about a program, as the replay needs them.
pub fn program_info(
    view_loc: i32,
    projection_loc: Option<i32>,
    builtin_projection: bool,
    projection_ubo: Option<crate::state::share::UboMember>,
    identity: bool,
    fragcoord_loc: i32,
) -> ProgramInfo {
    ProgramInfo {
        view_loc,
        projection_loc,
        projection_ubo,
        ubo_cache: None,
        identity,
        fragcoord_loc,
        builtin_projection,
        centre_set: false,
        hidden_uniforms: Vec::new(),
    }
}
