//! The device window for programs whose context cannot draw into an X window of ours (EGL on
//! any platform, OSMesa): the weave is read back and put into the window as an image, on an
//! X connection of the layer's own (the program may be using its own from another thread).
//! It costs a read-back and a copy to the server per frame, which a GLX program does not pay.

use super::monitor::Rect;
use super::x11::{panel_window, xlib};
use std::os::raw::c_char;
use x11_dl::xlib::{self, Xlib};

pub struct ImageWindow {
    x: &'static Xlib,
    dpy: *mut xlib::Display,
    window: xlib::Window,
    visual: *mut xlib::Visual,
    gc: xlib::GC,
    pub rect: Rect,
}

// SAFETY: the connection is ours alone and used under the device module's lock only.
unsafe impl Send for ImageWindow {}

impl Drop for ImageWindow {
    fn drop(&mut self) {
        // SAFETY: our own connection, closed once (destroying its windows).
        unsafe { (self.x.XCloseDisplay)(self.dpy) };
    }
}

impl ImageWindow {
    /// An override-redirect window covering `rect` on `$DISPLAY`'s default screen, which must
    /// be 24-bit TrueColor.
    pub fn open(rect: Rect) -> Result<ImageWindow, String> {
        let x = xlib()?;
        // SAFETY: a null name means $DISPLAY; the result is checked.
        let dpy = unsafe { (x.XOpenDisplay)(core::ptr::null()) };
        if dpy.is_null() {
            return Err(format!(
                "cannot open X display \"{}\"",
                std::env::var("DISPLAY").unwrap_or_default()
            ));
        }
        // SAFETY: an open display of ours.
        unsafe {
            let screen = (x.XDefaultScreen)(dpy);
            let (visual, depth) = ((x.XDefaultVisual)(dpy, screen), (x.XDefaultDepth)(dpy, screen));
            if depth != 24 || (*visual).class != xlib::TrueColor {
                (x.XCloseDisplay)(dpy);
                return Err(format!("the X screen is {depth}-bit, not 24-bit TrueColor"));
            }
            let window = panel_window(x, dpy, screen, (visual, depth, None), rect);
            let gc = (x.XCreateGC)(dpy, window, 0, core::ptr::null_mut());
            (x.XSync)(dpy, xlib::False);
            Ok(ImageWindow {
                x,
                dpy,
                window,
                visual,
                gc,
                rect,
            })
        }
    }

    /// Shows `rgba` (RGBA8 rows, bottom-up, `size` pixels) at the window's top-left corner.
    pub fn show(&self, rgba: &[u8], size: (u32, u32)) {
        let (w, h) = (size.0.min(self.rect.w), size.1.min(self.rect.h));
        // SAFETY: reading the visual's channel masks.
        let masks = unsafe {
            [
                (*self.visual).red_mask,
                (*self.visual).green_mask,
                (*self.visual).blue_mask,
            ]
        };
        let mut pixels = Vec::with_capacity((w * h) as usize);
        for row in (0..size.1).rev().take(h as usize) {
            let line = &rgba[(row * size.0 * 4) as usize..][..(w * 4) as usize];
            pixels.extend(
                line.chunks_exact(4)
                    .map(|p| (0..3).fold(0u32, |v, c| v | (u32::from(p[c]) << masks[c].trailing_zeros()))),
            );
        }
        // SAFETY: an image over `pixels` (w*h 32-bit pixels) in the window's visual; its data
        // pointer is taken back before the image is freed, so Xlib never frees our vector.
        unsafe {
            let img = (self.x.XCreateImage)(
                self.dpy,
                self.visual,
                24,
                xlib::ZPixmap,
                0,
                pixels.as_mut_ptr().cast::<c_char>(),
                w,
                h,
                32,
                0,
            );
            if img.is_null() {
                return;
            }
            (*img).byte_order = if cfg!(target_endian = "little") {
                xlib::LSBFirst
            } else {
                xlib::MSBFirst
            };
            (self.x.XPutImage)(self.dpy, self.window, self.gc, img, 0, 0, 0, 0, w, h);
            (*img).data = core::ptr::null_mut();
            (self.x.XDestroyImage)(img);
            // The frame is on the server before the program's next one starts.
            (self.x.XSync)(self.dpy, xlib::False);
        }
    }
}
