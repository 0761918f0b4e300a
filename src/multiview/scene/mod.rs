//! What the scene is, as far as the views need to know: which framebuffer the main camera
//! draws into (`tracker`), and its depth taken while it still holds the scene, read back for
//! auto-convergence (`convergence`), with the disparity record where it covers it
//! (`recorded`).
//!
//! May call `fast` (the synthesis warp takes its depth at the same moment) and `quilt`.

pub mod convergence;
mod recorded;
pub mod tracker;
