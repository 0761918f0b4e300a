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
//! once a frame is judged unchanged. What is not done: a kept view is not reprojected by the
//! camera's motion (a moving camera is a change), and a change seen by none of the rendered
//! views (an object visible only in views not rendered this frame) is not caught.

use super::Multiview;
use super::plan::ViewPlan;
use crate::config::Mode;
use crate::gl::*;
use crate::log::{self, Level};
use std::sync::atomic::AtomicBool;

static ANNOUNCED: AtomicBool = AtomicBool::new(false);
static MULTISAMPLED: AtomicBool = AtomicBool::new(false);

/// What must stay equal for kept views to stay valid, besides the pixels (as bit patterns).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signature(Vec<u64>);

impl Signature {
    pub fn of(mv: &Multiview) -> Signature {
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
}

/// Why an epoch ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    Signature,
    /// Pixels of rendered views differ from their kept renders.
    Pixels(u64),
}

/// The bookkeeping of `--reuse`, free of GL: which views to render, which kept views are
/// valid.
#[derive(Clone, Debug)]
pub struct Rotation {
    views: u32,
    centre: u32,
    /// The plain mode's rendered views (K evenly spaced).
    spaced: Vec<u32>,
    /// Every view but the centre, which the phases share out.
    others: Vec<u32>,
    period: u32,
    phase: u32,
    epoch: u64,
    /// Per view: the epoch its kept render belongs to.
    kept: Vec<Option<u64>>,
    signature: Option<Signature>,
    /// The last judged frame changed: render the spaced views next.
    moving: bool,
    /// Every view was exact on some frame of this epoch (said once per epoch).
    converged: bool,
}

impl Rotation {
    /// For `mode` over `views` views; `None` where reuse cannot help (every view rendered
    /// anyway, or a rotating set would be every view).
    pub fn new(mode: Mode, views: u32) -> Option<Rotation> {
        let k = match mode {
            Mode::Synth | Mode::SynthPixel => 1,
            Mode::Hybrid(k) => k,
            Mode::Exact => return None,
        };
        let spaced = ViewPlan::new(mode, views).rendered;
        let centre = views / 2;
        let others: Vec<u32> = (0..views).filter(|&v| v != centre).collect();
        let r = Rotation {
            views,
            centre,
            period: (others.len() as u32).div_ceil(k.clamp(1, views.max(1))),
            phase: 0,
            epoch: 0,
            kept: vec![None; views as usize],
            signature: None,
            moving: false,
            converged: false,
            spaced,
            others,
        };
        let fits = (0..r.period).all(|p| r.phase_set(p).len() < views as usize)
            && r.with_centre(r.spaced.clone()).len() < views as usize;
        (r.period >= 2 && fits).then_some(r)
    }

    pub fn period(&self) -> u32 {
        self.period
    }

    fn with_centre(&self, mut set: Vec<u32>) -> Vec<u32> {
        set.push(self.centre);
        set.sort_unstable();
        set.dedup();
        set
    }

    /// Phase `p`: every `period`-th view but the centre, from the `p`-th on, and the centre.
    fn phase_set(&self, p: u32) -> Vec<u32> {
        let set = self
            .others
            .iter()
            .copied()
            .skip(p as usize)
            .step_by(self.period as usize);
        self.with_centre(set.collect())
    }

    /// The views the next frame renders.
    pub fn next_rendered(&mut self) -> Vec<u32> {
        if self.moving {
            self.phase = 0;
            return self.with_centre(self.spaced.clone());
        }
        let set = self.phase_set(self.phase);
        self.phase = (self.phase + 1) % self.period;
        set
    }

    fn new_epoch(&mut self) {
        self.epoch += 1;
        self.converged = false;
    }

    /// Drops everything kept (the history was re-created).
    pub fn forget(&mut self) {
        self.kept.iter_mut().for_each(|k| *k = None);
        self.new_epoch();
    }

    /// At the warp point: ends the epoch when the signature changed; true when it did.
    pub fn check_signature(&mut self, s: Signature) -> bool {
        let changed = self.signature.as_ref().is_some_and(|old| *old != s);
        self.signature = Some(s);
        if changed {
            self.new_epoch();
        }
        changed
    }

    /// Views of `rendered` whose kept render is of this epoch: what to compare.
    pub fn comparable(&self, rendered: &[u32]) -> Vec<u32> {
        rendered.iter().copied().filter(|&v| self.valid(v)).collect()
    }

    /// The frame's verdict: `None` unchanged (or nothing to compare with).
    pub fn judge(&mut self, change: Option<Change>) {
        if change.is_some() {
            self.new_epoch();
        }
        self.moving = change.is_some();
    }

    /// `rendered` were kept this frame.
    pub fn kept(&mut self, rendered: &[u32]) {
        for &v in rendered {
            if let Some(k) = self.kept.get_mut(v as usize) {
                *k = Some(self.epoch);
            }
        }
    }

    pub fn valid(&self, v: u32) -> bool {
        self.kept.get(v as usize).copied().flatten() == Some(self.epoch)
    }

    /// Views not in `rendered` shown from the history this frame.
    pub fn from_history(&self, rendered: &[u32]) -> Vec<u32> {
        (0..self.views)
            .filter(|v| !rendered.contains(v) && self.valid(*v))
            .collect()
    }

    /// True the first time in an epoch that every view is exact (rendered or kept).
    pub fn newly_converged(&mut self, rendered: &[u32]) -> bool {
        let all = (0..self.views).all(|v| rendered.contains(&v) || self.valid(v));
        let first = all && !self.converged;
        self.converged |= all;
        first
    }
}

/// `--reuse` of one context: the rotation and the history quilt.
pub struct Reuse {
    pub rotation: Rotation,
    pub history: Option<super::history::History>,
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
            off: false,
            frame: 1,
        })
    }

    pub fn delete(&self, gl: &Gl) {
        if let Some(h) = &self.history {
            h.delete(gl);
        }
    }
}

/// At the end of a frame: the views the next one, `frame`, renders.
pub fn plan_next_frame(mv: &mut Multiview, frame: u64) {
    let Some(r) = mv.reuse.as_mut().filter(|r| !r.off) else {
        return;
    };
    r.frame = frame;
    if !mv.plan.fast() {
        // Synthesis failed and the plan went exact: so does reuse.
        r.off = true;
        return;
    }
    let next = r.rotation.next_rendered();
    mv.plan.set_rendered(next);
}

/// At the warp point, before the synthesised views are made: judges whether the scene
/// changed, keeps the rendered views, and copies the still-valid kept views into their
/// tiles. Returns the views so filled (the synthesis leaves them alone).
pub fn at_warp(gl: &Gl, mv: &mut Multiview) -> Vec<u32> {
    let signature = Signature::of(mv);
    let (info, rendered) = (mv.info, mv.plan.rendered.clone());
    let (Some(r), Some(quilt)) = (mv.reuse.as_mut().filter(|r| !r.off), mv.target.as_ref()) else {
        return vec![];
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
        return vec![];
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
                return vec![];
            }
        }
        r.rotation.forget();
        announce(&r.rotation, quilt.layout.views());
    }
    let Some(history) = r.history.as_ref() else {
        return vec![];
    };
    let rot = &mut r.rotation;
    let change = if rot.check_signature(signature) {
        Some(Change::Signature)
    } else {
        let compare = rot.comparable(&rendered);
        match history.differing(gl, info, quilt, &compare) {
            Some(0) => None,
            Some(n) => Some(Change::Pixels(n)),
            // The comparison could not run (an occlusion query of the app's is active).
            None => Some(Change::Pixels(u64::MAX)),
        }
    };
    if change.is_some() && !rot.moving {
        log::debug(format_args!(
            "reuse: frame {frame}: the scene changed ({change:?}): kept views dropped"
        ));
    }
    rot.judge(change);
    history.store(gl, info, quilt, &rendered);
    rot.kept(&rendered);
    let filled = rot.from_history(&rendered);
    history.restore(gl, info, quilt, &filled);
    if rot.newly_converged(&rendered) {
        log::info(format_args!(
            "reuse: frame {frame}: every view exact ({} rendered, {} kept)",
            rendered.len(),
            filled.len()
        ));
    }
    filled
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

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(x: u64) -> Signature {
        Signature(vec![x])
    }

    #[test]
    fn phases_cover_every_view_in_n_over_k_frames() {
        let mut r = Rotation::new(Mode::Hybrid(3), 9).unwrap();
        assert_eq!(r.period(), 3);
        let sets: Vec<Vec<u32>> = (0..3).map(|_| r.next_rendered()).collect();
        assert_eq!(sets, vec![vec![0, 3, 4, 7], vec![1, 4, 5, 8], vec![2, 4, 6]]);
        assert_eq!(r.next_rendered(), vec![0, 3, 4, 7], "and round again");
        let mut s = Rotation::new(Mode::Synth, 5).unwrap();
        assert_eq!(s.period(), 4);
        let sets: Vec<Vec<u32>> = (0..4).map(|_| s.next_rendered()).collect();
        assert_eq!(sets, vec![vec![0, 2], vec![1, 2], vec![2, 3], vec![2, 4]]);
        for (n, k) in [(48, 4), (45, 2), (10, 3), (7, 1)] {
            let mut r = Rotation::new(Mode::Hybrid(k), n).unwrap();
            let mut seen = vec![false; n as usize];
            for _ in 0..n.div_ceil(k) {
                let set = r.next_rendered();
                assert!(set.len() as u32 <= k + 1, "{n}/{k}: {set:?}");
                set.iter().for_each(|&v| seen[v as usize] = true);
            }
            assert!(seen.iter().all(|&s| s), "{n}/{k}");
        }
    }

    #[test]
    fn no_rotation_where_it_cannot_help() {
        assert!(Rotation::new(Mode::Exact, 9).is_none());
        assert!(Rotation::new(Mode::Hybrid(9), 9).is_none());
        assert!(
            Rotation::new(Mode::Hybrid(2), 3).is_none(),
            "{{0,2}} and the centre are all views"
        );
    }

    #[test]
    fn a_still_scene_converges_and_a_change_drops_everything() {
        let mut r = Rotation::new(Mode::Hybrid(3), 9).unwrap();
        let frame = |r: &mut Rotation, s: u64, change: Option<Change>| {
            let rendered = r.next_rendered();
            r.check_signature(sig(s));
            r.judge(change);
            r.kept(&rendered);
            (
                rendered.clone(),
                r.from_history(&rendered),
                r.newly_converged(&rendered),
            )
        };
        let (_, kept, done) = frame(&mut r, 1, None);
        assert!(kept.is_empty() && !done);
        assert_eq!(r.comparable(&[1, 4, 5, 8]), vec![4], "the centre is always comparable");
        let (_, kept, _) = frame(&mut r, 1, None);
        assert_eq!(kept, vec![0, 3, 7]);
        let (rendered, kept, done) = frame(&mut r, 1, None);
        assert!(done, "exact after ⌈9/3⌉ = 3 frames");
        assert_eq!(rendered.len() + kept.len(), 9);
        let (_, kept, _) = frame(&mut r, 1, Some(Change::Pixels(5)));
        assert!(kept.is_empty(), "a change drops, never smears");
        assert_eq!(r.next_rendered(), vec![0, 4, 8], "then the plain spaced views");
        r.check_signature(sig(1));
        r.judge(None);
        r.kept(&[0, 4, 8]);
        assert!(r.valid(4));
        assert!(r.check_signature(sig(2)), "a new camera or rig");
        assert!(!r.valid(4));
    }
}
