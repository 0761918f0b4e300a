//! Per-view replay.
//!
//! The app's default framebuffer is replaced by a quilt ([`target::QuiltTarget`]): whenever
//! the app binds framebuffer 0 we bind the quilt instead, and every draw issued while it is
//! bound is replayed once per view, with the viewport and scissor mapped into that view's
//! tile and the injected `holoinject_view` uniform (or, for fixed-function draws, the
//! projection matrix) set to that view's shift. Draws into the app's own framebuffers go to
//! layered shadows of them ([`shadow`], [`layers`]) when they depend on the view (the main
//! camera's scene, or a pass sampling a shadowed texture), else they are drawn once.
//!
//! The app keeps seeing its own state (`state::AppState`): its viewport and scissor stay in
//! GL between draws, `glGet*` answers report framebuffer 0 and its draw/read buffers, and
//! `glReadPixels` from framebuffer 0 reads the centre view.
//!
//! [`Multiview`] is this module's per-context data: the quilt, the shadows and their
//! bookkeeping, and the camera estimate the shifts come from. It does not own the app's
//! state (`state`) nor the presenting passes (`output::Presenter`); functions take those
//! they need as arguments.
//!
//! # Rooms
//! The module is five rooms, each a folder with an essay of its own. A room names only the
//! rooms below it (and this file's [`Multiview`]), never one above:
//!
//! | room | owns |
//! |---|---|
//! | [`replay`] | what the app's calls to framebuffer 0 and to view-dependent passes become per view: one draw per view, the shift, fixed-function and immediate mode, clears, reads, blits |
//! | [`shadows`] | the layered shadows of the app's framebuffers and the per-view images they draw into: when a pass is per view, their size, their lifetime |
//! | [`scene`] | what the scene is: where the main camera draws, its depth, auto-convergence |
//! | [`fast`] | the fast modes in the quilt: which views a frame renders, the warp point, reuse, `auto`, error measurement |
//! | [`quilt`] | the quilt itself: where each view lives, the render target standing in for the window, the disparity scale of its tiles |

// Rooms, top to bottom; a room names only rooms below it (checked by scripts/file-graph.py).
pub mod fast;
pub mod quilt;
pub mod replay;
pub mod scene;
pub mod shadows;

use crate::camera::CameraEstimate;
use crate::config::ViewSettings;
use crate::gl::GlInfo;
use crate::state::AppState;
use crate::state::orphans::LayerObjects;
use fast::{auto, measure, plan, reuse, synthesis};
use quilt::layout::QuiltLayout;
use quilt::target::QuiltTarget;
use replay::{screen_space, shift};
use scene::convergence;
use shadows::{layered, shadow, substitute};
use std::collections::{HashMap, HashSet};

pub use scene::convergence::update_convergence;

/// Counts of the objects of ours that die with their context (framebuffers and vertex arrays
/// are not shared); the shared ones are listed by `shared_objects`.
#[derive(Clone, Copy, Debug, Default)]
pub struct ContextObjects {
    pub framebuffers: usize,
    pub vertex_arrays: usize,
}

impl std::ops::Add for ContextObjects {
    type Output = ContextObjects;
    fn add(self, o: ContextObjects) -> ContextObjects {
        ContextObjects {
            framebuffers: self.framebuffers + o.framebuffers,
            vertex_arrays: self.vertex_arrays + o.vertex_arrays,
        }
    }
}

pub struct Multiview {
    pub info: GlInfo,
    pub settings: ViewSettings,
    pub target: Option<QuiltTarget>,
    pub camera: CameraEstimate,
    /// An internal failure in this context: the layer hands everything back, pass-through.
    pub failed: bool,
    /// The display list recording an immediate-mode block (`glBegin`..`glEnd`) for replay.
    pub immediate_list: u32,
    pub recording_immediate: bool,
    /// Layered shadows of the app's framebuffers, by app name; those that cannot be, with
    /// what they had attached then (see `shadow::attachments`).
    pub shadows: HashMap<u32, shadow::ShadowFbo>,
    pub unshadowable: HashMap<u32, Vec<shadow::Found>>,
    /// The per-view content of the app's textures and renderbuffers that shadows draw into.
    pub images: HashMap<layered::AppImage, layered::LayeredImage>,
    /// Objects whose layers stay at the app's size whatever `--fbo-scale` says (`downscale`).
    pub full_size: HashSet<layered::AppImage>,
    /// What each of the app's framebuffers has attached (see `shadow::FboFacts`).
    pub fbo_facts: HashMap<u32, shadow::FboFacts>,
    /// Framebuffers already logged as drawn once (not view-dependent), and as shadowed (true)
    /// or refused (false): each is said once at `info`.
    pub drawn_once: HashSet<u32>,
    pub announced: HashSet<(u32, bool)>,
    /// Kept from draw to draw so that replays do not allocate.
    pub substitutions: substitute::Substitutions,
    pub camera_uniforms: Vec<screen_space::CameraUniform>,
    /// Per-view shears of the fixed-function projection and of the camera projection.
    pub sheared: shift::ShearedProjections,
    /// The same at infinity, for draws attached to the camera (`camera::attached`).
    pub sheared_far: shift::ShearedProjections,
    pub sheared_camera: shift::ShearedProjections,
    /// Where the main camera draws, and the copy of its depth auto-convergence reads.
    pub scene: convergence::SceneDepth,
    /// Which views this frame renders, and whether the others have been synthesised.
    pub plan: plan::ViewPlan,
    pub synth: crate::synth::Synthesizer,
    /// `--measure-error`: the exact quilt kept on measured frames.
    pub measure: Option<measure::ErrorMeasure>,
    /// `--mode auto`: the choice of K.
    pub auto: Option<auto::Auto>,
    /// `--reuse`: the rotation of rendered views and the history quilt.
    pub reuse: Option<reuse::Reuse>,
    /// Each rendered view's disparity per pixel, as its draws gave it (`quilt::record`).
    pub record: crate::multiview::quilt::record::DisparityRecord,
    /// Per-buffer blending and DSA are there: the record can be written.
    pub record_supported: bool,
    /// The program fixed-function draws are recorded with (`replay::record_fixed`).
    pub record_fixed: replay::record_fixed::FixedProgram,
    /// This frame's guard band, columns each side of the rendered views (`fast::guard`), and
    /// what its strips cost.
    pub guard: u32,
    pub guard_meter: fast::guard::Meter,
}

impl Multiview {
    /// Multiview state for a context just made current on a surface of `window` pixels.
    pub fn new(info: GlInfo, settings: ViewSettings, window: (u32, u32)) -> Multiview {
        let layout = QuiltLayout::new(settings.quilt, settings.tile, window);
        let camera = CameraEstimate::new(&settings, layout.views(), layout.tile_w);
        let mode = synthesis::mode_for(&settings, info);
        let plan = plan::ViewPlan::new(mode, layout.views());
        let measure = (plan.fast() && settings.measure_error.is_some()).then(Default::default);
        let auto = auto::Auto::new(mode, &settings, layout.views());
        let mut plan = plan;
        let mut reuse = reuse::Reuse::new(&settings, mode, layout.views());
        if let Some(r) = reuse.as_mut() {
            plan.set_rendered(r.rotation.next_rendered());
        }
        Multiview {
            info,
            settings,
            target: None,
            camera,
            failed: false,
            immediate_list: 0,
            recording_immediate: false,
            shadows: Default::default(),
            unshadowable: Default::default(),
            images: Default::default(),
            full_size: Default::default(),
            fbo_facts: Default::default(),
            drawn_once: Default::default(),
            announced: Default::default(),
            substitutions: Vec::new(),
            camera_uniforms: Vec::new(),
            sheared: Default::default(),
            sheared_far: shift::ShearedProjections::at_infinity(),
            sheared_camera: Default::default(),
            scene: Default::default(),
            plan,
            synth: Default::default(),
            measure,
            auto,
            reuse,
            record: Default::default(),
            record_supported: !info.es && info.at_least(4, 5),
            record_fixed: Default::default(),
            guard: 0,
            guard_meter: Default::default(),
        }
    }

    /// Depthiness and convergence for `layout` and the scene seen so far.
    pub fn update_rig(&mut self, layout: QuiltLayout) {
        self.camera.update_rig(&self.settings, layout.views(), layout.tile_w);
    }

    /// Multiview applies to what is drawn to framebuffer 0 right now.
    pub fn on_default_draw(&self, app: &AppState) -> bool {
        self.target.is_some() && app.draw_fbo == 0 && !self.failed && !app.compiling_list
    }

    pub fn layout(&self) -> Option<QuiltLayout> {
        self.target.as_ref().map(|t| t.layout)
    }

    /// What of ours outlives this context in its share group: every texture, renderbuffer
    /// and display list (framebuffers and vertex arrays are per context, so the shadows'
    /// view framebuffers die with it).
    pub fn shared_objects(&self) -> LayerObjects {
        let mut o = LayerObjects::default();
        if let Some(t) = &self.target {
            o.textures.push(t.color);
            if t.sampled != t.color {
                o.textures.push(t.sampled);
            }
            o.renderbuffers.extend([t.depth, t.msaa_color]);
            if t.resolved_depth != t.depth {
                o.renderbuffers.push(t.resolved_depth);
            }
        }
        for image in self.images.values() {
            o.textures.extend(image.textures());
        }
        let (textures, program) = self.scene.shared_objects();
        o.textures.extend(textures);
        o.programs.extend(program);
        o.append(self.synth.shared_objects());
        o.textures.extend(self.record.textures());
        o.programs.extend(self.record_fixed.program());
        if let Some(m) = &self.measure {
            o.textures.push(m.texture());
        }
        if let Some(h) = self.reuse.as_ref().and_then(|r| r.history.as_ref()) {
            let (textures, renderbuffers, programs) = h.shared_objects();
            o.textures.extend(textures);
            o.renderbuffers.extend(renderbuffers);
            o.programs.extend(programs);
        }
        if let Some(r) = &self.reuse {
            let (textures, programs) = r.reprojector.shared_objects();
            o.textures.extend(textures);
            o.programs.extend(programs);
        }
        o.lists.push(self.immediate_list);
        o.without_zeros()
    }

    /// How many objects of ours live in this context only: the quilt's framebuffer, the
    /// shadows' view framebuffers, the depth copy's.
    pub fn context_objects(&self) -> ContextObjects {
        let (copy_fbos, copy_vaos) = self.scene.context_objects();
        let views: usize = self.shadows.values().map(|s| s.views.len()).sum();
        let history = self.reuse.as_ref().is_some_and(|r| r.history.is_some());
        let (moved_fbos, moved_vaos) = self.reuse.as_ref().map_or((0, 0), |r| r.reprojector.context_objects());
        ContextObjects {
            framebuffers: usize::from(self.target.is_some())
                + views
                + copy_fbos
                + 2 * usize::from(history)
                + moved_fbos,
            vertex_arrays: copy_vaos + usize::from(history) + moved_vaos,
        }
    }

    /// The shadow of the framebuffer the main camera draws into, when it is one and current.
    pub fn scene_shadow(&self) -> Option<&shadows::shadow::ShadowFbo> {
        self.scene
            .tracker
            .target
            .filter(|&t| t != 0)
            .and_then(|t| self.shadows.get(&t))
            .filter(|s| !s.stale)
    }

    /// The quilt's framebuffer name while it stands in for framebuffer 0.
    pub fn quilt_fbo(&self) -> Option<u32> {
        self.target.as_ref().filter(|_| !self.failed).map(|t| t.fbo)
    }
}
