//! An X server of the test's own (Xvfb with one screen of any size: the device tests need a
//! screen wider than the one `scripts/test.sh` starts) and what the tests ask it: top-level
//! windows by name with their geometry, and the screen's pixels.

use super::Image;
use std::ffi::CStr;
use std::io::Read;
use std::process::{Child, Command, Stdio};
use x11_dl::xlib::{self, Xlib};

pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    /// Starts `Xvfb -screen 0 {screen}` on a free display (`-displayfd`: the server picks it
    /// and writes its number once it accepts connections).
    pub fn start(screen: &str) -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-nolisten",
                "tcp",
                "-noreset",
                "-screen",
                "0",
                screen,
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (scripts/setup-debian.sh installs it)");
        let mut out = child.stdout.take().unwrap();
        let mut number = String::new();
        let mut byte = [0u8; 1];
        while out.read(&mut byte).unwrap_or(0) == 1 && byte[0] != b'\n' {
            number.push(byte[0] as char);
        }
        assert!(!number.is_empty(), "Xvfb did not report a display");
        Xvfb {
            child,
            display: format!(":{}", number.trim()),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A top-level window: its name and its rectangle on the root window.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopLevel {
    pub name: String,
    pub geometry: String,
    pub override_redirect: bool,
    pub viewable: bool,
}

pub struct XConn {
    x: Xlib,
    dpy: *mut xlib::Display,
}

impl XConn {
    pub fn open(display: &str) -> XConn {
        let x = Xlib::open().expect("libX11");
        let name = std::ffi::CString::new(display).unwrap();
        // SAFETY: a NUL-terminated display name; checked below.
        let dpy = unsafe { (x.XOpenDisplay)(name.as_ptr()) };
        assert!(!dpy.is_null(), "cannot open {display}");
        XConn { x, dpy }
    }

    fn root(&self) -> xlib::Window {
        // SAFETY: an open display.
        unsafe { (self.x.XDefaultRootWindow)(self.dpy) }
    }

    /// The root window's children, bottom to top.
    pub fn top_levels(&self) -> Vec<TopLevel> {
        let (mut root, mut parent, mut children, mut n) = (0, 0, core::ptr::null_mut(), 0u32);
        // SAFETY: an open display; the list is freed below.
        unsafe { (self.x.XQueryTree)(self.dpy, self.root(), &mut root, &mut parent, &mut children, &mut n) };
        if children.is_null() {
            return vec![];
        }
        // SAFETY: XQueryTree returned `n` windows.
        let list = unsafe { std::slice::from_raw_parts(children, n as usize) }.to_vec();
        // SAFETY: freeing what XQueryTree returned.
        unsafe { (self.x.XFree)(children.cast()) };
        list.into_iter().map(|w| self.describe(w)).collect()
    }

    fn describe(&self, w: xlib::Window) -> TopLevel {
        // SAFETY: an open display, a window it listed; the name is freed with XFree.
        unsafe {
            let mut a: xlib::XWindowAttributes = core::mem::zeroed();
            (self.x.XGetWindowAttributes)(self.dpy, w, &mut a);
            let mut p = core::ptr::null_mut();
            (self.x.XFetchName)(self.dpy, w, &mut p);
            let name = if p.is_null() {
                String::new()
            } else {
                let s = CStr::from_ptr(p).to_string_lossy().into_owned();
                (self.x.XFree)(p.cast());
                s
            };
            TopLevel {
                name,
                geometry: format!("{}x{}{:+}{:+}", a.width, a.height, a.x, a.y),
                override_redirect: a.override_redirect != 0,
                viewable: a.map_state == xlib::IsViewable,
            }
        }
    }

    /// The screen's pixels in `w`x`h`+`x`+`y` (what a screenshot shows), top-down RGB.
    pub fn grab(&self, x: i32, y: i32, w: u32, h: u32) -> Image {
        // SAFETY: an open display; the image is destroyed below.
        let img = unsafe { (self.x.XGetImage)(self.dpy, self.root(), x, y, w, h, !0, xlib::ZPixmap) };
        assert!(!img.is_null(), "XGetImage failed");
        let mut rgb = Vec::with_capacity((w * h * 3) as usize);
        // SAFETY: a live image of w x h; masks say where each channel is.
        unsafe {
            let (rm, gm, bm) = ((*img).red_mask, (*img).green_mask, (*img).blue_mask);
            let get = (*img).funcs.get_pixel.expect("XGetPixel");
            for py in 0..h as i32 {
                for px in 0..w as i32 {
                    let p = get(img, px, py);
                    for m in [rm, gm, bm] {
                        rgb.push(((p & m) >> m.trailing_zeros()) as u8);
                    }
                }
            }
            (self.x.XDestroyImage)(img);
        }
        Image {
            width: w,
            height: h,
            rgb,
        }
    }
}

impl Drop for XConn {
    fn drop(&mut self) {
        // SAFETY: closing our own connection once.
        unsafe { (self.x.XCloseDisplay)(self.dpy) };
    }
}
