//! `--present device`: the output shown on the Looking Glass monitor, in the layer's own
//! window, while the program's window shows `--preview`.
//!
//! Which monitor is decided once per process (`--monitor`, else the monitor whose EDID says
//! Looking Glass) and said in one line, as is every reason to fall back to the program's
//! window (no such monitor, no X display, a failure making the window).
//!
//! **Why the program's own context, not a second one sharing with it.** Framebuffers and
//! vertex arrays are not shared between contexts, and a second context would have to be made
//! with the program's config and kept in step with its share group. The device window is
//! made with the program's visual instead, so at each swap the program's context is made
//! current on it (the real `glXMakeContextCurrent`, not our hook), the output is drawn there
//! by the same code that draws into the program's window (`compose::present`: the weave 1:1
//! when the monitor is the calibration's size), swapped, and the program's drawables are made
//! current again. Making current changes no GL state but the drawable: a context's viewport
//! is set at its first make-current only, and `compose` restores what it touches.
//!
//! EGL and OSMesa contexts cannot draw into an X window of ours (an EGL display may not even
//! be an X11 one), so for them the weave is read back and put into the window as an image
//! (`device_image`): exact too, at the cost of a read-back per frame.

use super::device_image::ImageWindow;
use super::device_window::DeviceWindow;
use super::monitor::{self, Monitor};
use super::{Presenter, glx};
use crate::config::parse::MonitorSpec;
use crate::config::{Output, Present, Preview, Settings};
use crate::gl::Gl;
use crate::log;
use crate::multiview::Multiview;
use crate::state::{Current, Platform};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};

static FAILED: AtomicBool = AtomicBool::new(false);
static WINDOW: Mutex<Option<DeviceWindow>> = Mutex::new(None);
static IMAGE_WINDOW: Mutex<Option<ImageWindow>> = Mutex::new(None);

/// Presents this frame: the output on the device and the preview in the program's window
/// (`window` pixels), or the output in the program's window when there is no device.
pub fn present_frame(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    cur: &Current,
    window: (u32, u32),
    settings: &Settings,
) -> Result<(), String> {
    // The context's own: `--output` changed live (holoinject ctl, hotkeys) is there.
    let output = mv.settings.output;
    let Some(monitor) = device_for(settings) else {
        return presenter.present(gl, mv, window, output);
    };
    let shown = match cur.ctx.platform {
        Platform::Glx => on_device(gl, presenter, mv, cur, monitor, output),
        _ => as_image(gl, presenter, mv, monitor, output),
    };
    if let Err(e) = shown {
        FAILED.store(true, Ordering::Relaxed);
        log::error(format_args!(
            "--present device: {e}; presenting in the program's window from now on"
        ));
        return presenter.present(gl, mv, window, output);
    }
    match settings.view.preview {
        Preview::Mono => presenter.present(gl, mv, window, Output::Mono),
        Preview::Quilt => presenter.present(gl, mv, window, Output::Quilt),
        Preview::Off => presenter.blank(gl, mv.info),
    }
}

/// The device's monitor when this frame goes there.
fn device_for(settings: &Settings) -> Option<&'static Monitor> {
    if settings.view.present != Present::Device || FAILED.load(Ordering::Relaxed) {
        return None;
    }
    target_monitor(settings)
}

/// The monitor `--present device` uses, decided (and said) once.
pub fn target_monitor(settings: &Settings) -> Option<&'static Monitor> {
    static TARGET: OnceLock<Option<Monitor>> = OnceLock::new();
    TARGET
        .get_or_init(|| match choose(settings) {
            Ok(m) => {
                log::info(format_args!("--present device: on {}", m.describe()));
                check_size(&m, settings);
                Some(m)
            }
            Err(e) => {
                log::warn(format_args!(
                    "--present device: {e}; presenting in the program's window"
                ));
                None
            }
        })
        .as_ref()
}

fn choose(settings: &Settings) -> Result<Monitor, String> {
    let detected = monitor::detect();
    match (&settings.view.monitor, &detected) {
        // A rectangle given by hand needs no server answer; a name does.
        (Some(spec @ MonitorSpec::Geometry { .. }), _) => {
            return monitor::select(spec, detected.as_deref().unwrap_or(&[]));
        }
        (Some(MonitorSpec::Name(n)), Err(e)) => return Err(format!("--monitor {n}: {e}")),
        (Some(spec), Ok(found)) => return monitor::select(spec, found),
        (None, _) => {}
    }
    let monitors = detected?;
    monitor::find_looking_glass(&monitors).cloned().ok_or_else(|| {
        let seen: Vec<String> = monitors.iter().map(Monitor::describe).collect();
        format!(
            "no Looking Glass connected (monitors: {}; pick one with --monitor NAME|WxH+X+Y)",
            if seen.is_empty() {
                "none".into()
            } else {
                seen.join(", ")
            }
        )
    })
}

/// The weave is made for the calibration's screen: another size cannot line up with the
/// lenticules, so it is said (and the weave is fitted into the monitor anyway).
fn check_size(m: &Monitor, settings: &Settings) {
    let Some(device) = &settings.view.device else {
        return;
    };
    let c = &device.calibration;
    let g = m.geometry;
    if (g.w, g.h) != (c.screen_w, c.screen_h) {
        log::warn(format_args!(
            "--present device: monitor {} is {}x{} but the calibration of {} is for {}x{}: the weave is scaled and will not line up with the lenticules (set the monitor to its native mode, or pass this unit's visual.json with --device)",
            m.name, g.w, g.h, device.name, c.screen_w, c.screen_h
        ));
    }
}

fn on_device(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    cur: &Current,
    monitor: &Monitor,
    output: Output,
) -> Result<(), String> {
    let (display, context) = (cur.binding.display, cur.ctx.handle);
    let mut slot = WINDOW.lock().unwrap_or_else(|e| e.into_inner());
    if slot.as_ref().is_none_or(|w| w.display != display) {
        *slot = Some(glx::window_for_context(display, context, monitor.geometry)?);
    }
    let win = slot.as_ref().expect("made above");
    let size = (win.rect.w, win.rect.h);
    glx::make_current(display, win.window as usize, win.window as usize, context)?;
    std::mem::swap(&mut presenter.staging, &mut presenter.device_staging);
    let drawn = presenter.present(gl, mv, size, output);
    std::mem::swap(&mut presenter.staging, &mut presenter.device_staging);
    glx::swap(display, win.window as usize);
    glx::make_current(display, cur.binding.draw, cur.binding.read, context)
        .map_err(|e| format!("{e} (the program's drawable)"))?;
    drawn
}

/// EGL and OSMesa programs: the weave read back and put into a window of our own connection.
fn as_image(
    gl: &Gl,
    presenter: &mut Presenter,
    mv: &Multiview,
    monitor: &Monitor,
    output: Output,
) -> Result<(), String> {
    if output != Output::Native {
        return Err(format!(
            "{output:?} output is shown on the device for GLX programs only"
        ));
    }
    let mut slot = IMAGE_WINDOW.lock().unwrap_or_else(|e| e.into_inner());
    if slot.is_none() {
        *slot = Some(ImageWindow::open(monitor.geometry)?);
    }
    let (rgba, size) = super::compose::woven_pixels(gl, presenter, mv)?;
    slot.as_ref().expect("made above").show(&rgba, size);
    Ok(())
}
