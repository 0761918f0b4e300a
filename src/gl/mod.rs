//! Generated GL/GLX/EGL bindings (gl_generator, Khronos XML) and small GL helpers.
//!
//! The layer never calls GL through the exported symbols (that would re-enter our own hooks):
//! each context gets its own [`Gl`] table loaded through the *real* `*GetProcAddress` of the
//! platform that created it.

#[allow(clippy::all, non_upper_case_globals, non_snake_case, non_camel_case_types, dead_code)]
#[allow(unsafe_op_in_unsafe_fn, unused_imports, missing_docs)]
#[allow(clippy::undocumented_unsafe_blocks)] // generated
mod bindings {
    include!(concat!(env!("OUT_DIR"), "/gl_bindings.rs"));
}
pub use bindings::types::GLenum;
pub use bindings::*;

/// GLX bindings; `glx::types` holds the X11/GLX types (and the GL ones again).
#[allow(clippy::all, non_upper_case_globals, non_snake_case, non_camel_case_types, dead_code)]
#[allow(unsafe_op_in_unsafe_fn, unused_imports, missing_docs)]
#[allow(clippy::undocumented_unsafe_blocks)] // generated
pub mod glx {
    include!(concat!(env!("OUT_DIR"), "/glx_bindings.rs"));
}

pub mod depth_copy;
pub mod depth_write;
pub mod egl;
pub mod format;
pub mod guard;
mod info;
pub use info::{GlInfo, software_renderer};
pub mod pbo;
pub mod program;
pub mod readback;
pub mod stats_query;
pub mod unpack;

/// A context's GL table, shared between the threads that make the context current.
pub struct SharedGl(pub Gl);
// SAFETY: the table holds only function addresses, valid on every thread; calling them is
// only done by the thread the context is current on.
unsafe impl Send for SharedGl {}
// SAFETY: as for `Send`: shared references only read function addresses.
unsafe impl Sync for SharedGl {}

impl std::ops::Deref for SharedGl {
    type Target = Gl;
    fn deref(&self) -> &Gl {
        &self.0
    }
}
