//! The target each texture name was created with, per share group.
//!
//! Layered shadows need to know whether an attached texture is a 2D one, and Mesa 22.3
//! answers `GL_TEXTURE_TARGET` queries with GL_INVALID_ENUM, so the layer remembers the
//! target from the app's own `glBindTexture`/`glCreateTextures`. Texture names are shared
//! objects: a render target created in a root or worker context (one without a surface,
//! hence without multiview) and attached to a framebuffer in another context must be known
//! there, so the record belongs to the share group, and a deleted name leaves it (GL hands
//! freed names out again, possibly for another target).
//!
//! `glBindTexture` is one of the hottest calls an app makes. Each thread keeps the names it
//! has already seen recorded in its current group, valid until a deletion in the group bumps
//! the group's generation: binding a known name costs a thread-local lookup and one atomic
//! load, no lock.

use crate::gl::types::GLenum;
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

#[derive(Default)]
pub struct TextureTargets {
    /// The share group's id (keys the per-thread cache).
    group: u64,
    targets: Mutex<HashMap<u32, GLenum>>,
    /// Bumped by every deletion: per-thread caches older than this are dropped.
    generation: AtomicU64,
}

/// Names this thread has seen recorded in share group `group` at `generation`.
#[derive(Default)]
struct Seen {
    group: u64,
    generation: u64,
    names: HashSet<u32>,
}

thread_local! {
    static SEEN: RefCell<Seen> = RefCell::new(Seen::default());
}

impl TextureTargets {
    pub fn new(group: u64) -> TextureTargets {
        TextureTargets {
            group,
            ..Default::default()
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<u32, GLenum>> {
        self.targets.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// `glBindTexture(target, name)`: the first bind of a name gives its target (a later
    /// bind to another target is the app's GL error and changes nothing).
    pub fn bound(&self, target: GLenum, name: u32) {
        if name == 0 {
            return;
        }
        let generation = self.generation.load(Ordering::Acquire);
        let known = SEEN.with(|s| {
            let mut s = s.borrow_mut();
            if s.group != self.group || s.generation != generation {
                *s = Seen {
                    group: self.group,
                    generation,
                    names: HashSet::new(),
                };
            }
            !s.names.insert(name)
        });
        if !known {
            self.lock().entry(name).or_insert(target);
        }
    }

    /// `glCreateTextures(target, …)`: new names, whatever they were before.
    pub fn created(&self, target: GLenum, names: &[u32]) {
        let mut map = self.lock();
        names
            .iter()
            .filter(|&&n| n != 0)
            .for_each(|&n| _ = map.insert(n, target));
    }

    /// `glDeleteTextures`: the names are free for reuse with any target.
    pub fn deleted(&self, names: &[u32]) {
        let mut map = self.lock();
        let before = map.len();
        names.iter().for_each(|n| _ = map.remove(n));
        if map.len() != before {
            self.generation.fetch_add(1, Ordering::AcqRel);
        }
    }

    /// The target `name` was created with, 0 if unknown.
    pub fn target_of(&self, name: u32) -> GLenum {
        self.lock().get(&name).copied().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gl::{TEXTURE_2D, TEXTURE_CUBE_MAP};

    #[test]
    fn first_bind_gives_the_target() {
        let t = TextureTargets::new(1001);
        t.bound(TEXTURE_2D, 5);
        t.bound(TEXTURE_CUBE_MAP, 5);
        t.bound(TEXTURE_2D, 0);
        assert_eq!(t.target_of(5), TEXTURE_2D);
        assert_eq!(t.target_of(0), 0);
        assert_eq!(t.target_of(6), 0);
    }

    /// Regression: a deleted name re-created with another target kept the old one.
    #[test]
    fn deleted_name_reused_with_another_target() {
        let t = TextureTargets::new(1002);
        t.bound(TEXTURE_CUBE_MAP, 3);
        t.deleted(&[3]);
        assert_eq!(t.target_of(3), 0);
        t.bound(TEXTURE_2D, 3);
        assert_eq!(t.target_of(3), TEXTURE_2D);
        t.created(TEXTURE_CUBE_MAP, &[3]);
        assert_eq!(t.target_of(3), TEXTURE_CUBE_MAP);
    }

    /// Two groups used in turn on one thread: the per-thread cache of one never hides a
    /// name from the other.
    #[test]
    fn per_thread_cache_is_per_group() {
        let (a, b) = (TextureTargets::new(1003), TextureTargets::new(1004));
        a.bound(TEXTURE_2D, 7);
        b.bound(TEXTURE_CUBE_MAP, 7);
        a.bound(TEXTURE_2D, 7);
        assert_eq!((a.target_of(7), b.target_of(7)), (TEXTURE_2D, TEXTURE_CUBE_MAP));
    }

    /// A name recorded on one thread and deleted on another is recorded again on the first.
    #[test]
    fn deletion_on_another_thread_reaches_this_threads_cache() {
        let t = std::sync::Arc::new(TextureTargets::new(1005));
        t.bound(TEXTURE_CUBE_MAP, 9);
        let other = t.clone();
        std::thread::spawn(move || other.deleted(&[9])).join().unwrap();
        t.bound(TEXTURE_2D, 9);
        assert_eq!(t.target_of(9), TEXTURE_2D);
    }
}
