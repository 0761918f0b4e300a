//! Objects shared by every context of a share group: programs (with what the layer learned
//! about them at link time), the app's sources of shaders we rewrote, the tracked values
//! of matrix uniforms, the target of each texture name (see `textures`), and the layer
//! objects destroyed contexts left behind (see `orphans`).

use super::orphans::LayerObjects;
use super::textures::TextureTargets;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// Where a `mat4` uniform-block member lives (a projection uploaded through a buffer).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UboMember {
    pub block: u32,
    pub offset: i32,
    pub row_major: bool,
}

/// What the layer knows about one linked program: facts fixed at link time, shared read-only
/// (contexts keep an `Arc` of the current program's, see `state::program`), and whether its
/// view uniform holds the centre view, which draws in any context of the group update.
#[derive(Debug, Default)]
pub struct ProgramInfo {
    /// Location of `holoinject_view`, or -1 when the program was left untouched.
    pub view_loc: i32,
    /// Location of `holoinject_comfort` (the comfort remap), or -1.
    pub remap_loc: i32,
    /// The remap value the program holds, as `f32` bits (all zero: off, GL's initial value),
    /// so a draw sets it only when it changed.
    pub remap_set: [AtomicU32; 4],
    /// Location of the leftmost matrix uniform of the gl_Position expression (P, VP or MVP),
    /// when it is a plain uniform whose uploads we see.
    pub projection_loc: Option<i32>,
    /// `projection_loc` is the first of four elements of a `vec4` array holding the matrix
    /// (`shader::vec4_matrix`): `Some(true)` when they are its rows. Uploads of vec4s that
    /// cover all four are tracked as the matrix at that location.
    pub projection_vec4: Option<bool>,
    /// Otherwise, the uniform-block member holding it, and its value as last read (with the
    /// buffer generation it was read at).
    pub projection_ubo: Option<UboMember>,
    /// gl_Position comes from the compatibility built-ins (`ftransform`, `gl_ModelView…`).
    pub builtin_projection: bool,
    /// Locations of the `gl_Position` chain's matrices, in multiplication order, when every
    /// one is a plain uniform (else empty): where the camera's view-projection is read
    /// (`multiview::motion`).
    pub camera_chain: Vec<i32>,
    /// Location of `holoinject_fragcoord` in the fragment shader, or -1.
    pub fragcoord_loc: i32,
    /// Why its fragment shader addresses texels in pixels (`shader::fragcoord::
    /// pixel_addressing`): its targets and sampled layers are not scaled (`--fbo-scale`).
    pub pixel_addressing: Option<&'static str>,
    /// gl_Position is given directly (full-screen passes, NDC quads): not the main camera.
    pub identity: bool,
    /// Its fragment shader writes the disparity record (`shader::record`).
    pub records: bool,
    /// The view uniform holds the centre view's values (so single draws need no update).
    pub centre_set: AtomicBool,
    /// Active-uniform indices of our own uniforms, ascending: hidden from the app's
    /// introspection, whose indices are renumbered around them.
    pub hidden_uniforms: Vec<u32>,
}

/// Some program's projection is held in a vec4 array: only then are vec4 uploads looked at.
pub static VEC4_PROJECTIONS: AtomicBool = AtomicBool::new(false);

#[derive(Default)]
pub struct GroupState {
    pub programs: HashMap<u32, Arc<ProgramInfo>>,
    /// App sources of shader objects whose source we replaced (for glGetShaderSource).
    pub original_sources: HashMap<u32, String>,
    /// Last value uploaded to each (program, location) mat4 uniform, column-major.
    pub matrices: HashMap<(u32, i32), [f32; 16]>,
}

#[derive(Default)]
pub struct ShareGroup {
    pub id: u64,
    state: Mutex<GroupState>,
    /// Texture targets, under their own lock (recorded on first binds, read per shadow).
    pub textures: TextureTargets,
    orphans: Mutex<LayerObjects>,
    /// `orphans` is not empty (checked without locking at every make-current and swap).
    has_orphans: AtomicBool,
    /// Bumped by every change to `programs` and every write to `matrices`: a context's
    /// snapshot of its current program is good while these are what it last saw.
    pub links: AtomicU64,
    pub uploads: AtomicU64,
}

impl ShareGroup {
    pub fn new(id: u64) -> ShareGroup {
        ShareGroup {
            id,
            textures: TextureTargets::new(id),
            ..Default::default()
        }
    }

    pub fn lock(&self) -> MutexGuard<'_, GroupState> {
        crate::log::costs::group_lock();
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Records what a link found about `program` (replacing what an earlier link found).
    pub fn linked(&self, program: u32, info: ProgramInfo) {
        self.lock().programs.insert(program, Arc::new(info));
        self.links.fetch_add(1, Ordering::AcqRel);
    }

    /// `program`'s projection held in a vec4 array: (first element's location, rows?).
    pub fn vec4_projection(&self, program: u32) -> Option<(i32, bool)> {
        let state = self.lock();
        let info = state.programs.get(&program)?;
        Some((info.projection_loc?, info.projection_vec4?))
    }

    /// Records a `mat4` uniform upload; returns the upload generation before it.
    pub fn uploaded(&self, program: u32, loc: i32, m: [f32; 16]) -> u64 {
        self.lock().matrices.insert((program, loc), m);
        self.uploads.fetch_add(1, Ordering::AcqRel)
    }

    /// Takes the layer objects of destroyed context `handle`, to be deleted by the next
    /// context of the group that is current.
    pub fn adopt(&self, handle: usize, objects: LayerObjects) {
        let n = objects.count();
        self.orphans.lock().unwrap_or_else(|e| e.into_inner()).append(objects);
        self.has_orphans.store(true, Ordering::Release);
        crate::log::debug(format_args!(
            "context {handle:#x}: {n} layer objects handed to share group {} for deletion",
            self.id
        ));
    }

    /// Deletes what destroyed contexts left, with `gl` of a context of this group current on
    /// the calling thread.
    pub fn delete_orphans(&self, gl: &crate::gl::Gl) {
        if !self.has_orphans.load(Ordering::Acquire) {
            return;
        }
        let objects = {
            let mut orphans = self.orphans.lock().unwrap_or_else(|e| e.into_inner());
            self.has_orphans.store(false, Ordering::Release);
            std::mem::take(&mut *orphans)
        };
        if objects.count() == 0 {
            return;
        }
        objects.delete(gl);
        crate::log::debug(format_args!(
            "share group {}: {} layer objects of destroyed contexts deleted",
            self.id,
            objects.count()
        ));
    }
}
