//! The sample apps on an EGL device (`--backend egl-device`: `EGL_EXT_platform_device`, a
//! pbuffer, no window system at all), the only headless path on NVIDIA's driver, which has
//! no surfaceless platform; `scripts/bench-gpu.sh` benchmarks there. Mesa lists llvmpipe as
//! a software device, so the path is tested here as the GPU machine will take it. The layer
//! sees only another EGL display: pass-through is the app's frame, the quilt matches the
//! app's own reference, its centre is the frame and its side views differ.

use super::{app_args, dir_for, injected, passthrough_identical, quilt_matches_reference, split_app};
use crate::util::*;

const BACKEND: &str = "egl-device";

/// The app really ran on a device display (not the surfaceless platform), with the layer,
/// and needed no X server (an empty DISPLAY names none).
fn assert_device_display(spec: &str) {
    let (path, extra) = split_app(spec);
    let mut args = app_args(BACKEND);
    args.extend(extra);
    let out = under_layer(
        &["--log", "info", "--exit-after", "1"],
        path,
        &args,
        &[("HOLOAPPS_VERBOSE", "1"), ("DISPLAY", "")],
    );
    assert_success(&out, &format!("{spec} on {BACKEND}"));
    assert_layer_loaded(&out);
    assert!(
        stderr(&out).contains("egl-device (device "),
        "{spec}: not on an EGL device:\n{}",
        stderr(&out)
    );
}

fn side_views_differ(spec: &str) {
    let dir = dir_for("sides3x3", spec, BACKEND);
    injected(&dir, spec, BACKEND, &["--output", "quilt", "--quilt", "3x3"]);
    let quilt_png = dir.join("dump/f000003_qs3x3a1.3333.png");
    let quilt = read_png(&quilt_png);
    let (left, right) = (tile(&quilt, 3, 3, 3), tile(&quilt, 3, 3, 5));
    assert_images_differ(&left, &right, &quilt_png, &format!("{spec} {BACKEND}: views 3 and 5"));
}

macro_rules! egl_device_tests {
    ($($name:ident: $app:literal;)*) => {$(
        #[test]
        fn $name() {
            assert_device_display($app);
            passthrough_identical($app, BACKEND);
            quilt_matches_reference($app, BACKEND, "3x3");
            side_views_differ($app);
        }
    )*};
}

egl_device_tests! {
    cubes_on_an_egl_device: "cubes";
    deferred_on_an_egl_device: "deferred";
}
