//! What the app's calls become per view.
//!
//! A draw to framebuffer 0 or to a view-dependent framebuffer is replayed once per view with
//! only the view state changed (`draw`, deciding the shift with `shift`; uniforms through
//! `link` and `ubo`, camera projections in screen-space passes through `screen_space`;
//! immediate mode and raster positions through `immediate` and `raster`). `framebuffer` keeps
//! framebuffer 0 looking like the app's own while the quilt stands in for it (bindings,
//! `glGet*` answers); `transfers` makes its clears, reads and blits, and those of shadowed
//! framebuffers, per view.
//!
//! The top room: it may call every room below (`shadows` for where a pass goes, `scene` to
//! count camera draws, `fast` for the warp point, `quilt` for tiles); nothing below calls it.

pub mod draw;
pub mod framebuffer;
pub mod immediate;
pub mod link;
pub mod lists;
pub mod raster;
pub mod record;
pub mod record_fixed;
pub mod screen_space;
pub mod shift;
pub mod transfers;
pub mod ubo;
