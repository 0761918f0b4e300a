//! GL entry points, grouped by what the layer does with them.

mod attachment;
mod buffer;
mod frame;
mod framebuffer;
mod immediate;
mod introspection;
mod program;
mod query;
mod raster;
mod shadowed;
mod texparam;
mod texture;

pub(crate) use attachment::*;
pub(crate) use buffer::*;
pub(crate) use frame::*;
pub(crate) use framebuffer::*;
pub(crate) use immediate::*;
pub(crate) use introspection::*;
pub(crate) use program::*;
pub(crate) use query::*;
pub(crate) use raster::*;
pub(crate) use shadowed::*;
pub(crate) use texparam::*;
pub(crate) use texture::*;

/// The handler of every `view` entry of the policy table (generated shims call it with the
/// real call): replays `f` once per view when multiview applies to the current draw, else
/// calls it once.
pub(crate) fn per_view(f: impl Fn()) {
    let done = crate::hook::layer::with_active(|cur, app, mv, gl| {
        crate::multiview::replay::draw::draw(gl, app, mv, &cur.ctx.group, &f)
    });
    if done.is_none() {
        f()
    }
}

/// `per_view` for replays that issue GL calls of their own.
fn per_view_gl(f: impl Fn(&crate::gl::Gl)) {
    crate::hook::layer::with_active(|cur, app, mv, gl| {
        crate::multiview::replay::draw::draw(gl, app, mv, &cur.ctx.group, || f(gl))
    });
}
