//! Every option, defined once: the launcher parses and documents them from this table, the
//! layer reads the matching `HOLOINJECT_*` variables with the same value checks.

/// One launcher option `--long`, read by the layer as `HOLOINJECT_LONG` (dashes → underscores).
pub struct OptDef {
    pub long: &'static str,
    /// Value syntax shown in help; empty for flags.
    pub value: &'static str,
    pub help: &'static str,
    /// Checks a value; `Err` is a one-line reason. Values of options the layer cannot honour
    /// yet are rejected here, so nothing is silently ignored.
    pub check: fn(&str) -> Result<(), String>,
    /// Launcher-only: not passed to the layer.
    pub launcher_only: bool,
}

impl OptDef {
    pub fn env_name(&self) -> String {
        format!("HOLOINJECT_{}", self.long.to_ascii_uppercase().replace('-', "_"))
    }
}

type Check = fn(&str) -> Result<(), String>;

const fn opt(long: &'static str, value: &'static str, help: &'static str, check: Check) -> OptDef {
    OptDef {
        long,
        value,
        help,
        check,
        launcher_only: false,
    }
}

#[rustfmt::skip]
pub static OPTIONS: &[OptDef] = &[
    opt("quilt", "CxR", "quilt columns x rows (views = C*R, at most 1024); default the device's, else 8x6",
        |v| super::parse::quilt(v).map(|_| ())),
    opt("tile", "WxH", "one view's tile in pixels; default the device's, else the window's (quilt capped at 8192 px)",
        |v| super::parse::grid(v).map(|_| ())),
    opt("device", "NAME|PATH", "display: a preset in presets/devices/ (e.g. portrait, go, 16-gen3-landscape) or a unit's visual.json",
        |v| super::device::load(v).map(|_| ())),
    opt("weave-filter", "nearest|blend|gaussian:S", "how native output mixes views between lenticules (default blend)",
        |v| super::parse::weave_filter(v).map(|_| ())),
    opt("preset", "NAME|PATH|none", "per-application preset (TOML): a name in presets/ or ~/.config/holoinject/presets/, a file, or none; default: chosen by the program's name",
        |v| super::preset_files::check_spec(v, &|k| std::env::var(k).ok())),
    opt("mode", "exact|synth|synth:pixel|hybrid:K[:pixel]|auto", "how views are made: exact re-renders every view (default); synth renders the centre and warps the rest; hybrid:K renders K and warps the rest from the two nearest; :pixel splats every pixel and fills holes by pull-push instead of warping a grid (the baseline)",
        |v| super::parse::mode(v).map(|_| ())),
    opt("frame-budget", "MS", "--mode auto: the frame time to meet, in ms (default 33.3); with another mode it is reported and ignored",
        |v| super::parse::frame_budget(v).map(|_| ())),
    OptDef { long: "reuse", value: "", help: "with synth or hybrid:K: render a rotating set of views and keep each view's last exact render while the scene is unchanged, so a still scene becomes exact",
        check: |v| super::parse::switch(v).map(|_| ()), launcher_only: false },
    opt("reuse-motion", "off|TOL", "with --reuse: kept views follow the tracked camera motion, reprojected pixel by pixel and used where their eye distance is within TOL (relative, default 0.02) of the synthesised view's; off: camera motion drops them",
        |v| super::parse::reuse_motion(v).map(|_| ())),
    opt("synth-threshold", "PX", "synthesis: split a grid cell while its disparity range in the outermost view exceeds PX tile pixels (default 1)",
        |v| super::parse::synth_threshold(v).map(|_| ())),
    opt("synth-warp", "rows|grid|gather", "synthesis warp: rows (default: a compute pass per row, no triangles), grid (Didyk's adaptive quad grid drawn as triangles) or gather (one pass per view, each pixel finds what lands on it: the GPU's shape)",
        |v| super::parse::synth_warp(v).map(|_| ())),
    opt("rows-on", "auto|gpu|cpu", "where the row warp's scan runs: auto (default: the CPU under a software rasteriser such as llvmpipe, whose compute passes access storage one lane at a time; else the GPU), gpu (a compute pass) or cpu (this process's threads, the storage mapped)",
        |v| super::parse::rows_on(v).map(|_| ())),
    opt("guard-band", "auto|off|N", "synthesis (row warp, the scene drawn to the window): render N columns beyond each side of every rendered view (auto, the default: as many as the background moves between a synthesised view and its source, up to a quarter of the tile), so the outer views show what lies beyond the rendered view's edge instead of its border pixels stretched",
        |v| super::parse::guard_band(v).map(|_| ())),
    opt("measure-error", "LIST|every:N", "on these frames render the exact quilt too and log each synthesised view's PSNR against it",
        |v| super::parse::frames(v).map(|_| ())),
    opt("output", "native|quilt|sbs|anaglyph|mono", "what is presented at swap (default: native with --device, else quilt)",
        |v| super::parse::output(v).map(|_| ())),
    opt("present", "device|window", "where the output is shown: device (the layer's own full-screen window on the Looking Glass monitor; default with --output native) or window (the program's window; default otherwise)",
        |v| super::parse::present(v).map(|_| ())),
    opt("monitor", "NAME|WxH+X+Y", "the Looking Glass monitor for --present device: a RandR monitor, output or EDID name, or a screen rectangle; default: the monitor whose EDID name starts with LKG",
        |v| super::parse::monitor(v).map(|_| ())),
    opt("preview", "mono|quilt|off", "what the program's own window shows while the output goes to the device (default mono: the centre view)",
        |v| super::parse::preview(v).map(|_| ())),
    opt("depthiness", "S", "disparity at infinity (NDC) between centre and outermost view; default 4 px between neighbours",
        |v| super::parse::finite(v).map(|_| ())),
    opt("view-cone", "DEG", "depthiness in physical terms: angle between the outermost cameras seen from the convergence plane",
        |v| super::parse::view_cone(v).map(|_| ())),
    opt("convergence", "auto|C", "eye-space distance (w units) of the zero-parallax plane; auto follows the scene (default)",
        |v| super::parse::convergence(v).map(|_| ())),
    opt("focus", "F", "post-hoc zero-parallax shift (NDC) between centre and outermost view", |v| super::parse::finite(v).map(|_| ())),
    opt("depth-remap", "F,B,DF,DB|off", "comfort: keep the outermost view's disparity (tile px, + behind the screen) as is in [-F, B], compress it beyond towards -DF and DB; default the device's range, else off",
        |v| super::comfort::depth_remap(v).map(|_| ())),
    opt("edge-fade", "off|PX", "comfort: fade what stands in front of the screen within PX tile pixels of a view's left/right border (default off)",
        |v| super::comfort::edge_fade(v).map(|_| ())),
    opt("dof", "off|on|STRENGTH", "comfort: blur what lies behind the comfortable range, more the farther (on = 1; default off)",
        |v| super::comfort::dof(v).map(|_| ())),
    opt("comfort", "on|off", "off turns the depth remap, edge fade and depth of field all off (default on: what the options and device give)",
        |v| super::comfort::comfort(v).map(|_| ())),
    opt("sky-at-infinity", "on|off", "draws attached to the camera (a sky box around the eye: a model-view with no translation) get the disparity of infinity (default on)",
        |v| super::parse::switch(v).map(|_| ())),
    opt("disparity-record", "on|off", "every rendered view records the disparity each draw gave its pixels, read by the warps, auto-convergence, the depth of field, the edge fade and --dump-disparity instead of converting depth with one camera (default on)",
        |v| super::parse::switch(v).map(|_| ())),
    opt("fbo-views", "auto|all|none", "which of the program's own framebuffers get a layer per view: auto (view-dependent passes; default), all, none",
        |v| super::parse::fbo_views(v).map(|_| ())),
    opt("fbo-scale", "window|tile|F", "resolution of those layers: tile (default: what the program draws at the window's size it draws at the tile's, never upscaled; framebuffers of a size of their own keep it), window (the program's own) or F in (0, 1] times the program's",
        |v| super::parse::fbo_scale(v).map(|_| ())),
    opt("dump", "DIR", "write presented frames (and quilts) as PNG into DIR", super::parse::nonempty),
    OptDef { long: "dump-disparity", value: "", help: "with --dump: also a false-colour PNG of each view's disparity, in pixels of the outermost view (f{frame}_disparity_qs{C}x{R}a{aspect}.png, legend below)",
        check: |v| super::parse::switch(v).map(|_| ()), launcher_only: false },
    opt("dump-frames", "LIST|every:N", "frames to dump, e.g. 1,10,30 or every:10 (default: every frame)",
        |v| super::parse::frames(v).map(|_| ())),
    opt("record", "FILE.mp4", "record the quilt video with ffmpeg, named FILE_qs{C}x{R}a{aspect}.mp4 (the Looking Glass convention), at the program's measured frame rate",
        super::parse::record_path),
    opt("exit-after", "N", "exit the program (status 0) right after frame N is presented and dumped",
        |v| super::parse::frame_number(v).map(|_| ())),
    OptDef { long: "gpu-counts", value: "", help: "count per frame what the GPU is given: the program's draws, draws submitted (replays and the layer's own passes), fragment and compute invocations (pipeline-statistics queries), bytes read back; medians at info when --exit-after ends the run",
        check: |v| super::parse::switch(v).map(|_| ()), launcher_only: false },
    opt("osmesa-boundary", "finish|flush", "call that ends a frame for OSMesa contexts, which never swap (default finish)",
        |v| super::parse::boundary(v).map(|_| ())),
    OptDef { long: "overlay", value: "", help: "draw the live values into the presented image for two seconds after each change (holoinject ctl, hotkeys)",
        check: |v| super::parse::switch(v).map(|_| ()), launcher_only: false },
    opt("hotkeys", "off|MOD+MOD", "modifiers held with the live-control keys (ctrl, alt, shift, super; default ctrl+alt), or off; grabbed on the layer's own X connection",
        |v| super::parse::hotkeys(v).map(|_| ())),
    opt("log", "LEVEL", "stderr log level: off|error|warn|info|debug|trace (default warn)",
        |v| crate::log::Level::parse(v).map(|_| ()).ok_or_else(|| "expected off|error|warn|info|debug|trace".into())),
    OptDef { long: "dry-run", value: "", help: "print the environment and command instead of running it", check: |_| Ok(()), launcher_only: true },
];

pub fn find(long: &str) -> Option<&'static OptDef> {
    OPTIONS.iter().find(|o| o.long == long)
}
