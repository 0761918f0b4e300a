//! The frame boundary (a swap, or `glFinish`/`glFlush` for OSMesa contexts, which never
//! swap), in order: number the frame, delete what destroyed contexts left, time it; compose
//! the quilt into the window (dumping the quilt first and the weave after); dump what is
//! presented; present (the real swap); then set the next frame up (auto-convergence, a quilt
//! resized with the window), count the layer's objects every 100 frames (`census`) and
//! honour `--exit-after`. Frames are numbered from 1 per process.
//!
//! Live changes (`holoinject ctl`, hotkeys: `config::live`) are applied here, on the render
//! thread, before anything of the frame is presented: each context's settings take the new
//! values, the output of this frame already follows them, and the rig of the next frame
//! (depthiness, convergence, focus) is computed from them.

use crate::config::{Settings, live};
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
    crate::control::start_once();
    let (generation, asked) = live::apply_pending(frame);
    let asked = asked.map(|dir| asked_dump(settings, dir));
    let dumping = asked.as_ref().unwrap_or(settings);
    let dumps = settings.dumps(frame) || asked.is_some();
    crate::state::delete_orphans();
    let measured = settings.view.mode != crate::config::Mode::Exact
        && settings.view.measure_error.as_ref().is_some_and(|f| f.contains(frame));
    timing::tick(frame, measured);
    let mut result = Ok(());
    if settings.multiview() {
        result = multiview_frame(frame, surface, (dumping, dumps), generation);
    }
    if dumps {
        result = result.and(dump::presented(frame, surface, dumping));
        if let Err(e) = &result {
            log::once(
                &DUMP_FAILED,
                Level::Error,
                format_args!("frame {frame} not dumped: {e}"),
            );
        }
    }
    if let Some(s) = &asked {
        let dir = s.dump_dir.as_ref().map(|d| d.display().to_string()).unwrap_or_default();
        log::info(format_args!("live: frame {frame} dumped into {dir}"));
        live::dump_done(frame, result.map_err(|e| format!("frame {frame} not dumped: {e}")));
    }
    super::gpu_counts::end_frame(frame, measured);
    present();
    super::gpu_counts::begin_frame(frame);
    if settings.exit_after == Some(frame) {
        exit_after(frame);
    }
}

/// The settings a dump asked for live uses: its directory (empty: `--dump`'s, else
/// `holoinject-dumps` in the program's working directory).
fn asked_dump(settings: &Settings, dir: std::path::PathBuf) -> Settings {
    let dir = match (dir.as_os_str().is_empty(), &settings.dump_dir) {
        (false, _) => dir,
        (true, Some(d)) => d.clone(),
        (true, None) => std::path::PathBuf::from("holoinject-dumps"),
    };
    Settings {
        dump_dir: Some(dir),
        ..settings.clone()
    }
}

/// Quilt composition into the window (and its dumps), then the next frame's set-up.
fn multiview_frame(
    frame: u64,
    surface: usize,
    (settings, dumps): (&Settings, bool),
    generation: u64,
) -> Result<(), String> {
    let done = super::layer::with_layer(|cur, app, layer, gl| {
        if cur.binding.draw != surface || layer.views.target.is_none() {
            return Ok(());
        }
        let Some(window) = crate::state::surface_size(cur) else {
            return Ok(());
        };
        if layer.live_generation != generation {
            apply_live(&mut layer.views);
            layer.live_generation = generation;
        }
        let (mv, presenter) = (&mut layer.views, &mut layer.presenter);
        // Our passes write the quilt from here on: never into the disparity record.
        if mv.record.quilt.is_some() {
            crate::multiview::quilt::record::DisparityRecord::release_quilt(gl, mv.quilt_fbo());
        }
        crate::multiview::fast::synthesis::end_frame(gl, mv, frame);
        if let Some(t) = &mv.target {
            // As the window resolves at its swap.
            t.resolve_all(gl, mv.info, crate::gl::COLOR_BUFFER_BIT);
        }
        presenter.overlay.lines = overlay_lines(settings, frame);
        if let Err(e) = crate::output::device::present_frame(gl, presenter, mv, cur, window, settings) {
            log::once(&COMPOSE_FAILED, Level::Error, format_args!("{e}"));
        }
        if let (Some(path), Some(t)) = (&settings.record, &mv.target) {
            presenter.recorder.frame(gl, mv.info, t.resolved_fbo, t.layout, path);
            if settings.exit_after == Some(frame) {
                presenter.recorder.flush(gl);
            }
        }
        let mut result = Ok(());
        if dumps {
            result = presenter.dump(frame, gl, mv, settings);
            if let Err(e) = &result {
                log::once(
                    &DUMP_FAILED,
                    Level::Error,
                    format_args!("quilt of frame {frame} not dumped: {e}"),
                );
            }
        }
        crate::multiview::update_convergence(gl, app, mv);
        // After the comfort pass (in `present_frame`), the last reader of this frame's record.
        let layout = mv.layout();
        mv.record.clear(gl, layout);
        crate::multiview::replay::framebuffer::ensure_target(gl, app, mv, window);
        observe(&mv.camera.rig, mv.settings.output);
        super::census::log_if_due(frame, layer);
        result
    });
    done.unwrap_or(Ok(()))
}

/// Every live value into this context's settings (the rig follows at `update_convergence`).
fn apply_live(mv: &mut crate::multiview::Multiview) {
    let values = live::store().values.clone();
    for (key, value) in values {
        if let Some(v) = value {
            mv.settings.set(key, &v);
        }
    }
}

/// The numbers in force, for `get`, hotkey steps and the overlay.
fn observe(rig: &crate::camera::ViewRig, output: crate::config::Output) {
    let numbers = [
        ("depthiness", rig.depthiness),
        ("convergence", rig.convergence),
        ("focus", rig.focus),
    ];
    live::observe(&numbers, &[("output", output.name())]);
}

/// `--overlay`: the live values for two seconds after a change.
fn overlay_lines(settings: &Settings, frame: u64) -> Vec<String> {
    if !settings.overlay {
        return vec![];
    }
    live::overlay_lines(std::time::Duration::from_secs(2), frame).unwrap_or_default()
}

fn exit_after(frame: u64) -> ! {
    crate::output::record::finish();
    let counts = crate::config::settings()
        .gpu_counts
        .then(log::counts::summary)
        .flatten();
    for line in [timing::summary(), log::costs::summary(), counts].into_iter().flatten() {
        log::info(format_args!("{line}"));
    }
    log::info(format_args!(
        "exit-after: frame {frame} presented; exiting with status 0"
    ));
    // `exit` would run the app's atexit handlers and C++ destructors from inside its swap
    // call, where GL/X11 teardown can hang or crash; flushing stdio is all the app is owed.
    crate::control::server::remove_socket();
    // SAFETY: flushing all C streams and ending the process are always allowed.
    unsafe {
        libc::fflush(core::ptr::null_mut());
        libc::_exit(0)
    }
}
