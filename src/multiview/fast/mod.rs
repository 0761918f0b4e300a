//! The fast modes inside the quilt (DESIGN §5): which views a frame renders (`plan`), the
//! warp point where the others are synthesised by `synth` (`synthesis`), temporal reuse of
//! exact views (`reuse`, with `history`, `rotation` and `motion`), the choice of K under a
//! frame budget (`auto`), the exact quilt kept for `--measure-error` (`measure`), and the
//! columns rendered beyond the rendered views' sides for the warp (`guard`).
//!
//! May call `quilt` only; the image-space warps themselves are the crate's `synth`.

pub mod auto;
pub mod guard;
pub mod history;
pub mod measure;
pub mod motion;
pub mod plan;
pub mod reuse;
pub mod rotation;
pub mod synthesis;
