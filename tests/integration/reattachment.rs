//! Layered shadows outlive the app's attachment calls (issue 11): renderers built on VTK's
//! render passes (f3d, ParaView) attach the same textures again before every pass, send
//! their sampling parameters again, and detach the colour textures once the pass is drawn,
//! while later passes still sample them. `framebuffers --reattach` does exactly that every
//! frame; `--late-swizzle` changes a sampling parameter of the scene texture after the
//! layer has shadowed it. Both must give the app's own reference quilt, and the shadow must
//! be made (and logged) once, not once per frame.
//!
//! Run: `cargo test --release --test integration reattachment:: -- --nocapture`.

use crate::util::*;
use std::path::{Path, PathBuf};

/// Depthiness, convergence and focus of the sample-app quilt tests (`sample_apps`).
const RIG: [&str; 6] = ["--depthiness", "0.12", "--convergence", "9", "--focus", "0.01"];

fn args<'a>(frames: &'a str, switch: &'a str) -> Vec<&'a str> {
    vec!["--backend", "egl", "--size", "320x240", "--frames", frames, switch]
}

/// The app's own 3x3 reference quilt of its last frame.
fn reference(dir: &Path, frames: &str, switch: &str) -> PathBuf {
    let out = dir.join("reference.png");
    let mut a = args(frames, switch);
    a.extend(["--reference-quilt", "3x3", "--out", out.to_str().unwrap()]);
    a.extend(RIG);
    assert_success(&run(&app("framebuffers"), &a, &[]), "reference quilt");
    out
}

/// The last frame's 3x3 quilt under the layer, and what the layer said at `--log info`.
fn injected(dir: &Path, frames: &str, switch: &str) -> (PathBuf, String) {
    let dump = dir.join("dump");
    let mut options = vec!["--log", "info", "--output", "quilt", "--quilt", "3x3"];
    options.extend(RIG);
    options.extend(dump_and_exit_at(&dump, frames));
    let out = under_layer(&options, app("framebuffers"), &args(frames, switch), &[]);
    assert_success(&out, "run under the layer");
    assert_layer_loaded(&out);
    assert_no_gl_error(&out);
    let quilt = dump.join(format!("f{:06}_qs3x3a1.3333.png", frames.parse::<u32>().unwrap()));
    (quilt, stderr(&out))
}

/// Before the fix the shadow was dropped at the detach and made again at the next draw, with
/// the frame's scene lost (every tile showed the vignette over the cleared colour) and
/// "shadowed" logged every frame.
#[test]
fn targets_reattached_every_frame_keep_their_shadow() {
    let dir = temp_dir("reattach_every_frame");
    let frames = "30";
    let expected = reference(&dir, frames, "--reattach");
    let (quilt, log) = injected(&dir, frames, "--reattach");
    assert_tiles_psnr(&expected, &quilt, (3, 3), 40.0, "framebuffers --reattach, frame 30");
    let shadowed: Vec<&str> = log.lines().filter(|l| l.contains(" shadowed with ")).collect();
    assert_eq!(
        shadowed.len(),
        1,
        "the scene framebuffer must be shadowed once in {frames} frames:\n{log}"
    );
    let q = read_png(&quilt);
    assert_parallax_grows(&q, &quilt, (3, 3), 4, &[5], 30, "framebuffers --reattach");
}

/// A sampling parameter set after the shadow exists reaches the layer views that stand in
/// for the texture: red and blue swapped in every view, as in the app's own quilt.
#[test]
fn texture_parameters_set_after_the_shadow_are_mirrored() {
    let dir = temp_dir("reattach_late_swizzle");
    let expected = reference(&dir, "3", "--late-swizzle");
    let (quilt, _) = injected(&dir, "3", "--late-swizzle");
    assert_tiles_psnr(&expected, &quilt, (3, 3), 40.0, "framebuffers --late-swizzle");
}
