//! A context's snapshot of its current program, so that a draw needs no share-group lock.
//!
//! Link-time facts live in the share group (`ProgramInfo`, behind an `Arc`), and so do the
//! matrices the app uploads. A context takes an `Arc` of its current program's facts and a
//! copy of its projection uniform at `glUseProgram`, and keeps the copy current as it uploads
//! it. Two generation counters of the group tell a draw, with two atomic loads, whether
//! anything it cannot have seen happened since (a relink, or an upload from another context):
//! only then is the snapshot taken again, under the lock.

use super::share::{ProgramInfo, ShareGroup};
use std::sync::Arc;
use std::sync::atomic::Ordering;

#[derive(Clone, Debug, Default)]
pub struct ProgramSnapshot {
    pub program: u32,
    /// None: a program the layer knows nothing about (not linked while multiview was on).
    pub info: Option<Arc<ProgramInfo>>,
    /// The last value uploaded to `info.projection_loc`, column-major.
    pub projection: Option<[f32; 16]>,
    /// A block-held projection as last read, with the buffer generation it was read at.
    pub ubo_cache: Option<(u64, [f32; 16])>,
    /// Every `mat4` uniform value of a program whose `gl_Position` is given in NDC (a
    /// screen-space pass may hold the camera's projection or its inverse), else the values of
    /// its `camera_chain`: (location, value).
    pub matrices: Vec<(i32, [f32; 16])>,
    links_seen: u64,
    uploads_seen: u64,
}

impl ProgramSnapshot {
    /// Takes the snapshot of `program` (at `glUseProgram`, or when it went stale).
    pub fn take(&mut self, group: &ShareGroup, program: u32) {
        let links = group.links.load(Ordering::Acquire);
        let uploads = group.uploads.load(Ordering::Acquire);
        let state = group.lock();
        let info = state.programs.get(&program).cloned();
        let projection = info
            .as_ref()
            .and_then(|i| i.projection_loc)
            .and_then(|loc| state.matrices.get(&(program, loc)).copied());
        self.matrices.clear();
        if let Some(i) = info.as_ref().filter(|i| i.identity || !i.camera_chain.is_empty()) {
            let followed = |loc: &i32| i.identity || i.camera_chain.contains(loc);
            let of_program = state
                .matrices
                .iter()
                .filter(|((p, loc), _)| *p == program && followed(loc));
            self.matrices.extend(of_program.map(|(&(_, loc), m)| (loc, *m)));
        }
        drop(state);
        let same = self.program == program && self.info.as_ref().map(Arc::as_ptr) == info.as_ref().map(Arc::as_ptr);
        if !same {
            self.ubo_cache = None;
        }
        self.program = program;
        self.info = info;
        self.projection = projection;
        self.links_seen = links;
        self.uploads_seen = uploads;
    }

    /// The snapshot of `program` for a draw: taken again only if it is of another program or
    /// the group changed in a way this context did not follow.
    pub fn current(&mut self, group: &ShareGroup, program: u32) -> &ProgramSnapshot {
        let fresh = self.program == program
            && group.links.load(Ordering::Acquire) == self.links_seen
            && group.uploads.load(Ordering::Acquire) == self.uploads_seen;
        if !fresh {
            self.take(group, program);
        }
        self
    }

    /// This context uploaded `m` to `program`'s uniform `loc` (already recorded in the group,
    /// whose upload generation was `before` just before): follow it when nobody else wrote
    /// in between, else leave the snapshot stale for the next draw to retake.
    pub fn uploaded(&mut self, program: u32, loc: i32, m: [f32; 16], before: u64) {
        if before != self.uploads_seen {
            return;
        }
        self.uploads_seen = before + 1;
        if program != self.program {
            return;
        }
        if self.info.as_ref().and_then(|i| i.projection_loc) == Some(loc) {
            self.projection = Some(m);
        }
        if self
            .info
            .as_ref()
            .is_some_and(|i| i.identity || i.camera_chain.contains(&loc))
        {
            match self.matrices.iter_mut().find(|(l, _)| *l == loc) {
                Some(entry) => entry.1 = m,
                None => self.matrices.push((loc, m)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::share::ProgramInfo;

    fn group_with(program: u32, projection_loc: i32) -> ShareGroup {
        let g = ShareGroup::new(900);
        g.linked(
            program,
            ProgramInfo {
                view_loc: 0,
                projection_loc: Some(projection_loc),
                ..Default::default()
            },
        );
        g
    }

    #[test]
    fn follows_its_own_uploads_without_retaking() {
        let g = group_with(3, 5);
        let mut s = ProgramSnapshot::default();
        s.take(&g, 3);
        let m = [2.0; 16];
        let before = g.uploaded(3, 5, m);
        s.uploaded(3, 5, m, before);
        let locks = g.uploads.load(Ordering::Acquire);
        assert_eq!(s.current(&g, 3).projection, Some(m));
        // Still fresh: nothing was retaken (the seen generation is the group's).
        assert_eq!(s.uploads_seen, locks);
        // An upload to another program by this context keeps it fresh too.
        let before = g.uploaded(4, 5, [7.0; 16]);
        s.uploaded(4, 5, [7.0; 16], before);
        assert_eq!(s.uploads_seen, g.uploads.load(Ordering::Acquire));
        assert_eq!(s.projection, Some(m));
    }

    #[test]
    fn an_upload_from_another_context_or_a_relink_is_seen_at_the_next_draw() {
        let g = group_with(3, 5);
        let mut s = ProgramSnapshot::default();
        s.take(&g, 3);
        // Another context uploads (its snapshot, not ours, follows).
        g.uploaded(3, 5, [4.0; 16]);
        assert_eq!(s.current(&g, 3).projection, Some([4.0; 16]));
        // Relinked elsewhere with the projection somewhere else.
        g.linked(
            3,
            ProgramInfo {
                view_loc: 1,
                projection_loc: Some(6),
                ..Default::default()
            },
        );
        let snap = s.current(&g, 3);
        assert_eq!(snap.info.as_ref().map(|i| i.view_loc), Some(1));
        assert_eq!(snap.projection, None);
    }

    #[test]
    fn a_stale_upload_of_ours_does_not_skip_another_contexts() {
        let g = group_with(3, 5);
        let mut s = ProgramSnapshot::default();
        s.take(&g, 3);
        g.uploaded(3, 5, [4.0; 16]); // another context
        let before = g.uploaded(3, 9, [1.0; 16]); // ours, to another uniform
        s.uploaded(3, 9, [1.0; 16], before);
        // Ours came after theirs: the snapshot must still be retaken to see theirs.
        assert_eq!(s.current(&g, 3).projection, Some([4.0; 16]));
    }
}
