//! Window-system back-ends. Each one creates a context, hands out GL entry
//! points through its own loader and defines the frame boundary that the
//! holoinject layer hooks (swap, or glFinish for OSMesa).
use crate::cli::Backend;
use std::ffi::c_void;

mod egl;
mod glx;
mod osmesa;
mod x11win;

pub use egl::{Handle as EglHandle, HeadlessDisplay as EglHeadlessDisplay};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// OpenGL 3.3 core.
    Core33,
    /// Compatibility / legacy context with the fixed-function pipeline.
    Legacy,
    /// OpenGL ES 3.0 (EGL back-ends only).
    Gles3,
    /// OpenGL ES 2.0 (EGL back-ends only).
    Gles2,
}

impl Profile {
    pub fn is_es(self) -> bool {
        matches!(self, Profile::Gles3 | Profile::Gles2)
    }
}

pub trait Platform {
    fn get_proc_address(&self, name: &str) -> *const c_void;
    fn end_frame(&mut self);
    fn size(&self) -> (u32, u32);
    fn describe(&self) -> String;
}

pub fn create(backend: Backend, size: (u32, u32), profile: Profile) -> Result<Box<dyn Platform>, String> {
    // GLX and OSMesa can create ES contexts only through extensions that Mesa
    // does not offer everywhere; EGL is the standard way to get one.
    if profile.is_es() && !matches!(backend, Backend::Egl | Backend::EglX11) {
        return Err(format!("{profile:?} needs --backend egl or egl-x11 (got {backend:?})"));
    }
    Ok(match backend {
        Backend::Glx => Box::new(glx::Glx::new(size, profile)?),
        Backend::Egl => Box::new(egl::Egl::new_headless(size, profile)?),
        Backend::EglX11 => Box::new(egl::Egl::new_x11(size, profile)?),
        Backend::OsMesa => Box::new(osmesa::OsMesa::new(size, profile)?),
    })
}
