//! `glFinish`/`glFlush` end a frame only for contexts that never swap (OSMesa), as chosen by
//! `HOLOINJECT_OSMESA_BOUNDARY` (default `finish`).

use crate::config::Boundary;

pub(crate) fn glFinish(real: impl Fn()) {
    boundary_or_call(Boundary::Finish, real);
}

pub(crate) fn glFlush(real: impl Fn()) {
    boundary_or_call(Boundary::Flush, real);
}

fn boundary_or_call(kind: Boundary, real: impl Fn()) {
    match crate::state::swapless_surface() {
        Some(surface) if crate::config::settings().osmesa_boundary == kind => {
            crate::hook::frame::boundary(surface, real)
        }
        _ => real(),
    }
}
