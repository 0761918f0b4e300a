//! The quilt behaves like the window it stands in for (issue 11). Whatever the window's
//! format (multisampled, sRGB written with `GL_FRAMEBUFFER_SRGB`, without alpha bits) and
//! however thin, smooth and blended the drawing, the centre tile of a 1x1, 5x1 and 3x3
//! quilt is the app's own frame bit for bit, and so is what the app reads back from
//! framebuffer 0 (its `--screenshot`: `glReadPixels`, or a resolving blit when multisampled).
//!
//! Measured before the quilt was made like the window (320x240, pixels off by more than one
//! level at 1x1): `lines` 85 on every back-end (orientation), 6,739 with 4 samples (the
//! quilt was single-sampled), 4,498 for `cubes` with 4 samples, all 76,800 with `--srgb`
//! (the quilt was linear), 191 for surfaceless EGL's alpha-less config, which has 10 bits
//! per channel (the quilt had 8). The alpha-less GLX window was already right (an RGB8
//! quilt); it stays checked.

use super::{dir_for, injected, plain_screenshot};
use crate::util::*;

/// Also: no GL error from the layer (the app counts them through `KHR_debug`), presenting
/// into a multisampled window included (a blit cannot scale into one).
fn centre_is_the_window(spec: &str, backend: &str) {
    let spec = &format!("{spec} --debug-output");
    for quilt in ["1x1", "5x1", "3x3"] {
        let dir = dir_for(&format!("window_{quilt}"), spec, backend);
        let plain = plain_screenshot(&dir, spec, backend);
        let out = injected(&dir, spec, backend, &["--output", "quilt", "--quilt", quilt]);
        // The run ends at the layer's --exit-after, before the app's count: each error is
        // also printed as it happens.
        assert!(
            !stderr(&out).contains("gl-debug: error"),
            "{spec} {backend} {quilt}: GL errors under the layer:\n{}",
            stderr(&out)
        );
        let (cols, rows) = quilt.split_once('x').unwrap();
        let (cols, rows) = (cols.parse::<u32>().unwrap(), rows.parse::<u32>().unwrap());
        let quilt_png = dir.join(format!("dump/f000003_qs{quilt}a1.3333.png"));
        let centre = tile(&read_png(&quilt_png), cols, rows, cols * rows / 2);
        let what = format!("{spec} {backend} {quilt}");
        let at = dir.join("centre.png");
        save(&centre, &at);
        assert_within(&read_png(&plain), &centre, &at, EXACT, &format!("{what}: centre tile"));
        let read_back = dir.join("injected-screenshot.png");
        assert_files_within(&plain, &read_back, EXACT, &format!("{what}: the app's read-back"));
    }
}

macro_rules! window_format_tests {
    ($($name:ident: $app:literal, $backend:literal;)*) => {$(
        #[test]
        fn $name() {
            centre_is_the_window($app, $backend);
        }
    )*};
}

window_format_tests! {
    smooth_lines_glx: "lines", "glx";
    smooth_lines_egl: "lines", "egl";
    smooth_lines_osmesa: "lines", "osmesa";
    multisampled_glx: "lines --samples 4", "glx";
    multisampled_egl: "lines --samples 4", "egl";
    multisampled_shaders_glx: "cubes --samples 4", "glx";
    multisampled_es_egl: "gles --samples 4", "egl";
    srgb_writes_glx: "lines --srgb", "glx";
    no_alpha_glx: "lines --no-alpha", "glx";
    ten_bits_no_alpha_egl: "lines --no-alpha", "egl";
    every_format_at_once_glx: "legacy --samples 4 --srgb --no-alpha", "glx";
}
