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
    /// screen-space pass may hold the camera's projection or its inverse): (location, value).
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
        if info.as_ref().is_some_and(|i| i.identity) {
            let of_program = state.matrices.iter().filter(|((p, _), _)| *p == program);
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
        if self.info.as_ref().is_some_and(|i| i.identity) {
            match self.matrices.iter_mut().find(|(l, _)| *l == loc) {
                Some(entry) => entry.1 = m,
                None => self.matrices.push((loc, m)),
            }
        }
    }
}
