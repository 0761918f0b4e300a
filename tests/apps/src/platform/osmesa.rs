//! OSMesa back-end: software rendering into an app-owned buffer. There is no
//! swap, so glFinish is the frame boundary the layer watches for.
use super::{Platform, Profile};
use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW};
use std::ffi::{CString, c_char, c_int, c_void};
use std::ptr;

type Ctx = *mut c_void;

const OSMESA_FORMAT: c_int = 0x22;
const OSMESA_RGBA: c_int = 0x1908;
const OSMESA_DEPTH_BITS: c_int = 0x30;
const OSMESA_STENCIL_BITS: c_int = 0x31;
const OSMESA_PROFILE: c_int = 0x33;
const OSMESA_CORE_PROFILE: c_int = 0x34;
const OSMESA_COMPAT_PROFILE: c_int = 0x35;
const OSMESA_CONTEXT_MAJOR_VERSION: c_int = 0x36;
const OSMESA_CONTEXT_MINOR_VERSION: c_int = 0x37;
const GL_UNSIGNED_BYTE: u32 = 0x1401;

pub struct OsMesa {
    _lib: Library,
    ctx: Ctx,
    destroy: unsafe extern "C" fn(Ctx),
    get_proc: unsafe extern "C" fn(*const c_char) -> *const c_void,
    finish: unsafe extern "C" fn(),
    // Must outlive the context: OSMesa renders straight into it.
    _buffer: Vec<u8>,
    size: (u32, u32),
}

fn load_lib() -> Result<Library, String> {
    let open = |n| unsafe { Library::open(Some(n), RTLD_NOW | RTLD_LOCAL) };
    open("libOSMesa.so.8")
        .or_else(|_| open("libOSMesa.so.6"))
        .map_err(|e| format!("cannot load libOSMesa.so.8 or libOSMesa.so.6: {e}"))
}

impl OsMesa {
    pub fn new(size: (u32, u32), profile: Profile) -> Result<Self, String> {
        type Create = unsafe extern "C" fn(*const c_int, Ctx) -> Ctx;
        type MakeCurrent = unsafe extern "C" fn(Ctx, *mut c_void, u32, c_int, c_int) -> u8;
        let lib = load_lib()?;
        let e = |e: libloading::Error| format!("libOSMesa: {e}");
        unsafe {
            let create: Create = *lib.get(b"OSMesaCreateContextAttribs\0").map_err(e)?;
            let make_current: MakeCurrent = *lib.get(b"OSMesaMakeCurrent\0").map_err(e)?;
            let destroy: unsafe extern "C" fn(Ctx) = *lib.get(b"OSMesaDestroyContext\0").map_err(e)?;
            let get_proc: unsafe extern "C" fn(*const c_char) -> *const c_void =
                *lib.get(b"OSMesaGetProcAddress\0").map_err(e)?;
            let (prof, maj, min) = match profile {
                Profile::Core33 => (OSMESA_CORE_PROFILE, 3, 3),
                Profile::Legacy => (OSMESA_COMPAT_PROFILE, 2, 1),
                Profile::Gles3 | Profile::Gles2 => unreachable!("refused in platform::create"),
            };
            #[rustfmt::skip]
            let attrs = [
                OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
                OSMESA_PROFILE, prof, OSMESA_CONTEXT_MAJOR_VERSION, maj,
                OSMESA_CONTEXT_MINOR_VERSION, min, 0,
            ];
            let ctx = create(attrs.as_ptr(), ptr::null_mut());
            if ctx.is_null() {
                return Err(format!("OSMesaCreateContextAttribs failed for {profile:?}"));
            }
            let len = size.0 as usize * size.1 as usize * 4;
            let mut buffer = Vec::new();
            if buffer.try_reserve_exact(len).is_err() {
                destroy(ctx);
                return Err(format!("cannot allocate a {}x{} OSMesa colour buffer", size.0, size.1));
            }
            buffer.resize(len, 0u8);
            let ok = make_current(
                ctx,
                buffer.as_mut_ptr().cast(),
                GL_UNSIGNED_BYTE,
                size.0 as c_int,
                size.1 as c_int,
            );
            if ok == 0 {
                destroy(ctx);
                return Err("OSMesaMakeCurrent failed".into());
            }
            let finish = get_proc(c"glFinish".as_ptr());
            if finish.is_null() {
                destroy(ctx);
                return Err("OSMesaGetProcAddress(glFinish) failed".into());
            }
            let finish = std::mem::transmute::<*const c_void, unsafe extern "C" fn()>(finish);
            Ok(OsMesa {
                _lib: lib,
                ctx,
                destroy,
                get_proc,
                finish,
                _buffer: buffer,
                size,
            })
        }
    }
}

impl Platform for OsMesa {
    fn get_proc_address(&self, name: &str) -> *const c_void {
        let c = CString::new(name).unwrap();
        unsafe { (self.get_proc)(c.as_ptr()) }
    }
    fn end_frame(&mut self) {
        unsafe { (self.finish)() }
    }
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn describe(&self) -> String {
        "osmesa".into()
    }
}

impl Drop for OsMesa {
    fn drop(&mut self) {
        unsafe { (self.destroy)(self.ctx) }
    }
}
