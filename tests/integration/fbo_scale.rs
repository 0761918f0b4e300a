//! `--fbo-scale`: the layers of the programs' own framebuffers at a smaller resolution,
//! against `--fbo-scale window` (the program's own) of the same frame. OSMesa, so no X
//! server is needed; `MESA_DEBUG=1` makes Mesa print every GL error as it is raised.

use crate::util::*;
use std::path::{Path, PathBuf};

/// A 640x480 program in 160x120 tiles: `tile` scales its layers by 0.25.
const SIZE: &str = "640x480";
const QUILT: &str = "5x1";
const TILE: &str = "160x120";
/// The synthesis tests' rig, with convergence fixed so that a frame's views do not depend on
/// what earlier frames' depth said.
const RIG: [&str; 6] = ["--depthiness", "0.12", "--convergence", "9", "--focus", "0"];

/// Lowest per-view PSNR of `tile` against `window` accepted, per app. Measured here (worst
/// view of five): framebuffers 22.0 dB, bloom 23.2, deferred 31.8, ssao 30.9; bounds 2 dB
/// below. The difference is the trade itself: passes drawn at a quarter of the resolution,
/// and kernels in texels (framebuffers' sharpen, bloom's blur) four times wider on screen.
/// A layer mapped at the wrong scale, or a view drawn from another view's layer, is checked
/// against the outer views' own neighbours below.
const MIN_PSNR: [(&str, f64); 4] = [
    ("framebuffers", 20.0),
    ("bloom", 21.0),
    ("deferred", 29.0),
    ("ssao", 28.0),
];

/// Frame 3 of `app` (with `app_args`) under the layer with `--fbo-scale scale`: the quilt's
/// path and stderr (the layer's log at `info`, and Mesa's error lines).
fn quilt_at(dir: &Path, app_name: &str, scale: &str, app_args: &[&str]) -> (PathBuf, String) {
    let dump = dir.join(format!("{app_name}-{scale}"));
    let mut options = vec!["--log", "info", "--output", "quilt", "--quilt", QUILT, "--tile", TILE];
    options.extend(["--fbo-scale", scale]);
    options.extend(RIG);
    options.extend(dump_and_exit_at(&dump, "3"));
    let mut args = vec!["--backend", "osmesa", "--size", SIZE, "--frames", "3"];
    args.extend_from_slice(app_args);
    let out = under_layer(&options, app(app_name), &args, &[MESA_DEBUG_ENV]);
    let what = format!("{app_name} --fbo-scale {scale}");
    assert_success(&out, &what);
    assert_layer_loaded(&out);
    assert_no_gl_error(&out);
    let err = stderr(&out);
    assert!(!err.contains("holoinject: warn"), "{what}:\n{err}");
    (dump.join(format!("f000003_qs{QUILT}a1.3333.png")), err)
}

fn tile_of(quilt: &Image, i: u32) -> Image {
    tile(quilt, 5, 1, i)
}

/// Multi-pass scenes with `tile` layers: every view close to `window`'s, depth still moving
/// views apart, no GL error that `window` does not have.
#[test]
fn tile_layers_keep_multipass_views_close_to_window() {
    let dir = temp_dir("fbo_scale_tile");
    for (name, min) in MIN_PSNR {
        let (window, window_log) = quilt_at(&dir, name, "window", &[]);
        let (tile, tile_log) = quilt_at(&dir, name, "tile", &[]);
        assert!(
            tile_log.contains("layers (160x120, scaled by 0.250x0.250)"),
            "{name}: no scaled shadow in the log:\n{tile_log}"
        );
        assert!(!window_log.contains("scaled by"), "{window_log}");
        let (w, t) = (read_png(&window), read_png(&tile));
        let psnr = tile_psnr(&w, &t, 5, 1);
        let mean = psnr.iter().sum::<f64>() / psnr.len() as f64;
        eprintln!("{name}: --fbo-scale tile against window, per view: {psnr:.2?} dB (mean {mean:.2})");
        for (i, p) in psnr.iter().enumerate() {
            assert!(
                *p >= min,
                "{name}: view {i}: {p:.2} dB against window, at least {min} expected ({psnr:.2?})"
            );
        }
        // An outer view of `tile` is closer to `window`'s same view than to its neighbour.
        for (view, next) in [(0, 1), (4, 3)] {
            let other = tile_psnr(&tile_of(&w, next), &tile_of(&t, view), 1, 1)[0];
            eprintln!("{name}: tile view {view} against window view {next}: {other:.2} dB");
            assert!(
                psnr[view as usize] > other,
                "{name}: view {view} looks like view {next} ({other:.2} dB)"
            );
        }
        assert_depth_parallax(&t, &tile, 5, 40, &format!("{name} --fbo-scale tile"));
        assert_no_added_gl_errors(&window_log, &tile_log, &format!("{name} --fbo-scale tile"));
    }
}

/// The truth for a view shown in a 320x240 tile is the program itself at 320x240. Under the
/// default (`tile`), a 640x480 program's quilt of 320x240 tiles has a centre view equal to
/// the program run at 320x240, bit for bit, and every view within the sample apps' tolerance
/// (40 dB per tile) of the program's own reference quilt at that size. (`window` draws each
/// view at 640x480 and minifies it: 23.6-26.3 dB on framebuffers and bloom, issue 24.)
/// One exception, measured: ssao tiles its 4x4 rotation noise by a uniform the program
/// computes from its window (`noiseScale = window / 4`), which no mapping of pixels can see;
/// at tile size the pattern repeats twice as often in the layer (centre 50.7 dB against the
/// program at tile size, at most 9 levels off), so its centre is held to 45 dB.
#[test]
fn tile_sized_passes_are_the_program_at_tile_size() {
    let dir = temp_dir("fbo_scale_truth");
    let rig = ["--depthiness", "0.12", "--convergence", "9", "--focus", "0.01"];
    for (name, centre_db) in [
        ("framebuffers", None),
        ("bloom", None),
        ("deferred", None),
        ("ssao", Some(45.0)),
    ] {
        let at = |what: &str| dir.join(format!("{name}-{what}"));
        let small = ["--backend", "osmesa", "--size", "320x240", "--frames", "3"];
        let (plain, reference) = (at("plain.png"), at("reference.png"));
        let mut args = small.to_vec();
        args.extend(["--screenshot", plain.to_str().unwrap()]);
        assert_success(&run(&app(name), &args, &[]), &format!("{name} at 320x240"));
        let mut args = small.to_vec();
        args.extend(["--reference-quilt", "3x3", "--out", reference.to_str().unwrap()]);
        args.extend(rig);
        assert_success(
            &run(&app(name), &args, &[]),
            &format!("{name}'s reference quilt at 320x240"),
        );
        let dump = at("layer");
        let mut options = vec![
            "--log", "info", "--output", "quilt", "--quilt", "3x3", "--tile", "320x240",
        ];
        options.extend(rig);
        options.extend(dump_and_exit_at(&dump, "3"));
        let args = ["--backend", "osmesa", "--size", SIZE, "--frames", "3"];
        let out = under_layer(&options, app(name), &args, &[MESA_DEBUG_ENV]);
        assert_success(&out, &format!("{name} under the layer"));
        assert_no_gl_error(&out);
        let log = stderr(&out);
        assert!(
            log.contains("scaled by 0.500x0.500"),
            "{name}: not scaled by default:\n{log}"
        );
        let quilt = dump.join("f000003_qs3x3a1.3333.png");
        let centre = tile(&read_png(&quilt), 3, 3, 4);
        save(&centre, &at("centre.png"));
        match centre_db {
            None => assert_identical(&plain, &at("centre.png")),
            Some(db) => {
                let p = tile_psnr(&read_png(&plain), &centre, 1, 1)[0];
                assert!(
                    p >= db,
                    "{name}: centre view {p:.2} dB against the program at tile size"
                );
            }
        }
        assert_tiles_psnr(&reference, &quilt, (3, 3), 40.0, &format!("{name}, tile-sized passes"));
    }
}

/// `0.5` halves every layer, and says so once per framebuffer.
#[test]
fn fbo_scale_half_halves_the_layers() {
    let dir = temp_dir("fbo_scale_half");
    let (_, window_log) = quilt_at(&dir, "framebuffers", "window", &[]);
    let (half, log) = quilt_at(&dir, "framebuffers", "0.5", &[]);
    let line = "shadowed with 5 layers (320x240, scaled by 0.500x0.500)";
    assert_eq!(log.matches(line).count(), 1, "{log}");
    assert!(window_log.contains("shadowed with 5 layers (640x480)"), "{window_log}");
    assert!(has_content(&half));
}

/// A pass reading its texels by pixel address (`texelFetch` at `gl_FragCoord`) cannot read a
/// scaled layer: that framebuffer stays at the program's size (said once), and once that is
/// decided the frame is `window`'s bit for bit.
#[test]
fn texel_fetch_keeps_the_program_size() {
    let dir = temp_dir("fbo_scale_fetch");
    let fetch = ["--texel-fetch"];
    let (window, _) = quilt_at(&dir, "framebuffers", "window", &fetch);
    let (tile, log) = quilt_at(&dir, "framebuffers", "tile", &fetch);
    let said = "layers at the program's size (a program drawing into it or sampling it reads texelFetch)";
    assert_eq!(log.matches(said).count(), 1, "{log}");
    assert!(has_content(&window));
    assert_identical(&window, &tile);
}
