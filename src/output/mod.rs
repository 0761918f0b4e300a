//! Presenting: the quilt becomes what the window shows (quilt, lenticular weave, side by
//! side, anaglyph, the centre view), frames are dumped as PNGs, frame times are measured.
//! With `--present device` the output goes to the layer's own window on the Looking Glass
//! monitor (`device`, found by `monitor`) and the program's window shows the preview.
//! The order of things at the frame boundary is `hook::frame`'s; this module provides the
//! steps. [`Presenter`] is its per-context data: our full-screen passes and the
//! native-resolution weave target.

pub mod comfort;
mod comfort_images;
mod comfort_record;
pub mod compose;
pub mod device;
pub mod device_image;
pub mod device_window;
pub mod dump;
pub mod dump_disparity;
pub mod encoder;
pub mod glx;
pub mod monitor;
pub mod native;
pub mod overlay;
pub mod pass;
pub mod png;
pub mod quilt_file;
pub mod quilt_name;
pub mod record;
pub mod staging;
pub mod timing;
pub mod weave;
pub mod x11;

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
    /// The same for the device window (`--present device`), which has another size: kept
    /// apart so neither is remade every frame.
    pub device_staging: Option<staging::Staging>,
    /// `--record`: this context's read-back buffers, when it records.
    pub recorder: record::Recorder,
    /// `--overlay`: the live values, drawn over what is presented.
    pub overlay: overlay::Overlay,
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

    /// The program's window left black (`--preview off`); all GL state touched is restored.
    pub fn blank(&mut self, gl: &Gl, info: crate::gl::GlInfo) -> Result<(), String> {
        compose::blank(gl, info)
    }

    /// The quilt and, after a native present, the weave, as PNGs of frame `frame`.
    pub fn dump(&self, frame: u64, gl: &Gl, mv: &mut Multiview, settings: &Settings) -> Result<(), String> {
        dump::quilt(frame, gl, mv, settings)?;
        if settings.dump_disparity {
            dump_disparity::disparity(frame, gl, mv, settings)?;
        }
        if mv.settings.output == Output::Native {
            dump::native(frame, gl, self, mv.info, settings)?;
        }
        Ok(())
    }

    /// How many objects of ours live in this context only: the weave's framebuffer, the
    /// passes' vertex array.
    pub fn context_objects(&self) -> crate::multiview::ContextObjects {
        crate::multiview::ContextObjects {
            framebuffers: usize::from(self.native.as_ref().is_some_and(|n| n.fbo != 0))
                + usize::from(self.overlay.fbo != 0)
                + self.comfort.framebuffers(),
            vertex_arrays: usize::from(self.passes.vao != 0),
        }
    }

    /// What of ours outlives the context in its share group: the weave texture and the
    /// passes' programs.
    pub fn shared_objects(&self) -> LayerObjects {
        let mut o = LayerObjects::default();
        o.textures.extend(self.native.as_ref().map(|n| n.color));
        o.textures.extend(self.staging.as_ref().map(|s| s.color));
        o.textures.extend(self.device_staging.as_ref().map(|s| s.color));
        o.textures.push(self.overlay.texture);
        o.textures.extend(self.comfort.textures());
        o.renderbuffers.extend(self.comfort.renderbuffers());
        o.programs.extend(self.passes.programs());
        o.buffers.extend(self.recorder.buffers());
        o.without_zeros()
    }
}
