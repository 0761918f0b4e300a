//! Comparing images. Every comparison here that fails leaves three images beside the compared
//! file before it panics, and names them in its message: `<name>-expected.png`,
//! `<name>-actual.png` and `<name>-diff.png` (`<name>` is the compared file without `.png`).
//! The diff is black where the pixels are equal, grey where they differ within the
//! comparison's per-channel level (rounding), white beyond it; images of two sizes are
//! compared over the larger, white where only one of them has a pixel. `.gitignore` keeps
//! these names out of commits.

use super::image::{Image, horizontal_shift, read_png, save, tile, tile_psnr};
use std::path::{Path, PathBuf};

/// How far an image may be from the expected one: at most `pixels` pixels with a channel
/// more than `level` apart.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub level: u8,
    pub pixels: usize,
}

pub const EXACT: Tolerance = Tolerance { level: 0, pixels: 0 };

/// A frame the layer handed back after an internal failure against the program's own frame:
/// the rewritten vertex shader stays linked with a zero shift and is compiled differently,
/// which moves some varyings by a rounding (`model`, `compat120`). Measured when centre
/// views were still drawn at a tile's offset (which rounds too): at most 11 edge pixels of
/// 76,800, plus a few hundred pixels one level off. More than 16 pixels off by more than one
/// level means a real difference. (Centre views of a working quilt are compared exactly: it
/// is drawn where and as the window is.)
pub const CENTRE_VIEW: Tolerance = Tolerance { level: 1, pixels: 16 };

/// Exact equality of two PNG files.
pub fn assert_identical(expected: &Path, actual: &Path) {
    assert_files_within(expected, actual, EXACT, "");
}

/// `actual` (a PNG file) against `expected` (a PNG file) within `tol`.
pub fn assert_files_within(expected: &Path, actual: &Path, tol: Tolerance, what: &str) {
    let what = format!(
        "{what}{}{} vs {}",
        if what.is_empty() { "" } else { ": " },
        expected.display(),
        actual.display()
    );
    assert_within(&read_png(expected), &read_png(actual), actual, tol, &what);
}

/// `actual` against `expected` within `tol`; on failure the images go beside `at`. Returns
/// how many pixels differ at all.
pub fn assert_within(expected: &Image, actual: &Image, at: &Path, tol: Tolerance, what: &str) -> usize {
    if (expected.width, expected.height) != (actual.width, actual.height) {
        let msg = format!(
            "{what}: size differs: {}x{} expected, {}x{}",
            expected.width, expected.height, actual.width, actual.height
        );
        fail_with_images(&msg, at, expected, actual, tol.level);
    }
    let (off, any) = (pixels_off(expected, actual, tol.level), pixels_off(expected, actual, 0));
    if off > tol.pixels {
        let msg = format!(
            "{what}: {off} pixels differ by more than {} level(s), at most {} may ({any} differ at all)",
            tol.level, tol.pixels
        );
        fail_with_images(&msg, at, expected, actual, tol.level);
    }
    any
}

/// Per-tile PSNR of a quilt file against its reference quilt file; fails if a tile is below
/// `min_db`. Prints and returns the tiles' PSNR.
pub fn assert_tiles_psnr(
    reference: &Path,
    quilt: &Path,
    (cols, rows): (u32, u32),
    min_db: f64,
    what: &str,
) -> Vec<f64> {
    let (expected, actual) = (read_png(reference), read_png(quilt));
    if (expected.width, expected.height) != (actual.width, actual.height) {
        fail_with_images(&format!("{what}: quilt sizes differ"), quilt, &expected, &actual, 1);
    }
    let psnr = tile_psnr(&expected, &actual, cols, rows);
    let worst = psnr.iter().copied().fold(f64::INFINITY, f64::min);
    let finite: Vec<f64> = psnr.iter().copied().filter(|p| p.is_finite()).collect();
    let mean = if finite.is_empty() {
        f64::INFINITY
    } else {
        finite.iter().sum::<f64>() / finite.len() as f64
    };
    let identical = psnr.len() - finite.len();
    eprintln!(
        "{what}: {identical}/{} tiles identical; others mean {mean:.2} dB, worst tile {worst:.2} dB",
        psnr.len()
    );
    if worst < min_db {
        let msg = format!("{what}: worst tile {worst:.2} dB < {min_db} dB: {psnr:?}");
        fail_with_images(&msg, quilt, &expected, &actual, 1);
    }
    psnr
}

/// Largest per-channel difference and the fraction of channels that differ at all.
pub fn difference(a: &[u8], b: &[u8]) -> (u8, f64) {
    assert_eq!(a.len(), b.len());
    let max = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
    let differing = a.iter().zip(b).filter(|(x, y)| x != y).count();
    (max, differing as f64 / a.len() as f64)
}

/// `actual` (the file `at`) against an `expected` image computed independently: no channel
/// more than `max` apart, and fewer than `fraction` of the channels differing at all.
pub fn assert_channels_close(expected: &Image, actual: &Image, at: &Path, max: u8, fraction: f64, what: &str) {
    if (expected.width, expected.height) != (actual.width, actual.height) {
        fail_with_images(&format!("{what}: sizes differ"), at, expected, actual, max);
    }
    let (worst, frac) = difference(&expected.rgb, &actual.rgb);
    eprintln!(
        "{what}: max channel difference {worst}, {:.4}% of channels differ",
        frac * 100.0
    );
    if worst > max || frac >= fraction {
        let msg = format!(
            "{what}: max channel difference {worst} (at most {max}), {:.4}% of channels differ (less than {}%)",
            frac * 100.0,
            fraction * 100.0
        );
        fail_with_images(&msg, at, expected, actual, max);
    }
}

/// Two images that must not be equal (`a` stands as expected, `b` as actual in the failure
/// images).
pub fn assert_images_differ(a: &Image, b: &Image, at: &Path, what: &str) {
    if a.rgb == b.rgb && (a.width, a.height) == (b.width, b.height) {
        fail_with_images(&format!("{what}: the images are identical"), at, a, b, 0);
    }
}

/// Horizontal shifts (px, searched in ±`max`) of the tiles `views` of a quilt (the file `at`)
/// from its tile `centre`: each must be larger than the one before, the first non-zero.
/// Prints and returns them; on failure each view's images go beside `at` as `…-view{i}`.
pub fn assert_parallax_grows(
    quilt: &Image,
    at: &Path,
    grid: (u32, u32),
    centre: u32,
    views: &[u32],
    max: i32,
    what: &str,
) -> Vec<i32> {
    let tile_of = |i| tile(quilt, grid.0, grid.1, i);
    let centre = tile_of(centre);
    let shifts: Vec<i32> = views
        .iter()
        .map(|&i| horizontal_shift(&centre, &tile_of(i), max).abs())
        .collect();
    eprintln!("{what}: views {views:?} shifted by {shifts:?} px from the centre");
    if !(shifts.windows(2).all(|w| w[1] > w[0]) && shifts[0] > 0) {
        let written: Vec<String> = views
            .iter()
            .map(|&i| {
                let view = tile_of(i);
                let diff = diff_image(&centre, &view, 0);
                write_failure_images(&suffixed(at, &format!("-view{i}")), &centre, &view, &diff)
            })
            .collect();
        panic!("{what}: parallax does not grow: {shifts:?}\n{}", written.join("\n"));
    }
    shifts
}

/// Writes the failure images of a comparison beside `at` and panics with `msg` naming them.
pub fn fail_with_images(msg: &str, at: &Path, expected: &Image, actual: &Image, level: u8) -> ! {
    let diff = diff_image(expected, actual, level);
    panic!("{msg}\n{}", write_failure_images(at, expected, actual, &diff))
}

/// Writes `<at>-expected.png`, `<at>-actual.png` and `<at>-diff.png` (see the module doc) and
/// returns a line naming them.
pub fn write_failure_images(at: &Path, expected: &Image, actual: &Image, diff: &Image) -> String {
    let names = ["expected", "actual", "diff"].map(|s| suffixed(at, &format!("-{s}")));
    save(expected, &names[0]);
    save(actual, &names[1]);
    save(diff, &names[2]);
    let [e, a, d] = names.map(|p| p.display().to_string());
    format!("images: {e} {a} {d}")
}

/// The difference image of `expected` and `actual` (see the module doc).
pub fn diff_image(expected: &Image, actual: &Image, level: u8) -> Image {
    let (width, height) = (expected.width.max(actual.width), expected.height.max(actual.height));
    let rgb = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            let v = match (expected.pixel(x, y), actual.pixel(x, y)) {
                (Some(p), Some(q)) => match channel_distance(p, q) {
                    0 => 0,
                    d if d <= level => 96,
                    _ => 255,
                },
                _ => 255,
            };
            [v; 3]
        })
        .collect();
    Image { width, height, rgb }
}

/// `at` (a `.png` or `.f32` file, or a name without extension) with `suffix` added to its
/// stem, as a `.png` file.
pub fn suffixed(at: &Path, suffix: &str) -> PathBuf {
    let stem = match at.extension().and_then(|e| e.to_str()) {
        Some("png" | "f32") => at.with_extension(""),
        _ => at.to_path_buf(),
    };
    let mut name = stem.into_os_string();
    name.push(format!("{suffix}.png"));
    PathBuf::from(name)
}

fn channel_distance(p: &[u8], q: &[u8]) -> u8 {
    p.iter().zip(q).map(|(a, b)| a.abs_diff(*b)).max().unwrap_or(0)
}

/// Pixels with any channel more than `level` apart (images of one size).
pub fn pixels_off(e: &Image, a: &Image, level: u8) -> usize {
    e.rgb
        .chunks(3)
        .zip(a.rgb.chunks(3))
        .filter(|(x, y)| channel_distance(x, y) > level)
        .count()
}

/// The helpers' own failure path: a failing comparison leaves its three images and names them.
mod tests {
    use super::*;

    fn flat(width: u32, height: u32, v: u8) -> Image {
        let rgb = vec![v; (width * height * 3) as usize];
        Image { width, height, rgb }
    }

    fn panic_message(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
        let payload = std::panic::catch_unwind(f).expect_err("the comparison passed");
        match payload.downcast::<String>() {
            Ok(s) => *s,
            Err(p) => p.downcast_ref::<&str>().unwrap().to_string(),
        }
    }

    #[test]
    fn failing_comparison_leaves_expected_actual_and_diff() {
        let dir = crate::util::temp_dir("util_failure_images");
        let at = dir.join("f000003_qs3x3a1.3333.png");
        let (expected, mut actual) = (flat(4, 2, 10), flat(4, 2, 10));
        actual.rgb[0] = 11; // within level 1: grey in the diff
        actual.rgb[5] = 200; // beyond: white
        let tol = Tolerance { level: 1, pixels: 0 };
        let msg = panic_message(|| {
            assert_within(&expected, &actual, &at, tol, "test");
        });
        let diff = read_png(&dir.join("f000003_qs3x3a1.3333-diff.png"));
        for name in ["expected", "actual", "diff"] {
            let p = dir.join(format!("f000003_qs3x3a1.3333-{name}.png"));
            assert!(p.exists() && msg.contains(&p.display().to_string()), "{msg}");
        }
        assert!(msg.contains("1 pixels differ by more than 1 level(s)"), "{msg}");
        assert_eq!(&diff.rgb[..9], &[96, 96, 96, 255, 255, 255, 0, 0, 0]);
        assert_eq!(read_png(&dir.join("f000003_qs3x3a1.3333-actual.png")).rgb, actual.rgb);
    }

    #[test]
    fn failing_psnr_leaves_the_quilts_and_their_diff() {
        let dir = crate::util::temp_dir("util_failure_psnr");
        let (reference, quilt) = (dir.join("reference.png"), dir.join("quilt.png"));
        let mut actual = flat(4, 2, 100);
        actual.rgb[0] = 0; // tile 1 (the top row) at 18.92 dB, tile 0 identical
        save(&flat(4, 2, 100), &reference);
        save(&actual, &quilt);
        let msg = panic_message(|| {
            assert_tiles_psnr(&reference, &quilt, (1, 2), 40.0, "test");
        });
        assert!(msg.contains("worst tile 18.92 dB") && msg.contains("< 40 dB"), "{msg}");
        for name in ["expected", "actual", "diff"] {
            let p = dir.join(format!("quilt-{name}.png"));
            assert!(p.exists() && msg.contains(&p.display().to_string()), "{msg}");
        }
    }

    #[test]
    fn images_of_two_sizes_fail_with_a_diff_over_the_larger() {
        let dir = crate::util::temp_dir("util_failure_sizes");
        let (expected, actual) = (flat(2, 2, 0), flat(3, 1, 0));
        let msg = panic_message(|| {
            assert_within(&expected, &actual, &dir.join("out.png"), EXACT, "test");
        });
        assert!(msg.contains("size differs"), "{msg}");
        let diff = read_png(&dir.join("out-diff.png"));
        assert_eq!((diff.width, diff.height), (3, 2));
        let white: Vec<usize> = (0..6).filter(|i| diff.rgb[i * 3] == 255).collect();
        assert_eq!(white, [2, 3, 4, 5]);
    }
}
