//! `synth:pixel` and `hybrid:K:pixel`, the per-pixel baseline (DESIGN §5), on the sample
//! apps against `--mode exact` of the same frame, as `synthesis` checks the grid warp.

use crate::synthesis::{RIG, assert_hud_in_place, assert_hybrid2_near_exact, quilt_in};
use crate::util::*;

/// Pixels of tile `i` that are pure black: what a hole the filling missed looks like (the
/// canvas is cleared to 0 and `cubes` draws nothing black).
fn black_pixels(q: &Image, cols: u32, i: u32) -> usize {
    tile(q, cols, 1, i).rgb.chunks(3).filter(|p| *p == [0, 0, 0]).count()
}

/// One rendered view, four splatted: the centre is exact, the others match exact's views to
/// a bound a little below what this scene measures (27.7-30.9 dB, the outer views lowest,
/// the same on every run; the grid warp scores 27.4-29.1, a view merely copied from the
/// centre 15-17), they show depth as exact does, and pull-push left no hole.
#[test]
fn pixel_views_match_exact_fill_holes_and_show_depth() {
    require_display();
    let dir = temp_dir("synth_pixel_cubes");
    let (exact, _) = quilt_in(&dir, "cubes", "5x1", "exact", &[]);
    let (pixel, log) = quilt_in(&dir, "cubes", "5x1", "synth:pixel", &[]);
    assert!(
        log.contains("synthesis: 1 of 5 views rendered, the others splatted per pixel"),
        "{log}"
    );
    let (e, s) = (read_png(&exact), read_png(&pixel));
    let psnr = tile_psnr(&e, &s, 5, 1);
    eprintln!("synth:pixel against exact, per view: {psnr:.2?}");
    assert!(
        psnr[2].is_infinite(),
        "the rendered centre view must be exact: {psnr:?}"
    );
    for (i, p) in psnr.iter().enumerate().filter(|&(i, _)| i != 2) {
        assert!(*p >= 27.0, "view {i}: {p:.2} dB against exact ({psnr:.2?})");
        let copied = tile_psnr(&tile(&e, 5, 1, i as u32), &tile(&s, 5, 1, 2), 1, 1)[0];
        assert!(
            *p > copied + 6.0,
            "view {i}: {p:.2} dB, barely better than the centre copied ({copied:.2})"
        );
    }
    for i in 0..5 {
        assert_eq!(
            black_pixels(&e, 5, i),
            0,
            "exact view {i} has black pixels: the hole check means nothing"
        );
        assert_eq!(black_pixels(&s, 5, i), 0, "view {i}: holes left unfilled");
    }
    assert_depth_parallax(&s, &pixel, 5, 40, "cubes under synth:pixel");
}

/// K = 2 per pixel: the two outer views rendered, the middle three splatted from both
/// (nearer wins). Measured 30.5-31.3 dB on every run (the grid's `hybrid:2`: 26.7-27.2).
#[test]
fn hybrid_pixel_splats_from_both_rendered_views() {
    assert_hybrid2_near_exact("synth_pixel_hybrid2", "hybrid:2:pixel", 29.5);
}

/// The HUD `legacy` draws after its scene is drawn in every view, never splatted.
#[test]
fn hud_stays_in_place_under_per_pixel_synthesis() {
    assert_hud_in_place("synth_pixel_hud", "synth:pixel");
}

/// KHR_debug counts no GL error under `synth:pixel`, in a core context (`cubes`) and in a
/// compatibility one (`legacy`, where the splat's point state includes `GL_POINT_SMOOTH`,
/// which a core context would reject).
#[test]
fn per_pixel_synthesis_raises_no_gl_error() {
    require_display();
    for name in ["cubes", "legacy"] {
        let mut options = vec!["--output", "quilt", "--quilt", "5x1", "--mode", "synth:pixel"];
        options.extend(RIG);
        let args = [
            "--backend",
            "glx",
            "--size",
            "160x120",
            "--frames",
            "3",
            "--debug-output",
        ];
        let out = under_layer(&options, app(name), &args, &[]);
        assert_success(&out, name);
        assert!(
            stderr(&out).contains("gl-debug: errors=0"),
            "{name}: GL errors under synth:pixel:\n{}",
            stderr(&out)
        );
    }
}
