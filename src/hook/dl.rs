//! `dlsym` / `dlopen` interposers.
//!
//! glibc decides what `RTLD_NEXT`, `$ORIGIN` and the dlopen namespace mean from the *return
//! address* of the call. A wrapper that called the real function would make this library the
//! caller: other libraries' `RTLD_NEXT` lookups would break and two preloaded interposers
//! would recurse. So both are naked functions: they ask a Rust `decide_*` function what to do
//! and then either return our answer or tail-jump into the real function with the caller's
//! return address untouched.
//!
//! The real functions come from `dlvsym` (glibc ≥ 2.34 has no `__libc_dlsym`), resolved
//! lazily into atomics: other libraries' constructors call `dlsym` before ours would run, and
//! re-entering a `OnceLock` from inside its own initialiser deadlocks.

use core::ffi::{CStr, c_char, c_int, c_void};
use std::sync::atomic::{AtomicUsize, Ordering};

static REAL_DLSYM: AtomicUsize = AtomicUsize::new(0);
static REAL_DLOPEN: AtomicUsize = AtomicUsize::new(0);

const GLIBC_VERSIONS: [&CStr; 2] = [c"GLIBC_2.34", c"GLIBC_2.2.5"];

fn resolve(slot: &AtomicUsize, name: &CStr) -> usize {
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

/// Our hook for `name` when the real function exists behind `handle`, else null (forward).
extern "C" fn decide_dlsym(handle: *mut c_void, name: *const c_char) -> *const c_void {
    resolve(&REAL_DLSYM, c"dlsym");
    let Some(id) = super::find(name) else {
        return core::ptr::null();
    };
    std::panic::catch_unwind(|| {
        let real = real_dlsym(handle, name);
        if real.is_null() {
            return core::ptr::null();
        }
        if super::HOOKS[id].api != super::HookApi::Gl {
            super::real::remember(id, real);
        }
        crate::log::debug(format_args!(
            "dlsym({handle:p}, {}) -> hook",
            super::HOOKS[id].name.to_string_lossy()
        ));
        super::HOOKS[id].addr.0
    })
    .unwrap_or(core::ptr::null())
}

/// The flags the real `dlopen` gets: `RTLD_DEEPBIND` is dropped for GL libraries, because a
/// deep-bound libGL would resolve its own entry points past our preloaded hooks.
extern "C" fn decide_dlopen(file: *const c_char, flags: c_int) -> c_int {
    resolve(&REAL_DLOPEN, c"dlopen");
    if flags & libc::RTLD_DEEPBIND == 0 || file.is_null() {
        return flags;
    }
    // SAFETY: dlopen callers pass a NUL-terminated path.
    let path = unsafe { CStr::from_ptr(file) }.to_bytes();
    let base = path.rsplit(|&b| b == b'/').next().unwrap_or(path);
    let gl = [
        &b"libGL"[..],
        b"libEGL",
        b"libOpenGL",
        b"libGLX",
        b"libOSMesa",
        b"libGLES",
    ];
    if gl.iter().any(|p| base.starts_with(p)) {
        return flags & !libc::RTLD_DEEPBIND;
    }
    flags
}

#[cfg(target_arch = "x86_64")]
#[unsafe(naked)]
#[unsafe(no_mangle)]
/// # Safety
/// Same contract as glibc's `dlsym`.
pub unsafe extern "C" fn dlsym(handle: *mut c_void, name: *const c_char) -> *mut c_void {
    core::arch::naked_asm!(
        "push rdi",
        "push rsi",
        "sub rsp, 8",
        "call {decide}",
        "add rsp, 8",
        "pop rsi",
        "pop rdi",
        "test rax, rax",
        "jz 2f",
        "ret",
        "2:",
        "jmp qword ptr [rip + {real}]",
        decide = sym decide_dlsym,
        real = sym REAL_DLSYM,
    )
}

#[cfg(target_arch = "x86_64")]
#[unsafe(naked)]
#[unsafe(no_mangle)]
/// # Safety
/// Same contract as glibc's `dlopen`.
pub unsafe extern "C" fn dlopen(file: *const c_char, flags: c_int) -> *mut c_void {
    core::arch::naked_asm!(
        "push rdi",
        "push rsi",
        "sub rsp, 8",
        "call {decide}",
        "add rsp, 8",
        "pop rsi",
        "pop rdi",
        "mov esi, eax",
        "jmp qword ptr [rip + {real}]",
        decide = sym decide_dlopen,
        real = sym REAL_DLOPEN,
    )
}
