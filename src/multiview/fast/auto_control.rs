//! The choice of K in `--mode auto`, from frame costs as plain numbers. It is kept apart from
//! the GL side (`auto.rs`) because this is where a controller flaps and where flapping is
//! cured, and flapping is a property of cost sequences: the tests (`auto_control_tests.rs`)
//! write the sequences a shared machine makes (spikes, alternation, load that comes and goes,
//! a lasting step) and count the changes, instead of hoping that a loaded machine makes them
//! during a test run.
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
//! views for the scene's disocclusions, else the largest that fits (the least error: the most
//! views rendered), else, when nothing fits, the fastest. A scene whose disparity range is
//! under the synthesis threshold is warped exactly from one view: K = 1 whatever the budget.
//!
//! **Hysteresis: K follows what lasts.** A change of K shows (views turn from rendered to
//! synthesised and back), and the load of a shared machine comes and goes far faster than a
//! user wants the picture to change, so each way a frame time moves meets its own rule:
//! - *a dead band*: the current K stays until its cost is `OVER` (5 %) over the budget;
//!   another K is taken only when predicted `HEADROOM` (5 %) under it, and for being cheaper
//!   only when `GAIN` (5 %) cheaper. A K just taken has 10 % of room before it is left.
//! - *a call must last*: leaving a K that is over the budget is called for on `OVER_FRAMES`
//!   (5) frames in a row, so with the median of `RECENT` (5) frames the load must have lasted
//!   about 7 frames; any other move (more views, or a cheaper K) on `BETTER_FRAMES` (15). A
//!   spike moves no median; an alternating load flips the median every frame, and the call
//!   with it, which starts the count again.
//! - *a hold*: no change for `HOLD` (20) frames after one, whatever is called for: the new K
//!   is measured on its own frames before it is judged, and no two changes come closer.
//! - *a back-off*: a K left for going over the budget is not taken again for `BACK_OFF`
//!   frames, twice as long each further time: a K that sits at the budget otherwise looked
//!   affordable again after every run of cheap frames.
//!
//! Measuring an end and a flat scene are not choices and bypass the last three (an end is
//! measured for `PROBE_FRAMES` frames and left: exact can cost seconds a frame).

use crate::config::Mode;
use crate::multiview::fast::plan::ViewPlan;

/// Frames after a change of K whose time is not used (resources reallocated).
const SETTLE: u32 = 1;
/// Frames at the current K whose median is its cost.
const RECENT: usize = 5;
/// The current K keeps fitting up to this fraction over the budget.
const OVER: f64 = 0.05;
/// Another K fits when predicted this fraction under the budget.
const HEADROOM: f64 = 0.05;
/// Another K is cheaper when it costs this fraction less than the current one.
const GAIN: f64 = 0.05;
/// Frames in a row a measurement (an end, a flat scene) must be called for.
const PATIENCE: u32 = 3;
/// Frames in a row leaving a K that is over the budget must be called for.
pub const OVER_FRAMES: u32 = 5;
/// Frames in a row any other change must be called for.
pub const BETTER_FRAMES: u32 = 15;
/// Frames after a change before K changes again for its cost.
pub const HOLD: u32 = 20;
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
const FLAT: &str = "the scene's disparity range is under the synthesis threshold";

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

/// What a frame calls for when it wants another K; a change is made once the same kind of
/// call has lasted its `frames()` in a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Call {
    /// An end to measure, or a flat scene: not a choice of cost, not held.
    Measure,
    /// The current K is over the budget.
    Over,
    /// The current K fits, another is better (more views, or cheaper).
    Better,
}

impl Call {
    fn frames(self) -> u32 {
        match self {
            Call::Measure => PATIENCE,
            Call::Over => OVER_FRAMES,
            Call::Better => BETTER_FRAMES,
        }
    }
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
    /// The kind of change called for, and on how many frames in a row.
    pending: Option<(Call, u32)>,
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
        // An end measured only to know its cost is left at once; kept, it is a K like any other.
        let measured = self.probing && self.recent.len() >= PROBE_FRAMES;
        self.probing &= !measured;
        let (want, why) = self.want();
        if want == self.k {
            self.pending = None;
            return None;
        }
        (measured || self.lasted(why)).then(|| self.change(want, why, measured))
    }

    /// Counts this frame's call for another K (for `why`): true once the same kind of call
    /// has lasted its frames in a row, and a change for cost once K has been held.
    fn lasted(&mut self, why: &str) -> bool {
        let call = self.call(why);
        let count = match self.pending {
            Some((c, n)) if c == call => n + 1,
            _ => 1,
        };
        self.pending = Some((call, count));
        count >= call.frames() && (call == Call::Measure || self.since_change >= HOLD)
    }

    /// Moves to `want`; `measured`: leaving an end that was only measured.
    fn change(&mut self, want: u32, why: &'static str, measured: bool) -> Change {
        let change = Change {
            from: self.k,
            to: want,
            predicted_ms: self.predict(want),
            why,
        };
        if !measured {
            self.back_off_if_over_budget();
        }
        (self.k, self.since_change, self.pending) = (want, 0, None);
        self.recent.clear();
        self.probing = [MEASURING_SYNTH, MEASURING_EXACT].contains(&why);
        change
    }

    /// The kind of call a frame that wants another K for `why` makes.
    fn call(&self, why: &str) -> Call {
        if [MEASURING_SYNTH, MEASURING_EXACT, FLAT].contains(&why) {
            Call::Measure
        } else if self.over(self.k) {
            Call::Over
        } else {
            Call::Better
        }
    }

    /// `k` is predicted over the budget, past the band the current K is allowed.
    fn over(&self, k: u32) -> bool {
        self.predict(k).is_some_and(|t| t > self.budget_ms * (1.0 + OVER))
    }

    /// The current K is being left: when it is for going over the budget, it is not taken
    /// again for a while, longer each time. A K whose cost sits at the budget is otherwise
    /// retried whenever a run of cheap frames at a neighbouring K scales its estimate under
    /// it (seen on bloom under a loaded machine: 2 ↔ 3 every few frames).
    fn back_off_if_over_budget(&mut self) {
        if self.over(self.k) {
            let slot = &mut self.back_off[(self.k - 1) as usize];
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
            return (1, FLAT);
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
        // The current K stays while within `OVER` over the budget, another is taken only
        // `HEADROOM` under it, so a K whose cost sits at the budget does not flicker.
        let band = |k: u32| if k == self.k { 1.0 + OVER } else { 1.0 - HEADROOM };
        let predicted: Vec<(u32, f64)> = (1..=self.views).filter_map(|k| Some((k, self.predict(k)?))).collect();
        let fits: Vec<(u32, f64)> = predicted
            .iter()
            .copied()
            .filter(|&(k, t)| t <= self.budget_ms * band(k) && !self.backing_off(k))
            .collect();
        let required = self.required();
        let cheapest = |set: &mut dyn Iterator<Item = (u32, f64)>| {
            set.map(|(k, t)| (k, if k == self.k { t * (1.0 - GAIN) } else { t }))
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

#[cfg(test)]
#[path = "auto_control_tests.rs"]
mod tests;
