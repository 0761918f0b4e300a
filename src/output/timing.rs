//! The layer's own frame timing: wall time between frame boundaries, reported as a median
//! (at info level every `WINDOW` frames, and when `--exit-after` ends the run). Benchmark
//! scripts read these lines; medians, because these machines are shared and noisy.

use std::sync::Mutex;
use std::time::Instant;

const WINDOW: usize = 100;
/// Frames skipped before measuring (shader compilation, first-use allocations).
pub const WARM_UP: u64 = 10;

struct Timing {
    last: Option<Instant>,
    intervals_ms: Vec<f64>,
    all_ms: Vec<f64>,
}

static TIMING: Mutex<Timing> = Mutex::new(Timing {
    last: None,
    intervals_ms: Vec::new(),
    all_ms: Vec::new(),
});

pub fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

/// Called at every frame boundary, before presenting; `measured`: the frame also rendered
/// every view exactly to measure the error (`--measure-error`), so its time is not counted.
pub fn tick(frame: u64, measured: bool) {
    let now = Instant::now();
    let mut t = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(last) = t.last.replace(now).filter(|_| frame > WARM_UP && !measured) {
        let ms = now.duration_since(last).as_secs_f64() * 1e3;
        t.intervals_ms.push(ms);
        t.all_ms.push(ms);
    }
    if t.intervals_ms.len() >= WINDOW {
        let m = median(&mut t.intervals_ms).unwrap_or(0.0);
        crate::log::info(format_args!(
            "frame time: median {m:.3} ms over frames {}-{frame}",
            frame + 1 - WINDOW as u64
        ));
        t.intervals_ms.clear();
    }
}

/// Summary line for the whole run (after warm-up).
pub fn summary() -> Option<String> {
    let mut t = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    let n = t.all_ms.len();
    median(&mut t.all_ms)
        .map(|m| format!("frame time: median {m:.3} ms over {n} frames (after {WARM_UP} warm-up frames)"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(super::median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(super::median(&mut [4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(super::median(&mut []), None);
    }
}
