//! What a frame asks of the GPU, counted (`--gpu-counts`): the program's draw calls, the draw
//! calls that reached the driver (the program's, once per view they were replayed into, and
//! the layer's own draws, dispatches, clears and blits), the bytes the layer read back to the
//! CPU, and the fragment and compute invocations the driver shaded (a pipeline-statistics
//! query; see `gl::stats_query`). llvmpipe is bound by fill and nobody plays on it, so these
//! are the figures a GPU owner can read: a GPU pays per submission and per fragment.
//!
//! The call counters always run (one relaxed add per call, far below a draw's own cost); the
//! layer's calls are counted inside the generated GL table (`build.rs` adds the counting to
//! the commands that draw or read back), so no call site can be missed. Per frame the
//! counters are taken and reset at the boundary, and at exit the medians over the frames that
//! were also timed are reported (same frames as `output::timing`'s median).

use std::cell::Cell;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

thread_local! {
    /// A program's draw is being replayed: its GL calls are the program's, not the layer's.
    static REPLAYING: Cell<bool> = const { Cell::new(false) };
}

static APP_DRAWS: AtomicU64 = AtomicU64::new(0);
static REPLAYED: AtomicU64 = AtomicU64::new(0);
static LAYER_CALLS: AtomicU64 = AtomicU64::new(0);
static READ_BACK: AtomicU64 = AtomicU64::new(0);

/// One of the program's draw calls reached the layer.
#[inline]
pub fn app_draw() {
    APP_DRAWS.fetch_add(1, Relaxed);
}

/// The program's draw goes to the driver once more (one view, or unreplayed) through `f`.
#[inline]
pub fn replay<R>(f: impl FnOnce() -> R) -> R {
    REPLAYED.fetch_add(1, Relaxed);
    let outer = REPLAYING.try_with(|r| r.replace(true)).unwrap_or(false);
    let result = f();
    let _ = REPLAYING.try_with(|r| r.set(outer));
    result
}

/// The layer submitted a draw, dispatch, clear, blit or copy of its own (called by the GL
/// table; a replayed draw of the program's that goes through the table is not the layer's).
#[inline]
pub fn layer_call() {
    if !REPLAYING.try_with(Cell::get).unwrap_or(false) {
        LAYER_CALLS.fetch_add(1, Relaxed);
    }
}

/// The layer read `bytes` back from the driver (called by the GL table).
#[inline]
pub fn read_back(bytes: u64) {
    READ_BACK.fetch_add(bytes, Relaxed);
}

/// Bytes `glReadPixels` writes for a `width`x`height` rectangle of `format`/`type_`.
pub fn pixel_bytes(width: i32, height: i32, format: u32, type_: u32) -> u64 {
    let components: u64 = match format {
        0x1907 | 0x80E0 | 0x8D98 => 3, // RGB, BGR, RGB_INTEGER
        0x1908 | 0x80E1 | 0x8D99 | 0x8D9A => 4,
        0x8227 | 0x8228 | 0x84F9 => 2, // RG, RG_INTEGER, DEPTH_STENCIL
        _ => 1,
    };
    let size: u64 = match type_ {
        0x1400 | 0x1401 => 1, // BYTE, UNSIGNED_BYTE
        0x1402 | 0x1403 | 0x140B => 2,
        0x84FA | 0x8C3B | 0x8C3E | 0x8368 => return width.max(0) as u64 * height.max(0) as u64 * 4, // packed
        _ => 4,
    };
    width.max(0) as u64 * height.max(0) as u64 * components * size
}

/// One frame's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameCounts {
    pub app_draws: u64,
    pub replayed: u64,
    pub layer_calls: u64,
    pub read_back: u64,
    /// From the statistics query; `None` where the driver has none.
    pub fragments: Option<u64>,
    pub compute: Option<u64>,
    /// Pixels of one view's tile, to express fragments in full-tile passes.
    pub tile_pixels: u64,
    /// The frame counts in the summary (timed: after the warm-up, not measured).
    pub keep: bool,
}

/// The counters since the last call, reset.
pub fn take() -> FrameCounts {
    FrameCounts {
        app_draws: APP_DRAWS.swap(0, Relaxed),
        replayed: REPLAYED.swap(0, Relaxed),
        layer_calls: LAYER_CALLS.swap(0, Relaxed),
        read_back: READ_BACK.swap(0, Relaxed),
        ..FrameCounts::default()
    }
}

static FRAMES: Mutex<Vec<FrameCounts>> = Mutex::new(Vec::new());

/// Keeps a frame's counts for the summary.
pub fn keep(c: FrameCounts) {
    FRAMES.lock().unwrap_or_else(|e| e.into_inner()).push(c);
}

fn median(mut v: Vec<u64>) -> f64 {
    v.sort_unstable();
    match v.len() {
        0 => 0.0,
        n if n % 2 == 1 => v[n / 2] as f64,
        n => (v[n / 2 - 1] + v[n / 2]) as f64 / 2.0,
    }
}

/// The summary line (medians per frame), when frames were kept.
pub fn summary() -> Option<String> {
    let frames = FRAMES.lock().unwrap_or_else(|e| e.into_inner()).clone();
    (!frames.is_empty()).then(|| summary_of(&frames))
}

fn summary_of(frames: &[FrameCounts]) -> String {
    let m = |f: fn(&FrameCounts) -> u64| median(frames.iter().map(f).collect());
    let stat = |f: fn(&FrameCounts) -> Option<u64>| {
        let v: Option<Vec<u64>> = frames.iter().map(f).collect();
        v.map(median)
    };
    let shown = |v: Option<f64>| v.map_or("n/a (no pipeline-statistics query)".to_string(), |v| format!("{v:.0}"));
    let fragments = stat(|c| c.fragments);
    let tile_pixels = median(frames.iter().map(|c| c.tile_pixels).collect());
    let tiles = fragments.filter(|_| tile_pixels > 0.0).map(|f| f / tile_pixels);
    format!(
        "gpu counts: per frame, median over {} frames: app draws {:.0}, draws submitted {:.0} (layer's own {:.0}), fragments {}, compute invocations {}, tile-equivalents {}, bytes read back {:.0}",
        frames.len(),
        m(|c| c.app_draws),
        m(|c| c.replayed + c.layer_calls),
        m(|c| c.layer_calls),
        shown(fragments),
        shown(stat(|c| c.compute)),
        tiles.map_or("n/a".to_string(), |t| format!("{t:.1}")),
        m(|c| c.read_back),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_pixels_sizes() {
        assert_eq!(pixel_bytes(10, 2, 0x1908, 0x1401), 80); // RGBA, UNSIGNED_BYTE
        assert_eq!(pixel_bytes(10, 2, 0x1902, 0x1406), 80); // DEPTH_COMPONENT, FLOAT
        assert_eq!(pixel_bytes(3, 1, 0x1907, 0x1401), 9); // RGB, UNSIGNED_BYTE
        assert_eq!(pixel_bytes(-1, 5, 0x1908, 0x1401), 0);
    }

    #[test]
    fn summary_takes_medians_and_says_when_the_driver_cannot_count() {
        let f = |d, fr| FrameCounts {
            app_draws: d,
            replayed: 9 * d,
            layer_calls: 4,
            read_back: 0,
            fragments: fr,
            compute: Some(7),
            tile_pixels: 100,
            keep: true,
        };
        let s = summary_of(&[f(1, Some(1000)), f(3, Some(3000)), f(2, Some(2000))]);
        assert!(
            s.contains("median over 3 frames: app draws 2, draws submitted 22 (layer's own 4)"),
            "{s}"
        );
        assert!(
            s.contains("fragments 2000, compute invocations 7, tile-equivalents 20.0"),
            "{s}"
        );
        let s = summary_of(&[f(1, None)]);
        assert!(s.contains("fragments n/a"), "{s}");
        assert!(s.contains("tile-equivalents n/a"), "{s}");
    }
}
