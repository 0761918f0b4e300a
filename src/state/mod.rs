//! Per-context shadow state.
//!
//! Contexts live in one process-wide registry keyed by (platform, handle); resources are
//! shared per share group; each thread knows its current context (and the surface it draws
//! to). Contexts made current without us seeing their creation (created before a `dlopen`,
//! or through an entry point we do not wrap) are registered lazily, in a share group of their
//! own.

pub mod app;
mod context;
pub mod lock;
pub mod orphans;
pub mod program;
pub mod share;
mod surface;
pub mod textures;

pub use app::{AppState, TextureUnits};
pub use context::{Binding, Context, ContextLayer, Platform, Tracked};
pub use share::ShareGroup;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
pub use surface::size as surface_size;

type Key = (Platform, usize);

static REGISTRY: Mutex<Option<HashMap<Key, Arc<Context>>>> = Mutex::new(None);
static NEXT_GROUP: AtomicU64 = AtomicU64::new(1);

thread_local! {
    static CURRENT: RefCell<Option<Current>> = const { RefCell::new(None) };
}

/// What a thread has current: the context and the surface it draws to.
#[derive(Clone)]
pub struct Current {
    pub ctx: Arc<Context>,
    pub binding: Binding,
}

fn registry() -> MutexGuard<'static, Option<HashMap<Key, Arc<Context>>>> {
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// The layer's first sight of GL activity: the start-up line, then the settings (whose
/// problems are reported once, after it).
fn announce() {
    crate::log::announce();
    crate::config::settings();
}

pub fn context_created(platform: Platform, handle: usize, display: usize, share: usize) {
    announce();
    let mut reg = registry();
    let map = reg.get_or_insert_with(HashMap::new);
    let group = match map.get(&(platform, share)) {
        Some(shared) if share != 0 => shared.group.clone(),
        _ => new_group(),
    };
    let id = group.id;
    let ctx = Arc::new(Context::new(platform, handle, display, group));
    crate::log::info(format_args!(
        "{platform:?} context {handle:#x} created (share group {id})"
    ));
    map.insert((platform, handle), ctx);
}

fn new_group() -> Arc<ShareGroup> {
    Arc::new(ShareGroup::new(NEXT_GROUP.fetch_add(1, Ordering::Relaxed)))
}

fn lookup_or_adopt(platform: Platform, handle: usize, display: usize) -> Arc<Context> {
    let mut reg = registry();
    let map = reg.get_or_insert_with(HashMap::new);
    map.entry((platform, handle))
        .or_insert_with(|| {
            let group = new_group();
            crate::log::info(format_args!("{platform:?} context {handle:#x} adopted at make-current"));
            Arc::new(Context::new(platform, handle, display, group))
        })
        .clone()
}

/// `handle == 0` releases the thread's context.
pub fn make_current(platform: Platform, handle: usize, binding: Binding) {
    // The previous context is current here no more: if it was destroyed meanwhile, this is
    // the layer's last reference and its objects go to its share group now, in time to be
    // deleted below when the new context shares them.
    let previous = CURRENT.with(|c| c.borrow_mut().take());
    drop(previous);
    if handle == 0 {
        return;
    }
    announce();
    let ctx = lookup_or_adopt(platform, handle, binding.display);
    ctx.on_made_current();
    if let Some((gl, _)) = ctx.gl() {
        ctx.group.delete_orphans(gl);
    }
    CURRENT.with(|c| *c.borrow_mut() = Some(Current { ctx, binding }));
}

pub fn context_destroyed(platform: Platform, handle: usize) {
    let (removed, alive) = {
        let mut reg = registry();
        let map = reg.get_or_insert_with(HashMap::new);
        (map.remove(&(platform, handle)), map.len())
    };
    crate::log::info(format_args!(
        "{platform:?} context {handle:#x} destroyed ({alive} tracked)"
    ));
    // A context destroyed while current stays alive until released (GLX/EGL semantics): a
    // thread that has it current keeps a reference, and the last one hands its objects over.
    drop(removed);
}

/// Deletes what destroyed contexts left in the share group of the calling thread's current
/// context (at frame boundaries: a root context may stay current for good).
pub fn delete_orphans() {
    with_current(|cur| {
        let Some(cur) = cur else { return };
        if let Some((gl, _)) = cur.ctx.gl() {
            cur.ctx.group.delete_orphans(gl);
        }
    });
}

pub fn display_terminated(platform: Platform, display: usize) {
    if let Some(map) = registry().as_mut() {
        map.retain(|k, ctx| k.0 != platform || ctx.display != display);
    }
}

/// The calling thread's current context and binding, if any.
pub fn current() -> Option<Current> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Runs `f` with the calling thread's current context without cloning it (the per-draw path).
pub fn with_current<R>(f: impl FnOnce(Option<&Current>) -> R) -> R {
    CURRENT.with(|c| f(c.borrow().as_ref()))
}

/// The real GL function behind hook `id` for the calling thread's current context (GL entry
/// points differ per context: an OSMesa context and a libGL one in one process have
/// different `glFinish`es), else the process-wide one.
pub fn real_gl(id: usize) -> *const core::ffi::c_void {
    CURRENT
        .with(|c| c.borrow().as_ref().map(|cur| cur.ctx.real_gl(id)))
        .filter(|p| !p.is_null())
        .unwrap_or_else(|| crate::real::global(id))
}

/// Runs `f` with the app's state in the calling thread's current context, if it has one.
pub fn with_app<R>(f: impl FnOnce(&mut AppState) -> R) -> Option<R> {
    with_current(|cur| {
        let cur = cur?;
        let mut t = cur.ctx.tracked()?;
        t.app.as_mut().map(f)
    })
}

/// For contexts that never swap (OSMesa): the surface whose frame `glFinish` ends.
pub fn swapless_surface() -> Option<usize> {
    CURRENT.with(|c| {
        c.borrow()
            .as_ref()
            .filter(|cur| cur.ctx.platform == Platform::Osmesa)
            .map(|cur| cur.binding.draw)
    })
}
