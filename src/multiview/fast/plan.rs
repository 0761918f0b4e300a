//! Which views a frame renders, and when the others are synthesised (DESIGN §5).
//!
//! In `exact` every view is rendered. In the fast modes only some are (the centre for
//! `synth`, K evenly spaced for `hybrid:K`), and the others are warped from them at the
//! *warp point*: the first moment the views stop being a pure function of the scene, i.e.
//! the first draw or clear into framebuffer 0 that is not view-dependent (a HUD, a 2D menu, a
//! clear) after view-dependent draws, or the swap. Everything drawn after the warp point is
//! drawn in every view, so HUDs stay exactly in place and are never warped.

use crate::config::Mode;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ViewPlan {
    /// Views rendered by replaying the app's draws, ascending.
    pub rendered: Vec<u32>,
    /// `rendered` as a mask by view index.
    mask: Vec<bool>,
    /// A view-dependent draw reached framebuffer 0 since the last warp.
    pub scene_dirty: bool,
    /// The views have been synthesised this frame: from now on every view is drawn.
    pub warped: bool,
    /// This frame renders every view (exact mode, or a frame measured against exact).
    pub all: bool,
    /// This frame synthesises the views that are not rendered (on a measured frame, over
    /// their exact renders, which are kept to compare against).
    pub synthesise: bool,
    pub per_pixel: bool,
}

impl ViewPlan {
    /// The plan for `views` views under `mode`.
    pub fn new(mode: Mode, views: u32) -> ViewPlan {
        let n = views.max(1);
        let (rendered, per_pixel): (Vec<u32>, bool) = match mode {
            Mode::Exact => ((0..n).collect(), false),
            Mode::Synth => (vec![n / 2], false),
            Mode::SynthPixel => (vec![n / 2], true),
            Mode::Hybrid(k) => (spaced(k, n), false),
            Mode::HybridPixel(k) => (spaced(k, n), true),
            // `auto` starts from the centre view; `auto` changes K with `set_rendered`.
            Mode::Auto => (vec![n / 2], false),
        };
        let mut mask = vec![false; n as usize];
        for &r in &rendered {
            mask[r as usize] = true;
        }
        let all = rendered.len() == n as usize;
        ViewPlan {
            all,
            synthesise: !all,
            rendered,
            mask,
            scene_dirty: false,
            warped: false,
            per_pixel,
        }
    }

    /// From the next `new_frame` on, K evenly spaced views are rendered (as `hybrid:K`;
    /// K = 1: the centre, K ≥ N: every view).
    pub fn set_spaced(&mut self, k: u32) {
        self.set_rendered(spaced(k, self.views()));
    }

    /// Renders `rendered` (ascending) from the next frame on (`--reuse` rotates the set);
    /// `new_frame` then decides the rest.
    pub fn set_rendered(&mut self, rendered: Vec<u32>) {
        self.mask.iter_mut().for_each(|m| *m = false);
        for &r in &rendered {
            if let Some(m) = self.mask.get_mut(r as usize) {
                *m = true;
            }
        }
        self.rendered = rendered;
    }

    pub fn views(&self) -> u32 {
        self.mask.len() as u32
    }

    /// Views are synthesised in this mode (some frames may still be measured exactly).
    pub fn fast(&self) -> bool {
        self.rendered.len() < self.mask.len()
    }

    /// View `i` is drawn by the draw being replayed now.
    pub fn draws(&self, i: u32) -> bool {
        self.all || self.warped || self.mask.get(i as usize).copied().unwrap_or(false)
    }

    /// View `i` is drawn by replaying the app's draws (before the warp point).
    pub fn renders(&self, i: u32) -> bool {
        self.all || self.mask.get(i as usize).copied().unwrap_or(false)
    }

    /// The rendered view nearest to `i` (ties: the lower one).
    pub fn nearest(&self, i: u32) -> u32 {
        self.rendered
            .iter()
            .copied()
            .min_by_key(|&r| (r.abs_diff(i), r))
            .unwrap_or(i)
    }

    /// The rendered views on either side of `i` (equal when `i` is outside their span or
    /// rendered itself).
    pub fn neighbours(&self, i: u32) -> (u32, u32) {
        let left = self.rendered.iter().copied().filter(|&r| r <= i).max();
        let right = self.rendered.iter().copied().filter(|&r| r >= i).min();
        match (left, right) {
            (Some(l), Some(r)) => (l, r),
            (Some(l), None) => (l, l),
            (None, Some(r)) => (r, r),
            (None, None) => (i, i),
        }
    }

    /// A draw into framebuffer 0 is about to be replayed; true when the views must be
    /// synthesised first (it is not view-dependent and the scene has been drawn).
    pub fn before_default_draw(&mut self, view_dependent: bool) -> bool {
        if !self.synthesise || self.warped {
            return false;
        }
        if view_dependent {
            self.scene_dirty = true;
            return false;
        }
        self.scene_dirty
    }

    /// The views were synthesised.
    pub fn mark_warped(&mut self) {
        self.warped = true;
        self.scene_dirty = false;
    }

    /// A new frame: nothing drawn, nothing warped; `measured`: every view is rendered
    /// exactly as well.
    pub fn new_frame(&mut self, measured: bool) {
        self.scene_dirty = false;
        self.warped = false;
        self.all = measured || !self.fast();
        self.synthesise = self.fast();
    }
}

/// K evenly spaced views of `n` including both ends (K = 1: the centre).
fn spaced(k: u32, n: u32) -> Vec<u32> {
    let k = k.clamp(1, n);
    if k == 1 {
        return vec![n / 2];
    }
    let mut v: Vec<u32> = (0..k)
        .map(|j| ((j as f64 * (n - 1) as f64 / (k - 1) as f64).round()) as u32)
        .collect();
    v.dedup();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rendered_views_by_mode() {
        assert_eq!(ViewPlan::new(Mode::Exact, 5).rendered, vec![0, 1, 2, 3, 4]);
        assert_eq!(ViewPlan::new(Mode::Synth, 9).rendered, vec![4]);
        assert_eq!(ViewPlan::new(Mode::Hybrid(2), 48).rendered, vec![0, 47]);
        assert_eq!(ViewPlan::new(Mode::Hybrid(4), 48).rendered, vec![0, 16, 31, 47]);
        assert!(ViewPlan::new(Mode::Hybrid(48), 48).all);
        assert!(ViewPlan::new(Mode::Hybrid(99), 9).all);
        assert!(!ViewPlan::new(Mode::Synth, 9).all);
    }

    #[test]
    fn set_rendered_takes_effect_at_the_next_frame() {
        let mut p = ViewPlan::new(Mode::Auto, 9);
        assert_eq!(p.rendered, vec![4]);
        p.set_spaced(3);
        p.new_frame(false);
        assert_eq!(p.rendered, vec![0, 4, 8]);
        assert!(p.fast() && !p.all && !p.draws(1) && p.draws(8));
        p.set_spaced(9);
        p.new_frame(false);
        assert!(!p.fast() && p.all && !p.synthesise);
    }

    #[test]
    fn neighbours_and_nearest() {
        let p = ViewPlan::new(Mode::Hybrid(3), 9);
        assert_eq!(p.rendered, vec![0, 4, 8]);
        assert_eq!(p.neighbours(2), (0, 4));
        assert_eq!(p.neighbours(4), (4, 4));
        assert_eq!(p.nearest(6), 4);
        assert_eq!(p.nearest(7), 8);
        let s = ViewPlan::new(Mode::Synth, 9);
        assert_eq!(s.neighbours(0), (4, 4));
    }

    #[test]
    fn warp_point_is_the_first_flat_draw_after_the_scene() {
        let mut p = ViewPlan::new(Mode::Synth, 9);
        assert!(!p.before_default_draw(false), "a clear before the scene");
        assert!(!p.before_default_draw(true));
        assert!(!p.draws(0) && p.draws(4));
        assert!(p.before_default_draw(false), "the HUD after the scene");
        p.mark_warped();
        assert!(p.draws(0));
        assert!(!p.before_default_draw(true) && !p.before_default_draw(false));
        p.new_frame(false);
        assert!(!p.draws(0));
        p.new_frame(true);
        assert!(p.draws(0), "a measured frame renders every view");
        assert!(
            !p.before_default_draw(true) && p.before_default_draw(false),
            "and synthesises them too"
        );
        let mut e = ViewPlan::new(Mode::Exact, 9);
        assert!(!e.before_default_draw(true) && !e.before_default_draw(false));
    }
}
