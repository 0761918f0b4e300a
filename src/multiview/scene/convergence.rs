//! Auto-convergence from the scene's depth: the scene target's depth copied when it is about
//! to change (or at the swap), estimated at the swap, and the next frame's target chosen.
//! Which framebuffer and when: see `scene`. What a copy needs to know of its source is asked
//! of GL at the swap, so that a copy taken inside a draw call asks GL nothing.

use super::tracker::{Candidate, Phase, SceneTracker};
use crate::camera::convergence;
use crate::config::Convergence;
use crate::gl::depth_copy::{self, DepthCopy, Restore, SourceFormat};
use crate::gl::{Gl, SCISSOR_TEST};
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::intersect;
use crate::state::AppState;

/// Every how many rows of the scene's depth (and record) are read back at the swap: the
/// harmonic mean, the depth fit and `--mode auto`'s parallax range and hole rate are
/// statistics over rows (hole jumps are between neighbours along a row), which a quarter of
/// the rows gives as well as all of them, for a quarter of the bytes (2.8 MB a frame at a
/// 420x560 tile: what a GPU waits for).
const READ_ROW_STEP: i32 = 4;

/// The scene's depth: where it is drawn, and our copy of it.
#[derive(Default)]
pub struct SceneDepth {
    pub tracker: SceneTracker,
    pub(super) copy: DepthCopy,
    /// Where this frame's copy came from, once taken, and the rectangle of it.
    taken: Option<(Source, [i32; 4])>,
    /// The target's camera draws and all camera draws of the frame it was chosen in.
    share: (u32, u32),
    /// The framebuffer copies of the target come from, and its depth format.
    described: Option<(u32, SourceFormat)>,
    /// At the swap: the view the ending frame rendered nearest the centre. By the time the
    /// swap's copy is taken the plan is the next frame's, which may render other views
    /// (`--mode auto` changing K).
    pub ended_view: Option<u32>,
}

/// Where a copy of the target's depth comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Source {
    /// Framebuffer 0: the quilt's centre tile.
    Quilt,
    /// An app framebuffer's layered shadow: its centre layer.
    Shadow,
    /// An app framebuffer without a shadow: its own attachment.
    App,
}

impl SceneDepth {
    /// Our textures and program (shared by the share group).
    pub fn shared_objects(&self) -> ([u32; 3], Option<u32>) {
        self.copy.shared_objects()
    }

    /// The depth format of `fbo` as asked of GL at the last swap, if the copies come from it:
    /// the synthesis' own copy of the same depth need not ask again.
    pub fn described(&self, fbo: u32) -> Option<SourceFormat> {
        self.described.filter(|d| d.0 == fbo).map(|d| d.1)
    }

    /// Our framebuffers and vertex arrays (per context).
    pub fn context_objects(&self) -> (usize, usize) {
        self.copy.context_objects()
    }
}

/// Copies the scene target's depth now, before anything changes it (see `scene`). Called
/// when the tracker asks (in a draw or a clear), and at the swap.
pub fn take_depth(gl: &Gl, app: &mut AppState, mv: &mut Multiview) {
    mv.scene.tracker.phase = Phase::Taken;
    crate::multiview::fast::synthesis::capture_depth(gl, mv);
    copy_for_convergence(gl, app, mv);
}

/// The convergence's copy of the target's depth (centre view), when it is read back.
fn copy_for_convergence(gl: &Gl, app: &mut AppState, mv: &mut Multiview) {
    if !reads_depth(mv) {
        return;
    }
    let Some(target) = mv.scene.tracker.target else { return };
    let Some((fbo, rect, from)) = source(mv, target) else {
        return;
    };
    let format = match mv.scene.described {
        Some((described, format)) if described == fbo => Ok(format),
        // A source that appeared since the swap (a shadow made this frame): asked now.
        _ => checked_describe(gl, mv, fbo, from),
    };
    let format = match format {
        Ok(f) => f,
        Err(e) => return unreadable(target, &e),
    };
    let map = |f: u32| if f == 0 { mv.quilt_fbo().unwrap_or(0) } else { f };
    let restore = Restore {
        draw_fbo: map(app.draw_fbo),
        read_fbo: map(app.read_fbo),
        scissor: app.enabled(gl, SCISSOR_TEST),
    };
    mv.scene
        .copy
        .take_rows(gl, mv.info, (fbo, format), rect, restore, READ_ROW_STEP);
    mv.scene.taken = Some((from, rect));
}

/// Auto-convergence and `--mode auto` read the scene's depth back at the swap.
pub fn reads_depth(mv: &Multiview) -> bool {
    mv.settings.convergence == Convergence::Auto || mv.auto.is_some()
}

/// Before a clear or an invalidation of the app's `fbo` (`depth`: of its depth buffer too):
/// the scene's depth is copied first if this erases it.
pub fn before_erase(gl: &Gl, app: &mut AppState, mv: &mut Multiview, fbo: u32, depth: bool) {
    if mv.scene.tracker.clear(fbo, depth) {
        take_depth(gl, app, mv);
    }
}

fn unreadable(target: u32, e: &str) {
    crate::log::once_for(
        ("scene-depth", u64::from(target)),
        crate::log::Level::Info,
        format_args!("auto-convergence: the depth of framebuffer {target} cannot be read: {e}"),
    );
}

/// The rendered view nearest the centre: the centre itself, except in a fast mode that does
/// not render it (hybrid:K with an even K), whose centre tile or layer holds no depth yet
/// when the copy is taken.
pub fn centre(mv: &Multiview) -> u32 {
    mv.scene
        .ended_view
        .unwrap_or_else(|| mv.plan.nearest(mv.camera.rig.centre()))
}

/// The framebuffer holding the target's depth as the centre view saw it.
fn source_fbo(mv: &Multiview, target: u32) -> Option<(u32, Source)> {
    let centre = centre(mv) as usize;
    Some(if target == 0 {
        (mv.target.as_ref()?.fbo, Source::Quilt)
    } else if let Some(s) = mv.shadows.get(&target) {
        (*s.views.get(centre).or(s.views.last())?, Source::Shadow)
    } else {
        (target, Source::App)
    })
}

/// `source_fbo`, and the rectangle of it the camera drew into (its viewport there).
fn source(mv: &Multiview, target: u32) -> Option<(u32, [i32; 4], Source)> {
    let (fbo, from) = source_fbo(mv, target)?;
    let viewport = mv.scene.tracker.viewport;
    let rect = match (from, mv.target.as_ref(), mv.shadows.get(&target)) {
        (Source::Quilt, Some(quilt), _) => {
            let centre = centre(mv);
            intersect(quilt.layout.map_rect(centre, viewport), quilt.layout.tile_rect(centre))
        }
        (Source::Shadow, _, Some(s)) => intersect(s.scale.rect_out(viewport), [0, 0, s.size.0, s.size.1]),
        _ => intersect(viewport, [0, 0, i32::MAX, i32::MAX]),
    };
    (rect[2] > 0 && rect[3] > 0).then_some((fbo, rect, from))
}

/// Where view `view`'s scene depth is at the swap, and the rectangle of it the camera drew
/// into: its tile of the quilt, or its layer of the scene framebuffer's shadow; `None` for a
/// scene framebuffer without a shadow (one depth for every view) or a multisampled quilt.
pub fn view_depth(mv: &Multiview, view: u32) -> Option<(u32, [i32; 4])> {
    let target = mv.scene.tracker.target.unwrap_or(0);
    let viewport = mv.scene.tracker.viewport;
    let (fbo, rect) = if target == 0 {
        let q = mv.target.as_ref()?;
        let tile = q.layout.tile_rect(view);
        let drawn = intersect(q.layout.map_rect(view, viewport), tile);
        (q.resolved_fbo, if drawn[2] > 0 && drawn[3] > 0 { drawn } else { tile })
    } else {
        let s = mv.shadows.get(&target)?;
        let fbo = *s.views.get(view as usize)?;
        (fbo, intersect(s.scale.rect_out(viewport), [0, 0, s.size.0, s.size.1]))
    };
    (rect[2] > 0 && rect[3] > 0).then_some((fbo, rect))
}

/// `depth_copy::describe`, after checking that an app's framebuffer still exists.
fn checked_describe(gl: &Gl, mv: &Multiview, fbo: u32, from: Source) -> Result<SourceFormat, String> {
    // SAFETY: a query on a name, binding nothing.
    if from == Source::App && unsafe { gl.IsFramebuffer(fbo) } == 0 {
        return Err("it was deleted".into());
    }
    depth_copy::describe(gl, mv.info, fbo)
}

/// At the swap: the frame's estimate, and the next frame's scene target.
pub fn update_convergence(gl: &Gl, app: &mut AppState, mv: &mut Multiview) {
    let Some(layout) = mv.layout() else {
        mv.scene.ended_view = None;
        return;
    };
    // `--mode auto` reads the scene's depth too, for what the scene needs (`auto`); the
    // fast modes follow the scene's framebuffer to warp by its depth, and the depth of field,
    // the edge fade and `--dump-disparity` to read its disparity record.
    let records =
        mv.settings.disparity_record && (mv.settings.comfort.post_pass() || crate::config::settings().dump_disparity);
    if reads_depth(mv) || mv.plan.fast() || records {
        // Not `take_depth`: at the swap the frame has been warped (`synthesis::end_frame`
        // runs first) and the plan is the next frame's, which must not get this depth.
        if mv.scene.tracker.phase == Phase::Drawn {
            mv.scene.tracker.phase = Phase::Taken;
            copy_for_convergence(gl, app, mv);
        }
        estimate(gl, mv);
        mv.scene.ended_view = None;
        choose_target(gl, mv);
    } else {
        mv.scene.ended_view = None;
        mv.scene.tracker.end_frame();
    }
    mv.update_rig(layout);
}

/// Harmonic mean depth of this frame's copy, smoothed into the convergence.
fn estimate(gl: &Gl, mv: &mut Multiview) {
    let (Some((from, rect)), Some(target)) = (mv.scene.taken.take(), mv.scene.tracker.target) else {
        return;
    };
    // No projection read: the depth model is fitted to this frame's record and depth.
    let fit = mv.camera.last_depth.is_none() || mv.camera.depth_fitted;
    let mut depths = match mv.scene.copy.read(gl, mv.info) {
        Ok(d) => d,
        Err(e) => return unreadable(target, &e),
    };
    if crate::synth::zero_to_one(gl) {
        // The estimates read window depth as (z_ndc + 1)/2; under `glClipControl(..,
        // GL_ZERO_TO_ONE)` it is z_ndc itself. The clears (0 and 1) keep their meaning.
        for d in depths.iter_mut().filter(|d| **d > 0.0 && **d < 1.0) {
            *d = (*d + 1.0) / 2.0;
        }
    }
    // Read back once, for the fit and the substitution.
    let record = super::recorded::read(gl, mv, centre(mv), rect, depths.len());
    if fit
        && let Some(r) = record
            .as_ref()
            .and_then(|rec| super::recorded::fit_depth_model(mv, rec, &depths))
    {
        mv.camera.last_depth = Some(r);
        mv.camera.depth_fitted = true;
    }
    let Some(range) = mv.camera.last_depth else {
        return;
    };
    let recorded = record.map_or(0, |rec| super::recorded::substitute(mv, range, &rec, &mut depths));
    let width = mv.scene.copy.copied().1[2].max(1) as usize;
    crate::multiview::fast::auto::scene_depth(mv, &depths, width, range);
    if mv.settings.convergence != Convergence::Auto {
        return;
    }
    let Some(c) = convergence::estimate(&depths, range) else {
        return;
    };
    crate::log::once_for(
        ("scene-depth-from", u64::from(target)),
        crate::log::Level::Info,
        format_args!(
            "auto-convergence: scene at {c:.4} (near {:.4}, far {:.4}) from framebuffer {target}{}, where the \
             main camera draws ({} of the frame's {} perspective draws){}{}",
            range.near(),
            range.far(),
            match from {
                Source::Quilt => " (the quilt's centre view)",
                Source::Shadow => " (its shadow's centre layer)",
                Source::App => "",
            },
            mv.scene.share.0,
            mv.scene.share.1,
            if mv.info.es {
                "; read through a colour pass (ES has no depth read-back)"
            } else {
                ""
            },
            match recorded {
                0 => String::new(),
                n => format!(
                    "; {:.1} % of its pixels from the disparity record",
                    100.0 * n as f64 / depths.len().max(1) as f64
                ),
            },
        ),
    );
    mv.camera.auto_convergence = Some(convergence::smooth(mv.camera.auto_convergence, c));
}

/// The framebuffer with the most camera draws this frame that a scene can be drawn into
/// (colour and depth; not a light's depth-only shadow map) becomes the next frame's target,
/// and its depth source is described for the copies to come.
fn choose_target(gl: &Gl, mv: &mut Multiview) {
    let candidates = mv.scene.tracker.end_frame();
    let total = candidates.iter().map(|c| c.draws).sum();
    let info = mv.info;
    let scene = |c: &&Candidate| c.fbo == 0 || depth_copy::is_scene_target(gl, info, c.fbo);
    let chosen = candidates.iter().find(scene);
    mv.scene.tracker.target = chosen.map(|c| c.fbo);
    mv.scene.share = (chosen.map_or(0, |c| c.draws), total);
    mv.scene.described = chosen
        .and_then(|c| source_fbo(mv, c.fbo))
        .and_then(|(fbo, from)| Some((fbo, checked_describe(gl, mv, fbo, from).ok()?)));
}
