//! GLX back-end. The glX* entry points are linked directly against libGL
//! (like most native apps), so the layer sees them through normal symbol
//! resolution; only glXCreateContextAttribsARB is fetched dynamically.
use super::x11win::{XWindow, open_display};
use super::{Platform, Profile, WindowConfig};
use std::ffi::{CString, c_int, c_void};
use std::ptr;
use x11::xlib::{self, Bool, Display, XVisualInfo};

type GlxFbConfig = *mut c_void;
type GlxContext = *mut c_void;
type CreateContextAttribs =
    unsafe extern "C" fn(*mut Display, GlxFbConfig, GlxContext, Bool, *const c_int) -> GlxContext;

#[link(name = "GL")]
unsafe extern "C" {
    fn glXChooseFBConfig(dpy: *mut Display, screen: c_int, attrs: *const c_int, n: *mut c_int) -> *mut GlxFbConfig;
    fn glXGetVisualFromFBConfig(dpy: *mut Display, cfg: GlxFbConfig) -> *mut XVisualInfo;
    fn glXGetFBConfigAttrib(dpy: *mut Display, cfg: GlxFbConfig, attr: c_int, value: *mut c_int) -> c_int;
    fn glXGetProcAddressARB(name: *const u8) -> *const c_void;
    fn glXMakeContextCurrent(dpy: *mut Display, draw: xlib::XID, read: xlib::XID, ctx: GlxContext) -> Bool;
    fn glXSwapBuffers(dpy: *mut Display, draw: xlib::XID);
    fn glXDestroyContext(dpy: *mut Display, ctx: GlxContext);
}

const GLX_DOUBLEBUFFER: c_int = 5;
const GLX_RED_SIZE: c_int = 8;
const GLX_GREEN_SIZE: c_int = 9;
const GLX_BLUE_SIZE: c_int = 10;
const GLX_ALPHA_SIZE: c_int = 11;
const GLX_DEPTH_SIZE: c_int = 12;
const GLX_STENCIL_SIZE: c_int = 13;
const GLX_X_VISUAL_TYPE: c_int = 0x22;
const GLX_SAMPLE_BUFFERS: c_int = 100000;
const GLX_SAMPLES: c_int = 100001;
const GLX_TRUE_COLOR: c_int = 0x8002;
const GLX_DRAWABLE_TYPE: c_int = 0x8010;
const GLX_RENDER_TYPE: c_int = 0x8011;
const GLX_X_RENDERABLE: c_int = 0x8012;
const GLX_CONTEXT_MAJOR_VERSION_ARB: c_int = 0x2091;
const GLX_CONTEXT_MINOR_VERSION_ARB: c_int = 0x2092;
const GLX_CONTEXT_PROFILE_MASK_ARB: c_int = 0x9126;
const GLX_CONTEXT_CORE_PROFILE_BIT_ARB: c_int = 1;
const GLX_CONTEXT_COMPATIBILITY_PROFILE_BIT_ARB: c_int = 2;

pub struct Glx {
    dpy: *mut Display,
    win: Option<XWindow>,
    ctx: GlxContext,
    size: (u32, u32),
}

/// The first config with exactly `alpha` alpha bits and `samples` samples: GLX sorts deeper
/// colour buffers first, so a minimum of 0 alpha bits alone would give an alpha config.
unsafe fn choose_config(dpy: *mut Display, alpha: c_int, samples: c_int) -> Option<GlxFbConfig> {
    #[rustfmt::skip]
    let attrs = [
        GLX_X_RENDERABLE, 1, GLX_DRAWABLE_TYPE, 1 /* WINDOW_BIT */,
        GLX_RENDER_TYPE, 1 /* RGBA_BIT */, GLX_X_VISUAL_TYPE, GLX_TRUE_COLOR,
        GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, GLX_ALPHA_SIZE, alpha,
        GLX_DEPTH_SIZE, 24, GLX_STENCIL_SIZE, 8, GLX_DOUBLEBUFFER, 1,
        GLX_SAMPLE_BUFFERS, (samples > 0) as c_int, GLX_SAMPLES, samples, 0,
    ];
    let mut n = 0;
    unsafe {
        let cfgs = glXChooseFBConfig(dpy, xlib::XDefaultScreen(dpy), attrs.as_ptr(), &mut n);
        if cfgs.is_null() {
            return None;
        }
        let attr = |cfg, a| {
            let mut v = 0;
            glXGetFBConfigAttrib(dpy, cfg, a, &mut v);
            v
        };
        let found = std::slice::from_raw_parts(cfgs, n.max(0) as usize)
            .iter()
            .copied()
            .find(|&c| attr(c, GLX_ALPHA_SIZE) == alpha && attr(c, GLX_SAMPLES) == samples);
        xlib::XFree(cfgs.cast());
        found
    }
}

fn context_attribs(profile: Profile) -> [c_int; 7] {
    let (maj, min, mask) = match profile {
        Profile::Core33 => (3, 3, GLX_CONTEXT_CORE_PROFILE_BIT_ARB),
        Profile::Legacy => (2, 1, GLX_CONTEXT_COMPATIBILITY_PROFILE_BIT_ARB),
        Profile::Gles3 | Profile::Gles2 => unreachable!("refused in platform::create"),
    };
    [
        GLX_CONTEXT_MAJOR_VERSION_ARB,
        maj,
        GLX_CONTEXT_MINOR_VERSION_ARB,
        min,
        GLX_CONTEXT_PROFILE_MASK_ARB,
        mask,
        0,
    ]
}

impl Glx {
    pub fn new(size: (u32, u32), profile: Profile, config: WindowConfig) -> Result<Self, String> {
        let dpy = open_display()?;
        unsafe {
            let samples = config.samples;
            // Some X servers only offer alpha-less RGB visuals; accept those.
            let cfg = if config.alpha {
                choose_config(dpy, 8, samples).or_else(|| choose_config(dpy, 0, samples))
            } else {
                choose_config(dpy, 0, samples)
            };
            let cfg = cfg.ok_or_else(|| {
                format!("glXChooseFBConfig: no RGB(A)8 / depth24 / stencil8 double-buffered config with {config:?}")
            })?;
            let vi = glXGetVisualFromFBConfig(dpy, cfg);
            if vi.is_null() {
                return Err("glXGetVisualFromFBConfig failed".into());
            }
            let win = XWindow::new(dpy, &*vi, size, "holoinject-apps");
            xlib::XFree(vi.cast());
            let f = glXGetProcAddressARB(c"glXCreateContextAttribsARB".as_ptr().cast());
            if f.is_null() {
                return Err("glXCreateContextAttribsARB is not available".into());
            }
            let create: CreateContextAttribs = std::mem::transmute(f);
            let attrs = context_attribs(profile);
            let ctx = create(dpy, cfg, ptr::null_mut(), xlib::True, attrs.as_ptr());
            if ctx.is_null() {
                return Err(format!("glXCreateContextAttribsARB failed for {profile:?}"));
            }
            if glXMakeContextCurrent(dpy, win.win, win.win, ctx) == 0 {
                glXDestroyContext(dpy, ctx);
                return Err("glXMakeContextCurrent failed".into());
            }
            Ok(Glx {
                dpy,
                win: Some(win),
                ctx,
                size,
            })
        }
    }
}

impl Platform for Glx {
    fn get_proc_address(&self, name: &str) -> *const c_void {
        let c = CString::new(name).unwrap();
        unsafe { glXGetProcAddressARB(c.as_ptr().cast()) }
    }
    fn end_frame(&mut self) {
        unsafe { glXSwapBuffers(self.dpy, self.win.as_ref().unwrap().win) }
    }
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn describe(&self) -> String {
        "glx".into()
    }
}

impl Drop for Glx {
    fn drop(&mut self) {
        unsafe {
            glXMakeContextCurrent(self.dpy, 0, 0, ptr::null_mut());
            glXDestroyContext(self.dpy, self.ctx);
            self.win.take();
            xlib::XCloseDisplay(self.dpy);
        }
    }
}
