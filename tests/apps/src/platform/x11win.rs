//! Plain Xlib window shared by the glx and egl-x11 back-ends.
use std::ptr;
use x11::xlib;

pub struct XWindow {
    pub dpy: *mut xlib::Display,
    pub win: xlib::Window,
    cmap: xlib::Colormap,
}

pub fn open_display() -> Result<*mut xlib::Display, String> {
    if std::env::var_os("DISPLAY").is_none() {
        return Err("DISPLAY is not set (use xvfb-run, or --backend egl/osmesa)".into());
    }
    let dpy = unsafe { xlib::XOpenDisplay(ptr::null()) };
    if dpy.is_null() {
        return Err("cannot open X display".into());
    }
    Ok(dpy)
}

impl XWindow {
    /// Window with the exact visual chosen by the GL config: an explicit
    /// colormap and border pixel avoid BadMatch on 32-bit ARGB visuals.
    pub fn new(dpy: *mut xlib::Display, vi: &xlib::XVisualInfo, size: (u32, u32), title: &str) -> Self {
        unsafe {
            let root = xlib::XRootWindow(dpy, vi.screen);
            let cmap = xlib::XCreateColormap(dpy, root, vi.visual, xlib::AllocNone);
            let mut swa: xlib::XSetWindowAttributes = std::mem::zeroed();
            swa.colormap = cmap;
            swa.event_mask = xlib::StructureNotifyMask | xlib::ExposureMask;
            let mask = xlib::CWBorderPixel | xlib::CWColormap | xlib::CWEventMask;
            let win = xlib::XCreateWindow(
                dpy,
                root,
                0,
                0,
                size.0,
                size.1,
                0,
                vi.depth,
                xlib::InputOutput as u32,
                vi.visual,
                mask,
                &mut swa,
            );
            let name = std::ffi::CString::new(title).unwrap();
            xlib::XStoreName(dpy, win, name.as_ptr());
            xlib::XMapWindow(dpy, win);
            xlib::XSync(dpy, xlib::False);
            XWindow { dpy, win, cmap }
        }
    }
}

impl Drop for XWindow {
    fn drop(&mut self) {
        unsafe {
            xlib::XDestroyWindow(self.dpy, self.win);
            xlib::XFreeColormap(self.dpy, self.cmap);
            xlib::XSync(self.dpy, xlib::False);
        }
    }
}
