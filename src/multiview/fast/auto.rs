//! `--mode auto --frame-budget MS`: how many views to render (K, as `hybrid:K`; K = 1 is
//! `synth`, K = N is `exact`), chosen at every frame's end from what frames have cost. This
//! file is what touches the frame: the clock, the scene's depth, the plan; the choice itself
//! and its hysteresis are `auto_control.rs`, pure, so that it can be driven with costs a test
//! writes rather than with the load of the machine the tests run on.
//!
//! **What is measured.** The time between two frame ends, attributed to the K that rendered
//! the frame (the warp of a frame happens inside it). Splitting a frame into replay and warp
//! by the CPU clock does not work on llvmpipe: its draws are binned and rasterised when
//! something waits for them (the warp's first read of a rendered tile, the swap), so a timer
//! around the warp measures the views' rasterisation too. K is therefore the only
//! explanatory variable. The first frames of the process (programs linked, resources
//! created) and frames measured against exact are not plain frames and are not used.
//!
//! **What the scene needs.** From the scene's depth (the copy auto-convergence reads back at
//! the swap, also taken in this mode when the convergence is fixed): the parallax range, and
//! the disocclusions one unit of camera offset opens, half the sum of the parallax jumps
//! (above the threshold) between horizontal neighbours, as a fraction of the tile. A view at
//! distance `d` (in `u`) from its nearest rendered view has about `d` times that in holes;
//! K is enough when its farthest view's share is under the controller's tolerance. A scene
//! whose range is under the synthesis threshold (flat, or far away) is warped exactly from
//! one view: K = 1 whatever the budget, and nothing else is measured; so is a program
//! without a perspective camera (nothing is shifted: every view is the same image).
//!
//! Each change is logged at info, and every `STATUS_FRAMES` frames at one K their median
//! time.

use crate::camera::projection::DepthRange;
use crate::config::Mode;
use crate::multiview::Multiview;
use std::time::Instant;

#[path = "auto_control.rs"]
mod control;
pub use control::{Change, Controller, HOLD, SceneNeeds};

/// Frames of the process whose time is not used (programs linked, resources created).
const WARM_UP: u64 = 5;

/// The parallax range and disocclusions of a scene from its window depths (`width` per row):
/// parallax `1 − c/w` (1 at the far plane), `px_per_parallax` tile pixels per unit of it in
/// the outermost view.
pub fn scene_needs(
    depths: &[f32],
    width: usize,
    range: DepthRange,
    c: f64,
    px_per_parallax: f64,
    threshold_px: f64,
) -> Option<SceneNeeds> {
    let parallax = |d: f32| -> Option<f64> {
        if d >= 1.0 {
            return Some(1.0);
        }
        let w = range.w_of_ndc(2.0 * f64::from(d) - 1.0);
        (d > 0.0 && w.is_finite() && w > 0.0).then(|| 1.0 - c / w)
    };
    let (mut lo, mut hi, mut holes, mut count) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize);
    for row in depths.chunks(width.max(1)) {
        let mut previous: Option<f64> = None;
        for p in row.iter().map(|&d| parallax(d)) {
            if let Some(p) = p {
                (lo, hi, count) = (lo.min(p), hi.max(p), count + 1);
                let jump = previous.map_or(0.0, |q| (p - q).abs() * px_per_parallax);
                if jump > threshold_px {
                    holes += jump / 2.0;
                }
            }
            previous = p;
        }
    }
    (count > 0).then(|| SceneNeeds {
        range_px: (hi - lo) * px_per_parallax,
        holes_per_u: holes / count as f64,
    })
}

/// Plain frames at one K between two status lines.
const STATUS_FRAMES: usize = 20;

/// The controller of a context in `--mode auto`, the clock between its frames, and the
/// frame times at the current K since the last status line (frame numbers, ms).
pub struct Auto {
    pub controller: Controller,
    last: Option<Instant>,
    times: Vec<(u64, f64)>,
    /// The frame that just ended rendered the centre view, whose depth is read back.
    centre_rendered: bool,
}

impl Auto {
    /// For a context running in `mode` (auto only).
    pub fn new(mode: Mode, settings: &crate::config::ViewSettings, views: u32) -> Option<Auto> {
        (mode == Mode::Auto).then(|| Auto {
            controller: Controller::new(views, settings.frame_budget_ms, settings.synth_threshold),
            last: None,
            times: Vec::new(),
            centre_rendered: false,
        })
    }
}

/// At the end of frame `frame`, before the plan's next frame: time it, and render the K the
/// controller asks for from the next frame on.
pub fn end_frame(mv: &mut Multiview, frame: u64) {
    let Some(auto) = mv.auto.as_mut() else { return };
    if mv.camera.last_depth.is_none() {
        // No perspective camera (yet): every view is the same image.
        auto.controller.scene(SceneNeeds {
            range_px: 0.0,
            holes_per_u: 0.0,
        });
    }
    auto.centre_rendered = mv.plan.renders(mv.camera.rig.centre());
    let now = Instant::now();
    let plain = frame > WARM_UP && !(mv.plan.all && mv.plan.fast());
    let ms = auto
        .last
        .replace(now)
        .filter(|_| plain)
        .map(|t| now.duration_since(t).as_secs_f64() * 1e3);
    let k = auto.controller.k();
    let Some(change) = auto.controller.frame(ms) else {
        auto.times.extend(ms.map(|ms| (frame, ms)));
        return status(auto, k);
    };
    auto.times.clear();
    crate::log::info(format_args!(
        "auto: frame {frame}: K {} → {} (predicted {}, budget {:.1} ms; {})",
        change.from,
        change.to,
        change.predicted_ms.map_or("unknown".into(), |t| format!("{t:.1} ms")),
        auto.controller.budget_ms(),
        change.why
    ));
    mv.plan.set_spaced(change.to);
}

/// Every `STATUS_FRAMES` plain frames at K = `k`: their median time against the budget.
fn status(auto: &mut Auto, k: u32) {
    if auto.times.len() < STATUS_FRAMES {
        return;
    }
    let (first, last) = (auto.times[0].0, auto.times[auto.times.len() - 1].0);
    let mut ms: Vec<f64> = auto.times.drain(..).map(|(_, t)| t).collect();
    ms.sort_by(f64::total_cmp);
    crate::log::info(format_args!(
        "auto: K {k}: median {:.1} ms over frames {first}-{last} (budget {:.1} ms)",
        ms[ms.len() / 2],
        auto.controller.budget_ms()
    ));
}

/// The scene's depth, read back at the swap (`width` values per row), handed to the
/// controller. It is the centre view's: at an even K, which does not render the centre, it
/// is not this frame's and is left out.
pub fn scene_depth(mv: &mut Multiview, depths: &[f32], width: usize, range: DepthRange) {
    let Some(auto) = mv.auto.as_mut().filter(|a| a.centre_rendered) else {
        return;
    };
    let rig = mv.camera.rig;
    let tile_w = mv.target.as_ref().map_or(1, |t| t.layout.tile_w);
    let px = rig.depthiness * f64::from(tile_w) / 2.0;
    if let Some(needs) = scene_needs(depths, width, range, rig.convergence, px, mv.settings.synth_threshold) {
        crate::log::debug(format_args!(
            "auto: scene parallax range {:.2} px, holes {:.4} % of a tile per unit offset",
            needs.range_px,
            needs.holes_per_u * 100.0
        ));
        auto.controller.scene(needs);
    }
}

#[cfg(test)]
#[path = "auto_tests.rs"]
mod tests;
