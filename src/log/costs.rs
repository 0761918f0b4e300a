//! What a draw costs the layer, counted (cargo feature `draw-costs`; without it every
//! function here is empty and inlined away): share-group locks taken, GL state queries made
//! and heap allocations done while a draw is being handled, and the draws themselves. The
//! launcher's `--log info` then prints the totals and per-draw means at exit
//! (`scripts/draw-costs.sh` builds and runs it).

#[cfg(feature = "draw-costs")]
mod counting {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;
    use std::sync::atomic::{AtomicU64, Ordering};

    pub static DRAWS: AtomicU64 = AtomicU64::new(0);
    pub static LOCKS: AtomicU64 = AtomicU64::new(0);
    pub static QUERIES: AtomicU64 = AtomicU64::new(0);
    pub static ALLOCS: AtomicU64 = AtomicU64::new(0);

    thread_local! {
        pub static IN_DRAW: Cell<bool> = const { Cell::new(false) };
    }

    pub fn in_draw() -> bool {
        IN_DRAW.try_with(Cell::get).unwrap_or(false)
    }

    pub fn count(c: &AtomicU64) {
        if in_draw() {
            c.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// The system allocator, counting the allocations made inside a draw.
    pub struct Counting;

    // SAFETY: every call is forwarded unchanged to the system allocator.
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            count(&ALLOCS);
            // SAFETY: same contract as ours.
            unsafe { System.alloc(layout) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            // SAFETY: same contract as ours.
            unsafe { System.dealloc(ptr, layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            count(&ALLOCS);
            // SAFETY: same contract as ours.
            unsafe { System.realloc(ptr, layout, new_size) }
        }
    }
}

#[cfg(feature = "draw-costs")]
#[global_allocator]
static ALLOCATOR: counting::Counting = counting::Counting;

/// A draw is being handled from now until the guard drops.
pub struct DrawScope(());

#[inline(always)]
pub fn draw() -> DrawScope {
    #[cfg(feature = "draw-costs")]
    {
        counting::DRAWS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        counting::IN_DRAW.with(|d| d.set(true));
    }
    DrawScope(())
}

impl Drop for DrawScope {
    #[inline(always)]
    fn drop(&mut self) {
        #[cfg(feature = "draw-costs")]
        counting::IN_DRAW.with(|d| d.set(false));
    }
}

#[inline(always)]
pub fn group_lock() {
    #[cfg(feature = "draw-costs")]
    counting::count(&counting::LOCKS);
}

#[inline(always)]
pub fn gl_query() {
    #[cfg(feature = "draw-costs")]
    counting::count(&counting::QUERIES);
}

/// One line with the totals, when counting is built in and something was drawn.
pub fn summary() -> Option<String> {
    #[cfg(feature = "draw-costs")]
    {
        use std::sync::atomic::Ordering::Relaxed;
        let draws = counting::DRAWS.load(Relaxed);
        let per = |c: &std::sync::atomic::AtomicU64| c.load(Relaxed) as f64 / draws.max(1) as f64;
        return (draws > 0).then(|| {
            format!(
                "draw costs: {draws} draws; per draw {:.3} share-group locks, {:.3} GL queries, {:.3} allocations",
                per(&counting::LOCKS),
                per(&counting::QUERIES),
                per(&counting::ALLOCS)
            )
        });
    }
    #[allow(unreachable_code)]
    None
}
