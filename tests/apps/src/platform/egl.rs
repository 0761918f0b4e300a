//! EGL back-end. libEGL is dlopen'ed RTLD_LOCAL at run time, the way SDL and
//! GLFW do it, so the layer must catch it through dlsym/eglGetProcAddress
//! rather than through link-time symbols. Headless displays: `device`.
mod device;
mod headless;

pub use device::Headless;
pub use headless::{Handle, HeadlessDisplay};

use super::x11win::{XWindow, open_display};
use super::{Platform, Profile, WindowConfig};
use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW};
use std::ffi::{CString, c_char, c_void};
use std::ptr;

type Ptr = *mut c_void;
type EglInt = i32;

const EGL_NONE: EglInt = 0x3038;
const EGL_SURFACE_TYPE: EglInt = 0x3033;
const EGL_PBUFFER_BIT: EglInt = 0x1;
const EGL_WINDOW_BIT: EglInt = 0x4;
const EGL_RENDERABLE_TYPE: EglInt = 0x3040;
const EGL_OPENGL_BIT: EglInt = 0x8;
const EGL_OPENGL_ES2_BIT: EglInt = 0x4;
const EGL_OPENGL_ES3_BIT: EglInt = 0x40;
const EGL_NATIVE_VISUAL_ID: EglInt = 0x302E;
const EGL_ALPHA_SIZE: EglInt = 0x3021;
const EGL_SAMPLES: EglInt = 0x3031;
const EGL_SAMPLE_BUFFERS: EglInt = 0x3032;
const EGL_WIDTH: EglInt = 0x3057;
const EGL_HEIGHT: EglInt = 0x3056;
const EGL_OPENGL_API: u32 = 0x30A2;
const EGL_OPENGL_ES_API: u32 = 0x30A0;
const EGL_CONTEXT_MAJOR_VERSION: EglInt = 0x3098;
const EGL_CONTEXT_MINOR_VERSION: EglInt = 0x30FB;
const EGL_CONTEXT_OPENGL_PROFILE_MASK: EglInt = 0x30FD;
const EGL_PLATFORM_X11_KHR: u32 = 0x31D5;

struct Api {
    _lib: Library,
    get_proc_address: unsafe extern "C" fn(*const c_char) -> *const c_void,
    get_error: unsafe extern "C" fn() -> EglInt,
    query_string: unsafe extern "C" fn(Ptr, EglInt) -> *const c_char,
    initialize: unsafe extern "C" fn(Ptr, *mut EglInt, *mut EglInt) -> u32,
    bind_api: unsafe extern "C" fn(u32) -> u32,
    choose_config: unsafe extern "C" fn(Ptr, *const EglInt, *mut Ptr, EglInt, *mut EglInt) -> u32,
    get_config_attrib: unsafe extern "C" fn(Ptr, Ptr, EglInt, *mut EglInt) -> u32,
    create_pbuffer: unsafe extern "C" fn(Ptr, Ptr, *const EglInt) -> Ptr,
    create_window_surface: unsafe extern "C" fn(Ptr, Ptr, usize, *const EglInt) -> Ptr,
    create_context: unsafe extern "C" fn(Ptr, Ptr, Ptr, *const EglInt) -> Ptr,
    make_current: unsafe extern "C" fn(Ptr, Ptr, Ptr, Ptr) -> u32,
    swap_buffers: unsafe extern "C" fn(Ptr, Ptr) -> u32,
    destroy_context: unsafe extern "C" fn(Ptr, Ptr) -> u32,
    destroy_surface: unsafe extern "C" fn(Ptr, Ptr) -> u32,
    terminate: unsafe extern "C" fn(Ptr) -> u32,
}

impl Api {
    fn load() -> Result<Api, String> {
        let lib = unsafe { Library::open(Some("libEGL.so.1"), RTLD_NOW | RTLD_LOCAL) }
            .map_err(|e| format!("cannot load libEGL.so.1: {e}"))?;
        macro_rules! sym {
            ($n:literal) => {
                *unsafe { lib.get(concat!($n, "\0").as_bytes()) }.map_err(|e| format!("libEGL: {e}"))?
            };
        }
        Ok(Api {
            get_proc_address: sym!("eglGetProcAddress"),
            get_error: sym!("eglGetError"),
            query_string: sym!("eglQueryString"),
            initialize: sym!("eglInitialize"),
            bind_api: sym!("eglBindAPI"),
            choose_config: sym!("eglChooseConfig"),
            get_config_attrib: sym!("eglGetConfigAttrib"),
            create_pbuffer: sym!("eglCreatePbufferSurface"),
            create_window_surface: sym!("eglCreateWindowSurface"),
            create_context: sym!("eglCreateContext"),
            make_current: sym!("eglMakeCurrent"),
            swap_buffers: sym!("eglSwapBuffers"),
            destroy_context: sym!("eglDestroyContext"),
            destroy_surface: sym!("eglDestroySurface"),
            terminate: sym!("eglTerminate"),
            _lib: lib,
        })
    }

    fn err(&self, what: &str) -> String {
        format!("{what} failed (EGL error 0x{:04X})", unsafe { (self.get_error)() })
    }

    /// EGL 1.5 core entry point first, then the EXT one that older Mesa has.
    fn platform_display(&self, platform: u32, native: Ptr) -> Result<Ptr, String> {
        type GetPlatformDisplay = unsafe extern "C" fn(u32, Ptr, *const isize) -> Ptr;
        type GetPlatformDisplayExt = unsafe extern "C" fn(u32, Ptr, *const EglInt) -> Ptr;
        unsafe {
            let f = (self.get_proc_address)(c"eglGetPlatformDisplay".as_ptr());
            if !f.is_null() {
                let f: GetPlatformDisplay = std::mem::transmute(f);
                return Ok(f(platform, native, ptr::null()));
            }
            let f = (self.get_proc_address)(c"eglGetPlatformDisplayEXT".as_ptr());
            if f.is_null() {
                return Err("neither eglGetPlatformDisplay nor eglGetPlatformDisplayEXT exists".into());
            }
            let f: GetPlatformDisplayExt = std::mem::transmute(f);
            Ok(f(platform, native, ptr::null()))
        }
    }
}

pub struct Egl {
    api: Api,
    dpy: Ptr,
    surface: Ptr,
    ctx: Ptr,
    size: (u32, u32),
    kind: String,
    // Dropped after the EGL objects (see Drop).
    win: Option<XWindow>,
}

/// Client API and EGL_RENDERABLE_TYPE bit for a profile.
fn api_for(profile: Profile) -> (u32, EglInt, &'static str) {
    match profile {
        Profile::Core33 | Profile::Legacy => (EGL_OPENGL_API, EGL_OPENGL_BIT, "EGL_OPENGL_API"),
        Profile::Gles3 => (EGL_OPENGL_ES_API, EGL_OPENGL_ES3_BIT, "EGL_OPENGL_ES_API"),
        Profile::Gles2 => (EGL_OPENGL_ES_API, EGL_OPENGL_ES2_BIT, "EGL_OPENGL_ES_API"),
    }
}

fn context_attribs(profile: Profile) -> [EglInt; 7] {
    let (maj, min, mask) = match profile {
        Profile::Core33 => (3, 3, 1),
        Profile::Legacy => (2, 1, 2),
        // ES has no profile mask (EGL_BAD_ATTRIBUTE); end the list early.
        Profile::Gles3 => {
            return [
                EGL_CONTEXT_MAJOR_VERSION,
                3,
                EGL_CONTEXT_MINOR_VERSION,
                0,
                EGL_NONE,
                0,
                0,
            ];
        }
        Profile::Gles2 => return [EGL_CONTEXT_MAJOR_VERSION, 2, EGL_NONE, 0, 0, 0, 0],
    };
    [
        EGL_CONTEXT_MAJOR_VERSION,
        maj,
        EGL_CONTEXT_MINOR_VERSION,
        min,
        EGL_CONTEXT_OPENGL_PROFILE_MASK,
        mask,
        EGL_NONE,
    ]
}

impl Egl {
    /// A headless display (surfaceless Mesa or a device) + pbuffer: needs no X server at all.
    pub fn new_headless(
        size: (u32, u32),
        profile: Profile,
        config: WindowConfig,
        which: Headless,
    ) -> Result<Self, String> {
        let api = Api::load()?;
        let (dpy, kind) = device::open(&api, which)?;
        let mut e = Egl {
            api,
            dpy,
            surface: ptr::null_mut(),
            ctx: ptr::null_mut(),
            size,
            kind,
            win: None,
        };
        let cfg = e.init(EGL_PBUFFER_BIT, profile, config)?;
        let attrs = [EGL_WIDTH, size.0 as EglInt, EGL_HEIGHT, size.1 as EglInt, EGL_NONE];
        e.surface = unsafe { (e.api.create_pbuffer)(e.dpy, cfg, attrs.as_ptr()) };
        if e.surface.is_null() {
            return Err(e.api.err("eglCreatePbufferSurface"));
        }
        e.make_context(cfg, profile)?;
        Ok(e)
    }

    pub fn new_x11(size: (u32, u32), profile: Profile, config: WindowConfig) -> Result<Self, String> {
        let api = Api::load()?;
        let xdpy = open_display()?;
        let dpy = api.platform_display(EGL_PLATFORM_X11_KHR, xdpy.cast())?;
        let mut e = Egl {
            api,
            dpy,
            surface: ptr::null_mut(),
            ctx: ptr::null_mut(),
            size,
            kind: "egl-x11".into(),
            win: None,
        };
        let cfg = e.init(EGL_WINDOW_BIT, profile, config)?;
        let win = unsafe { x_window_for(&e.api, dpy, cfg, xdpy, size)? };
        e.surface = unsafe { (e.api.create_window_surface)(e.dpy, cfg, win.win as usize, [EGL_NONE].as_ptr()) };
        e.win = Some(win);
        if e.surface.is_null() {
            return Err(e.api.err("eglCreateWindowSurface"));
        }
        e.make_context(cfg, profile)?;
        Ok(e)
    }

    fn init(&mut self, surface_type: EglInt, profile: Profile, config: WindowConfig) -> Result<Ptr, String> {
        init_display(&self.api, self.dpy, surface_type, profile, config)
    }

    fn make_context(&mut self, cfg: Ptr, profile: Profile) -> Result<(), String> {
        let a = &self.api;
        unsafe {
            self.ctx = (a.create_context)(self.dpy, cfg, ptr::null_mut(), context_attribs(profile).as_ptr());
            if self.ctx.is_null() {
                return Err(a.err(&format!("eglCreateContext({profile:?})")));
            }
            if (a.make_current)(self.dpy, self.surface, self.surface, self.ctx) == 0 {
                return Err(a.err("eglMakeCurrent"));
            }
        }
        Ok(())
    }
}

/// eglInitialize, eglBindAPI (for the calling thread) and an RGB(A)8/D24/S8 config with
/// exactly the alpha bits and samples asked (EGL sorts deeper colour buffers first).
fn init_display(
    a: &Api,
    dpy: Ptr,
    surface_type: EglInt,
    profile: Profile,
    config: WindowConfig,
) -> Result<Ptr, String> {
    let (api, renderable, api_name) = api_for(profile);
    let alpha = if config.alpha { 8 } else { 0 };
    unsafe {
        if dpy.is_null() || (a.initialize)(dpy, ptr::null_mut(), ptr::null_mut()) == 0 {
            return Err(a.err("eglGetPlatformDisplay/eglInitialize"));
        }
        if (a.bind_api)(api) == 0 {
            return Err(a.err(&format!("eglBindAPI({api_name})")));
        }
        #[rustfmt::skip]
        let attrs = [
            EGL_SURFACE_TYPE, surface_type, EGL_RENDERABLE_TYPE, renderable,
            0x3024, 8, 0x3023, 8, 0x3022, 8, EGL_ALPHA_SIZE, alpha, // R G B A
            0x3025, 24, 0x3026, 8,                                    // depth stencil
            EGL_SAMPLE_BUFFERS, (config.samples > 0) as EglInt, EGL_SAMPLES, config.samples, EGL_NONE,
        ];
        let mut cfgs = [ptr::null_mut(); 64];
        let mut n = 0;
        if (a.choose_config)(dpy, attrs.as_ptr(), cfgs.as_mut_ptr(), cfgs.len() as EglInt, &mut n) == 0 {
            return Err(a.err("eglChooseConfig"));
        }
        let attr = |cfg, name| {
            let mut v = 0;
            (a.get_config_attrib)(dpy, cfg, name, &mut v);
            v
        };
        cfgs[..n.max(0) as usize]
            .iter()
            .copied()
            .find(|&c| attr(c, EGL_ALPHA_SIZE) == alpha && attr(c, EGL_SAMPLES) == config.samples)
            .ok_or_else(|| format!("eglChooseConfig: no RGB(A)8 / depth 24 / stencil 8 config with {config:?}"))
    }
}

/// X window whose visual matches the EGL config.
unsafe fn x_window_for(
    a: &Api,
    dpy: Ptr,
    cfg: Ptr,
    xdpy: *mut x11::xlib::Display,
    size: (u32, u32),
) -> Result<XWindow, String> {
    use x11::xlib;
    unsafe {
        let mut vid = 0;
        (a.get_config_attrib)(dpy, cfg, EGL_NATIVE_VISUAL_ID, &mut vid);
        let mut tmpl: xlib::XVisualInfo = std::mem::zeroed();
        tmpl.visualid = vid as xlib::VisualID;
        let mut n = 0;
        let vi = xlib::XGetVisualInfo(xdpy, xlib::VisualIDMask, &mut tmpl, &mut n);
        if vi.is_null() || n == 0 {
            return Err(format!("no X visual for EGL native visual id {vid}"));
        }
        let win = XWindow::new(xdpy, &*vi, size, "holoinject-apps (egl)");
        xlib::XFree(vi.cast());
        Ok(win)
    }
}

impl Platform for Egl {
    fn get_proc_address(&self, name: &str) -> *const c_void {
        let c = CString::new(name).unwrap();
        unsafe { (self.api.get_proc_address)(c.as_ptr()) }
    }
    fn end_frame(&mut self) {
        // A no-op for pbuffers, but it is the frame boundary the layer hooks.
        unsafe { (self.api.swap_buffers)(self.dpy, self.surface) };
    }
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn describe(&self) -> String {
        self.kind.clone()
    }
}

impl Drop for Egl {
    fn drop(&mut self) {
        let a = &self.api;
        unsafe {
            (a.make_current)(self.dpy, ptr::null_mut(), ptr::null_mut(), ptr::null_mut());
            if !self.ctx.is_null() {
                (a.destroy_context)(self.dpy, self.ctx);
            }
            if !self.surface.is_null() {
                (a.destroy_surface)(self.dpy, self.surface);
            }
            (a.terminate)(self.dpy);
        }
        if let Some(w) = self.win.take() {
            let xdpy = w.dpy;
            drop(w);
            unsafe { x11::xlib::XCloseDisplay(xdpy) };
        }
    }
}
