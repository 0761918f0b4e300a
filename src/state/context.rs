//! One application context: its platform, share group, the GL table the layer calls
//! through (loaded once, via the platform's real loader, at first make-current), the app's
//! state in it, and the layer's per-context data (owned by the layers above, which `state`
//! does not name: see [`ContextLayer`]).

use super::ShareGroup;
use super::app::AppState;
use super::lock::{GlGuard, GlMutex};
use super::orphans::LayerObjects;
use crate::gl::{Gl, GlInfo, SharedGl};
use crate::real::{self, HOOK_COUNT, HOOKS, id};
use core::ffi::{CStr, c_void};
use std::any::Any;
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

/// The layer's own per-context data (replay state, GPU objects, presenter), defined by the
/// layers above `state`. `state` only needs to know what of it outlives the context.
pub trait ContextLayer: Any + Send {
    /// What of ours lives on in the share group after this context is destroyed.
    fn shared_objects(&self) -> LayerObjects;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// What a context's lock guards: the app's state (once the context has been current) and the
/// layer's data (once multiview is set up in it).
#[derive(Default)]
pub struct Tracked {
    pub app: Option<AppState>,
    pub layer: Option<Box<dyn ContextLayer>>,
}

pub struct Context {
    pub platform: Platform,
    pub handle: usize,
    pub display: usize,
    pub group: Arc<ShareGroup>,
    tracked: GlMutex<Tracked>,
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
            tracked: GlMutex::new(Tracked::default()),
            gl: OnceLock::new(),
            real,
        }
    }

    /// The app's state and the layer's data in this context, locked (uncontended in
    /// practice: a context is current on one thread at a time); `None` when the calling thread
    /// holds it already: a hook re-entered from inside a real GL call the layer makes with it
    /// locked (the app's synchronous debug callback calling GL), which must pass straight
    /// through (see `lock`).
    pub fn tracked(&self) -> Option<GlGuard<'_, Tracked>> {
        self.tracked.enter()
    }

    fn loader(&self) -> *const c_void {
        real::global(match self.platform {
            Platform::Glx => id::glXGetProcAddressARB,
            Platform::Egl => id::eglGetProcAddress,
            Platform::Osmesa => id::OSMesaGetProcAddress,
        })
    }

    /// Loads the GL table and, the first time, reads the app's state from GL.
    pub fn on_made_current(&self) {
        let Some((gl, info)) = self.gl() else { return };
        let Some(mut t) = self.tracked() else { return };
        if t.app.is_none() {
            t.app = Some(AppState::read(gl, *info));
        }
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
        let layer = self.tracked.get_mut().layer.take();
        let objects = layer.map(|l| l.shared_objects()).unwrap_or_default();
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
