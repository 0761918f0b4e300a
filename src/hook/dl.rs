//! `dlsym` / `dlopen` interposers.
//!
//! glibc decides what `RTLD_NEXT`, `$ORIGIN` and the dlopen namespace mean from the *return
//! address* of the call. A wrapper that called the real function would make this library the
//! caller: other libraries' `RTLD_NEXT` lookups would break and two preloaded interposers
//! would recurse. So both are naked functions: they ask a Rust `decide_*` function what to do
//! and then either return our answer or tail-jump into the real function with the caller's
//! return address untouched.
//!
//! The real functions come from `crate::real::dl`.

use crate::real::{HOOKS, HookApi, dl};
use core::ffi::{CStr, c_char, c_int, c_void};

/// What `dlsym` answers instead of forwarding: "no such symbol".
const ABSENT: *const c_void = core::ptr::without_provenance(1);

/// Our hook for `name` when the real function exists behind `handle`; `ABSENT` for a window
/// system function of ours that exists nowhere else; else null (forward).
///
/// Forwarding a pseudo-handle lookup for a name we export cannot say "absent": the real
/// `dlsym(RTLD_NEXT)` of a program (preloaded libraries come right after it) or
/// `dlsym(RTLD_DEFAULT)` finds our own export. A program probing for `eglGetProcAddress`
/// without libEGL loaded (glretrace, through waffle) then called a hook with nothing behind
/// it, which logged an error; it must get null, as it does without the layer. GL entry
/// points keep the hook: each context resolves its own through its platform's loader.
///
/// # Safety
/// Called only by `dlsym` below, with its caller's arguments (dlsym's contract: `handle` a
/// valid handle or pseudo-handle, `name` NUL-terminated or null).
unsafe extern "C" fn decide_dlsym(handle: *mut c_void, name: *const c_char) -> *const c_void {
    dl::require(&dl::REAL_DLSYM, c"dlsym");
    if name.is_null() {
        return core::ptr::null();
    }
    // SAFETY: dlsym's contract: a NUL-terminated symbol name.
    let name = unsafe { CStr::from_ptr(name) };
    let Some(id) = crate::real::find(name) else {
        return core::ptr::null();
    };
    let ours = super::ADDRS[id].0;
    std::panic::catch_unwind(|| {
        // SAFETY: the app's own handle, valid by dlsym's contract.
        let mut real = unsafe { dl::real_dlsym(handle, name) };
        let pseudo = handle == libc::RTLD_NEXT || handle == libc::RTLD_DEFAULT;
        if real == ours {
            real = core::ptr::null();
        }
        if real.is_null() && pseudo && HOOKS[id].api != HookApi::Gl {
            real = crate::real::global(id);
            if real.is_null() {
                return ABSENT;
            }
        }
        if real.is_null() {
            return core::ptr::null();
        }
        if HOOKS[id].api != HookApi::Gl {
            crate::real::remember(id, real);
        }
        crate::log::debug(format_args!(
            "dlsym({handle:p}, {}) -> hook",
            HOOKS[id].name.to_string_lossy()
        ));
        ours
    })
    .unwrap_or(core::ptr::null())
}

/// The flags the real `dlopen` gets: `RTLD_DEEPBIND` is dropped for GL libraries, because a
/// deep-bound libGL would resolve its own entry points past our preloaded hooks.
///
/// # Safety
/// Called only by `dlopen` below, with its caller's arguments (`file` NUL-terminated or null).
unsafe extern "C" fn decide_dlopen(file: *const c_char, flags: c_int) -> c_int {
    dl::require(&dl::REAL_DLOPEN, c"dlopen");
    if flags & libc::RTLD_DEEPBIND == 0 || file.is_null() {
        return flags;
    }
    // SAFETY: dlopen's contract: a NUL-terminated path.
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
        "cmp rax, 1",
        "jne 3f",
        "xor eax, eax",
        "3:",
        "ret",
        "2:",
        // Never 0: `decide_dlsym` aborted if the real dlsym could not be found.
        "jmp qword ptr [rip + {real}]",
        decide = sym decide_dlsym,
        real = sym dl::REAL_DLSYM,
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
        // Never 0: `decide_dlopen` aborted if the real dlopen could not be found.
        "jmp qword ptr [rip + {real}]",
        decide = sym decide_dlopen,
        real = sym dl::REAL_DLOPEN,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    #[test]
    fn the_real_dlsym_is_not_ours() {
        let slot = AtomicUsize::new(0);
        let real = dl::resolve(&slot, c"dlsym");
        assert_ne!(real, 0);
        assert_ne!(real, dlsym as *const () as usize, "ours is not the real one");
    }
}
