//! An HDR game's off-screen passes at the tile's size (`--fbo-scale tile`, the default):
//! OpenArena's `opengl2` renderer draws the scene into a window-sized framebuffer, then
//! measures its brightness through framebuffers of their own sizes (256x256 luminance
//! targets, 1x1 averages) to expose the picture. Scaling those with the window's would change
//! what the game computes: the picture went dark (centre tile mean 17 against 31). Only
//! framebuffers whose size follows the window's may be scaled; the others keep theirs.
//!
//! The truth for a view shown at tile size is the program run at that size; a recording
//! replays at its own size, so the centre view is compared with the plain frame halved (2x2
//! box): what `--fbo-scale window` gives is the bar, as both draw the same picture at
//! different resolutions.

use super::weapon::{OPENARENA, SCREEN, game};
use super::{plain_snapshot, record};
use crate::util::*;
use std::path::Path;

/// A frame with the map on screen (faded in by frame 50).
const FRAME: u32 = 56;
/// The tile: half the window each way, so `tile` scales window-sized layers by 0.5.
const TILE: (u32, u32) = (SCREEN.0 / 2, SCREEN.1 / 2);
/// How much darker or brighter `tile`'s centre view may be than `window`'s (mean of RGB,
/// relative). Measured: 32.2 against 31.7 (1.6 %); scaled luminance targets gave 17 against
/// 31 (-45 %).
const BRIGHTNESS: f64 = 0.08;
/// PSNR (dB) `tile` may lose against `window`, both against the plain frame halved.
/// Measured: 30.8 against 32.0.
const PSNR_LOSS_DB: f64 = 2.5;

fn centre_view(dir: &Path, trace: &Path, scale: &str) -> (Image, String) {
    let dump = dir.join(scale);
    let n = FRAME.to_string();
    let tile = format!("{}x{}", TILE.0, TILE.1);
    let mut options = vec![
        "--quilt", "3x3", "--tile", &tile, "--output", "quilt", "--preset", "none",
    ];
    options.extend(["--convergence", "12", "--log", "info", "--fbo-scale", scale]);
    options.extend(dump_and_exit_at(&dump, &n));
    let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &[]);
    assert_success(&out, &format!("openarena replayed under --fbo-scale {scale}"));
    let aspect = holoinject::multiview::quilt::layout::QuiltLayout::new((3, 3), Some(TILE), SCREEN).file_tag();
    let quilt = read_png(&dump.join(format!("f{FRAME:06}_{aspect}.png")));
    (tile_of(&quilt, 4), stderr(&out))
}

fn tile_of(q: &Image, i: u32) -> Image {
    tile(q, 3, 3, i)
}

/// `img` at half its size, each pixel the mean of a 2x2 block.
fn halved(img: &Image) -> Image {
    let (w, h) = (img.width / 2, img.height / 2);
    let mut rgb = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let at = |dx: u32, dy: u32| u32::from(img.pixel(2 * x + dx, 2 * y + dy).unwrap()[c]);
                rgb.push(((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2) / 4) as u8);
            }
        }
    }
    Image {
        width: w,
        height: h,
        rgb,
    }
}

fn mean(img: &Image) -> f64 {
    img.rgb.iter().map(|&v| f64::from(v)).sum::<f64>() / img.rgb.len() as f64
}

#[test]
fn openarena_keeps_its_exposure_with_tile_sized_passes() {
    require_display();
    assert!(
        Path::new(OPENARENA).exists(),
        "{OPENARENA} missing: scripts/setup-debian.sh installs openarena"
    );
    let dir = temp_dir("openarena_hdr");
    let home = dir.join("home");
    std::fs::create_dir_all(&home).unwrap();
    let argv = game(&home);
    let argv: Vec<&str> = argv.iter().map(String::as_str).collect();
    let trace = record(&dir, "openarena", "gl", &argv, "60", FRAME);
    let (plain, _) = plain_snapshot(&dir, "glretrace", &trace, FRAME);
    let truth = halved(&read_png(&plain));
    let [(tile, tile_log), (window, _)] = std::thread::scope(|s| {
        let (dir, trace) = (&dir, &trace);
        ["tile", "window"]
            .map(|scale| s.spawn(move || centre_view(dir, trace, scale)))
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
    });
    let (t, w) = (mean(&tile), mean(&window));
    let (pt, pw) = (tile_psnr(&truth, &tile, 1, 1)[0], tile_psnr(&truth, &window, 1, 1)[0]);
    eprintln!(
        "openarena centre view: mean {t:.1} (tile) / {w:.1} (window); against the plain frame halved {pt:.2} / {pw:.2} dB"
    );
    assert!(
        (t - w).abs() <= BRIGHTNESS * w,
        "tile-sized passes changed the exposure: centre mean {t:.1} against {w:.1} with window-sized ones"
    );
    assert!(pt >= pw - PSNR_LOSS_DB, "tile {pt:.2} dB against window {pw:.2} dB");
    assert!(
        tile_log.contains("scaled by 0.500x0.500"),
        "the window-sized scene framebuffer was not scaled:\n{tile_log}"
    );
    assert!(
        tile_log.contains("does not follow the 640x480 window"),
        "no framebuffer of its own size kept it:\n{tile_log}"
    );
}
