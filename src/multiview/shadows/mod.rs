//! Layered shadows of the app's framebuffers.
//!
//! A pass drawn into the app's own framebuffer that depends on the view (the main camera's
//! scene, or a pass sampling a per-view image) goes to a shadow: one framebuffer per view,
//! each attached to a layer of a per-view copy of the app's texture or renderbuffer
//! (`shadow`, `layered`). `layers` decides which passes need one and builds it; `substitute`
//! binds view i's layer wherever the app samples its texture; `lifetime` follows what the
//! app's calls do to the objects behind a shadow; `sampling` keeps the layers sampled like
//! the app's texture; `scale` and `downscale` decide at what size the layers are drawn.
//!
//! May call `fast` (the warp point, when a pass reads the quilt) and `quilt`; never `replay`.

pub mod downscale;
pub mod layered;
pub mod layers;
pub mod lifetime;
pub mod mipmaps;
pub mod sampling;
pub mod scale;
pub mod shadow;
pub mod substitute;
