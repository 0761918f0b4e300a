//! The types option values become, and for the options that name one of a few choices the
//! words that name them (`--output native|quilt|…`): a new variant and its word change
//! together, so they live together, next to the inverse (`Output::name`). `parse` re-exports
//! the word parsers, so every option's syntax is still found there; the value syntax built
//! from numbers (grids, frame lists, modes, the monitor) stays in `parse`.

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FrameSet {
    List(Vec<u64>),
    Every(u64),
}

impl FrameSet {
    pub fn contains(&self, frame: u64) -> bool {
        match self {
            FrameSet::List(l) => l.contains(&frame),
            FrameSet::Every(n) => frame.is_multiple_of(*n),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    Native,
    Quilt,
    SideBySide,
    Anaglyph,
    Mono,
}

/// Where the output is shown (`--present`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Present {
    /// In the layer's own borderless window covering the Looking Glass monitor.
    Device,
    /// In the program's own window.
    Window,
}

/// What the program's own window shows while the output goes to the device (`--preview`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preview {
    Mono,
    Quilt,
    Off,
}

impl Output {
    /// The option value naming it (`--output`).
    pub fn name(self) -> &'static str {
        match self {
            Output::Native => "native",
            Output::Quilt => "quilt",
            Output::SideBySide => "sbs",
            Output::Anaglyph => "anaglyph",
            Output::Mono => "mono",
        }
    }
}

pub fn output(v: &str) -> Result<Output, String> {
    match v {
        "mono" => Ok(Output::Mono),
        "quilt" => Ok(Output::Quilt),
        "sbs" => Ok(Output::SideBySide),
        "anaglyph" => Ok(Output::Anaglyph),
        "native" => Ok(Output::Native),
        _ => Err(format!("`{v}`: expected native|quilt|sbs|anaglyph|mono")),
    }
}

pub fn present(v: &str) -> Result<Present, String> {
    match v.trim() {
        "device" => Ok(Present::Device),
        "window" => Ok(Present::Window),
        _ => Err(format!("`{v}`: expected device|window")),
    }
}

pub fn preview(v: &str) -> Result<Preview, String> {
    match v.trim() {
        "mono" => Ok(Preview::Mono),
        "quilt" => Ok(Preview::Quilt),
        "off" => Ok(Preview::Off),
        _ => Err(format!("`{v}`: expected mono|quilt|off")),
    }
}

/// Which of the app's framebuffers get layered shadows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FboViews {
    /// Those a view-dependent pass draws into (main camera, or sampling a layered texture).
    Auto,
    /// Every one drawn into (e.g. to measure what drawing shadow maps once saves).
    All,
    /// None: off-screen passes show the centre view.
    None,
}

pub fn fbo_views(v: &str) -> Result<FboViews, String> {
    match v.trim() {
        "auto" => Ok(FboViews::Auto),
        "all" => Ok(FboViews::All),
        "none" => Ok(FboViews::None),
        _ => Err(format!("`{v}`: expected auto|all|none")),
    }
}

/// The resolution of the layers of shadowed framebuffers (`--fbo-scale`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FboScale {
    /// The app's own size: every view's off-screen passes as the program renders them.
    Window,
    /// Scaled so that the window maps to one tile (each axis at most 1).
    Tile,
    /// This fraction, in (0, 1], of the app's size.
    Factor(f64),
}

/// `--fbo-scale`: `window`, `tile` or a factor in (0, 1] (layers are never larger than the
/// app's framebuffers: upscaling would cost more than the program's own passes).
pub fn fbo_scale(v: &str) -> Result<FboScale, String> {
    match v.trim() {
        "window" => Ok(FboScale::Window),
        "tile" => Ok(FboScale::Tile),
        f => match f.parse::<f64>() {
            Ok(x) if x > 0.0 && x <= 1.0 => Ok(FboScale::Factor(x)),
            _ => Err(format!("`{v}`: expected window|tile|F with 0 < F <= 1")),
        },
    }
}

/// How views are made (DESIGN §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Every view re-rendered.
    Exact,
    /// The centre view rendered, the others warped by an adaptive quad grid.
    Synth,
    /// The centre view rendered, the others splatted per pixel (the baseline).
    SynthPixel,
    /// K evenly spaced views rendered, the others warped from their two nearest.
    Hybrid(u32),
    /// As `Hybrid`, the others splatted per pixel from their two nearest.
    HybridPixel(u32),
    /// K chosen per frame to meet `ViewSettings::frame_budget_ms` (`multiview::auto`).
    Auto,
}

/// `--frame-budget` when `--mode auto` is given without one: 30 frames per second.
pub const DEFAULT_FRAME_BUDGET_MS: f64 = 33.3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Convergence {
    Auto,
    Fixed(f64),
}

/// How the native weave mixes views between lenticules (`--weave-filter`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WeaveFilter {
    Nearest,
    BlendNext,
    /// `sigma` in views.
    Gaussian {
        sigma: f32,
    },
}

impl WeaveFilter {
    /// The shader's `u_filter` value.
    pub fn mode(self) -> i32 {
        match self {
            WeaveFilter::Nearest => 0,
            WeaveFilter::BlendNext => 1,
            WeaveFilter::Gaussian { .. } => 2,
        }
    }
}

pub fn weave_filter(v: &str) -> Result<WeaveFilter, String> {
    use WeaveFilter as Filter;
    match v.trim() {
        "nearest" => Ok(Filter::Nearest),
        "blend" => Ok(Filter::BlendNext),
        g => match g.strip_prefix("gaussian:").map(str::parse::<f32>) {
            Some(Ok(sigma)) if sigma > 0.0 && sigma <= 8.0 => Ok(Filter::Gaussian { sigma }),
            _ => Err(format!(
                "`{v}`: expected nearest|blend|gaussian:SIGMA (SIGMA in views, 0 < SIGMA <= 8)"
            )),
        },
    }
}

/// How synthesised views are warped (README "Choosing a mode").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SynthWarp {
    /// One compute invocation per target row: no triangles (default; measured faster and
    /// closer to exact on llvmpipe).
    Rows,
    /// Didyk et al.'s adaptive quad grid, drawn as triangles.
    Grid,
    /// Each target pixel finds what lands on it: one pass per view (issue 23).
    Gather,
}

/// Where the row warp's scan runs (`--rows-on`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowsOn {
    /// The CPU under a software rasteriser (its GPU is the CPU), else the GPU.
    Auto,
    Gpu,
    Cpu,
}

/// The synthesis sources' guard band (`--guard-band`): columns rendered beyond each side of
/// a rendered view's tile, which the row warp moves into view where a synthesised view sees
/// past the rendered view's edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GuardBand {
    Off,
    /// As wide as the largest disparity of the background (parallax 0 to 1) between a
    /// synthesised view and its source, up to a quarter of the tile width.
    Auto,
    /// This many columns each side.
    Columns(u32),
}

/// `--guard-band`.
pub fn guard_band(v: &str) -> Result<GuardBand, String> {
    match v.trim() {
        "off" | "0" => Ok(GuardBand::Off),
        "auto" => Ok(GuardBand::Auto),
        n => match n.parse::<u32>() {
            Ok(c) if c <= 4096 => Ok(GuardBand::Columns(c)),
            _ => Err(format!("`{v}`: expected auto, off or a number of columns (0 to 4096)")),
        },
    }
}

/// `--rows-on`.
pub fn rows_on(v: &str) -> Result<RowsOn, String> {
    match v.trim() {
        "auto" => Ok(RowsOn::Auto),
        "gpu" => Ok(RowsOn::Gpu),
        "cpu" => Ok(RowsOn::Cpu),
        _ => Err(format!("`{v}`: expected auto, gpu or cpu")),
    }
}

/// `--synth-warp`.
pub fn synth_warp(v: &str) -> Result<SynthWarp, String> {
    match v.trim() {
        "rows" => Ok(SynthWarp::Rows),
        "grid" => Ok(SynthWarp::Grid),
        "gather" => Ok(SynthWarp::Gather),
        _ => Err(format!("`{v}`: expected rows, grid or gather")),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    Finish,
    Flush,
}

pub fn boundary(v: &str) -> Result<Boundary, String> {
    match v.trim() {
        "finish" => Ok(Boundary::Finish),
        "flush" => Ok(Boundary::Flush),
        _ => Err(format!("`{v}`: expected finish|flush")),
    }
}
