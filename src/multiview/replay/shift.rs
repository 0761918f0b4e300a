//! How a draw's views differ, decided once per draw from what the layer already knows: the
//! current program's link-time facts and projection (`state::program`), or the shadowed
//! fixed-function projection. Nothing here locks the share group or asks GL, except once
//! after something the layer could not follow (a relink elsewhere, `glPopAttrib`).

use crate::camera::projection::{self, ProjectionKind};
use crate::gl::Gl;
use crate::multiview::Multiview;
use crate::shader::ViewMode;
use crate::state::share::UboMember;
use crate::state::{AppState, ShareGroup};

/// How a draw's views differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shift {
    /// `holoinject_view` at this location, with the shader-side projection mode (see
    /// `glsl-patches/view_shift.glsl`); `camera`: the draw is seen through the main camera
    /// (not a full-screen pass with positions given in NDC).
    /// `infinity`: the draw is attached to the camera and gets the shift of infinity.
    Uniform {
        loc: i32,
        mode: ViewMode,
        camera: bool,
        infinity: bool,
    },
    /// Fixed function: the app's projection, sheared per view; `infinity`: the draw is
    /// attached to the camera (`camera::attached`) and gets the shift of infinity.
    Projection { p: [f32; 16], infinity: bool },
    /// Nothing view-dependent (orthographic fixed function, or a program we left alone).
    None,
}

impl Shift {
    /// A draw that makes its target view-dependent.
    pub fn camera(&self) -> bool {
        match self {
            Shift::Uniform { mode, camera, .. } => *camera && *mode != ViewMode::Orthographic,
            Shift::Projection { .. } => true,
            Shift::None => false,
        }
    }

    /// A draw of the scene seen through the camera: view-dependent and not attached to the
    /// camera (a sky around the eye sets no scene depth: a depth clear after it is not the
    /// scene's end).
    pub fn scene(&self) -> bool {
        match self {
            Shift::Uniform { infinity, .. } | Shift::Projection { infinity, .. } => self.camera() && !infinity,
            Shift::None => false,
        }
    }
}

/// The shift of the draw about to be made with the app's current program (or fixed
/// function).
pub fn of(gl: &Gl, app: &mut AppState, mv: &mut Multiview, group: &ShareGroup) -> Shift {
    let program = app.program;
    if program == 0 {
        if mv.info.es {
            return Shift::None;
        }
        let p = app.fixed_projection(gl);
        return match mode_of(program, Some(p), true, mv) {
            m if m.is_perspective() => {
                let infinity = fixed_attached(gl, app, mv, &p);
                if let Some(r) = mv.reuse.as_mut().filter(|_| !infinity) {
                    r.camera.see(0, &[], &[]);
                }
                Shift::Projection { p, infinity }
            }
            _ => Shift::None,
        };
    }
    let snapshot = app.current.current(group, program);
    let Some(info) = snapshot.info.clone().filter(|p| p.view_loc >= 0) else {
        return Shift::None;
    };
    let matrix = if info.builtin_projection {
        Some(app.fixed_projection(gl))
    } else if info.projection_loc.is_some() {
        snapshot.projection
    } else {
        info.projection_ubo.and_then(|m| ubo_projection(gl, app, program, m))
    };
    // A matrix read from a vec4 array (wined3d's `vs_c`) may be followed by the shader's own
    // depth edit (Direct3D's [0, w] made GL's [-w, w]): its depth terms are not the draw's.
    let mode = mode_of(program, matrix, info.projection_vec4.is_none(), mv);
    let infinity = mode.is_perspective() && !info.identity && program_attached(gl, app, mv, group, &info);
    if mode.is_perspective()
        && !info.identity
        && !infinity
        && let Some(r) = mv.reuse.as_mut()
    {
        let values = &app.current.current(group, program).matrices;
        r.camera.see(program, &info.camera_chain, values);
    }
    Shift::Uniform {
        loc: info.view_loc,
        mode,
        camera: !info.identity,
        infinity,
    }
}

/// Whether a fixed-function draw is attached to the camera (`camera::attached`): asked of
/// the shadowed model-view, so GL is asked only after the model-view changed.
fn fixed_attached(gl: &Gl, app: &mut AppState, mv: &Multiview, projection: &[f32; 16]) -> bool {
    if !mv.settings.sky_at_infinity {
        return false;
    }
    let modelview = app.fixed_modelview(gl);
    let attached = crate::camera::attached::camera_attached(projection, &modelview, || app.depth_writes(gl));
    if attached {
        crate::log::once_for(
            ("camera-attached", 0),
            crate::log::Level::Info,
            format_args!(
                "fixed function: draws under the camera's rotation alone (a sky around the eye) are \
                 put at infinity (--sky-at-infinity off keeps them at their depth)"
            ),
        );
    }
    attached
}

/// Longest `gl_Position` chain of uniforms read for the camera-attached test (P·V·M is 3).
const MAX_CHAIN: usize = 8;

/// Whether a draw of `info`'s program is attached to the camera: by the fixed model-view
/// for programs built on the compatibility matrices, else by its `gl_Position` chain.
fn program_attached(
    gl: &Gl,
    app: &mut AppState,
    mv: &Multiview,
    group: &ShareGroup,
    info: &crate::state::share::ProgramInfo,
) -> bool {
    if !mv.settings.sky_at_infinity {
        return false;
    }
    let attached = if info.builtin_projection {
        let (projection, modelview) = (app.fixed_projection(gl), app.fixed_modelview(gl));
        crate::camera::attached::camera_attached(&projection, &modelview, || app.depth_writes(gl))
    } else {
        let values = &app.current.current(group, app.program).matrices;
        // On the stack: this runs for every perspective draw, and replays do not allocate.
        let mut chain = [[0f32; 16]; MAX_CHAIN];
        let n = info.camera_chain.len();
        let found = n <= MAX_CHAIN
            && info
                .camera_chain
                .iter()
                .zip(chain.iter_mut())
                .all(|(loc, slot)| values.iter().find(|(l, _)| l == loc).map(|(_, m)| *slot = *m).is_some());
        let projection = info
            .projection_loc
            .and_then(|p| info.camera_chain.iter().position(|&l| l == p));
        found && crate::camera::attached::chain_attached(&chain[..n], projection)
    };
    if attached {
        crate::log::once_for(
            ("camera-attached", u64::from(app.program)),
            crate::log::Level::Info,
            format_args!(
                "program {}: draws whose view has no translation (a sky around the eye) are put at \
                 infinity (--sky-at-infinity off keeps them at their depth)",
                app.program
            ),
        );
    }
    attached
}

/// A block-held projection, read again only when a buffer that can reach a uniform binding
/// was written since.
fn ubo_projection(gl: &Gl, app: &mut AppState, program: u32, m: UboMember) -> Option<[f32; 16]> {
    let generation = super::ubo::generation();
    if let Some((_, value)) = app.current.ubo_cache.filter(|(g, _)| *g == generation) {
        return Some(value);
    }
    let value = super::ubo::read(gl, program, m)?;
    app.current.ubo_cache = Some((generation, value));
    Some(value)
}

/// "program N" or "fixed function", formatted only when a log line is written.
struct ProgramName(u32);

impl std::fmt::Display for ProgramName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            0 => f.write_str("fixed function"),
            p => write!(f, "program {p}"),
        }
    }
}

/// The shader-side projection mode of `matrix`; a perspective one also updates the camera
/// estimate (focal scale and, when `depth` says its depth terms are the draw's, the depth
/// model and the bare camera projection; else the depth model is fitted to what is drawn).
fn mode_of(program: u32, matrix: Option<[f32; 16]>, depth: bool, mv: &mut Multiview) -> ViewMode {
    let name = ProgramName(program);
    let Some(p) = matrix.and_then(|m| projection::classify(&m)) else {
        crate::log::once_for(
            ("unknown-projection", u64::from(program)),
            crate::log::Level::Debug,
            format_args!("{name}: projection unknown or not finite; w == 1 vertices are left unshifted"),
        );
        return ViewMode::Unknown;
    };
    if p.kind == ProjectionKind::Orthographic {
        return ViewMode::Orthographic;
    }
    if !depth {
        mv.camera.last_fx = p.fx.or(mv.camera.last_fx);
        return ViewMode::of(Some(&p));
    }
    let m = matrix.unwrap_or_default();
    if m[3] == 0.0 && m[7] == 0.0 && m[15] == 0.0 && m[11] < 0.0 {
        mv.camera.camera_projection = Some(m);
    }
    if let Some(d) = p.depth {
        if mv.camera.last_depth.is_none() || mv.camera.depth_fitted {
            crate::log::info(format_args!(
                "{name}: perspective projection, near {:.6}, far {}{}",
                d.near(),
                Far(d.far()),
                if d.a > 0.0 { " (reversed-Z)" } else { "" }
            ));
        }
        mv.camera.last_depth = p.depth;
        mv.camera.depth_fitted = false;
        mv.camera.last_fx = p.fx.or(mv.camera.last_fx);
    }
    if let Some(issue) = p.issue {
        crate::log::once_for(
            ("depth-issue", u64::from(program)),
            crate::log::Level::Info,
            format_args!(
                "{name}: its projection has a {issue} (the shift stays exact; what cannot be \
                 read from it comes from the last good projection)"
            ),
        );
    }
    ViewMode::of(Some(&p))
}

struct Far(f64);

impl std::fmt::Display for Far {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() {
            write!(f, "{:.6}", self.0)
        } else {
            f.write_str("infinite")
        }
    }
}

/// The fixed-function projection of each view, computed once per projection and rig (not
/// per draw).
/// (Interior mutability: it is filled while replays hold the rest of `Multiview` shared.)
#[derive(Default)]
pub struct ShearedProjections(std::cell::RefCell<Sheared>);

#[derive(Default)]
struct Sheared {
    /// Shears of infinity (`x += k w`: no convergence term), for camera-attached draws.
    infinity: bool,
    source: Option<([f32; 16], [u64; 4])>,
    /// Per view: the shear and its inverse (for passes that un-project), both made in f64.
    views: Vec<([f32; 16], [f32; 16])>,
}

impl ShearedProjections {
    /// The shears that put everything at infinity.
    pub fn at_infinity() -> ShearedProjections {
        ShearedProjections(std::cell::RefCell::new(Sheared {
            infinity: true,
            ..Default::default()
        }))
    }

    /// View `i`'s shear of `p`.
    pub fn get(&self, rig: &crate::camera::ViewRig, p: &[f32; 16], i: u32) -> [f32; 16] {
        self.both(rig, p, i).0
    }

    /// The inverse of view `i`'s shear of `p` (the shear itself if it is singular).
    pub fn inverse(&self, rig: &crate::camera::ViewRig, p: &[f32; 16], i: u32) -> [f32; 16] {
        self.both(rig, p, i).1
    }

    /// View `i`'s shear of `p` with its image moved by `dh` more (NDC), and its inverse: a
    /// guard band's strip (`fast::guard`), made for the draw (not kept: a strip is two
    /// draws of the frame's many).
    pub fn moved(&self, rig: &crate::camera::ViewRig, p: &[f32; 16], i: u32, dh: f32) -> ([f32; 16], [f32; 16]) {
        if dh == 0.0 {
            return self.both(rig, p, i);
        }
        let infinity = self.0.borrow().infinity;
        let rig = crate::camera::ViewRig {
            convergence: if infinity { 0.0 } else { rig.convergence },
            ..*rig
        };
        let m = rig.shear_moved(i, &p.map(f64::from), f64::from(dh));
        let inv = crate::camera::invert(&m).unwrap_or(m);
        (m.map(|x| x as f32), inv.map(|x| x as f32))
    }

    fn both(&self, rig: &crate::camera::ViewRig, p: &[f32; 16], i: u32) -> ([f32; 16], [f32; 16]) {
        let mut s = self.0.borrow_mut();
        let key = (
            *p,
            [
                rig.depthiness.to_bits(),
                rig.convergence.to_bits(),
                rig.focus.to_bits(),
                u64::from(rig.views),
            ],
        );
        if s.source != Some(key) {
            let p64 = p.map(f64::from);
            let rig = crate::camera::ViewRig {
                convergence: if s.infinity { 0.0 } else { rig.convergence },
                ..*rig
            };
            s.views.clear();
            s.views.extend((0..rig.views).map(|v| {
                let m = rig.shear(v, &p64);
                let inv = crate::camera::invert(&m).unwrap_or(m);
                (m.map(|x| x as f32), inv.map(|x| x as f32))
            }));
            s.source = Some(key);
        }
        s.views[(i as usize).min(s.views.len().saturating_sub(1))]
    }
}
