//! The real `dlsym` and `dlopen`, from `dlvsym` (glibc >= 2.34 has no `__libc_dlsym`),
//! resolved lazily into atomics: other libraries' constructors call `dlsym` before ours
//! would run, and re-entering a `OnceLock` from inside its own initialiser deadlocks. The
//! interposers that forward to them are `hook::dl`; if glibc has neither version, they abort
//! with one line instead of jumping to address 0.

use core::ffi::{CStr, c_char, c_int, c_void};
use std::sync::atomic::{AtomicUsize, Ordering};

pub static REAL_DLSYM: AtomicUsize = AtomicUsize::new(0);
pub static REAL_DLOPEN: AtomicUsize = AtomicUsize::new(0);

const GLIBC_VERSIONS: [&CStr; 2] = [c"GLIBC_2.34", c"GLIBC_2.2.5"];

/// The real `name` from the C library (cached in `slot`), or 0.
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

/// A real function the interposers forward to that the C library does not have under any
/// version we know.
#[derive(Debug, PartialEq, Eq)]
pub struct Missing(&'static CStr);

impl Missing {
    /// `holoinject: fatal: cannot find the real NAME (GLIBC_2.34 / GLIBC_2.2.5)`, built in
    /// `buf` (no allocation: this runs inside the first `dlsym` of the process).
    fn line<'b>(&self, buf: &'b mut [u8; 128]) -> &'b [u8] {
        let mut n = 0;
        let mut put = |bytes: &[u8]| {
            let k = bytes.len().min(buf.len() - n);
            buf[n..n + k].copy_from_slice(&bytes[..k]);
            n += k;
        };
        put(b"holoinject: fatal: cannot find the real ");
        put(self.0.to_bytes());
        for (i, version) in GLIBC_VERSIONS.iter().enumerate() {
            put(if i == 0 { b" (" } else { b" / " });
            put(version.to_bytes());
        }
        put(b")\n");
        &buf[..n]
    }

    /// Says so on stderr and aborts: the interposer has nowhere to forward the call to.
    fn abort(&self) -> ! {
        let mut buf = [0u8; 128];
        let line = self.line(&mut buf);
        // SAFETY: writing our own buffer to fd 2 and aborting are allowed in any state.
        unsafe {
            libc::write(2, line.as_ptr().cast(), line.len());
            libc::abort()
        }
    }
}

/// The real `name`, which the naked interposers below jump to.
fn resolve_required(slot: &AtomicUsize, name: &'static CStr) -> Result<usize, Missing> {
    match resolve(slot, name) {
        0 => Err(Missing(name)),
        f => Ok(f),
    }
}

/// `resolve_required`, aborting with one line instead of letting an interposer jump to 0.
pub fn require(slot: &AtomicUsize, name: &'static CStr) {
    if let Err(missing) = resolve_required(slot, name) {
        missing.abort()
    }
}

/// The real `dlsym`, called from our own code (we are the caller: fine for lookups of GL
/// entry points, whose answer does not depend on who asks).
///
/// # Safety
/// `handle` is `RTLD_DEFAULT`, `RTLD_NEXT`, or a handle from `dlopen` not yet closed.
pub(crate) unsafe fn real_dlsym(handle: *mut c_void, name: &CStr) -> *const c_void {
    let f = resolve(&REAL_DLSYM, c"dlsym");
    if f == 0 {
        return core::ptr::null();
    }
    type Dlsym = unsafe extern "C" fn(*mut c_void, *const c_char) -> *const c_void;
    // SAFETY: `f` is glibc's dlsym, which has this signature.
    let f = unsafe { core::mem::transmute::<usize, Dlsym>(f) };
    // SAFETY: the caller vouches for `handle`; `name` is NUL-terminated.
    unsafe { f(handle, name.as_ptr()) }
}

/// `name` in the already-loaded library `soname`, or null (never loads anything).
pub(crate) fn symbol_in_loaded(soname: &CStr, name: &CStr) -> *const c_void {
    let open = resolve(&REAL_DLOPEN, c"dlopen");
    if open == 0 {
        return core::ptr::null();
    }
    type Dlopen = unsafe extern "C" fn(*const c_char, c_int) -> *mut c_void;
    // SAFETY: `open` is glibc's dlopen, which has this signature.
    let open = unsafe { core::mem::transmute::<usize, Dlopen>(open) };
    // SAFETY: a NUL-terminated soname; RTLD_NOLOAD never loads or runs constructors.
    let h = unsafe { open(soname.as_ptr(), libc::RTLD_NOLOAD | libc::RTLD_LAZY) };
    if h.is_null() {
        return core::ptr::null();
    }
    // SAFETY: `h` was just returned by dlopen and is closed only below.
    let p = unsafe { real_dlsym(h, name) };
    // SAFETY: balances the reference count taken by the NOLOAD open above.
    unsafe { libc::dlclose(h) };
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_symbol_glibc_lacks_is_missing_not_address_zero() {
        let slot = AtomicUsize::new(0);
        assert_eq!(resolve(&slot, c"holoinject_no_such_function"), 0);
        assert_eq!(
            resolve_required(&slot, c"holoinject_no_such_function"),
            Err(Missing(c"holoinject_no_such_function"))
        );
        assert_eq!(slot.load(Ordering::Relaxed), 0, "nothing cached");
    }

    #[test]
    fn the_real_dlsym_and_dlopen_are_found() {
        for name in [c"dlsym", c"dlopen"] {
            let slot = AtomicUsize::new(0);
            let f = resolve_required(&slot, name).expect("glibc has it");
            assert_eq!(slot.load(Ordering::Relaxed), f, "cached");
        }
    }

    #[test]
    fn the_fatal_line_names_the_function_and_versions() {
        let mut buf = [0u8; 128];
        assert_eq!(
            Missing(c"dlsym").line(&mut buf),
            b"holoinject: fatal: cannot find the real dlsym (GLIBC_2.34 / GLIBC_2.2.5)\n"
        );
    }
}
