//! The frame boundary: what happens when the app presents (swap, or `glFinish` for OSMesa).
//! Frames are numbered from 1 per process. Today: dump what is presented, then present, then
//! honour `--exit-after`. The quilt composition and lenticular weave will hook in here.

pub mod compose;
mod dump;
pub mod native;
pub mod pass;
pub mod png;
mod surface;
pub mod timing;

pub use surface::size as surface_size;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

static FRAME: AtomicU64 = AtomicU64::new(0);
static DUMP_FAILED: AtomicBool = AtomicBool::new(false);

/// Ends the frame drawn to `surface` (a GLX drawable, EGL surface or OSMesa buffer);
/// `present` is the real swap.
pub fn frame_boundary(surface: usize, present: impl FnOnce()) {
    let frame = FRAME.fetch_add(1, Ordering::Relaxed) + 1;
    let settings = crate::config::settings();
    crate::state::delete_orphans();
    timing::tick(frame);
    if settings.multiview() {
        multiview_frame(frame, surface, settings);
    }
    if settings.dumps(frame)
        && let Err(e) = dump::presented(frame, surface, settings)
    {
        crate::log::once(
            &DUMP_FAILED,
            crate::log::Level::Error,
            format_args!("frame {frame} not dumped: {e}"),
        );
    }
    present();
    if settings.exit_after == Some(frame) {
        exit_after(frame);
    }
}

static COMPOSE_FAILED: AtomicBool = AtomicBool::new(false);

/// Quilt dump, composition into the window, auto-convergence and resizing for the next frame.
fn multiview_frame(frame: u64, surface: usize, settings: &crate::config::Settings) {
    crate::multiview::with_active(|cur, mv, gl| {
        if cur.binding.draw != surface || mv.target.is_none() {
            return;
        }
        let Some(window) = surface::size(cur) else { return };
        if settings.dumps(frame)
            && let Err(e) = dump::quilt(frame, gl, mv, settings)
        {
            crate::log::once(
                &DUMP_FAILED,
                crate::log::Level::Error,
                format_args!("quilt of frame {frame} not dumped: {e}"),
            );
        }
        if let Err(e) = compose::present(gl, mv, window, settings.view.output) {
            crate::log::once(&COMPOSE_FAILED, crate::log::Level::Error, format_args!("{e}"));
        }
        if settings.dumps(frame)
            && settings.view.output == crate::config::Output::Native
            && let Err(e) = dump::native(frame, gl, mv, settings)
        {
            crate::log::once(
                &DUMP_FAILED,
                crate::log::Level::Error,
                format_args!("native image of frame {frame} not dumped: {e}"),
            );
        }
        crate::multiview::update_convergence(gl, mv);
        crate::multiview::framebuffer::ensure_target(gl, mv, window);
    });
}

fn exit_after(frame: u64) -> ! {
    if let Some(line) = timing::summary() {
        crate::log::info(format_args!("{line}"));
    }
    crate::log::info(format_args!(
        "exit-after: frame {frame} presented; exiting with status 0"
    ));
    // `exit` would run the app's atexit handlers and C++ destructors from inside its swap
    // call, where GL/X11 teardown can hang or crash; flushing stdio is all the app is owed.
    // SAFETY: flushing all C streams and ending the process are always allowed.
    unsafe {
        libc::fflush(core::ptr::null_mut());
        libc::_exit(0)
    }
}

pub mod weave;
