//! The guard band (`--guard-band`): columns rendered beyond the rendered view's sides, which
//! the row warp moves into the synthesised views where they see past that view's edge.

use crate::synthesis::RIG;
use crate::util::*;
use std::path::{Path, PathBuf};

/// A portrait window: the cubes reach the tile's sides.
const SIZE: &str = "240x320";
/// Border columns of a 240-px tile judged: the outermost 5 %.
const BORDER: u32 = 12;

/// Frame 3 of cubes at 5x1 under `mode` and `extra` options: the quilt and the log.
fn quilt(dir: &Path, name: &str, mode: &str, extra: &[&str]) -> (PathBuf, String) {
    let dump = dir.join(name);
    let mut options = vec!["--log", "debug", "--output", "quilt", "--quilt", "5x1", "--mode", mode];
    options.extend(RIG);
    options.extend_from_slice(extra);
    options.extend(dump_and_exit_at(&dump, "3"));
    let out = under_layer(
        &options,
        app("cubes"),
        &["--backend", "glx", "--size", SIZE, "--frames", "3"],
        &[],
    );
    assert_success(&out, &format!("cubes --mode {mode} {extra:?}"));
    let err = stderr(&out);
    assert!(!err.contains("holoinject: warn"), "{err}");
    (dump.join("f000003_qs5x1a0.75.png"), err)
}

/// PSNR of view `v`'s outer `BORDER` columns (the worse side), and of the whole view, of
/// `fast` against `exact` (quilts of 5x1 tiles).
fn border_and_view(exact: &Image, fast: &Image, v: u32) -> (f64, f64) {
    let (e, f) = (tile(exact, 5, 1, v), tile(fast, 5, 1, v));
    let (w, h) = (e.width, e.height);
    let left = psnr_in(&e, &f, (0, 0, BORDER, h));
    let right = psnr_in(&e, &f, (w - BORDER, 0, w, h));
    (left.min(right), tile_psnr(&e, &f, 1, 1)[0])
}

/// Cubes cut by the tile's sides: with the band the outer views show the rest of them where,
/// without it, the warp stretches the border pixels. The rendered view stays exact; the outer
/// views' border columns come much closer to exact (measured: view 0 from 21.6 to 29.7 dB, view 4 from 29.6 to 33.1 dB) and no view
/// gets worse; the log says how wide the band was (the rig's 14.4 px at infinity in the outer
/// views, plus one, the room a quarter of the tile: 16).
#[test]
fn the_band_shows_what_lies_beyond_the_rendered_views_edge() {
    require_display();
    let dir = temp_dir("guard_band_cubes");
    let (exact, _) = quilt(&dir, "exact", "exact", &[]);
    let (off, _) = quilt(&dir, "off", "synth", &["--guard-band", "off"]);
    let (band, log) = quilt(&dir, "auto", "synth", &["--guard-band", "auto", "--rows-on", "cpu"]);
    assert!(log.contains("guard band: 16 columns each side"), "{log}");
    // The compute pass reads the band as the CPU's scan does (66-78 dB between them without
    // one: colours mixed in 1/256 steps instead of floats).
    let (gpu, _) = quilt(&dir, "gpu", "synth", &["--guard-band", "auto", "--rows-on", "gpu"]);
    let same = tile_psnr(&read_png(&band), &read_png(&gpu), 5, 1);
    assert!(
        same.iter().all(|&p| p >= 60.0),
        "CPU and GPU scans with the band: {same:.2?}"
    );
    let (e, o, b) = (read_png(&exact), read_png(&off), read_png(&band));
    let with = tile_psnr(&e, &b, 5, 1);
    assert!(with[2].is_infinite(), "the rendered view must stay exact: {with:.2?}");
    for v in [0, 1, 3, 4] {
        let (border_off, view_off) = border_and_view(&e, &o, v);
        let (border_on, view_on) = border_and_view(&e, &b, v);
        eprintln!("view {v}: border {border_off:.2} -> {border_on:.2} dB, whole view {view_off:.2} -> {view_on:.2} dB");
        assert!(view_on >= view_off - 0.05, "view {v}: {view_off:.2} -> {view_on:.2} dB");
        if v == 0 || v == 4 {
            assert!(
                border_on >= border_off + 3.0,
                "view {v}'s border columns: {border_off:.2} -> {border_on:.2} dB against exact"
            );
        }
    }
}

/// `app` at 5x1 of 320x240 under `synth` with `--guard-band band` for `frames` frames on
/// `backend`: the layer's log (debug).
fn run_for(app_name: &str, band: &str, backend: &str, frames: &str) -> String {
    let options = [
        "--log",
        "debug",
        "--mode",
        "synth",
        "--quilt",
        "5x1",
        "--guard-band",
        band,
    ];
    let mut options = options.to_vec();
    options.extend(["--exit-after", frames]);
    let args = ["--backend", backend, "--size", "320x240", "--frames", frames];
    let out = under_layer(&options, app(app_name), &args, &[]);
    assert_success(&out, &format!("{app_name} --guard-band {band}"));
    stderr(&out)
}

/// A band the scene's draws make dear (asteroids: 5,000 draws a frame, each drawn twice more
/// for the strips) is dropped by `auto`, said at info; asked for by width it stays.
#[test]
fn auto_drops_a_band_that_costs_more_than_it_is_worth() {
    require_display();
    let auto = run_for("asteroids", "auto", "glx", "40");
    assert!(auto.contains("guard band: its strips take"), "{auto}");
    assert!(auto.contains("more than 10 %"), "{auto}");
    assert!(auto.contains("guard band: 0 columns"), "{auto}");
    let fixed = run_for("asteroids", "12", "glx", "40");
    assert!(fixed.contains("guard band: 12 columns each side"), "{fixed}");
    assert!(!fixed.contains("tried again"), "{fixed}");
}

/// A scene on a plain background that never reaches the tile's sides (cubes in a landscape
/// window): the band holds the border's own colour, so `auto` drops it, said at info.
#[test]
fn auto_drops_a_band_that_shows_nothing_new() {
    let err = run_for("cubes", "auto", "osmesa", "20");
    assert!(
        err.contains("columns each side of the rendered views from frame"),
        "{err}"
    );
    assert!(
        err.contains("the band shows nothing the border's own pixels stretched would not"),
        "{err}"
    );
    assert!(err.contains("guard band: 0 columns"), "{err}");
}
