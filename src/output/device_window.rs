//! The layer's own window on the Looking Glass monitor: borderless, exactly at the monitor's
//! rectangle, with the program's visual so the program's own GLX context can draw into it.
//!
//! It is override-redirect: the window manager neither decorates, moves nor resizes it, so
//! its pixels are the panel's pixels, which the weave needs (a managed full-screen window
//! can be offset by a panel or a compositor's rounding). It selects no input: the program
//! keeps the keyboard and mouse, and no events of ours reach the program's event loop.
//! It is made on the program's own `Display` connection, from the thread that swaps, the
//! only place the program's context may be used; X errors while making it are caught so
//! the program's error handler (often one that exits) never sees them.

use super::monitor::Rect;
use super::x11::{panel_window, xlib};
use std::os::raw::c_int;
use std::sync::atomic::{AtomicI32, Ordering};
use x11_dl::xlib::{self, Xlib};

pub struct DeviceWindow {
    pub display: usize,
    pub window: xlib::Window,
    pub rect: Rect,
}

static X_ERROR: AtomicI32 = AtomicI32::new(0);

unsafe extern "C" fn note_error(_: *mut xlib::Display, e: *mut xlib::XErrorEvent) -> c_int {
    // SAFETY: Xlib passes a valid event.
    X_ERROR.store(i32::from(unsafe { (*e).error_code }), Ordering::Relaxed);
    0
}

/// Runs `f` with X errors recorded instead of reaching the program's handler; `Err` names the
/// first error's code.
fn catching_errors<R>(x: &Xlib, dpy: *mut xlib::Display, f: impl FnOnce() -> R) -> Result<R, String> {
    X_ERROR.store(0, Ordering::Relaxed);
    // SAFETY: an open display; the previous handler is put back before returning.
    let previous = unsafe {
        (x.XSync)(dpy, xlib::False);
        (x.XSetErrorHandler)(Some(note_error))
    };
    let r = f();
    // SAFETY: as above.
    unsafe {
        (x.XSync)(dpy, xlib::False);
        (x.XSetErrorHandler)(previous);
    }
    match X_ERROR.load(Ordering::Relaxed) {
        0 => Ok(r),
        code => Err(format!("X error {code} while making the device window")),
    }
}

impl DeviceWindow {
    /// A window of `visual` (depth `depth`) covering `rect` on screen `screen`, mapped on top.
    ///
    /// # Safety
    /// `display` is the program's open `Display*`; `visual` belongs to its screen `screen`.
    pub unsafe fn create(
        display: usize,
        screen: c_int,
        visual: *mut xlib::Visual,
        depth: c_int,
        rect: Rect,
    ) -> Result<DeviceWindow, String> {
        let x = xlib()?;
        let dpy = display as *mut xlib::Display;
        let window = catching_errors(x, dpy, || {
            // SAFETY: the caller's display and visual.
            unsafe {
                let colormap = (x.XCreateColormap)(dpy, (x.XRootWindow)(dpy, screen), visual, xlib::AllocNone);
                panel_window(x, dpy, screen, (visual, depth, Some(colormap)), rect)
            }
        })?;
        Ok(DeviceWindow { display, window, rect })
    }
}
