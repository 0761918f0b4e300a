//! Interposition: the exported entry points (generated from `policy.txt`), the `dlsym` /
//! `dlopen` interposers, and the handlers, which decide the order of things (at make-current,
//! draw, swap) and hand over to `state`, `multiview` and `output`.
//!
//! # Safety contract
//! Every exported shim catches panics from its handler; after the first one the whole layer
//! turns itself into pass-through (`is_active() == false`) and logs once, because a handler
//! that panicked may have left our shadow state inconsistent with the app's GL state.

use core::ffi::c_void;
use std::sync::atomic::{AtomicBool, Ordering};

pub mod census;
pub mod dl;
pub mod frame;
mod gpu_counts;
pub(crate) mod handlers;
mod heap;
pub mod layer;

// Generated: its unsafe blocks are the shims' calls of the real functions, one pattern
// documented once in build.rs (`gen_shim`).
#[allow(unsafe_op_in_unsafe_fn, clippy::all, clippy::undocumented_unsafe_blocks)]
mod exports {
    include!(concat!(env!("OUT_DIR"), "/hooks.rs"));
}
pub use crate::real::{HOOK_COUNT, HOOKS, HookApi, Policy, id};
pub use exports::ADDRS;

/// A function address in a `static` table.
#[derive(Clone, Copy)]
pub struct HookAddr(pub *const c_void);
// SAFETY: code addresses are immutable and valid on every thread.
unsafe impl Sync for HookAddr {}

static DISABLED: AtomicBool = AtomicBool::new(false);

/// False once a handler has failed: from then on every hook is a plain pass-through.
#[inline]
pub fn is_active() -> bool {
    !DISABLED.load(Ordering::Relaxed)
}

/// Called by hook `id`'s shim when its handler panicked: the first time, the frame in
/// progress is handed back to the app (`layer::abandon`), the layer turns pass-through for
/// good and says so once; later panics (from other threads already inside a handler) are
/// silent.
pub fn handler_panicked(id: usize) {
    if !DISABLED.swap(true, Ordering::Relaxed) {
        let _ = std::panic::catch_unwind(layer::abandon);
        crate::log::error(format_args!(
            "internal error in the {} hook; the layer is now pass-through for the rest of this run",
            HOOKS[id].name.to_string_lossy()
        ));
    }
}

static FAIL_ID: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(usize::MAX);
static FAIL_INIT: AtomicBool = AtomicBool::new(false);

/// Forced internal error for robustness tests: `HOLOINJECT_TEST_FAIL=NAME` makes the handler
/// of hook NAME panic, which must leave the app running, pass-through.
#[inline]
pub fn fail_point(id: usize) {
    if !FAIL_INIT.load(Ordering::Relaxed) {
        let target = std::env::var("HOLOINJECT_TEST_FAIL").ok();
        let found = target.and_then(|t| HOOKS.iter().position(|h| h.name.to_bytes() == t.as_bytes()));
        FAIL_ID.store(found.unwrap_or(usize::MAX), Ordering::Relaxed);
        FAIL_INIT.store(true, Ordering::Relaxed);
    }
    if FAIL_ID.load(Ordering::Relaxed) == id {
        panic!(
            "HOLOINJECT_TEST_FAIL: forced failure in {}",
            HOOKS[id].name.to_string_lossy()
        );
    }
}
