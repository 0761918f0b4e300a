//! The layer's own live GL objects, counted from what it holds and logged at `info` every
//! `EVERY` frames, so that a long run shows whether anything piles up (`scripts/soak.py`
//! reads the line). Counting walks the shadows and images once per `EVERY` frames and asks
//! GL nothing; below `info` it is skipped altogether. The layer makes no buffer objects.

use super::layer::Layer;
use crate::log::{self, Level};
use crate::state::ContextLayer;

pub const EVERY: u64 = 100;

/// At the boundary of frame `frame`, for the context presenting it.
pub fn log_if_due(frame: u64, layer: &Layer) {
    if !frame.is_multiple_of(EVERY) || !log::enabled(Level::Info) {
        return;
    }
    let shared = layer.shared_objects();
    let own = layer.views.context_objects() + layer.presenter.context_objects();
    let total = shared.count() + own.framebuffers + own.vertex_arrays;
    log::info(format_args!(
        "layer GL objects at frame {frame}: textures {}, renderbuffers {}, framebuffers {}, \
         programs {}, vertex arrays {}, display lists {}, total {total} \
         ({} framebuffer shadows, {} layered images)",
        shared.textures.len(),
        shared.renderbuffers.len(),
        own.framebuffers,
        shared.programs.len(),
        own.vertex_arrays,
        shared.lists.len(),
        layer.views.shadows.len(),
        layer.views.images.len(),
    ));
}
