//! One application context: its platform, share group and the GL table the layer calls
//! through (loaded once, via the platform's real loader, at first make-current).

use super::ShareGroup;
use super::lock::{GlGuard, GlMutex};
use crate::gl::{Gl, SharedGl};
use crate::hook::{HOOK_COUNT, HOOKS, id, real};
use core::ffi::{CStr, c_void};
use std::sync::atomic::{AtomicPtr, Ordering};
use std::sync::{Arc, OnceLock};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Platform {
    Glx,
    Egl,
    Osmesa,
}

/// The surfaces a context is bound to on one thread.
#[derive(Clone, Copy, Debug, Default)]
pub struct Binding {
    pub display: usize,
    pub draw: usize,
    pub read: usize,
    /// Known only where the platform says it at make-current (OSMesa).
    pub size: Option<(u32, u32)>,
}

/// What `glGetString(GL_VERSION)` says about the context.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlInfo {
    pub es: bool,
    pub major: u32,
    pub minor: u32,
}

impl GlInfo {
    pub fn parse(version: &str) -> GlInfo {
        let es = version.starts_with("OpenGL ES");
        let numbers = version.trim_start_matches(|c: char| !c.is_ascii_digit());
        let mut it = numbers
            .split(|c: char| !c.is_ascii_digit())
            .filter_map(|n| n.parse().ok());
        GlInfo {
            es,
            major: it.next().unwrap_or(1),
            minor: it.next().unwrap_or(0),
        }
    }

    pub fn at_least(&self, major: u32, minor: u32) -> bool {
        (self.major, self.minor) >= (major, minor)
    }
}

pub struct Context {
    pub platform: Platform,
    pub handle: usize,
    pub display: usize,
    pub group: Arc<ShareGroup>,
    /// Multiview state (None until the context is first made current with multiview on).
    pub mv: GlMutex<Option<crate::multiview::Multiview>>,
    gl: OnceLock<Option<(SharedGl, GlInfo)>>,
    real: Box<[AtomicPtr<c_void>]>,
}

impl Context {
    pub fn new(platform: Platform, handle: usize, display: usize, group: Arc<ShareGroup>) -> Context {
        let real = (0..HOOK_COUNT).map(|_| AtomicPtr::new(core::ptr::null_mut())).collect();
        Context {
            platform,
            handle,
            display,
            group,
            mv: GlMutex::new(None),
            gl: OnceLock::new(),
            real,
        }
    }

    /// The multiview state, locked; `None` when the calling thread holds it already: a hook
    /// re-entered from inside a real GL call the layer makes with it locked (the app's
    /// synchronous debug callback calling GL), which must pass straight through.
    pub fn mv(&self) -> Option<GlGuard<'_, Option<crate::multiview::Multiview>>> {
        self.mv.enter()
    }

    fn loader(&self) -> *const c_void {
        real::global(match self.platform {
            Platform::Glx => id::glXGetProcAddressARB,
            Platform::Egl => id::eglGetProcAddress,
            Platform::Osmesa => id::OSMesaGetProcAddress,
        })
    }

    pub fn on_made_current(&self) {
        let _ = self.gl();
    }

    /// The layer's own GL table for this context; only valid while it is current.
    pub fn gl(&self) -> Option<&(SharedGl, GlInfo)> {
        self.gl
            .get_or_init(|| {
                let loader = self.loader();
                if loader.is_null() {
                    return None;
                }
                let gl = Gl::load_with(|name| {
                    let name = std::ffi::CString::new(name).unwrap_or_default();
                    // SAFETY: `loader` is the platform's real `*GetProcAddress` (non-null here).
                    unsafe { real::via_loader(loader, &name) }
                });
                let info = version_string(&gl).map(|v| GlInfo::parse(&v))?;
                crate::log::info(format_args!("context {:#x}: {info:?}", self.handle));
                Some((SharedGl(gl), info))
            })
            .as_ref()
    }

    /// Real GL entry point of hook `id` through this context's loader (cached).
    pub fn real_gl(&self, id: usize) -> *const c_void {
        let p = self.real[id].load(Ordering::Acquire);
        if !p.is_null() {
            return p;
        }
        // SAFETY: `loader()` is the platform's real `*GetProcAddress`, or null.
        let p = unsafe { real::via_loader(self.loader(), HOOKS[id].name) };
        self.real[id].store(p as *mut c_void, Ordering::Release);
        p
    }
}

impl Drop for Context {
    /// The layer's last reference goes once the context is destroyed and current nowhere:
    /// the objects the layer made in it that its share group keeps are handed to the group
    /// (see `orphans`), unless this was the group's last context.
    fn drop(&mut self) {
        let mv = self.mv.get_mut().take();
        let objects = mv.map(|mv| mv.shared_objects()).unwrap_or_default();
        if objects.count() == 0 {
            return;
        }
        if Arc::strong_count(&self.group) == 1 {
            crate::log::debug(format_args!(
                "context {:#x}: {} layer objects freed with share group {}, whose last context it was",
                self.handle,
                objects.count(),
                self.group.id
            ));
            return;
        }
        self.group.adopt(self.handle, objects);
    }
}

fn version_string(gl: &Gl) -> Option<String> {
    // SAFETY: the context is current on this thread (we are inside make-current).
    let p = unsafe { gl.GetString(crate::gl::VERSION) };
    if p.is_null() {
        return None;
    }
    // SAFETY: glGetString answers a static NUL-terminated string.
    Some(unsafe { CStr::from_ptr(p.cast()) }.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::GlInfo;

    #[test]
    fn parses_desktop_and_es_version_strings() {
        let d = GlInfo::parse("4.5 (Compatibility Profile) Mesa 22.3.6");
        assert_eq!(
            d,
            GlInfo {
                es: false,
                major: 4,
                minor: 5
            }
        );
        let e = GlInfo::parse("OpenGL ES 3.2 Mesa 22.3.6");
        assert_eq!(
            e,
            GlInfo {
                es: true,
                major: 3,
                minor: 2
            }
        );
        assert!(e.at_least(3, 0) && !e.at_least(3, 3));
    }
}
