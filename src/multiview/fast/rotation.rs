//! The bookkeeping of `--reuse` (`reuse`), free of GL: which views each frame renders and
//! which kept views are valid (the epochs, the signature, the verdicts).

use super::plan::ViewPlan;
use crate::config::Mode;

/// What must stay equal for kept views to stay valid, besides the pixels (as bit patterns).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signature(pub Vec<u64>);

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
    /// Per view: the camera's view-projection its kept render was made with, when known.
    camera: Vec<Option<[f64; 16]>>,
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
            Mode::Hybrid(k) | Mode::HybridPixel(k) => k,
            // `auto` chooses the rendered views itself.
            Mode::Exact | Mode::Auto => return None,
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
            camera: vec![None; views as usize],
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

    pub fn centre(&self) -> u32 {
        self.centre
    }

    /// The last judged frame changed.
    pub fn moving(&self) -> bool {
        self.moving
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

    /// `rendered` were kept this frame, seen through `camera`.
    pub fn kept(&mut self, rendered: &[u32], camera: Option<[f64; 16]>) {
        for &v in rendered {
            if let Some(k) = self.kept.get_mut(v as usize) {
                *k = Some(self.epoch);
                self.camera[v as usize] = camera;
            }
        }
    }

    /// The camera view `v`'s kept render was made with.
    pub fn kept_camera(&self, v: u32) -> Option<[f64; 16]> {
        self.camera.get(v as usize).copied().flatten()
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

    /// True the first time in an epoch that every view is exact (rendered, or kept and not
    /// `moved`: reprojected by the camera's motion).
    pub fn newly_converged(&mut self, rendered: &[u32], moved: &[u32]) -> bool {
        let all = (0..self.views).all(|v| rendered.contains(&v) || self.valid(v) && !moved.contains(&v));
        let first = all && !self.converged;
        self.converged |= all;
        first
    }
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
            r.kept(&rendered, None);
            (
                rendered.clone(),
                r.from_history(&rendered),
                r.newly_converged(&rendered, &[]),
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
        r.kept(&[0, 4, 8], None);
        assert!(r.valid(4));
        assert!(r.check_signature(sig(2)), "a new camera or rig");
        assert!(!r.valid(4));
    }
}
