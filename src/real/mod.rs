//! Finding the real functions behind our hooks: `dlsym`/`dlvsym`, the GL libraries already
//! loaded, and the platforms' `*GetProcAddress`. No state beyond caches of addresses, and no
//! knowledge of contexts: per-context GL lookups are `state::real_gl`, which calls
//! [`via_loader`] with the loader of the context's platform.
//!
//! Order (after apitrace's `glproc_gl.cpp`): the cache; `dlsym(RTLD_NEXT)`; the GL libraries
//! already loaded, by soname with `RTLD_NOLOAD` (an app may have opened them `RTLD_LOCAL`,
//! which `RTLD_NEXT` cannot see); finally the platform's own `*GetProcAddress` for extension
//! entry points no library exports. GL (not GLX/EGL) entry points are resolved per context
//! through the loader of the platform that made it current, because an OSMesa context and a
//! libGL one in the same process have different `glFinish`es.

pub mod dl;

use core::ffi::{CStr, c_char, c_void};
use std::sync::atomic::{AtomicPtr, Ordering};

#[allow(clippy::all)]
mod names {
    include!(concat!(env!("OUT_DIR"), "/names.rs"));
}
pub use names::{HOOK_COUNT, HOOKS, id};

/// The API an entry point belongs to (decides which loader finds it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HookApi {
    Gl,
    Glx,
    Egl,
    Osmesa,
}

/// What the layer does with an entry point (`src/hook/policy.txt`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Policy {
    Track,
    Frame,
    Proc,
    /// Replayed per view by the generated handler.
    View,
    /// Replayed per view by a handler of its own (`view+`).
    ViewOwn,
    /// May change the shadowed fixed-function projection (generated handler).
    Matrix,
}

/// One entry point of the policy table.
pub struct HookEntry {
    pub name: &'static CStr,
    pub api: HookApi,
    pub policy: Policy,
}

/// Finds an entry point by C name without allocating (this runs inside `dlsym`).
pub fn find(name: &CStr) -> Option<usize> {
    let bytes = name.to_bytes();
    let first = *bytes.first()?;
    if first != b'g' && first != b'e' && first != b'O' {
        return None;
    }
    HOOKS.binary_search_by(|h| h.name.to_bytes().cmp(bytes)).ok()
}

const SONAMES: &[&CStr] = &[
    c"libGL.so.1",
    c"libGLX.so.0",
    c"libOpenGL.so.0",
    c"libEGL.so.1",
    c"libGLESv2.so.2",
    c"libGLESv1_CM.so.1",
    c"libOSMesa.so.8",
    c"libOSMesa.so.6",
];

#[allow(clippy::declare_interior_mutable_const)]
const NULL: AtomicPtr<c_void> = AtomicPtr::new(core::ptr::null_mut());
static CACHE: [AtomicPtr<c_void>; HOOK_COUNT] = [NULL; HOOK_COUNT];

/// The real function behind hook `id`, process-wide.
pub fn global(id: usize) -> *const c_void {
    let p = CACHE[id].load(Ordering::Acquire);
    if !p.is_null() {
        return p;
    }
    let found = lookup(id);
    remember(id, found);
    found
}

/// Records a real address found by the app's own lookup (first one wins).
pub(crate) fn remember(id: usize, p: *const c_void) {
    if !p.is_null() {
        let _ = CACHE[id].compare_exchange(
            core::ptr::null_mut(),
            p as *mut c_void,
            Ordering::AcqRel,
            Ordering::Acquire,
        );
    }
}

/// What a hook returns when its real function cannot be found (it should never be reached:
/// we only hand out hooks for functions that exist).
pub(crate) fn missing<R: ZeroReturn>(id: usize) -> R {
    crate::log::once_for(
        ("missing", id as u64),
        crate::log::Level::Error,
        format_args!(
            "no real {} found; the call is ignored",
            HOOKS[id].name.to_string_lossy()
        ),
    );
    R::ZERO
}

/// The return types of hooked entry points (what `build.rs` emits), each with the value a
/// hook whose real function is missing returns: unit, 0, `GL_FALSE`/`EGL_FALSE`/`False`, or
/// NULL. A hook with any other return type does not compile until its zero is chosen here.
pub(crate) trait ZeroReturn: Copy {
    const ZERO: Self;
}

impl ZeroReturn for () {
    const ZERO: Self = ();
}

/// `GLboolean`.
impl ZeroReturn for u8 {
    const ZERO: Self = 0;
}

/// `GLint`, `Bool` (GLX).
impl ZeroReturn for i32 {
    const ZERO: Self = 0;
}

/// `GLenum`, `GLuint`, `EGLBoolean`.
impl ZeroReturn for u32 {
    const ZERO: Self = 0;
}

/// `GLXContext`, `EGLContext`, `OSMesaGetProcAddress`'s answer.
impl ZeroReturn for *const c_void {
    const ZERO: Self = core::ptr::null();
}

/// OSMesa contexts.
impl ZeroReturn for *mut c_void {
    const ZERO: Self = core::ptr::null_mut();
}

/// `__GLXextFuncPtr`.
impl ZeroReturn for crate::gl::glx::types::__GLXextFuncPtr {
    const ZERO: Self = core::ptr::null_mut();
}

/// `__eglMustCastToProperFunctionPointerType`.
impl ZeroReturn for crate::gl::egl::types::__eglMustCastToProperFunctionPointerType {
    const ZERO: Self = core::ptr::null_mut();
}

fn lookup(id: usize) -> *const c_void {
    let loader = match HOOKS[id].api {
        HookApi::Egl => Some(id::eglGetProcAddress),
        HookApi::Glx | HookApi::Gl => Some(id::glXGetProcAddressARB),
        HookApi::Osmesa => None,
    };
    // A loader must not be asked for itself.
    lookup_name(HOOKS[id].name, loader.filter(|&l| l != id))
}

/// The real function `name` (one we do not hook), through the same chain.
pub fn by_name(name: &CStr, api: HookApi) -> *const c_void {
    let loader = match api {
        HookApi::Egl => Some(id::eglGetProcAddress),
        HookApi::Glx | HookApi::Gl => Some(id::glXGetProcAddressARB),
        HookApi::Osmesa => None,
    };
    lookup_name(name, loader)
}

fn lookup_name(name: &CStr, loader: Option<usize>) -> *const c_void {
    // SAFETY: RTLD_NEXT is a pseudo-handle dlsym always accepts.
    let p = unsafe { dl::real_dlsym(libc::RTLD_NEXT, name) };
    if !p.is_null() {
        return p;
    }
    for soname in SONAMES {
        let p = dl::symbol_in_loaded(soname, name);
        if !p.is_null() {
            return p;
        }
    }
    // SAFETY: `global` of a loader hook is that loader's real entry point, or null.
    loader.map_or(core::ptr::null(), |l| unsafe { via_loader(global(l), name) })
}

/// Calls a real `*GetProcAddress` loader for `name`.
///
/// # Safety
/// `loader` is null or the address of a platform loader (`glXGetProcAddress[ARB]`,
/// `eglGetProcAddress`, `OSMesaGetProcAddress`): a function taking a C string and returning
/// an address.
pub unsafe fn via_loader(loader: *const c_void, name: &CStr) -> *const c_void {
    if loader.is_null() {
        return core::ptr::null();
    }
    type Loader = unsafe extern "C" fn(*const c_char) -> *const c_void;
    // SAFETY: the caller guarantees `loader` is a non-null function with this signature.
    let f = unsafe { core::mem::transmute::<*const c_void, Loader>(loader) };
    // SAFETY: `name` is NUL-terminated; loaders only read it.
    unsafe { f(name.as_ptr()) }
}

#[cfg(test)]
mod tests {
    use super::{HOOKS, find};

    #[test]
    fn finds_hooks_by_exact_name() {
        let id = find(c"glDrawArrays").expect("a hooked name");
        assert_eq!(HOOKS[id].name, c"glDrawArrays");
        assert_eq!(find(c""), None);
        assert_eq!(find(c"glDrawArraysX"), None);
        assert_eq!(find(c"dlsym"), None);
    }
}
