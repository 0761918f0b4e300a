//! Several contexts and pbuffers on one headless display, for apps that manage contexts and
//! threads themselves (`twothreads`, `churn`).
use super::device::{self, Headless};
use super::{
    Api, EGL_HEIGHT, EGL_NONE, EGL_PBUFFER_BIT, EGL_WIDTH, EglInt, Ptr, api_for, context_attribs, init_display,
};
use crate::platform::{Profile, WindowConfig};
use std::ffi::{CString, c_void};
use std::ptr;

/// EGL calls are thread-safe, so the display may be shared between threads.
pub struct HeadlessDisplay {
    api: Api,
    dpy: Ptr,
    cfg: Ptr,
    profile: Profile,
}

/// An EGL context or surface handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Handle(Ptr);

unsafe impl Send for Handle {}
unsafe impl Sync for Handle {}
unsafe impl Send for HeadlessDisplay {}
unsafe impl Sync for HeadlessDisplay {}

impl HeadlessDisplay {
    pub fn new(profile: Profile) -> Result<Self, String> {
        let api = Api::load()?;
        let (dpy, _) = device::open(&api, Headless::Any)?;
        let cfg = init_display(&api, dpy, EGL_PBUFFER_BIT, profile, WindowConfig::default())?;
        Ok(HeadlessDisplay { api, dpy, cfg, profile })
    }

    pub fn create_pbuffer(&self, size: (u32, u32)) -> Result<Handle, String> {
        let attrs = [EGL_WIDTH, size.0 as EglInt, EGL_HEIGHT, size.1 as EglInt, EGL_NONE];
        let s = unsafe { (self.api.create_pbuffer)(self.dpy, self.cfg, attrs.as_ptr()) };
        if s.is_null() {
            return Err(self.api.err("eglCreatePbufferSurface"));
        }
        Ok(Handle(s))
    }

    /// A context of the display's profile, in `share`'s share group if given.
    pub fn create_context(&self, share: Option<Handle>) -> Result<Handle, String> {
        let share = share.map_or(ptr::null_mut(), |h| h.0);
        let attrs = context_attribs(self.profile);
        let c = unsafe { (self.api.create_context)(self.dpy, self.cfg, share, attrs.as_ptr()) };
        if c.is_null() {
            return Err(self.api.err(&format!("eglCreateContext({:?})", self.profile)));
        }
        Ok(Handle(c))
    }

    /// Binds the profile's client API for the calling thread (eglBindAPI is
    /// per thread), then makes `ctx` current on `surface`; None releases.
    pub fn make_current(&self, target: Option<(Handle, Handle)>) -> Result<(), String> {
        let (api, _, api_name) = api_for(self.profile);
        let (s, c) = target.map_or((ptr::null_mut(), ptr::null_mut()), |(s, c)| (s.0, c.0));
        unsafe {
            if (self.api.bind_api)(api) == 0 {
                return Err(self.api.err(&format!("eglBindAPI({api_name})")));
            }
            if (self.api.make_current)(self.dpy, s, s, c) == 0 {
                return Err(self.api.err("eglMakeCurrent"));
            }
        }
        Ok(())
    }

    /// Makes `ctx` current with no surface at all (EGL_KHR_surfaceless_context, which
    /// the surfaceless platform always has, and Mesa's and NVIDIA's devices too): a resource-loading context with no
    /// framebuffer 0 (`churn`'s root context).
    pub fn make_current_surfaceless(&self, ctx: Handle) -> Result<(), String> {
        let (api, _, api_name) = api_for(self.profile);
        unsafe {
            if (self.api.bind_api)(api) == 0 {
                return Err(self.api.err(&format!("eglBindAPI({api_name})")));
            }
            if (self.api.make_current)(self.dpy, ptr::null_mut(), ptr::null_mut(), ctx.0) == 0 {
                return Err(self.api.err("eglMakeCurrent(EGL_NO_SURFACE)"));
            }
        }
        Ok(())
    }

    pub fn swap_buffers(&self, surface: Handle) -> Result<(), String> {
        if unsafe { (self.api.swap_buffers)(self.dpy, surface.0) } == 0 {
            return Err(self.api.err("eglSwapBuffers"));
        }
        Ok(())
    }

    pub fn get_proc_address(&self, name: &str) -> *const c_void {
        let c = CString::new(name).unwrap();
        unsafe { (self.api.get_proc_address)(c.as_ptr()) }
    }

    pub fn destroy_context(&self, ctx: Handle) {
        unsafe { (self.api.destroy_context)(self.dpy, ctx.0) };
    }

    pub fn destroy_surface(&self, surface: Handle) {
        unsafe { (self.api.destroy_surface)(self.dpy, surface.0) };
    }
}

impl Drop for HeadlessDisplay {
    fn drop(&mut self) {
        unsafe { (self.api.terminate)(self.dpy) };
    }
}
