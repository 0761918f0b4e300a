//! `--record FILE.mp4`: the quilt of every frame, as a video named by the Looking Glass
//! convention (`FILE_qs{C}x{R}a{aspect}.mp4`, the tag inserted when the name lacks it).
//!
//! Frame rate: *measured*, not passed as timestamps (a raw-video pipe carries none). The first
//! [`MEASURED_INTERVALS`] frame intervals after the first frame are timed (the median, so one
//! slow start-up frame does not count), then the encoder starts at that constant rate with
//! the next frame. A program whose rate changes a lot later plays back faster or slower
//! there; the summary at the end gives the program's own average rate next to the video's.
//!
//! Per frame the program's thread only queues a read of the quilt into one of two pixel pack
//! buffers and maps the one queued two frames earlier (`gl::pbo`): the copy out of GL is
//! the whole cost it pays. Encoding runs in ffmpeg, fed by a writer thread (`encoder`); when
//! ffmpeg falls behind, frames are dropped and counted rather than the program waiting.
//!
//! One recording per process: the first context that presents a quilt owns it.

use super::encoder::Encoder;
use crate::gl::{Gl, GlInfo, pbo};
use crate::log::{self, Level};
use crate::multiview::quilt::layout::QuiltLayout;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Frame intervals timed before the recording starts.
pub const MEASURED_INTERVALS: usize = 10;

static ENCODER: Mutex<Option<Encoder>> = Mutex::new(None);
static CLAIMED: AtomicBool = AtomicBool::new(false);
static DROP_WARNED: AtomicBool = AtomicBool::new(false);
static FAILED: AtomicBool = AtomicBool::new(false);
/// What recording costs the program's thread per frame (queueing the read, mapping the one
/// before, handing it over), in ms: the summary's median.
static COST_MS: Mutex<Vec<f64>> = Mutex::new(Vec::new());

#[derive(Default)]
enum State {
    #[default]
    Unclaimed,
    Measuring(Vec<Instant>),
    Recording,
    Off,
}

/// A context's side of the recording: the pack buffers and the reads in flight.
#[derive(Default)]
pub struct Recorder {
    state: State,
    pbos: Vec<u32>,
    /// Reads queued, oldest first: (pack buffer index, quilt layout at the time).
    in_flight: std::collections::VecDeque<(usize, QuiltLayout)>,
    next: usize,
    layout: Option<QuiltLayout>,
}

impl Recorder {
    pub fn buffers(&self) -> &[u32] {
        &self.pbos
    }

    /// Called once per frame after the quilt is final (resolved); `fbo` holds it.
    pub fn frame(&mut self, gl: &Gl, info: GlInfo, fbo: u32, layout: QuiltLayout, path: &std::path::Path) {
        match &mut self.state {
            State::Off => {}
            State::Unclaimed => self.claim(gl, info, path),
            State::Measuring(times) => {
                times.push(Instant::now());
                if times.len() > MEASURED_INTERVALS {
                    let fps = measured_fps(times);
                    self.start(gl, layout, path, fps);
                }
            }
            State::Recording => {
                let start = Instant::now();
                self.capture(gl, info, fbo, layout);
                let ms = start.elapsed().as_secs_f64() * 1e3;
                COST_MS.lock().unwrap_or_else(|e| e.into_inner()).push(ms);
            }
        }
    }

    fn claim(&mut self, gl: &Gl, info: GlInfo, path: &std::path::Path) {
        if CLAIMED.swap(true, Ordering::AcqRel) {
            self.state = State::Off;
            return;
        }
        let ready = super::encoder::find_ffmpeg().and_then(|_| {
            pbo::available(gl, info)
                .then_some(())
                .ok_or_else(|| format!("GL {}.{} cannot read into pixel buffers", info.major, info.minor))
        });
        self.state = match ready {
            Ok(()) => State::Measuring(vec![Instant::now()]),
            Err(e) => {
                log::warn(format_args!(
                    "--record {}: {e}; the program runs without recording",
                    path.display()
                ));
                State::Off
            }
        };
    }

    fn start(&mut self, gl: &Gl, layout: QuiltLayout, path: &std::path::Path, fps: f64) {
        let (named, renamed) = super::quilt_name::with_tag(path, &layout.file_tag());
        if renamed {
            log::warn(format_args!(
                "--record: writing {} (players read the quilt layout from the name)",
                named.display()
            ));
        }
        let size = (layout.width(), layout.height());
        match Encoder::start(&named, size, fps) {
            Ok(enc) => {
                log::info(format_args!(
                    "recording {}x{} quilts at {fps:.2} fps (measured over {MEASURED_INTERVALS} frames) to {}",
                    size.0,
                    size.1,
                    named.display()
                ));
                *ENCODER.lock().unwrap_or_else(|e| e.into_inner()) = Some(enc);
                register_exit_handler();
                self.pbos = (0..2)
                    .map(|_| pbo::create(gl, size.0 as usize * size.1 as usize * 4))
                    .collect();
                self.layout = Some(layout);
                self.state = State::Recording;
            }
            Err(e) => self.fail(&e),
        }
    }

    fn fail(&mut self, e: &str) {
        log::once(
            &FAILED,
            Level::Error,
            format_args!("--record: {e}; recording stopped, the program runs on"),
        );
        self.state = State::Off;
    }

    fn capture(&mut self, gl: &Gl, info: GlInfo, fbo: u32, layout: QuiltLayout) {
        if self.layout != Some(layout) {
            // The video's size is fixed at its start; a resized quilt ends it.
            self.fail("the quilt changed size (the window was resized)");
            finish();
            return;
        }
        if self.in_flight.len() == self.pbos.len() {
            self.deliver_oldest(gl, false);
        }
        let rect = [0, 0, layout.width() as i32, layout.height() as i32];
        pbo::start_read(gl, info, fbo, rect, self.pbos[self.next]);
        self.in_flight.push_back((self.next, layout));
        self.next = (self.next + 1) % self.pbos.len();
    }

    /// Maps the oldest read and queues it for the encoder (`wait`: even if the queue is full,
    /// for the last frames of a run).
    fn deliver_oldest(&mut self, gl: &Gl, wait: bool) {
        let Some((i, layout)) = self.in_flight.pop_front() else {
            return;
        };
        let bytes = layout.width() as usize * layout.height() as usize * 4;
        let mut frame = match pbo::take(gl, self.pbos[i], bytes) {
            Ok(f) => f,
            Err(e) => return self.fail(&e),
        };
        if let Some((a, b)) = layout.swapped() {
            super::dump::swap_tiles(&mut frame, layout, a, b);
        }
        let mut guard = ENCODER.lock().unwrap_or_else(|e| e.into_inner());
        let Some(enc) = guard.as_mut() else {
            return;
        };
        match enc.push(frame, wait) {
            Ok(true) => {}
            Ok(false) => log::once(
                &DROP_WARNED,
                Level::Warn,
                format_args!(
                    "--record: the encoder is slower than the program: frames are dropped (counted at the end)"
                ),
            ),
            Err(e) => {
                drop(guard);
                self.fail(&e);
            }
        }
    }

    /// The reads still in flight, handed to the encoder (the run is about to end).
    pub fn flush(&mut self, gl: &Gl) {
        while !self.in_flight.is_empty() {
            self.deliver_oldest(gl, true);
        }
    }
}

fn measured_fps(times: &[Instant]) -> f64 {
    let mut ms: Vec<f64> = times.windows(2).map(|w| (w[1] - w[0]).as_secs_f64() * 1e3).collect();
    let median = super::timing::median(&mut ms).unwrap_or(1000.0 / 60.0);
    (1000.0 / median.max(0.1)).min(1000.0)
}

/// Ends the recording: ffmpeg gets the queued frames and writes the file. Safe to call twice.
pub fn finish() {
    let Some(enc) = ENCODER.lock().unwrap_or_else(|e| e.into_inner()).take() else {
        return;
    };
    let (path, sent, dropped) = (enc.path.clone(), enc.sent, enc.dropped);
    let cost = super::timing::median(&mut COST_MS.lock().unwrap_or_else(|e| e.into_inner())).unwrap_or(0.0);
    match enc.finish() {
        Ok((n, fps)) => {
            let level = if dropped > 0 { Level::Warn } else { Level::Info };
            log::at(
                level,
                format_args!(
                    "--record: {} written: {n} frames at {fps:.2} fps ({} s); {dropped} of {} frames dropped because the encoder was behind; read-back on the program's thread: median {cost:.2} ms/frame",
                    path.display(),
                    (n as f64 / fps * 10.0).round() / 10.0,
                    sent + dropped
                ),
            );
        }
        Err(e) => log::error(format_args!("--record: {} is incomplete: {e}", path.display())),
    }
}

extern "C" fn finish_at_exit() {
    let _ = std::panic::catch_unwind(finish);
}

fn register_exit_handler() {
    // SAFETY: registering a plain `extern "C"` function that never unwinds.
    unsafe { libc::atexit(finish_at_exit) };
}
