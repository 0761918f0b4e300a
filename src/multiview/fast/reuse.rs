//! `--reuse`: temporal reuse of exact views (DESIGN §5; Hathaway 2009, who keeps rendered
//! points from frame to frame and adds a few new ones each frame).
//!
//! A fast mode renders K of N views and synthesises the rest, every frame, even when nothing
//! moves. With `--reuse` each frame renders a *rotating* set instead — the centre view, every
//! frame, and phase `p` of `P = ⌈(N-1)/K⌉ ≤ ⌈N/K⌉`: every P-th of the other views from the
//! p-th on, at most K of them. Every rendered view is kept (colour, depth and stencil of its tile, before anything
//! is drawn over the scene) in a history quilt of the quilt's own layout and formats
//! (`history`), marked with the *epoch* it was rendered in. While the epoch lasts, a view not
//! rendered this frame is shown from the history: exact. So a still scene is exact in every
//! view after P frames.
//!
//! The epoch ends — every kept view is dropped, nothing is smeared — the moment the scene
//! may have changed, judged at the warp point, before any kept view is shown:
//! - the signature changed: the main camera's projection and depth model, the rig
//!   (depthiness, convergence, focus: auto-convergence drifting changes every view but the
//!   centre), the quilt's layout;
//! - or a view rendered this frame differs, in any pixel, from its kept render of this
//!   epoch. The centre view is rendered every frame precisely so that there is always one:
//!   any change between two consecutive frames that the centre view sees is caught. The
//!   comparison runs on the GPU (a pass that discards equal pixels, counted by an occlusion
//!   query whose result is waited for: a kept view is never shown on a guess).
//!
//! After a change, the next frame renders the K evenly spaced views of plain `hybrid:K`
//! (and the centre), so a moving scene looks as it does without `--reuse`; rotation resumes
//! once a frame is judged unchanged.
//!
//! **A moving camera** (`--reuse-motion`, on by default) is not a change when the camera can
//! be followed: its view-projection is read from the matrices of the `gl_Position` chain
//! (`motion`) and each kept view remembers the one it was rendered with. When the camera
//! has moved since the centre view was kept, kept views can no longer be compared pixel for
//! pixel, and the epoch goes on; rotation goes on too, so every view is re-rendered every P
//! frames. A kept view is then not copied but moved after the synthesis, by
//! `VP_now · VP_then⁻¹` seen through its own shift (`camera::ViewRig::clip_motion`, f64), and
//! merged into the synthesised view pixel by pixel (`synth::reproject`): it replaces only the
//! stretches the row warp made over disocclusions, where it agrees in depth with the
//! stretch. Measured on `cubes`, it is less accurate than the warp elsewhere (one-pixel
//! points resample every edge, the warp only vertical ones), and a moving object is nearer
//! or farther than the background it uncovered, so it is dropped there, not smeared. An
//! unmoved camera takes the path above, bit for bit. The camera is not followed (motion is
//! a change, as before) where it cannot be read (one MVP per object, built-in or block-held
//! matrices: said once at debug), where the scene is drawn off-screen (its depth is not
//! kept), or under the grid and per-pixel warps (no hole marks).
//!
//! What is not done: a change seen by none of the rendered views (an object visible only in
//! views not rendered this frame) is not caught; with a moving camera, a change of colour
//! without a change of depth (a light, an animated texture) inside a disocclusion is not
//! either.

use super::rotation::{Change, Rotation, Signature};
use crate::config::Mode;
use crate::gl::*;
use crate::log::{self, Level};
use crate::multiview::Multiview;
use crate::synth::reproject::{MovedView, ReprojectJob};
use std::sync::atomic::AtomicBool;

static ANNOUNCED: AtomicBool = AtomicBool::new(false);
static MULTISAMPLED: AtomicBool = AtomicBool::new(false);
static OFF_SCREEN: AtomicBool = AtomicBool::new(false);

/// The signature of `mv`'s frame now.
fn signature(mv: &Multiview) -> Signature {
    let c = &mv.camera;
    let mut v: Vec<u64> = c
        .camera_projection
        .iter()
        .flatten()
        .map(|x| u64::from(x.to_bits()))
        .collect();
    v.push(u64::from(c.camera_projection.is_some()));
    if let Some(d) = c.last_depth {
        v.extend([d.a.to_bits(), d.b.to_bits()]);
    }
    let r = c.rig;
    v.extend([
        r.depthiness.to_bits(),
        r.convergence.to_bits(),
        r.focus.to_bits(),
        u64::from(r.views),
    ]);
    if let Some(l) = mv.layout() {
        v.extend([l.cols, l.rows, l.tile_w, l.tile_h].map(u64::from));
    }
    Signature(v)
}

/// `--reuse` of one context: the rotation and the history quilt.
pub struct Reuse {
    pub rotation: Rotation,
    pub history: Option<super::history::History>,
    /// The main camera's view-projection over the frame being drawn (`motion`).
    pub camera: super::motion::CameraTrack,
    /// Moves kept views by the camera's motion (`--reuse-motion`).
    pub reprojector: crate::synth::reproject::Reprojector,
    /// The history cannot be made or used here; reuse is off for good.
    pub off: bool,
    /// The number of the frame being drawn (frames count from 1).
    pub frame: u64,
}

impl Reuse {
    /// For a context running in `mode` (the one it really runs in) over `views` views.
    pub fn new(settings: &crate::config::ViewSettings, mode: Mode, views: u32) -> Option<Reuse> {
        if !settings.reuse {
            return None;
        }
        Rotation::new(mode, views).map(|rotation| Reuse {
            rotation,
            history: None,
            camera: Default::default(),
            reprojector: Default::default(),
            off: false,
            frame: 1,
        })
    }

    pub fn delete(&mut self, gl: &Gl) {
        if let Some(h) = &self.history {
            h.delete(gl);
        }
        self.reprojector.delete(gl);
    }
}

/// At the end of a frame: the views the next one, `frame`, renders.
pub fn plan_next_frame(mv: &mut Multiview, frame: u64) {
    let Some(r) = mv.reuse.as_mut().filter(|r| !r.off) else {
        return;
    };
    r.frame = frame;
    r.camera = Default::default();
    if !mv.plan.fast() {
        // Synthesis failed and the plan went exact: so does reuse.
        r.off = true;
        return;
    }
    let next = r.rotation.next_rendered();
    mv.plan.set_rendered(next);
}

/// What `at_warp` did with the kept views: copied into their tiles as they are (exact), or
/// left to be moved by the camera's motion over the synthesised view (`move_kept`), each
/// with its `VP_now · VP_then⁻¹`.
#[derive(Default)]
pub struct Reused {
    pub filled: Vec<u32>,
    pub moved: Vec<(u32, [f64; 16])>,
}

/// The camera's view-projection of this frame when kept views may follow it: motion on, the
/// depth model known, and the scene's depth in the quilt (what the history keeps).
fn camera_now(mv: &mut Multiview) -> Option<[f64; 16]> {
    let in_quilt = mv.scene.tracker.target.is_none_or(|t| t == 0);
    // Only the row warp marks the holes kept views fill (`synth::reproject`).
    let rows = mv.settings.synth_warp == crate::config::SynthWarp::Rows && !mv.plan.per_pixel;
    let usable = mv.settings.reuse_motion.is_some() && in_quilt && rows && mv.camera.last_depth.is_some();
    let vp = mv.reuse.as_mut()?.camera.take();
    if vp.is_some() && !in_quilt {
        log::once(
            &OFF_SCREEN,
            Level::Debug,
            format_args!(
                "reuse: the scene is drawn off-screen (its depth is not kept): camera motion drops the kept views"
            ),
        );
    }
    vp.filter(|_| usable)
}

/// At the warp point, before the synthesised views are made: judges whether the scene
/// changed, keeps the rendered views, and copies the still-valid kept views seen through
/// this frame's camera into their tiles (the synthesis leaves those alone); kept views seen
/// through another camera are returned to be moved after the synthesis. (Once the camera
/// stops, views kept while it moved are still moved, by the last part of its motion, until
/// each is rendered again.)
pub fn at_warp(gl: &Gl, mv: &mut Multiview) -> Reused {
    let signature = signature(mv);
    let camera = camera_now(mv);
    let (info, rendered) = (mv.info, mv.plan.rendered.clone());
    let (Some(r), Some(quilt)) = (mv.reuse.as_mut().filter(|r| !r.off), mv.target.as_ref()) else {
        return Reused::default();
    };
    let frame = r.frame;
    if quilt.samples > 0 {
        log::once(
            &MULTISAMPLED,
            Level::Warn,
            format_args!(
                "--reuse needs a single-sampled quilt (this one has {} samples): off",
                quilt.samples
            ),
        );
        r.off = true;
        return Reused::default();
    }
    if !r.history.as_ref().is_some_and(|h| h.fits(quilt)) {
        if let Some(old) = r.history.take() {
            old.delete(gl);
        }
        match super::history::History::create(gl, info, quilt) {
            Ok(h) => r.history = Some(h),
            Err(e) => {
                log::warn(format_args!("--reuse: the history quilt cannot be made ({e}): off"));
                r.off = true;
                return Reused::default();
            }
        }
        r.rotation.forget();
        announce(&r.rotation, quilt.layout.views());
    }
    let Some(history) = r.history.as_ref() else {
        return Reused::default();
    };
    let rot = &mut r.rotation;
    // Kept through this frame's camera (or the camera is not followed): valid pixel for pixel.
    let through_now = |rot: &Rotation, v: u32| camera.is_none() || rot.kept_camera(v) == camera;
    // The camera moved since the centre view was kept: there is nothing to compare pixel for
    // pixel; kept views are moved and merged pixel by pixel instead.
    let moving = camera.is_some() && rot.valid(rot.centre()) && !through_now(rot, rot.centre());
    let change = if rot.check_signature(signature) {
        Some(Change::Signature)
    } else if moving {
        None
    } else {
        let compare: Vec<u32> = rot
            .comparable(&rendered)
            .into_iter()
            .filter(|&v| through_now(rot, v))
            .collect();
        match history.differing(gl, info, quilt, &compare) {
            Some(0) => None,
            Some(n) => Some(Change::Pixels(n)),
            // The comparison could not run (an occlusion query of the app's is active).
            None => Some(Change::Pixels(u64::MAX)),
        }
    };
    if change.is_some() && !rot.moving() {
        log::debug(format_args!(
            "reuse: frame {frame}: the scene changed ({change:?}): kept views dropped"
        ));
    }
    rot.judge(change);
    history.store(gl, info, quilt, &rendered);
    let (filled, other): (Vec<u32>, Vec<u32>) = rot
        .from_history(&rendered)
        .into_iter()
        .partition(|&v| !moving && through_now(rot, v));
    let reused = Reused {
        filled,
        moved: camera.map_or(vec![], |now| {
            other
                .iter()
                .filter_map(|&v| Some((v, motion(rot.kept_camera(v)?, &now)?)))
                .collect()
        }),
    };
    rot.kept(&rendered, camera);
    history.restore(gl, info, quilt, &reused.filled);
    let moved: Vec<u32> = reused.moved.iter().map(|m| m.0).collect();
    if rot.newly_converged(&rendered, &moved) {
        log::info(format_args!(
            "reuse: frame {frame}: every view exact ({} rendered, {} kept)",
            rendered.len(),
            reused.filled.len()
        ));
    }
    reused
}

/// `VP_now · VP_then⁻¹` in f64; `None` when `then` is singular.
fn motion(then: [f64; 16], now: &[f64; 16]) -> Option<[f64; 16]> {
    let inv = crate::camera::invert(&then)?;
    let (now, inv) = (glam::DMat4::from_cols_array(now), glam::DMat4::from_cols_array(&inv));
    Some((now * inv).to_cols_array())
}

/// After the synthesis: the kept views `at_warp` returned to be moved, each over its
/// synthesised view (`synth::reproject`). A failure turns `--reuse` off, said once.
pub fn move_kept(gl: &Gl, mv: &mut Multiview, moved: &[(u32, [f64; 16])]) {
    if moved.is_empty() {
        return;
    }
    let (Some(depth_model), Some(quilt), Some(tolerance)) =
        (mv.camera.last_depth, mv.target.as_ref(), mv.settings.reuse_motion)
    else {
        return;
    };
    let (rig, info, layout) = (mv.camera.rig, mv.info, quilt.layout);
    let Some(marks) = mv.synth.hole_marks() else { return };
    // The synthesis' targets: every view not rendered (none was filled from the history).
    let targets: Vec<u32> = (0..layout.views()).filter(|v| !mv.plan.rendered.contains(v)).collect();
    let Some(r) = mv.reuse.as_mut() else { return };
    let Some(h) = r.history.as_ref() else { return };
    let views: Vec<MovedView> = moved
        .iter()
        .filter_map(|&(v, d)| {
            let (motion, offset) = rig.clip_motion(v, &d);
            Some(MovedView {
                origin: h.origin(v),
                rect: layout.tile_rect(v),
                layer: targets.iter().position(|&t| t == v)? as i32,
                back: crate::camera::invert(&motion)?,
                offset,
            })
        })
        .collect();
    let (color, depth) = h.textures();
    let job = ReprojectJob {
        color,
        depth,
        flipped: h.layout().flipped,
        dest_fbo: quilt.fbo,
        depth_format: h.depth_format(),
        tile: (layout.tile_w as i32, layout.tile_h as i32),
        depth_model,
        tolerance,
        marks,
        views: &views,
    };
    if let Err(e) = r.reprojector.run(gl, info, &job) {
        log::warn(format_args!("--reuse: kept views cannot follow the camera ({e}): off"));
        r.off = true;
    }
}

fn announce(rot: &Rotation, views: u32) {
    log::once(
        &ANNOUNCED,
        Level::Info,
        format_args!(
            "reuse: the centre view and a rotating set of views rendered each frame; a still scene is \
             exact in all {views} views after {} frames",
            rot.period()
        ),
    );
}
