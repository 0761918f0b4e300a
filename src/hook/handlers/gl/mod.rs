//! GL entry points, grouped by what the layer does with them.

mod buffer;
mod frame;
mod framebuffer;
mod immediate;
mod introspection;
mod program;
mod query;
mod raster;
mod shadowed;
mod texture;

pub use buffer::*;
pub use frame::*;
pub use framebuffer::*;
pub use immediate::*;
pub use introspection::*;
pub use program::*;
pub use query::*;
pub use raster::*;
pub use shadowed::*;
pub use texture::*;

/// The handler of every `view` entry of the policy table (generated shims call it with the
/// real call): replays `f` once per view when multiview applies to the current draw, else
/// calls it once.
pub fn per_view(f: impl Fn()) {
    let done = crate::hook::layer::with_active(|cur, app, mv, gl| {
        crate::multiview::replay::draw(gl, app, mv, &cur.ctx.group, &f)
    });
    if done.is_none() {
        f()
    }
}

/// `per_view` for replays that issue GL calls of their own.
fn per_view_gl(f: impl Fn(&crate::gl::Gl)) {
    crate::hook::layer::with_active(|cur, app, mv, gl| {
        crate::multiview::replay::draw(gl, app, mv, &cur.ctx.group, || f(gl))
    });
}
