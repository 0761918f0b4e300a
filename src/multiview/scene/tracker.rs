//! Where the scene's depth is, for auto-convergence (DESIGN §5, "Where depth comes from").
//!
//! Auto-convergence puts the zero-parallax plane at the harmonic mean depth of the scene, so
//! it needs the depth the main camera's perspective draws left behind. Framebuffer 0 holds
//! it only in programs that draw their scene straight to the window. Most modern renderers
//! (HDR, bloom, tone mapping, depth of field; VTK; glmark2's terrain) draw the scene into a
//! framebuffer of their own, post-process it, and composite the result onto framebuffer 0
//! with a full-screen quad; at the swap, framebuffer 0's depth is that quad's (or nothing),
//! and a convergence taken from it makes every view slide as a flat picture.
//!
//! So the layer follows the camera. Each draw that is seen through the main camera
//! (`Shift::camera`: a perspective projection, not a full-screen pass in NDC, not an
//! orthographic HUD) is counted against the framebuffer it lands in — two field writes, no
//! lock, no GL query, no allocation. At the swap, the framebuffer with the most camera draws
//! that has a colour and a depth attachment (a depth-only target is a light's shadow map) is
//! chosen as the next frame's *scene target*; ties go to the one drawn last.
//!
//! The depth must be taken while it still holds the scene. The engine pattern — scene
//! framebuffer, post passes into other framebuffers, composite onto framebuffer 0, swap —
//! leaves it intact until the swap, but a program may also reuse the target after its scene:
//! a full-screen pass or a HUD drawn into it, or a depth clear for a second pass (a weapon
//! model, another viewport). So the depth is copied (a GPU blit, no wait) at the first of
//! these moments after the camera has drawn into the target in a frame:
//!
//! - a draw into the target that is not the camera's (HUD, composite, full-screen pass);
//! - a clear of the target's depth;
//! - the swap.
//!
//! The first copy of a frame is the one used; it is read back at the swap. The copy comes
//! from the quilt's centre tile when the target is framebuffer 0, from the centre layer of
//! the target's layered shadow when it has one (the app's own attachment is not drawn while
//! the shadow lives), else from the app's attachment. The target is chosen from the previous
//! frame's draws, so the first frame with a camera gives no estimate; a camera that moves
//! to another framebuffer is followed one frame later.
//!
//! This file is the bookkeeping only (no GL); `convergence` does the copying and estimating.

/// Distinct framebuffers counted per frame; beyond that the least drawn-into is forgotten.
const SLOTS: usize = 8;

/// Where the camera has drawn this frame, and the state of the scene target's depth copy.
#[derive(Clone, Debug, Default)]
pub struct SceneTracker {
    /// (framebuffer, camera draws this frame, serial of the last one); count 0 = free.
    slots: [(u32, u32, u32); SLOTS],
    /// Slot of the last camera draw (most draws go where the previous one went).
    last: usize,
    serial: u32,
    /// The framebuffer chosen at the last swap, where the camera is expected to draw.
    pub target: Option<u32>,
    /// The camera's viewport in the target at its last draw there (the rectangle to copy).
    pub viewport: [i32; 4],
    pub phase: Phase,
}

/// The scene target's depth in the current frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Phase {
    /// The camera has not drawn into the target yet.
    #[default]
    Waiting,
    /// It has: the depth must be copied before anything else changes it.
    Drawn,
    /// Copied (or the copy failed); later changes do not matter this frame.
    Taken,
}

/// A framebuffer's share of the frame's camera draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Candidate {
    pub fbo: u32,
    pub draws: u32,
}

impl SceneTracker {
    /// A draw into `fbo` (per draw: keep it cheap). Returns true when the scene target's
    /// depth must be copied now, before this draw changes it.
    pub fn draw(&mut self, fbo: u32, camera: bool, viewport: [i32; 4]) -> bool {
        let into_target = self.target == Some(fbo);
        if !camera {
            return into_target && self.phase == Phase::Drawn;
        }
        self.count(fbo);
        if into_target {
            self.viewport = viewport;
            if self.phase == Phase::Waiting {
                self.phase = Phase::Drawn;
            }
        }
        false
    }

    /// A clear of `fbo`: true when it clears the scene's depth before it was copied.
    pub fn clear(&mut self, fbo: u32, depth: bool) -> bool {
        depth && self.target == Some(fbo) && self.phase == Phase::Drawn
    }

    fn count(&mut self, fbo: u32) {
        self.serial = self.serial.wrapping_add(1);
        let slot = match self.slots[self.last] {
            (f, n, _) if f == fbo && n > 0 => self.last,
            _ => self.find_slot(fbo),
        };
        let s = &mut self.slots[slot];
        *s = (fbo, s.1.saturating_add(1), self.serial);
        self.last = slot;
    }

    /// The slot counting `fbo`, else a free one, else the least drawn-into (emptied).
    fn find_slot(&mut self, fbo: u32) -> usize {
        let found = self.slots.iter().position(|&(f, n, _)| f == fbo && n > 0);
        let slot = found.unwrap_or_else(|| {
            (0..SLOTS)
                .min_by_key(|&i| (self.slots[i].1, self.slots[i].2))
                .unwrap_or(0)
        });
        if found.is_none() {
            self.slots[slot] = (fbo, 0, 0);
        }
        slot
    }

    /// The frame's camera draws per framebuffer, most first (ties: the last drawn first),
    /// and a new frame begins: counts emptied, the target's depth not drawn yet.
    pub fn end_frame(&mut self) -> Vec<Candidate> {
        let mut used: Vec<(u32, u32, u32)> = self.slots.iter().copied().filter(|s| s.1 > 0).collect();
        used.sort_by_key(|&(_, n, serial)| std::cmp::Reverse((n, serial)));
        self.slots = Default::default();
        self.phase = Phase::Waiting;
        used.into_iter()
            .map(|(fbo, draws, _)| Candidate { fbo, draws })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const VP: [i32; 4] = [0, 0, 400, 300];

    /// One frame of `draws` (framebuffer, camera?); returns the draws that asked for a copy.
    fn frame(t: &mut SceneTracker, draws: &[(u32, bool)]) -> Vec<usize> {
        let mut copies = Vec::new();
        for (i, &(fbo, camera)) in draws.iter().enumerate() {
            if t.draw(fbo, camera, VP) {
                t.phase = Phase::Taken;
                copies.push(i);
            }
        }
        copies
    }

    /// Scene framebuffer → post passes → composite onto framebuffer 0 (glmark2 terrain):
    /// the scene framebuffer is chosen, never framebuffer 0, and with no later draw into it
    /// the copy waits for the swap.
    #[test]
    fn composited_scene_is_found_in_its_framebuffer() {
        let mut t = SceneTracker::default();
        let terrain = [
            (2, false),
            (5, true),
            (5, true),
            (6, false),
            (7, false),
            (8, false),
            (0, false),
        ];
        assert!(frame(&mut t, &terrain).is_empty());
        assert_eq!(t.end_frame(), [Candidate { fbo: 5, draws: 2 }]);
        t.target = Some(5);
        assert!(frame(&mut t, &terrain).is_empty());
        assert_eq!(t.phase, Phase::Drawn, "copied at the swap");
    }

    /// A scene drawn to framebuffer 0, then a HUD and a full-screen pass over it: the depth
    /// is copied before the first of them, once.
    #[test]
    fn depth_is_copied_before_the_first_overwrite() {
        let mut t = SceneTracker {
            target: Some(0),
            ..Default::default()
        };
        let draws = [(0, false), (0, true), (0, true), (0, false), (0, true), (0, false)];
        assert_eq!(frame(&mut t, &draws), [3]);
        assert_eq!(t.end_frame(), [Candidate { fbo: 0, draws: 3 }]);
        assert_eq!(t.phase, Phase::Waiting);
    }

    #[test]
    fn a_depth_clear_after_the_scene_asks_for_a_copy() {
        let mut t = SceneTracker {
            target: Some(4),
            ..Default::default()
        };
        assert!(!t.clear(4, true), "the frame's first clear comes before the scene");
        t.draw(4, true, VP);
        assert!(!t.clear(4, false) && !t.clear(0, true));
        assert!(t.clear(4, true));
    }

    /// Most camera draws win (a reflection pass drawn first with fewer objects loses); on a
    /// tie the framebuffer drawn into last wins.
    #[test]
    fn most_camera_draws_win_then_the_last() {
        let mut t = SceneTracker::default();
        frame(&mut t, &[(3, true), (7, true), (7, true), (3, true), (0, true)]);
        let c = t.end_frame();
        assert_eq!(
            c.iter().map(|c| (c.fbo, c.draws)).collect::<Vec<_>>(),
            [(3, 2), (7, 2), (0, 1)]
        );
        frame(&mut t, &[(3, true), (7, true)]);
        assert_eq!(t.end_frame()[0].fbo, 7);
    }

    #[test]
    fn many_framebuffers_keep_the_most_drawn_into() {
        let mut t = SceneTracker::default();
        let mut draws: Vec<(u32, bool)> = vec![(100, true); 5];
        draws.extend((1..=20).map(|f| (f, true)));
        frame(&mut t, &draws);
        let c = t.end_frame();
        assert_eq!(c.len(), SLOTS);
        assert_eq!(c[0], Candidate { fbo: 100, draws: 5 });
    }
}
