//! Tiny GL contexts for `holoinject doctor`, one per back-end, made the way programs make
//! them (the platform library opened at run time, its own `*GetProcAddress`), so doctor needs
//! nothing but the launcher and the layer: GLX on a 16x16 pbuffer of `$DISPLAY`, EGL on
//! Mesa's surfaceless platform, OSMesa in a buffer of ours. All ask for OpenGL 3.3 core, which
//! Mesa answers with the highest version it has.

use std::ffi::{CString, c_char, c_int, c_void};

pub type GetProc = Box<dyn Fn(&str) -> *const c_void>;

/// A current context; its libraries and buffer stay alive as long as it does.
pub struct Probe {
    pub get_proc: GetProc,
    /// OSMesa renders into this buffer: it must live as long as the context.
    _buffer: Vec<u8>,
    pub size: (u32, u32),
}

fn open(names: &[&str]) -> Result<*mut c_void, String> {
    for n in names {
        let c = CString::new(*n).unwrap_or_default();
        // SAFETY: loading a system library by soname; it is never closed (its functions are
        // used until the probe process exits).
        let h = unsafe { libc::dlopen(c.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
        if !h.is_null() {
            return Ok(h);
        }
    }
    Err(format!("{} is not installed", names.join(" or ")))
}

/// # Safety
/// `T` must be the C function type of `name`.
unsafe fn sym<T: Copy>(lib: *mut c_void, name: &str) -> Result<T, String> {
    let c = CString::new(name).unwrap_or_default();
    // SAFETY: the caller names the symbol's type; a null result is refused.
    let p = unsafe { libc::dlsym(lib, c.as_ptr()) };
    if p.is_null() {
        return Err(format!("{name} is missing"));
    }
    // SAFETY: as above: `T` is a function pointer type of the symbol.
    Ok(unsafe { std::mem::transmute_copy::<*mut c_void, T>(&p) })
}

fn cstr_proc(f: unsafe extern "C" fn(*const c_char) -> *const c_void) -> GetProc {
    Box::new(move |name| {
        let c = CString::new(name).unwrap_or_default();
        // SAFETY: the platform's GetProcAddress with a NUL-terminated name.
        unsafe { f(c.as_ptr()) }
    })
}

pub fn osmesa(size: (u32, u32)) -> Result<Probe, String> {
    type Create = unsafe extern "C" fn(*const c_int, *mut c_void) -> *mut c_void;
    type MakeCurrent = unsafe extern "C" fn(*mut c_void, *mut c_void, u32, c_int, c_int) -> u8;
    let lib = open(&["libOSMesa.so.8", "libOSMesa.so.6"])?;
    // SAFETY: OSMesa's documented signatures; attributes: RGBA, depth 24, core 3.3, 0-ended.
    unsafe {
        let create: Create = sym(lib, "OSMesaCreateContextAttribs")?;
        let make_current: MakeCurrent = sym(lib, "OSMesaMakeCurrent")?;
        let get_proc = sym(lib, "OSMesaGetProcAddress")?;
        let attrs = [0x22, 0x1908, 0x30, 24, 0x33, 0x34, 0x36, 3, 0x37, 3, 0];
        let ctx = create(attrs.as_ptr(), std::ptr::null_mut());
        if ctx.is_null() {
            return Err("OSMesaCreateContextAttribs refused OpenGL 3.3 core".into());
        }
        let mut buffer = vec![0u8; size.0 as usize * size.1 as usize * 4];
        if make_current(
            ctx,
            buffer.as_mut_ptr().cast(),
            0x1401,
            size.0 as c_int,
            size.1 as c_int,
        ) == 0
        {
            return Err("OSMesaMakeCurrent failed".into());
        }
        Ok(Probe {
            get_proc: cstr_proc(get_proc),
            _buffer: buffer,
            size,
        })
    }
}

pub fn egl() -> Result<Probe, String> {
    type GetProcAddress = unsafe extern "C" fn(*const c_char) -> *const c_void;
    type PlatformDisplay = unsafe extern "C" fn(u32, *mut c_void, *const isize) -> *mut c_void;
    let lib = open(&["libEGL.so.1"])?;
    // SAFETY: EGL 1.5 signatures; every attribute list ends with EGL_NONE (0x3038).
    unsafe {
        let gpa: GetProcAddress = sym(lib, "eglGetProcAddress")?;
        let platform = gpa(c"eglGetPlatformDisplayEXT".as_ptr());
        if platform.is_null() {
            return Err("EGL_EXT_platform_base is missing".into());
        }
        let platform: PlatformDisplay = std::mem::transmute(platform);
        let dpy = platform(0x31DD, std::ptr::null_mut(), std::ptr::null()); // SURFACELESS_MESA
        let init: unsafe extern "C" fn(*mut c_void, *mut i32, *mut i32) -> u32 = sym(lib, "eglInitialize")?;
        if dpy.is_null() || init(dpy, std::ptr::null_mut(), std::ptr::null_mut()) == 0 {
            return Err("no surfaceless EGL display (EGL_MESA_platform_surfaceless)".into());
        }
        let bind: unsafe extern "C" fn(u32) -> u32 = sym(lib, "eglBindAPI")?;
        bind(0x30A2); // OPENGL_API
        type Choose = unsafe extern "C" fn(*mut c_void, *const i32, *mut *mut c_void, i32, *mut i32) -> u32;
        let choose: Choose = sym(lib, "eglChooseConfig")?;
        let (mut cfg, mut n) = (std::ptr::null_mut(), 0);
        let cfg_attrs = [0x3033, 0x1, 0x3040, 0x8, 0x3038]; // SURFACE_TYPE: PBUFFER, RENDERABLE_TYPE: OPENGL
        if choose(dpy, cfg_attrs.as_ptr(), &mut cfg, 1, &mut n) == 0 || n < 1 {
            return Err("eglChooseConfig: no OpenGL config".into());
        }
        type Create = unsafe extern "C" fn(*mut c_void, *mut c_void, *mut c_void, *const i32) -> *mut c_void;
        let create: Create = sym(lib, "eglCreateContext")?;
        let ctx_attrs = [0x3098, 3, 0x30FB, 3, 0x30FD, 1, 0x3038];
        let ctx = create(dpy, cfg, std::ptr::null_mut(), ctx_attrs.as_ptr());
        type MakeCurrent = unsafe extern "C" fn(*mut c_void, *mut c_void, *mut c_void, *mut c_void) -> u32;
        let make_current: MakeCurrent = sym(lib, "eglMakeCurrent")?;
        if ctx.is_null() || make_current(dpy, std::ptr::null_mut(), std::ptr::null_mut(), ctx) == 0 {
            return Err("eglCreateContext/eglMakeCurrent (surfaceless, OpenGL 3.3 core) failed".into());
        }
        Ok(Probe {
            get_proc: cstr_proc(gpa),
            _buffer: Vec::new(),
            size: (0, 0),
        })
    }
}

pub fn glx() -> Result<Probe, String> {
    type GetProcAddress = unsafe extern "C" fn(*const c_char) -> *const c_void;
    let x11 = open(&["libX11.so.6"])?;
    let gl = open(&["libGL.so.1"])?;
    // SAFETY: Xlib and GLX 1.4 signatures; attribute lists end with None (0).
    unsafe {
        let xopen: unsafe extern "C" fn(*const c_char) -> *mut c_void = sym(x11, "XOpenDisplay")?;
        let dpy = xopen(std::ptr::null());
        if dpy.is_null() {
            return Err("cannot open the X display ($DISPLAY)".into());
        }
        type Choose = unsafe extern "C" fn(*mut c_void, c_int, *const c_int, *mut c_int) -> *mut *mut c_void;
        let choose: Choose = sym(gl, "glXChooseFBConfig")?;
        let mut n = 0;
        let attrs = [0x8010, 0x4, 0x8011, 0x1, 0]; // DRAWABLE_TYPE: PBUFFER, RENDER_TYPE: RGBA
        let cfgs = choose(dpy, 0, attrs.as_ptr(), &mut n);
        if cfgs.is_null() || n < 1 {
            return Err("glXChooseFBConfig: no pbuffer config".into());
        }
        let cfg = *cfgs;
        let gpa: GetProcAddress = sym(gl, "glXGetProcAddressARB")?;
        type CreateAttribs =
            unsafe extern "C" fn(*mut c_void, *mut c_void, *mut c_void, c_int, *const c_int) -> *mut c_void;
        let create = gpa(c"glXCreateContextAttribsARB".as_ptr());
        if create.is_null() {
            return Err("GLX_ARB_create_context is missing".into());
        }
        let create: CreateAttribs = std::mem::transmute(create);
        let ctx_attrs = [0x2091, 3, 0x2092, 3, 0x9126, 1, 0];
        let ctx = create(dpy, cfg, std::ptr::null_mut(), 1, ctx_attrs.as_ptr());
        type Pbuffer = unsafe extern "C" fn(*mut c_void, *mut c_void, *const c_int) -> u64;
        let pbuffer: Pbuffer = sym(gl, "glXCreatePbuffer")?;
        let pb = pbuffer(dpy, cfg, [0x8041, 16, 0x8040, 16, 0].as_ptr());
        type MakeCurrent = unsafe extern "C" fn(*mut c_void, u64, u64, *mut c_void) -> c_int;
        let make_current: MakeCurrent = sym(gl, "glXMakeContextCurrent")?;
        if ctx.is_null() || pb == 0 || make_current(dpy, pb, pb, ctx) == 0 {
            return Err("glXCreateContextAttribsARB/glXMakeContextCurrent (OpenGL 3.3 core) failed".into());
        }
        Ok(Probe {
            get_proc: cstr_proc(gpa),
            _buffer: Vec::new(),
            size: (0, 0),
        })
    }
}
