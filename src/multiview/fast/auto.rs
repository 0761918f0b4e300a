//! `--mode auto --frame-budget MS`: how many views to render (K, as `hybrid:K`; K = 1 is
//! `synth`, K = N is `exact`), chosen at every frame's end from what frames have cost.
//!
//! **What is measured.** The time between two frame ends, attributed to the K that rendered
//! the frame (the warp of a frame happens inside it). Splitting a frame into replay and warp
//! by the CPU clock does not work on llvmpipe: its draws are binned and rasterised when
//! something waits for them (the warp's first read of a rendered tile, the swap), so a timer
//! around the warp measures the views' rasterisation too. K is therefore the only
//! explanatory variable, and a K's cost is the median of its last `RECENT` frames.
//!
//! **What is predicted.** A frame at K costs `a + r·K + g·K + w·s·(N−K)` below N (a: the
//! app and presenting; r: replaying one view; g: one source's parallax pyramid and grid; w:
//! warping one view from one source, s = 1 source at K = 1, 2 in between) and `a + r·N` at
//! N, where nothing is warped. Between the ends the cost is a line in K. The two ends are
//! measured first (K = 1, then K = N); the line through them bounds every `hybrid:K` from
//! below (the hybrid line lies above `synth` at K = 1 by `w·(N−1)` and above `exact` at N by
//! `g·N`), so a K in between is only tried when even that bound fits, and once two of them
//! have been measured the hybrid line is fitted to them. A measured K is predicted by its own
//! cost. While the controller stays at one K and its cost moves, every other K's is scaled by
//! the same factor: the scene got heavier or lighter for all K alike. (A K measured again
//! after a while is not taken as drift: its first frames after a change are too noisy, and
//! two K visited in turn would drag each other's estimates and oscillate.)
//!
//! **What is chosen.** Of the K predicted to fit the budget, the cheapest that renders enough
//! views for the scene's disocclusions (below), else the largest that fits (the least error:
//! the most views rendered), else, when nothing fits, the fastest. A scene whose disparity
//! range is under the synthesis threshold (flat, or far away) is warped exactly from one
//! view: K = 1 whatever the budget, and nothing else is measured; so is a program without a
//! perspective camera (nothing is shifted: every view is the same image).
//!
//! **What the scene needs.** From the scene's depth (the copy auto-convergence reads back at
//! the swap, also taken in this mode when the convergence is fixed): the parallax range, and
//! the disocclusions one unit of camera offset opens, half the sum of the parallax jumps
//! (above the threshold) between horizontal neighbours, as a fraction of the tile. A view at
//! distance `d` (in `u`) from its nearest rendered view has about `d` times that in holes;
//! K is enough when its farthest view's share is under `HOLE_TOLERANCE`.
//!
//! **Hysteresis.** The current K keeps fitting up to 5 % over the budget, another K must fit
//! under it (and, to be chosen for being cheaper, be 5 % cheaper); a change is made after it has been called for on
//! `PATIENCE` frames in a row (an end measured only to know its cost is left after
//! `PROBE_FRAMES` measured frames: exact can cost seconds a frame); the first frame after a change
//! (resources reallocated) and the first frames of the process are not measured. A K left
//! for going over the budget is not taken again for `BACK_OFF` frames, twice as long each
//! further time: on a shared machine runs of cheap frames come and go, and each one made a K
//! that sits at the budget look affordable again. Each change is logged at info, and every
//! `STATUS_FRAMES` frames at one K their median time.

use super::plan::ViewPlan;
use crate::camera::projection::DepthRange;
use crate::config::Mode;
use crate::multiview::Multiview;
use std::time::Instant;

/// Frames of the process whose time is not used (programs linked, resources created).
const WARM_UP: u64 = 5;
/// Frames after a change of K whose time is not used.
const SETTLE: u32 = 1;
/// Frames at the current K whose median is its cost.
const RECENT: usize = 5;
/// Dead band around the budget, as a fraction of it.
const BAND: f64 = 0.05;
/// Frames in a row a change must be called for before it is made.
const PATIENCE: u32 = 3;
/// Frames an end measured only to know its cost is measured for.
const PROBE_FRAMES: usize = 2;
/// Frames a K left for going over the budget is not chosen again, the first time; each
/// further time it is left so, twice as many (up to `MAX_BACK_OFF`).
const BACK_OFF: u64 = 30;
const MAX_BACK_OFF: u64 = 960;
/// Share of a synthesised tile's pixels in disocclusions that is left to the warp's
/// stretching: 0.2 % (about 470 pixels of a 420x560 tile), in the range where
/// `--measure-error` on `cubes` puts stretched holes at or above 30 dB.
const HOLE_TOLERANCE: f64 = 0.002;

const MEASURING_SYNTH: &str = "measuring synth";
const MEASURING_EXACT: &str = "measuring exact";

/// What the scene's depth says about the views it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneNeeds {
    /// Parallax range in tile pixels between the centre and the outermost view.
    pub range_px: f64,
    /// Share of a tile's pixels disoccluded per unit of camera offset `u`.
    pub holes_per_u: f64,
}

/// A change of K, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Change {
    pub from: u32,
    pub to: u32,
    pub predicted_ms: Option<f64>,
    pub why: &'static str,
}

/// The choice of K from costs and the scene's needs (no GL: unit-tested with fake costs).
#[derive(Clone, Debug)]
pub struct Controller {
    views: u32,
    budget_ms: f64,
    threshold_px: f64,
    k: u32,
    /// Estimated frame time by K − 1; `None` until a frame at that K has been measured.
    costs: Vec<Option<f64>>,
    /// The last frame times at the current K.
    recent: Vec<f64>,
    /// Largest `u` distance from a view to its nearest rendered view, by K − 1.
    distance: Vec<f64>,
    since_change: u32,
    pending: Option<(u32, u32)>,
    needs: Option<SceneNeeds>,
    /// The current K was chosen to be measured: it is left as soon as it has been.
    probing: bool,
    /// Frames seen.
    frames: u64,
    /// By K − 1: the frame before which that K is not taken again, and the back-off the next
    /// time it goes over the budget.
    back_off: Vec<(u64, u64)>,
}

impl Controller {
    /// `views` views, starting at K = 1; `threshold_px`: `--synth-threshold`.
    pub fn new(views: u32, budget_ms: f64, threshold_px: f64) -> Controller {
        let n = views.max(1);
        let u = |i: u32| {
            if n <= 1 {
                0.0
            } else {
                2.0 * i as f64 / (n - 1) as f64 - 1.0
            }
        };
        let distance = (1..=n)
            .map(|k| {
                let mut plan = ViewPlan::new(Mode::Auto, n);
                plan.set_spaced(k);
                (0..n).map(|i| (u(i) - u(plan.nearest(i))).abs()).fold(0.0, f64::max)
            })
            .collect();
        Controller {
            views: n,
            budget_ms,
            threshold_px,
            k: 1,
            costs: vec![None; n as usize],
            recent: Vec::new(),
            distance,
            since_change: 0,
            pending: None,
            needs: None,
            probing: false,
            frames: 0,
            back_off: vec![(0, BACK_OFF); n as usize],
        }
    }

    pub fn k(&self) -> u32 {
        self.k
    }

    pub fn budget_ms(&self) -> f64 {
        self.budget_ms
    }

    /// What the latest depth read-back says.
    pub fn scene(&mut self, needs: SceneNeeds) {
        self.needs = Some(needs);
    }

    /// A frame rendered at the current K ended; `ms`: its time, `None` when it is not a
    /// plain frame (warming up, or measured against exact). The change to make before the
    /// next frame, if any.
    pub fn frame(&mut self, ms: Option<f64>) -> Option<Change> {
        self.since_change = self.since_change.saturating_add(1);
        self.frames += 1;
        if let Some(ms) = ms.filter(|m| self.since_change > SETTLE && m.is_finite() && *m > 0.0) {
            self.observe(ms);
        }
        let (want, why) = self.want();
        if want == self.k {
            self.pending = None;
            return None;
        }
        let count = match self.pending {
            Some((k, c)) if k == want => c + 1,
            _ => 1,
        };
        self.pending = Some((want, count));
        if count < PATIENCE && !(self.probing && self.recent.len() >= PROBE_FRAMES) {
            return None;
        }
        let change = Change {
            from: self.k,
            to: want,
            predicted_ms: self.predict(want),
            why,
        };
        self.back_off_if_over_budget();
        (self.k, self.since_change, self.pending) = (want, 0, None);
        self.recent.clear();
        self.probing = [MEASURING_SYNTH, MEASURING_EXACT].contains(&why);
        Some(change)
    }

    /// The current K is being left: when it is for going over the budget, it is not taken
    /// again for a while, longer each time. A K whose cost sits at the budget is otherwise
    /// retried whenever a run of cheap frames at a neighbouring K scales its estimate under
    /// it (seen on bloom under a loaded machine: 2 ↔ 3 every few frames).
    fn back_off_if_over_budget(&mut self) {
        let over = self.predict(self.k).is_some_and(|t| t > self.budget_ms * (1.0 + BAND));
        let slot = &mut self.back_off[(self.k - 1) as usize];
        if over && !self.probing {
            *slot = (self.frames + slot.1, (slot.1 * 2).min(MAX_BACK_OFF));
        }
    }

    fn backing_off(&self, k: u32) -> bool {
        k != self.k && self.frames < self.back_off[(k - 1) as usize].0
    }

    /// A frame at the current K took `ms`: its estimate becomes the median of its last
    /// `RECENT` frames (a step in cost is followed within half of them, noise is not); while
    /// the controller stays at this K, every other K's estimate moves by the same factor.
    fn observe(&mut self, ms: f64) {
        if self.recent.len() == RECENT {
            self.recent.remove(0);
        }
        self.recent.push(ms);
        let mut sorted = self.recent.clone();
        sorted.sort_by(f64::total_cmp);
        let new = sorted[sorted.len() / 2];
        let i = (self.k - 1) as usize;
        let factor = match self.costs[i] {
            Some(old) if self.recent.len() > 1 => new / old,
            _ => 1.0,
        };
        for (j, c) in self.costs.iter_mut().enumerate() {
            if let Some(c) = c.as_mut().filter(|_| j != i) {
                *c *= factor;
            }
        }
        self.costs[i] = Some(new);
    }

    /// The predicted frame time at `k`, once both ends have been measured (or `k` itself).
    pub fn predict(&self, k: u32) -> Option<f64> {
        let n = self.views;
        if let Some(c) = self.costs.get(k.checked_sub(1)? as usize).copied().flatten() {
            return Some(c);
        }
        let (t1, tn) = (self.costs[0]?, self.costs[(n - 1) as usize]?);
        let slope = (tn - t1) / f64::from(n - 1);
        let hybrid: Vec<(f64, f64)> = (2..n)
            .filter_map(|j| Some((f64::from(j), self.costs[(j - 1) as usize]?)))
            .collect();
        let x = f64::from(k);
        Some(match hybrid.as_slice() {
            [] => t1 + slope * (x - 1.0),
            [(xh, th)] => th + slope * (x - xh),
            points => fit_line(points, x),
        })
    }

    /// The smallest K whose farthest synthesised view has few enough holes (N until the
    /// scene has been seen).
    fn required(&self) -> u32 {
        let Some(needs) = self.needs else { return self.views };
        (1..=self.views)
            .find(|&k| needs.holes_per_u * self.distance[(k - 1) as usize] <= HOLE_TOLERANCE)
            .unwrap_or(self.views)
    }

    fn flat(&self) -> bool {
        self.needs.is_some_and(|s| s.range_px < self.threshold_px)
    }

    /// The K this frame calls for, and why.
    fn want(&self) -> (u32, &'static str) {
        if self.flat() {
            return (1, "the scene's disparity range is under the synthesis threshold");
        }
        if self.costs[(self.k - 1) as usize].is_none() {
            return (self.k, "");
        }
        for (end, why) in [(1, MEASURING_SYNTH), (self.views, MEASURING_EXACT)] {
            if self.costs[(end - 1) as usize].is_none() {
                return (end, why);
            }
        }
        self.choose()
    }

    /// Cheapest sufficient K that fits, else the largest that fits, else the fastest; the
    /// current K is favoured by the dead band.
    fn choose(&self) -> (u32, &'static str) {
        // A dead band on both sides: the current K stays while within 5 % over the budget, another
        // is taken only 5 % under it, so a K whose cost sits at the budget does not flicker.
        let band = |k: u32| if k == self.k { 1.0 + BAND } else { 1.0 - BAND };
        let predicted: Vec<(u32, f64)> = (1..=self.views).filter_map(|k| Some((k, self.predict(k)?))).collect();
        let fits: Vec<(u32, f64)> = predicted
            .iter()
            .copied()
            .filter(|&(k, t)| t <= self.budget_ms * band(k) && !self.backing_off(k))
            .collect();
        let required = self.required();
        let cheapest = |set: &mut dyn Iterator<Item = (u32, f64)>| {
            set.map(|(k, t)| (k, if k == self.k { t * (1.0 - BAND) } else { t }))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
                .map(|(k, _)| k)
        };
        if let Some(k) = cheapest(&mut fits.iter().copied().filter(|&(k, _)| k >= required)) {
            return (k, "fits the budget with enough views for the scene's disocclusions");
        }
        if let Some(&(k, _)) = fits.iter().max_by_key(|(k, _)| *k) {
            return (k, "the most views that fit the budget");
        }
        (
            cheapest(&mut predicted.iter().copied()).unwrap_or(self.k),
            "nothing fits the budget: the fastest",
        )
    }
}

/// Least-squares line through `points`, evaluated at `x`.
fn fit_line(points: &[(f64, f64)], x: f64) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), p| {
        (a + (p.0 - mx) * (p.1 - my), b + (p.0 - mx).powi(2))
    });
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    my + slope * (x - mx)
}

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
