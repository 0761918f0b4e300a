//! Window-system back-ends. Each one creates a context, hands out GL entry
//! points through its own loader and defines the frame boundary that the
//! holoinject layer hooks (swap, or glFinish for OSMesa).
use crate::cli::Backend;
use std::ffi::c_void;

mod egl;
mod glx;
mod osmesa;
mod x11win;

use egl::Headless;
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

/// What the app asks of its default framebuffer besides RGB8, depth 24 and stencil 8.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowConfig {
    /// Samples per pixel (0: single-sampled).
    pub samples: i32,
    /// Eight alpha bits, or none.
    pub alpha: bool,
}

impl Default for WindowConfig {
    fn default() -> Self {
        WindowConfig {
            samples: 0,
            alpha: true,
        }
    }
}

pub fn create(backend: Backend, size: (u32, u32), profile: Profile) -> Result<Box<dyn Platform>, String> {
    create_with(backend, size, profile, WindowConfig::default())
}

pub fn create_with(
    backend: Backend,
    size: (u32, u32),
    profile: Profile,
    config: WindowConfig,
) -> Result<Box<dyn Platform>, String> {
    // GLX and OSMesa can create ES contexts only through extensions that Mesa
    // does not offer everywhere; EGL is the standard way to get one.
    if profile.is_es() && !matches!(backend, Backend::Egl | Backend::EglDevice | Backend::EglX11) {
        return Err(format!(
            "{profile:?} needs --backend egl, egl-device or egl-x11 (got {backend:?})"
        ));
    }
    if backend == Backend::OsMesa && config != WindowConfig::default() {
        return Err("--samples and --no-alpha need --backend glx, egl, egl-device or egl-x11".into());
    }
    Ok(match backend {
        Backend::Glx => Box::new(glx::Glx::new(size, profile, config)?),
        Backend::Egl => Box::new(egl::Egl::new_headless(size, profile, config, Headless::Any)?),
        Backend::EglDevice => Box::new(egl::Egl::new_headless(size, profile, config, Headless::Device)?),
        Backend::EglX11 => Box::new(egl::Egl::new_x11(size, profile, config)?),
        Backend::OsMesa => Box::new(osmesa::OsMesa::new(size, profile)?),
    })
}
