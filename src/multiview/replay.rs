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
use crate::state::ShareGroup;
use crate::state::share::ProgramInfo;

/// Shader-side projection mode (see `glsl-patches/view_shift.glsl`).
#[derive(Clone, Copy, Debug, PartialEq)]

/// How a draw's views differ.
enum Shift {
    /// `holoinject_view` at this location; `camera`: the draw is seen through the main
    /// camera (not a full-screen pass with positions given in NDC).
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

fn mode_of(matrix: Option<[f32; 16]>, mv: &mut Multiview) -> ViewMode {
    match matrix.and_then(|m| projection::classify(&m)) {
        Some(p) if p.kind == ProjectionKind::Orthographic => ViewMode::Orthographic,
        Some(p) => {
            let m = matrix.unwrap_or_default();
            if m[3] == 0.0 && m[7] == 0.0 && m[15] == 0.0 && m[11] < 0.0 {
                mv.camera_projection = Some(m);
            }
            if let Some(d) = p.depth {
                if mv.last_depth.is_none() {
                    let far = if d.far().is_finite() {
                        format!("{:.6}", d.far())
                    } else {
                        "infinite".into()
                    };
                    crate::log::info(format_args!(
                        "{}: perspective projection, near {:.6}, far {far}{}",
                        program_name(mv.program),
                        d.near(),
                        if d.a > 0.0 { " (reversed-Z)" } else { "" }
                    ));
                }
                mv.last_depth = p.depth;
                mv.last_fx = p.fx.or(mv.last_fx);
            }
            if let Some(issue) = p.issue {
                crate::log::once_for(
                    ("depth-issue", u64::from(mv.program)),
                    crate::log::Level::Info,
                    format_args!(
                        "{}: its projection has a {issue} (the shift stays exact; what cannot be \
                         read from it comes from the last good projection)",
                        program_name(mv.program)
                    ),
                );
            }
            ViewMode::of(Some(&p))
        }
        None => {
            crate::log::once_for(
                ("unknown-projection", u64::from(mv.program)),
                crate::log::Level::Debug,
                format_args!(
                    "{}: projection unknown or not finite; w == 1 vertices are left unshifted",
                    program_name(mv.program)
                ),
            );
            ViewMode::Unknown
        }
    }
}

/// Where the current program's projection comes from, copied out of its share group: the
/// group's lock is never held across a GL call (GL may call the app back, and the app us).
enum ProjectionSource {
    /// The compatibility built-ins: `GL_PROJECTION`.
    Builtin,
    /// A plain uniform, with its last uploaded value.
    Tracked(Option<[f32; 16]>),
    /// A uniform-block member, with the value last read and its buffer generation.
    Block(super::ubo::UboMember, Option<(u64, [f32; 16])>),
    Unknown,
}

/// `holoinject_view`'s location, whether the program sees through the main camera, and where
/// its projection comes from; `None` for programs we left alone.
fn program_projection(group: &ShareGroup, program: u32) -> Option<(i32, bool, ProjectionSource)> {
    let state = group.lock();
    let info = state.programs.get(&program).filter(|p| p.view_loc >= 0)?;
    let source = if info.builtin_projection {
        ProjectionSource::Builtin
    } else if let Some(l) = info.projection_loc {
        ProjectionSource::Tracked(state.matrices.get(&(program, l)).copied())
    } else if let Some(m) = info.projection_ubo {
        ProjectionSource::Block(m, info.ubo_cache)
    } else {
        ProjectionSource::Unknown
    };
    Some((info.view_loc, !info.identity, source))
}

fn shift_for(gl: &Gl, mv: &mut Multiview, group: &ShareGroup) -> Shift {
    if mv.program == 0 {
        if mv.info.es {
            return Shift::None;
        }
        return match fixed_function_projection(gl) {
            Some(p) if mode_of(Some(p), mv).is_perspective() => Shift::Projection(p),
            _ => Shift::None,
        };
    }
    let Some((loc, camera, source)) = program_projection(group, mv.program) else {
        return Shift::None;
    };
    let matrix = match source {
        ProjectionSource::Builtin => fixed_function_projection(gl),
        ProjectionSource::Tracked(m) => m,
        ProjectionSource::Block(m, cache) => ubo_projection(gl, group, mv.program, m, cache),
        ProjectionSource::Unknown => None,
    };
    Shift::Uniform {
        loc,
        mode: mode_of(matrix, mv),
        camera,
    }
}

/// A block-held projection, read again only when buffers may have changed.
fn ubo_projection(
    gl: &Gl,
    group: &ShareGroup,
    program: u32,
    m: super::ubo::UboMember,
    cache: Option<(u64, [f32; 16])>,
) -> Option<[f32; 16]> {
    let generation = super::ubo::generation();
    if let Some((_, value)) = cache.filter(|(g, _)| *g == generation) {
        return Some(value);
    }
    let value = super::ubo::read(gl, program, m)?;
    if let Some(info) = group.lock().programs.get_mut(&program) {
        info.ubo_cache = Some((generation, value));
    }
    Some(value)
}

fn set_view_uniform(gl: &Gl, mv: &Multiview, loc: i32, i: u32, mode: ViewMode) {
    let v = mv.rig.params(i);
    // SAFETY: `loc` belongs to the program current in this context (ProgramUniform when
    // available, so separable pipelines work too).
    unsafe {
        if gl.ProgramUniform4f.is_loaded() {
            gl.ProgramUniform4f(mv.program, loc, v.k, v.c, v.h, mode.as_uniform());
        } else {
            gl.Uniform4f(loc, v.k, v.c, v.h, mode.as_uniform());
        }
    }
}

/// A draw into one of the app's own framebuffers: the centre view only.
fn draw_single(gl: &Gl, mv: &Multiview, group: &ShareGroup, f: impl Fn()) {
    if mv.program != 0 {
        let mut state = group.lock();
        if let Some(p) = state
            .programs
            .get_mut(&mv.program)
            .filter(|p| p.view_loc >= 0 && !p.centre_set)
        {
            p.centre_set = true;
            let loc = p.view_loc;
            drop(state);
            set_view_uniform(gl, mv, loc, mv.rig.centre(), ViewMode::Unknown);
        }
    }
    f()
}

/// Draws whose side effects must happen once: transform feedback captures every replay,
/// selection/feedback modes (picking) count every replay, and with rasterisation discarded
/// there is nothing per view to draw.
fn captures_once(gl: &Gl, mv: &Multiview) -> bool {
    // SAFETY: an enable query valid in GL 3.0+ / ES 3.0+, the only contexts with a quilt.
    mv.transform_feedback || mv.selecting || unsafe { gl.IsEnabled(RASTERIZER_DISCARD) } != 0
}

/// Replays `f` (the real draw) once per view when framebuffer 0 is the target.
pub fn draw(gl: &Gl, mv: &mut Multiview, group: &ShareGroup, f: impl Fn()) {
    draw_views(gl, mv, group, |_| f())
}

/// View index passed to `draw_views`' callback when the draw is not replayed.
pub const SINGLE: u32 = u32::MAX;

/// `draw`, with the view index (or `SINGLE`) given to the callback, for draws that need
/// per-view work of their own (raster positions).
pub fn draw_views(gl: &Gl, mv: &mut Multiview, group: &ShareGroup, f: impl Fn(u32)) {
    let Some(layout) = mv
        .layout()
        .filter(|_| !mv.failed && !mv.compiling_list && !captures_once(gl, mv))
    else {
        return draw_single(gl, mv, group, || f(SINGLE));
    };
    let subs = layers::substitutions(mv);
    let shift = shift_for(gl, mv, group);
    let identity = matches!(shift, Shift::Uniform { camera: false, .. });
    let camera_uniforms = screen_space::camera_uniforms(mv, group, identity);
    let app_matrix_mode =
        matches!(shift, Shift::Projection(_)).then(|| crate::gl::guard::get_i(gl, MATRIX_MODE) as u32);
    let set_view = |mv: &Multiview, i: u32| {
        layers::bind_layers(gl, mv, &subs, Some(i as usize));
        screen_space::set(gl, mv, &camera_uniforms, Some(i));
        match shift {
            Shift::Uniform { loc, mode, .. } => set_view_uniform(gl, mv, loc, i, mode),
            Shift::Projection(p) => load_projection(gl, &sheared(mv, i, &p), app_matrix_mode),
            Shift::None => {}
        }
    };
    if mv.app.draw_fbo == 0 {
        let fragcoord = fragcoord_loc(mv, group);
        draw_tiles(
            gl,
            mv,
            layout,
            |mv, i| {
                set_view(mv, i);
                set_fragcoord(gl, mv, fragcoord, Some((layout, i)));
            },
            &f,
        );
        set_fragcoord(gl, mv, fragcoord, None);
    } else if let Some(views) = layers::target_views(gl, mv, mv.app.draw_fbo, shift.camera(), &subs) {
        for (i, &fbo) in views.iter().enumerate() {
            // SAFETY: our view framebuffer in place of the app's; rebound below.
            unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, fbo) };
            set_view(mv, i as u32);
            f(i as u32);
        }
        // SAFETY: the app's own framebuffer back.
        unsafe { gl.BindFramebuffer(DRAW_FRAMEBUFFER, mv.app.draw_fbo) };
    } else {
        // An unshadowed target sampling layered textures sees the centre view's layer.
        layers::bind_layers(gl, mv, &subs, Some(mv.rig.centre() as usize));
        draw_single(gl, mv, group, || f(SINGLE));
        layers::bind_layers(gl, mv, &subs, None);
        return;
    }
    layers::bind_layers(gl, mv, &subs, None);
    screen_space::set(gl, mv, &camera_uniforms, None);
    if let Shift::Projection(p) = shift {
        load_projection(gl, &p, app_matrix_mode);
    }
    finish_shift(mv, &shift, group);
}

fn fragcoord_loc(mv: &Multiview, group: &ShareGroup) -> i32 {
    if mv.program == 0 {
        return -1;
    }
    group.lock().programs.get(&mv.program).map_or(-1, |p| p.fragcoord_loc)
}

/// `holoinject_fragcoord` of the current program: view i's tile origin and the window/tile
/// scale, or (0, 0, 1, 1) outside tiles.
fn set_fragcoord(gl: &Gl, mv: &Multiview, loc: i32, tile: Option<(QuiltLayout, u32)>) {
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
    unsafe { gl.ProgramUniform4f(mv.program, loc, v[0], v[1], v[2], v[3]) };
}

/// The tile loop: viewport and scissor mapped into each view's tile.
fn draw_tiles(gl: &Gl, mv: &Multiview, layout: QuiltLayout, set_view: impl Fn(&Multiview, u32), f: &impl Fn(u32)) {
    // SAFETY: a capability query, valid in every context.
    let scissored = unsafe { gl.IsEnabled(SCISSOR_TEST) } != 0;
    // SAFETY: the scissor test, viewport and scissor changed here are restored after the loop.
    unsafe { gl.Enable(SCISSOR_TEST) };
    for i in 0..layout.views() {
        let vp = layout.map_rect(i, mv.app.viewport);
        let tile = layout.tile_rect(i);
        let sc = if scissored {
            intersect(layout.map_rect(i, mv.app.scissor), tile)
        } else {
            tile
        };
        // SAFETY: as above: restored after the loop.
        unsafe {
            gl.Viewport(vp[0], vp[1], vp[2], vp[3]);
            gl.Scissor(sc[0], sc[1], sc[2], sc[3]);
        }
        set_view(mv, i);
        f(i);
    }
    let (v, s) = (mv.app.viewport, mv.app.scissor);
    // SAFETY: the app's viewport, scissor and scissor test back.
    unsafe {
        gl.Viewport(v[0], v[1], v[2], v[3]);
        gl.Scissor(s[0], s[1], s[2], s[3]);
        if !scissored {
            gl.Disable(SCISSOR_TEST);
        }
    }
}

fn sheared(mv: &Multiview, i: u32, p: &[f32; 16]) -> [f32; 16] {
    mv.rig.shear(i, &p.map(f64::from)).map(|v| v as f32)
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
fn finish_shift(mv: &Multiview, shift: &Shift, group: &ShareGroup) {
    if let Shift::Uniform { .. } = shift
        && let Some(p) = group.lock().programs.get_mut(&mv.program)
    {
        p.centre_set = false;
    }
}

/// Link-time facts about a program, as the replay needs them.
pub fn program_info(
    view_loc: i32,
    projection_loc: Option<i32>,
    builtin_projection: bool,
    projection_ubo: Option<super::ubo::UboMember>,
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
