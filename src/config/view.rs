//! The multiview settings, and the one way they change after start-up. `ViewSettings::set`
//! is shared by the environment, presets and live control (`live`), so a value changed while
//! the program runs means exactly what it means at start. What depends on the device (the
//! quilt, the output, where it is presented, the comfort range) is decided once all layers
//! are read (`resolve`, `ComfortChoice`), so an explicit value always wins over the device's.

use super::comfort;
use super::device;
use super::parse;
use super::values::{
    Convergence, DEFAULT_FRAME_BUDGET_MS, FboScale, FboViews, FrameSet, GuardBand, Mode, Output, Present, Preview,
    RowsOn, SynthWarp, WeaveFilter,
};

/// The multiview rig as configured (what is not given is decided per context from the
/// window size and the scene).
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSettings {
    pub output: Output,
    /// Default: `Device` with native output, else `Window`.
    pub present: Present,
    pub preview: Preview,
    /// `--monitor`: the device's monitor chosen by hand (else found by its EDID name).
    pub monitor: Option<parse::MonitorSpec>,
    pub quilt: (u32, u32),
    pub tile: Option<(u32, u32)>,
    pub device: Option<device::Device>,
    pub weave_filter: WeaveFilter,
    pub fbo_views: FboViews,
    /// Draws attached to the camera (a sky around the eye) at infinity (`camera::attached`).
    pub sky_at_infinity: bool,
    /// The fast modes read the disparity each draw gave its pixels (`shader::record`).
    pub disparity_record: bool,
    pub fbo_scale: FboScale,
    pub depthiness: Option<f64>,
    /// Angle (degrees) between the outermost cameras as seen from the convergence plane.
    pub view_cone: Option<f64>,
    pub convergence: Convergence,
    pub focus: f64,
    pub mode: Mode,
    /// `--reuse`: views rendered in turn, kept while the scene is unchanged (fast modes only).
    pub reuse: bool,
    /// `--reuse-motion`: kept views reprojected by the camera's motion, and the relative
    /// eye-distance tolerance of their pixels; `None`: camera motion drops them.
    pub reuse_motion: Option<f64>,
    /// Disparity range (tile pixels, outermost view) a synthesis grid cell may hold.
    pub synth_threshold: f64,
    pub synth_warp: SynthWarp,
    /// `--rows-on`: where the row warp's scan runs.
    pub rows_on: RowsOn,
    /// `--guard-band`: columns rendered beyond the rendered views' sides for the warp.
    pub guard_band: GuardBand,
    /// Frames on which the exact quilt is rendered too and the synthesised views compared.
    pub measure_error: Option<FrameSet>,
    /// `--mode auto`: the frame time to meet (ms).
    pub frame_budget_ms: f64,
    /// The comfort effects (read every frame, so they may change while the app runs).
    pub comfort: comfort::ComfortSettings,
}

impl ViewSettings {
    /// What was given explicitly wins; otherwise the device's quilt and native output, else
    /// 8x6 tiles of the window's size and the quilt itself as output.
    pub(super) fn resolve(
        &mut self,
        quilt: Option<(u32, u32)>,
        tile: Option<(u32, u32)>,
        output: Option<Output>,
        present: Option<Present>,
    ) {
        let dev = self.device.as_ref().map(|d| d.quilt);
        self.quilt = quilt.or(dev.map(|q| (q.columns, q.rows))).unwrap_or((8, 6));
        self.tile = tile.or(dev.filter(|_| quilt.is_none()).map(|q| (q.tile_width, q.tile_height)));
        self.output = output.unwrap_or(if self.device.is_some() {
            Output::Native
        } else {
            Output::Quilt
        });
        self.present = present.unwrap_or(if self.output == Output::Native {
            Present::Device
        } else {
            Present::Window
        });
    }
}

impl ViewSettings {
    /// `--frame-budget` (value and variable) applies to `--mode auto` only: elsewhere it is
    /// reported and ignored, like a bad value, so a budget never silently does nothing.
    pub(super) fn apply_budget(&mut self, budget: Option<(f64, String)>, report: &mut dyn FnMut(String)) {
        match budget {
            Some((ms, _)) if self.mode == Mode::Auto => self.frame_budget_ms = ms,
            Some((ms, var)) => report(format!("{var}={ms}: applies to --mode auto only; ignored")),
            None => {}
        }
    }
}

impl ViewSettings {
    /// Sets option `long` from its (already checked) value; the environment, presets and
    /// live changes (`live`) all go through here. Options that are not view settings are
    /// left to the caller.
    pub fn set(&mut self, long: &str, value: &str) {
        match long {
            "output" => self.output = parse::output(value).unwrap_or(self.output),
            "device" => self.device = device::load(value).ok(),
            "weave-filter" => self.weave_filter = parse::weave_filter(value).unwrap_or(self.weave_filter),
            "depthiness" => self.depthiness = parse::finite(value).ok(),
            "fbo-views" => self.fbo_views = parse::fbo_views(value).unwrap_or(FboViews::Auto),
            "sky-at-infinity" => self.sky_at_infinity = parse::switch(value).unwrap_or(true),
            "disparity-record" => self.disparity_record = parse::switch(value).unwrap_or(true),
            "fbo-scale" => self.fbo_scale = parse::fbo_scale(value).unwrap_or(FboScale::Tile),
            "view-cone" => self.view_cone = parse::view_cone(value).ok(),
            "convergence" => self.convergence = parse::convergence(value).unwrap_or(Convergence::Auto),
            "focus" => self.focus = parse::finite(value).unwrap_or(0.0),
            "mode" => self.mode = parse::mode(value).unwrap_or(Mode::Exact),
            "reuse" => self.reuse = parse::switch(value).unwrap_or(false),
            "reuse-motion" => self.reuse_motion = parse::reuse_motion(value).unwrap_or(Some(0.02)),
            "synth-threshold" => self.synth_threshold = parse::synth_threshold(value).unwrap_or(1.0),
            "synth-warp" => self.synth_warp = parse::synth_warp(value).unwrap_or(SynthWarp::Rows),
            "rows-on" => self.rows_on = parse::rows_on(value).unwrap_or(RowsOn::Auto),
            "guard-band" => self.guard_band = parse::guard_band(value).unwrap_or(GuardBand::Auto),
            "measure-error" => self.measure_error = parse::frames(value).ok(),
            "edge-fade" => self.comfort.edge_fade = comfort::edge_fade(value).unwrap_or(None),
            "dof" => self.comfort.dof = comfort::dof(value).unwrap_or(None),
            // At start-up the remap is chosen with the device's range (`ComfortChoice`); a
            // live change sets it, and the fade and blur measure from it.
            "depth-remap" => {
                if let Ok(r) = comfort::depth_remap(value) {
                    self.comfort.remap = r;
                    self.comfort.range = r.or(self.device.as_ref().and_then(|d| d.comfort));
                }
            }
            _ => {}
        }
    }
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            output: Output::Quilt,
            present: Present::Window,
            preview: Preview::Mono,
            monitor: None,
            quilt: (8, 6),
            tile: None,
            device: None,
            weave_filter: WeaveFilter::BlendNext,
            fbo_views: FboViews::Auto,
            sky_at_infinity: true,
            disparity_record: true,
            fbo_scale: FboScale::Tile,
            depthiness: None,
            view_cone: None,
            convergence: Convergence::Auto,
            focus: 0.0,
            mode: Mode::Exact,
            reuse: false,
            reuse_motion: Some(0.02),
            synth_threshold: 1.0,
            synth_warp: SynthWarp::Rows,
            rows_on: RowsOn::Auto,
            guard_band: GuardBand::Auto,
            measure_error: None,
            frame_budget_ms: DEFAULT_FRAME_BUDGET_MS,
            comfort: comfort::ComfortSettings::default(),
        }
    }
}

/// The comfort options as given, before the device's defaults are known.
pub(super) struct ComfortChoice {
    /// `--depth-remap`: `Some(None)` is an explicit `off`.
    pub remap: Option<Option<comfort::DepthRemap>>,
    /// `--comfort`.
    pub on: bool,
}

impl Default for ComfortChoice {
    fn default() -> Self {
        ComfortChoice { remap: None, on: true }
    }
}

impl ComfortChoice {
    /// An explicit `--depth-remap` wins; else the device's comfortable range turns the remap
    /// on; the fade and depth of field measure from the remap's range, else the device's.
    /// `--comfort off` turns all three off.
    pub(super) fn resolve(self, view: &mut ViewSettings) {
        let device = view.device.as_ref().and_then(|d| d.comfort);
        let c = &mut view.comfort;
        c.remap = self.remap.unwrap_or(device);
        c.range = c.remap.or(device);
        if !self.on {
            *c = comfort::ComfortSettings::default();
        }
    }
}
