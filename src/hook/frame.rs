//! The frame boundary (a swap, or `glFinish`/`glFlush` for OSMesa contexts, which never
//! swap), in order: number the frame, delete what destroyed contexts left, time it; compose
//! the quilt into the window (dumping the quilt first and the weave after); dump what is
//! presented; present (the real swap); then set the next frame up (auto-convergence, a quilt
//! resized with the window), count the layer's objects every 100 frames (`census`) and
//! honour `--exit-after`. Frames are numbered from 1 per process.

use crate::config::Settings;
use crate::log::{self, Level};
use crate::output::{dump, timing};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

static FRAME: AtomicU64 = AtomicU64::new(0);
static DUMP_FAILED: AtomicBool = AtomicBool::new(false);
static COMPOSE_FAILED: AtomicBool = AtomicBool::new(false);

/// Ends the frame drawn to `surface` (a GLX drawable, EGL surface or OSMesa buffer);
/// `present` is the real swap.
pub fn boundary(surface: usize, present: impl FnOnce()) {
    let frame = FRAME.fetch_add(1, Ordering::Relaxed) + 1;
    let settings = crate::config::settings();
    crate::state::delete_orphans();
    let measured = settings.view.mode != crate::config::Mode::Exact
        && settings.view.measure_error.as_ref().is_some_and(|f| f.contains(frame));
    timing::tick(frame, measured);
    if settings.multiview() {
        multiview_frame(frame, surface, settings);
    }
    if settings.dumps(frame)
        && let Err(e) = dump::presented(frame, surface, settings)
    {
        log::once(
            &DUMP_FAILED,
            Level::Error,
            format_args!("frame {frame} not dumped: {e}"),
        );
    }
    present();
    if settings.exit_after == Some(frame) {
        exit_after(frame);
    }
}

/// Quilt composition into the window (and its dumps), then the next frame's set-up.
fn multiview_frame(frame: u64, surface: usize, settings: &Settings) {
    super::layer::with_layer(|cur, app, layer, gl| {
        if cur.binding.draw != surface || layer.views.target.is_none() {
            return;
        }
        let Some(window) = crate::state::surface_size(cur) else {
            return;
        };
        let (mv, presenter) = (&mut layer.views, &mut layer.presenter);
        crate::multiview::synthesis::end_frame(gl, mv, frame);
        if let Some(t) = &mv.target {
            // As the window resolves at its swap.
            t.resolve_all(gl, mv.info, crate::gl::COLOR_BUFFER_BIT);
        }
        if let Err(e) = crate::output::device::present_frame(gl, presenter, mv, cur, window, settings) {
            log::once(&COMPOSE_FAILED, Level::Error, format_args!("{e}"));
        }
        if let (Some(path), Some(t)) = (&settings.record, &mv.target) {
            presenter.recorder.frame(gl, mv.info, t.resolved_fbo, t.layout, path);
            if settings.exit_after == Some(frame) {
                presenter.recorder.flush(gl);
            }
        }
        if settings.dumps(frame)
            && let Err(e) = presenter.dump(frame, gl, mv, settings)
        {
            log::once(
                &DUMP_FAILED,
                Level::Error,
                format_args!("quilt of frame {frame} not dumped: {e}"),
            );
        }
        crate::multiview::update_convergence(gl, app, mv);
        crate::multiview::framebuffer::ensure_target(gl, app, mv, window);
        super::census::log_if_due(frame, layer);
    });
}

fn exit_after(frame: u64) -> ! {
    crate::output::record::finish();
    for line in [timing::summary(), log::costs::summary()].into_iter().flatten() {
        log::info(format_args!("{line}"));
    }
    log::info(format_args!(
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
