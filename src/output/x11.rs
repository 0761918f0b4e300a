//! What both device windows need of libX11 (`device_window` on the program's connection,
//! `device_image` on one of ours): the library, opened once with `dlopen` (`x11-dl`) so the
//! layer loads in programs that never use X11, and the override-redirect window over the
//! panel. Shared from here rather than from either window, which are alternatives.

use super::monitor::Rect;
use std::os::raw::c_int;
use std::sync::OnceLock;
use x11_dl::xlib::{self, Xlib};

/// libX11, opened once.
pub fn xlib() -> Result<&'static Xlib, String> {
    static X: OnceLock<Result<Xlib, String>> = OnceLock::new();
    X.get_or_init(|| Xlib::open().map_err(|e| format!("libX11 could not be loaded: {e}")))
        .as_ref()
        .map_err(Clone::clone)
}

/// An override-redirect window of `visual` (depth `depth`, with `colormap` when it is not the
/// screen's default visual) covering `rect` on screen `screen`, named and mapped on top: the
/// window manager neither decorates, moves nor resizes it, so its pixels are the panel's.
///
/// # Safety
/// `dpy` is an open display; `visual` (and `colormap`) belong to its screen `screen`.
pub unsafe fn panel_window(
    x: &Xlib,
    dpy: *mut xlib::Display,
    screen: c_int,
    (visual, depth, colormap): (*mut xlib::Visual, c_int, Option<xlib::Colormap>),
    rect: Rect,
) -> xlib::Window {
    // SAFETY: the caller's display and visual; the attributes are ours.
    unsafe {
        let root = (x.XRootWindow)(dpy, screen);
        let mut attrs: xlib::XSetWindowAttributes = core::mem::zeroed();
        attrs.override_redirect = xlib::True;
        let mut mask = xlib::CWOverrideRedirect | xlib::CWBackPixel | xlib::CWBorderPixel;
        if let Some(c) = colormap {
            attrs.colormap = c;
            mask |= xlib::CWColormap;
        }
        let win = (x.XCreateWindow)(
            dpy,
            root,
            rect.x,
            rect.y,
            rect.w,
            rect.h,
            0,
            depth,
            xlib::InputOutput as u32,
            visual,
            mask,
            &mut attrs,
        );
        (x.XStoreName)(dpy, win, c"holoinject: Looking Glass".as_ptr());
        (x.XMapRaised)(dpy, win);
        win
    }
}
