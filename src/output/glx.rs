//! The few real GLX calls the device window needs, found past our own hooks (`real`), so
//! switching drawables is invisible to the layer's bookkeeping and to the frame count.

use super::device_window::DeviceWindow;
use super::monitor::Rect;
use super::x11::xlib;
use crate::real::{self, HookApi};
use std::ffi::CStr;
use std::os::raw::{c_int, c_void};
use x11_dl::xlib::XVisualInfo;

const GLX_SCREEN: c_int = 0x800C;
const GLX_FBCONFIG_ID: c_int = 0x8013;

type MakeContextCurrent = unsafe extern "C" fn(*mut c_void, usize, usize, *mut c_void) -> c_int;
type SwapBuffers = unsafe extern "C" fn(*mut c_void, usize);
type QueryContext = unsafe extern "C" fn(*mut c_void, *mut c_void, c_int, *mut c_int) -> c_int;
type ChooseFbConfig = unsafe extern "C" fn(*mut c_void, c_int, *const c_int, *mut c_int) -> *mut *mut c_void;
type VisualFromFbConfig = unsafe extern "C" fn(*mut c_void, *mut c_void) -> *mut XVisualInfo;

/// The real `name`, as a function of type `F`.
///
/// # Safety
/// `F` must be the C signature of `name`.
unsafe fn real_fn<F: Copy>(name: &CStr) -> Result<F, String> {
    let p = real::by_name(name, HookApi::Glx);
    if p.is_null() {
        return Err(format!("{} not found", name.to_string_lossy()));
    }
    // SAFETY: a non-null function pointer of the signature the caller vouches for.
    Ok(unsafe { core::mem::transmute_copy::<*const c_void, F>(&p) })
}

pub fn make_current(display: usize, draw: usize, read: usize, context: usize) -> Result<(), String> {
    // SAFETY: GLX's signature; the program's display and context, drawables of its screen.
    let ok = unsafe {
        let f: MakeContextCurrent = real_fn(c"glXMakeContextCurrent")?;
        f(display as _, draw, read, context as _)
    };
    if ok == 0 {
        return Err(format!("glXMakeContextCurrent({draw:#x}) failed"));
    }
    Ok(())
}

pub fn swap(display: usize, drawable: usize) {
    // SAFETY: GLX's signature; our window on the program's display.
    if let Ok(f) = unsafe { real_fn::<SwapBuffers>(c"glXSwapBuffers") } {
        // SAFETY: the real glXSwapBuffers on our window of the program's display.
        unsafe { f(display as _, drawable) };
    }
}

/// A device window at `rect` whose visual is that of `context`'s framebuffer config, so the
/// context can be made current on it.
pub fn window_for_context(display: usize, context: usize, rect: Rect) -> Result<DeviceWindow, String> {
    let dpy = display as *mut c_void;
    let (mut screen, mut id, mut n) = (0, 0, 0);
    // SAFETY: GLX signatures; the program's display and context; returned lists freed below.
    unsafe {
        let query: QueryContext = real_fn(c"glXQueryContext")?;
        if query(dpy, context as _, GLX_SCREEN, &mut screen) != 0
            || query(dpy, context as _, GLX_FBCONFIG_ID, &mut id) != 0
        {
            return Err("glXQueryContext could not tell the program's framebuffer config".into());
        }
        let choose: ChooseFbConfig = real_fn(c"glXChooseFBConfig")?;
        let attribs = [GLX_FBCONFIG_ID, id, 0];
        let configs = choose(dpy, screen, attribs.as_ptr(), &mut n);
        if configs.is_null() || n < 1 {
            return Err(format!("no framebuffer config {id:#x} on screen {screen}"));
        }
        let visual_of: VisualFromFbConfig = real_fn(c"glXGetVisualFromFBConfig")?;
        let vi = visual_of(dpy, *configs);
        let x = xlib()?;
        (x.XFree)(configs.cast());
        if vi.is_null() {
            return Err(format!("framebuffer config {id:#x} has no X visual"));
        }
        let made = DeviceWindow::create(display, screen, (*vi).visual, (*vi).depth, rect);
        (x.XFree)(vi.cast());
        made
    }
}
