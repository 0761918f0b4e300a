//! The disparity record per draw (DESIGN §5): which draws into the scene target record, into
//! what, with which blend. Storage and draw state are `quilt::record`; the shader side is
//! `shader::record`.

use crate::gl::*;
use crate::multiview::Multiview;
use crate::multiview::quilt::record::{DisparityRecord, RecordImage};
use crate::shader::record::RECORD_BUFFER;
use crate::state::AppState;

/// Which rendered views of a recorded draw write the record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Views {
    /// Every one: the warps (before the warp point), the comfort pass and
    /// `--dump-disparity` read them all.
    All,
    /// The one auto-convergence (and `--mode auto`) reads, nearest the centre: exact mode
    /// pays for one view's record, not every view's.
    Only(u32),
}

impl Views {
    /// The one view that records alone, if so.
    pub fn only(self) -> Option<u32> {
        match self {
            Views::All => None,
            Views::Only(v) => Some(v),
        }
    }

    pub fn includes(self, view: u32) -> bool {
        match self {
            Views::All => true,
            Views::Only(v) => v == view,
        }
    }
}

/// Whether this draw goes into the scene target of a frame whose record is read, with
/// recording on, and for which views. Asked once per draw, and only for draws seen through
/// the camera: the rest (a HUD, a full-screen pass) never reach the record, whose draw
/// buffer is there for recorded draws alone, so the scene's record stays under them.
pub fn wanted(app: &AppState, mv: &Multiview) -> Option<Views> {
    if !(mv.settings.disparity_record && mv.record_supported && mv.scene.tracker.target == Some(app.draw_fbo)) {
        return None;
    }
    let dumps = crate::config::settings().dump_disparity;
    if mv.plan.synthesise && !mv.plan.warped || mv.settings.comfort.post_pass() || dumps {
        Some(Views::All)
    } else if crate::multiview::scene::convergence::reads_depth(mv) {
        Some(Views::Only(crate::multiview::scene::convergence::centre(mv)))
    } else {
        None
    }
}

/// Its fragment shader writes the record (else the draw leaves "not recorded" there).
fn program_records(app: &AppState) -> bool {
    app.program != 0 && app.current.program == app.program && app.current.info.as_deref().is_some_and(|p| p.records)
}

/// A draw into the quilt (framebuffer 0, bound): the quilt's record attached (it stays until
/// something else writes the quilt, `quilt::record`), its write mask and the draw's blend set;
/// whether the app writes colour when it records (`done` then follows the draw).
pub fn quilt(gl: &Gl, app: &AppState, mv: &mut Multiview, views: Views, blending: bool) -> Option<bool> {
    let size = mv
        .target
        .as_ref()
        .filter(|t| t.samples == 0)
        .map(|t| (t.layout.storage_width() as i32, t.layout.height() as i32))?;
    let img = mv.record.quilt_image(gl, size);
    mv.record.mark(false, views.only());
    DisparityRecord::attach_bound(gl, img, 0);
    let writes = DisparityRecord::app_writes_colour(gl);
    DisparityRecord::mask(gl, writes && views == Views::All);
    mv.record.before_draw(gl, program_records(app), blending);
    Some(writes)
}

/// Before tile `view` of a draw into the quilt: the record unmasked for the view that
/// records alone (drawn last, after the tiles `quilt` left masked).
pub fn tile(gl: &Gl, views: Views, writes: bool, view: u32) {
    if writes && views.only() == Some(view) {
        DisparityRecord::mask(gl, true);
    }
}

/// After a recorded draw into the quilt: the record's mask and blend back to the app's.
pub fn done(gl: &Gl, mv: &mut Multiview, writes: bool) {
    DisparityRecord::mask(gl, writes);
    mv.record.after_draw(gl);
}

/// A draw into the shadow of the app's framebuffer: the record beside its layers (attached per
/// view framebuffer by the caller) with the draw's blend set, when it records.
pub fn shadow(gl: &Gl, app: &AppState, mv: &mut Multiview, views: Views, blending: bool) -> Option<RecordImage> {
    let fbo = app.draw_fbo;
    let s = mv.shadows.get(&fbo).filter(|s| !s.stale)?;
    let (size, layers) = (s.size, s.views.len() as i32);
    let held = mv
        .record
        .shadow
        .is_some_and(|(f, r)| f == fbo && r.size == size && r.layers == layers);
    // A multisampled shadow cannot take a single-sampled record, and an app's own eighth
    // colour buffer keeps its place.
    let fits = held
        || s.attached.iter().all(|a| {
            a.point != COLOR_ATTACHMENT0 + RECORD_BUFFER && {
                // (Not `TEXTURE_TARGET`: Mesa 22 refuses it to glGetTextureParameteriv.)
                let mut samples = 0;
                // SAFETY: a level parameter query on our own array.
                unsafe { gl.GetTextureLevelParameteriv(a.array, 0, TEXTURE_SAMPLES, &mut samples) };
                samples == 0
            }
        });
    if !fits {
        return None;
    }
    let img = mv.record.shadow_image(gl, fbo, size, layers);
    mv.record.mark(true, views.only());
    mv.record.before_draw(gl, program_records(app), blending);
    Some(img)
}
