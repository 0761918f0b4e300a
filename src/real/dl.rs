//! The real `dlsym` and `dlopen`, from `dlvsym` (glibc >= 2.34 has no `__libc_dlsym`),
//! resolved lazily into atomics: other libraries' constructors call `dlsym` before ours
//! would run, and re-entering a `OnceLock` from inside its own initialiser deadlocks. The
//! interposers that forward to them are `hook::dl`.

use core::ffi::{CStr, c_char, c_int, c_void};
use std::sync::atomic::{AtomicUsize, Ordering};

pub static REAL_DLSYM: AtomicUsize = AtomicUsize::new(0);
pub static REAL_DLOPEN: AtomicUsize = AtomicUsize::new(0);

const GLIBC_VERSIONS: [&CStr; 2] = [c"GLIBC_2.34", c"GLIBC_2.2.5"];

pub fn resolve(slot: &AtomicUsize, name: &CStr) -> usize {
    let cached = slot.load(Ordering::Acquire);
    if cached != 0 {
        return cached;
    }
    for version in GLIBC_VERSIONS {
        // SAFETY: dlvsym is not interposed by us; the arguments are valid C strings.
        let p = unsafe { libc::dlvsym(libc::RTLD_NEXT, name.as_ptr(), version.as_ptr()) };
        if !p.is_null() {
            slot.store(p as usize, Ordering::Release);
            return p as usize;
        }
    }
    0
}

/// The real `dlsym`, called from our own code (we are the caller: fine for lookups of GL
/// entry points, whose answer does not depend on who asks).
pub fn real_dlsym(handle: *mut c_void, name: *const c_char) -> *const c_void {
    let f = resolve(&REAL_DLSYM, c"dlsym");
    if f == 0 {
        return core::ptr::null();
    }
    // SAFETY: `f` is glibc's dlsym.
    let f: unsafe extern "C" fn(*mut c_void, *const c_char) -> *const c_void = unsafe { core::mem::transmute(f) };
    unsafe { f(handle, name) }
}

/// `name` in the already-loaded library `soname`, or null (never loads anything).
pub fn symbol_in_loaded(soname: &CStr, name: *const c_char) -> *const c_void {
    let open = resolve(&REAL_DLOPEN, c"dlopen");
    if open == 0 {
        return core::ptr::null();
    }
    // SAFETY: `open` is glibc's dlopen; RTLD_NOLOAD never loads or runs constructors.
    let open: unsafe extern "C" fn(*const c_char, c_int) -> *mut c_void = unsafe { core::mem::transmute(open) };
    let h = unsafe { open(soname.as_ptr(), libc::RTLD_NOLOAD | libc::RTLD_LAZY) };
    if h.is_null() {
        return core::ptr::null();
    }
    let p = real_dlsym(h, name);
    // SAFETY: balances the reference count taken by the NOLOAD open above.
    unsafe { libc::dlclose(h) };
    p
}
