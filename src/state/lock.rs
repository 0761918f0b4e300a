//! A mutex the layer may hold across a real GL call.
//!
//! GL may call back into the app from inside any call: a synchronous `KHR_debug` callback
//! (`GL_DEBUG_OUTPUT_SYNCHRONOUS`) runs on the calling thread, before the call returns, and
//! may itself call GL — through our hooks. A hook that then locked a mutex its own thread
//! already holds (the per-context multiview state, locked for a whole replayed draw) would
//! wait for itself forever. [`GlMutex::enter`] tells that case apart: it returns `None` when
//! the calling thread is the holder, and the hook passes the call straight through, exactly as
//! when multiview is off. Another thread holding it is ordinary contention, and is waited for.

use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, TryLockError};

#[derive(Default)]
pub struct GlMutex<T> {
    inner: Mutex<T>,
    /// [`thread_mark`] of the holder, 0 when free (or between the lock and the store).
    owner: AtomicUsize,
}

/// Holds a [`GlMutex`]; releases it when dropped.
pub struct GlGuard<'a, T> {
    owner: &'a AtomicUsize,
    guard: MutexGuard<'a, T>,
}

thread_local! {
    static MARK: u8 = const { 0 };
}

/// A number unique to each live thread, never 0: the address of a thread-local.
fn thread_mark() -> usize {
    MARK.with(|m| core::ptr::from_ref(m) as usize)
}

impl<T> GlMutex<T> {
    pub fn new(value: T) -> GlMutex<T> {
        GlMutex {
            inner: Mutex::new(value),
            owner: AtomicUsize::new(0),
        }
    }

    /// Locks, waiting for other threads; `None` when the calling thread holds it already
    /// (re-entered from a callback GL made inside a call we issued while holding it). A
    /// poisoned lock is taken as is: its holder's panic already turned the layer off.
    pub fn enter(&self) -> Option<GlGuard<'_, T>> {
        let me = thread_mark();
        let guard = match self.inner.try_lock() {
            Ok(g) => g,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            // Only this thread ever stores its own mark, and it clears it before unlocking, so
            // reading it here means this thread holds the lock now.
            Err(TryLockError::WouldBlock) if self.owner.load(Ordering::Relaxed) == me => return None,
            Err(TryLockError::WouldBlock) => self.inner.lock().unwrap_or_else(|p| p.into_inner()),
        };
        self.owner.store(me, Ordering::Relaxed);
        Some(GlGuard {
            owner: &self.owner,
            guard,
        })
    }

    pub fn get_mut(&mut self) -> &mut T {
        self.inner.get_mut().unwrap_or_else(|p| p.into_inner())
    }
}

impl<T> Drop for GlGuard<'_, T> {
    fn drop(&mut self) {
        // Before `guard` (a field, dropped after this) unlocks.
        self.owner.store(0, Ordering::Relaxed);
    }
}

impl<T> Deref for GlGuard<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.guard
    }
}

impl<T> DerefMut for GlGuard<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.guard
    }
}

#[cfg(test)]
mod tests {
    use super::GlMutex;
    use std::sync::mpsc;
    use std::time::Duration;

    #[test]
    fn reentry_on_the_holding_thread_is_refused_not_deadlocked() {
        let m = GlMutex::new(1);
        let mut outer = m.enter().expect("free lock");
        *outer += 1;
        assert!(m.enter().is_none(), "same thread, lock held: pass through");
        drop(outer);
        assert_eq!(*m.enter().expect("released"), 2);
    }

    #[test]
    fn other_threads_wait_for_the_holder() {
        let m = std::sync::Arc::new(GlMutex::new(0));
        let held = m.enter().unwrap();
        let (tx, rx) = mpsc::channel();
        let m2 = m.clone();
        let t = std::thread::spawn(move || {
            let mut g = m2.enter().expect("another thread waits, never refused");
            *g += 1;
            tx.send(()).unwrap();
        });
        assert!(rx.recv_timeout(Duration::from_millis(100)).is_err(), "must wait");
        drop(held);
        rx.recv_timeout(Duration::from_secs(10)).expect("gets it once released");
        t.join().unwrap();
        assert_eq!(*m.enter().unwrap(), 1);
    }
}
