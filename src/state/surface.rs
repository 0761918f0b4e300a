//! The size of the surface a context presents, asked of its platform (the app's viewport
//! says nothing reliable about it).

use super::{Current, Platform};
use crate::real::{self, HookApi};
use core::ffi::c_void;
use std::sync::atomic::{AtomicPtr, Ordering};

const GLX_WIDTH: i32 = 0x801D;
const GLX_HEIGHT: i32 = 0x801E;

static GLX_QUERY_DRAWABLE: AtomicPtr<c_void> = AtomicPtr::new(core::ptr::null_mut());
static EGL_QUERY_SURFACE: AtomicPtr<c_void> = AtomicPtr::new(core::ptr::null_mut());

fn cached(slot: &AtomicPtr<c_void>, name: &core::ffi::CStr, api: HookApi) -> *const c_void {
    let p = slot.load(Ordering::Acquire);
    if !p.is_null() {
        return p;
    }
    let p = real::by_name(name, api);
    slot.store(p as *mut c_void, Ordering::Release);
    p
}

pub fn size(cur: &Current) -> Option<(u32, u32)> {
    let b = &cur.binding;
    let (w, h) = match cur.ctx.platform {
        Platform::Osmesa => b.size?,
        Platform::Glx => {
            let f = cached(&GLX_QUERY_DRAWABLE, c"glXQueryDrawable", HookApi::Glx);
            if f.is_null() {
                return None;
            }
            // SAFETY: glXQueryDrawable(Display*, GLXDrawable, int, unsigned int*).
            let f: unsafe extern "C" fn(usize, usize, i32, *mut u32) = unsafe { core::mem::transmute(f) };
            let (mut w, mut h) = (0u32, 0u32);
            // SAFETY: the display and drawable the app made current; answers into locals.
            unsafe {
                f(b.display, b.draw, GLX_WIDTH, &mut w);
                f(b.display, b.draw, GLX_HEIGHT, &mut h);
            }
            (w, h)
        }
        Platform::Egl => {
            let f = cached(&EGL_QUERY_SURFACE, c"eglQuerySurface", HookApi::Egl);
            if f.is_null() {
                return None;
            }
            // SAFETY: eglQuerySurface(EGLDisplay, EGLSurface, EGLint, EGLint*) -> EGLBoolean.
            let f: unsafe extern "C" fn(usize, usize, i32, *mut i32) -> u32 = unsafe { core::mem::transmute(f) };
            let (mut w, mut h) = (0i32, 0i32);
            // SAFETY: the display and surface the app made current; answers into locals.
            let ok = unsafe {
                f(b.display, b.draw, crate::gl::egl::EGL_WIDTH, &mut w) != 0
                    && f(b.display, b.draw, crate::gl::egl::EGL_HEIGHT, &mut h) != 0
            };
            if !ok {
                return None;
            }
            (w.max(0) as u32, h.max(0) as u32)
        }
    };
    (w > 0 && h > 0).then_some((w, h))
}
