//! Presenting: the quilt becomes what the window shows (quilt, lenticular weave, side by
//! side, anaglyph, the centre view), frames are dumped as PNGs, frame times are measured.
//! The order of things at the frame boundary is `hook::frame`'s; this module provides the
//! steps. [`Presenter`] is its per-context data: our full-screen passes and the
//! native-resolution weave target.

pub mod comfort;
pub mod compose;
pub mod dump;
pub mod native;
pub mod pass;
pub mod png;
pub mod staging;
pub mod timing;
pub mod weave;

use crate::config::{Output, Settings};
use crate::gl::Gl;
use crate::multiview::Multiview;
use crate::state::orphans::LayerObjects;

/// What a context needs to present its quilt.
#[derive(Default)]
pub struct Presenter {
    pub passes: pass::Passes,
    pub native: Option<native::NativeTarget>,
    /// What a multisampled window's output is drawn into first.
    pub staging: Option<staging::Staging>,
    /// The copies the comfort post-pass reads.
    pub comfort: comfort::ComfortCopies,
}

static COMFORT_FAILED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

impl Presenter {
    /// Draws `mv`'s quilt into the real default framebuffer (`window` pixels) as `output`
    /// asks; all GL state touched is restored.
    /// The comfort post-pass (edge fade, depth of field) runs on the quilt first, so dumps
    /// show it too.
    pub fn present(&mut self, gl: &Gl, mv: &Multiview, window: (u32, u32), output: Output) -> Result<(), String> {
        if let Err(e) = comfort::apply(gl, &mut self.passes, &mut self.comfort, mv) {
            crate::log::once(
                &COMFORT_FAILED,
                crate::log::Level::Error,
                format_args!("comfort pass (--edge-fade, --dof) skipped: {e}"),
            );
        }
        compose::present(gl, self, mv, window, output)
    }

    /// The quilt and, after a native present, the weave, as PNGs of frame `frame`.
    pub fn dump(&self, frame: u64, gl: &Gl, mv: &Multiview, settings: &Settings) -> Result<(), String> {
        dump::quilt(frame, gl, mv, settings)?;
        if settings.view.output == Output::Native {
            dump::native(frame, gl, self, mv.info, settings)?;
        }
        Ok(())
    }

    /// How many objects of ours live in this context only: the weave's framebuffer, the
    /// passes' vertex array.
    pub fn context_objects(&self) -> crate::multiview::ContextObjects {
        crate::multiview::ContextObjects {
            framebuffers: usize::from(self.native.as_ref().is_some_and(|n| n.fbo != 0))
                + self.comfort.fbos.iter().filter(|&&f| f != 0).count(),
            vertex_arrays: usize::from(self.passes.vao != 0),
        }
    }

    /// What of ours outlives the context in its share group: the weave texture and the
    /// passes' programs.
    pub fn shared_objects(&self) -> LayerObjects {
        let mut o = LayerObjects::default();
        o.textures.extend(self.native.as_ref().map(|n| n.color));
        o.textures.extend(self.staging.as_ref().map(|s| s.color));
        o.textures.extend(self.comfort.textures);
        o.programs.extend(self.passes.programs());
        o.without_zeros()
    }
}
