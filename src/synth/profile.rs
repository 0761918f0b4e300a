//! Per-pass timings of a warp, logged at `trace` only: they wait for the GPU after every pass
//! (`glFinish`), which costs what they measure, so they are a diagnostic, never the default.
//! Each pass gets wall time and this thread's CPU time: with llvmpipe single-threaded
//! (`LP_NUM_THREADS=0`) the latter is the pass's whole cost, unaffected by other load.

use crate::gl::Gl;
use crate::log::Level;
use std::time::Instant;

pub struct Profile<'a> {
    gl: Option<&'a Gl>,
    last: (Instant, f64),
    parts: Vec<(&'static str, f64, f64)>,
    pub leaves: u64,
}

impl<'a> Profile<'a> {
    pub fn new(gl: &'a Gl) -> Profile<'a> {
        let gl = crate::log::enabled(Level::Trace).then_some(gl);
        let p = Profile {
            gl,
            last: (Instant::now(), thread_cpu_ms()),
            parts: Vec::new(),
            leaves: 0,
        };
        p.finish();
        p
    }

    pub fn on(&self) -> bool {
        self.gl.is_some()
    }

    fn finish(&self) {
        if let Some(gl) = self.gl {
            // SAFETY: a plain wait for the context's queued work.
            unsafe { gl.Finish() };
        }
    }

    /// Ends pass `name` (times of passes with the same name add up).
    pub fn lap(&mut self, name: &'static str) {
        if !self.on() {
            return;
        }
        self.finish();
        let ms = self.last.0.elapsed().as_secs_f64() * 1e3;
        let cpu = thread_cpu_ms() - self.last.1;
        match self.parts.iter_mut().find(|p| p.0 == name) {
            Some(p) => (p.1, p.2) = (p.1 + ms, p.2 + cpu),
            None => self.parts.push((name, ms, cpu)),
        }
        self.last = (Instant::now(), thread_cpu_ms());
    }
}

impl Drop for Profile<'_> {
    fn drop(&mut self) {
        if self.on() {
            let parts: Vec<String> = self
                .parts
                .iter()
                .map(|(n, ms, cpu)| format!("{n} {ms:.2} ms (cpu {cpu:.2})"))
                .collect();
            crate::log::trace(format_args!(
                "synthesis passes: {}; {} leaves",
                parts.join(", "),
                self.leaves
            ));
        }
    }
}

/// This thread's CPU time so far, in milliseconds.
fn thread_cpu_ms() -> f64 {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: a plain query into a local.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 * 1e3 + t.tv_nsec as f64 / 1e6
}
