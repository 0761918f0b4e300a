//! Depth-dependent parallax, measured by block matching: each textured block of a quilt's
//! centre tile is looked for, along the same rows, in another view's tile. A scene with depth
//! gives blocks that move by different amounts (near and far content on either side of the
//! convergence plane); a flat picture sliding sideways gives one shift for every block, so
//! the spread of the per-block shifts is what tells parallax from a slide.

use super::compare::{diff_image, suffixed, write_failure_images};
use super::image::{Image, tile};
use std::path::Path;

/// Block edge (px): large enough to hold texture, small enough to sit on one depth.
const BLOCK: u32 = 16;
/// A block needs this much horizontal structure (mean |∂x| per pixel and channel, in 8-bit
/// levels) to be matched at all: flat sky or cleared background has no shift to find.
const MIN_TEXTURE: f64 = 2.0;
/// The best match must be this much better than the block's mean error over the search
/// (repetitive texture or occlusion gives flat, unreliable minima).
const DISTINCT: f64 = 0.5;

/// The per-block shifts of one view against the centre, in block order (`None`: the block
/// has no texture or no reliable match).
pub struct BlockShifts {
    pub shifts: Vec<Option<f64>>,
}

impl BlockShifts {
    fn found(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.shifts.iter().flatten().copied().collect();
        v.sort_by(f64::total_cmp);
        v
    }

    pub fn count(&self) -> usize {
        self.shifts.iter().flatten().count()
    }

    pub fn median(&self) -> f64 {
        quantile(&self.found(), 0.5)
    }

    /// From the 10th to the 90th percentile: robust to the odd mismatched block.
    pub fn spread(&self) -> f64 {
        let v = self.found();
        quantile(&v, 0.9) - quantile(&v, 0.1)
    }
}

/// `q`-quantile of sorted values (NaN when empty).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn level(img: &Image, x: u32, y: u32, c: usize) -> f64 {
    img.rgb[((y * img.width + x) * 3) as usize + c] as f64
}

fn texture(img: &Image, x0: u32, y0: u32) -> f64 {
    let mut sum = 0.0;
    for y in y0..y0 + BLOCK {
        for x in x0..x0 + BLOCK - 1 {
            sum += (0..3)
                .map(|c| (level(img, x + 1, y, c) - level(img, x, y, c)).abs())
                .sum::<f64>();
        }
    }
    sum / f64::from(BLOCK * (BLOCK - 1) * 3)
}

/// Sum of squared differences between the block at (x0, y0) of `a` and the one `dx` to the
/// right in `b`.
fn ssd(a: &Image, b: &Image, x0: u32, y0: u32, dx: i32) -> f64 {
    let mut e = 0.0;
    for y in y0..y0 + BLOCK {
        for x in x0..x0 + BLOCK {
            let xb = (x as i32 + dx) as u32;
            e += (0..3)
                .map(|c| (level(a, x, y, c) - level(b, xb, y, c)).powi(2))
                .sum::<f64>();
        }
    }
    e
}

/// Shift (px, sub-pixel by a parabola through the best three) of one block, searched in ±max.
fn block_shift(a: &Image, b: &Image, x0: u32, y0: u32, max: i32) -> Option<f64> {
    let errors: Vec<f64> = (-max..=max).map(|dx| ssd(a, b, x0, y0, dx)).collect();
    let (best, &e0) = errors.iter().enumerate().min_by(|p, q| p.1.total_cmp(q.1))?;
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    if best == 0 || best == errors.len() - 1 || e0 > DISTINCT * mean {
        return None;
    }
    let (l, r) = (errors[best - 1], errors[best + 1]);
    let curvature = l - 2.0 * e0 + r;
    let sub = if curvature > 0.0 {
        0.5 * (l - r) / curvature
    } else {
        0.0
    };
    Some(best as f64 - max as f64 + sub)
}

/// Per-block horizontal shifts of `view` against `centre` (tiles of equal size), searched in
/// ±`max` px: positive when the view's content lies to the right.
pub fn block_shifts(centre: &Image, view: &Image, max: i32) -> BlockShifts {
    let shifts = block_origins(centre, max)
        .into_iter()
        .map(|(x0, y0)| {
            let textured = texture(centre, x0, y0) >= MIN_TEXTURE;
            textured.then(|| block_shift(centre, view, x0, y0, max)).flatten()
        })
        .collect();
    BlockShifts { shifts }
}

/// The top-left corners of the blocks `block_shifts` measures in a tile, in its order (rows
/// from the top; the search range `max` left out at both sides), and the block edge.
pub fn block_origins(tile: &Image, max: i32) -> Vec<(u32, u32)> {
    let m = max as u32;
    let mut origins = Vec::new();
    let mut y0 = 0;
    while y0 + BLOCK <= tile.height {
        let mut x0 = m;
        while x0 + BLOCK + m <= tile.width {
            origins.push((x0, y0));
            x0 += BLOCK;
        }
        y0 += BLOCK;
    }
    origins
}

/// The edge (px) of the blocks of `block_shifts`.
pub const SHIFT_BLOCK: u32 = BLOCK;

/// Median over the blocks found in both of |left + right|: zero when view i and view N-1-i
/// move every block by opposite amounts.
pub fn mirror_error(left: &BlockShifts, right: &BlockShifts) -> f64 {
    let mut sums: Vec<f64> = left
        .shifts
        .iter()
        .zip(&right.shifts)
        .filter_map(|(l, r)| Some((l.as_ref()? + r.as_ref()?).abs()))
        .collect();
    sums.sort_by(f64::total_cmp);
    quantile(&sums, 0.5)
}

/// The shifts of every view of a `cols`x1 (or any) quilt against view `centre`.
pub fn quilt_shifts(quilt: &Image, grid: (u32, u32), centre: u32, max: i32) -> Vec<BlockShifts> {
    let c = tile(quilt, grid.0, grid.1, centre);
    (0..grid.0 * grid.1)
        .map(|i| block_shifts(&c, &tile(quilt, grid.0, grid.1, i), max))
        .collect()
}

/// Left and right views move blocks by opposite amounts to within this (px): the measure's
/// own sub-pixel noise is ~0.2 px; occlusion edges differ between the two sides but move the
/// median little.
const MIRROR_PX: f64 = 1.0;

/// What `assert_depth_parallax` measured, per view: (median, spread, blocks found).
pub type ParallaxReport = Vec<(f64, f64, usize)>;

/// Depth-dependent parallax in a `cols`x1 quilt (the file `at`) with its centre at view
/// `cols / 2`: the outermost views' per-block shifts spread over more than a pixel, the
/// spread grows with the distance from the centre on both sides, and view i mirrors view
/// N-1-i. Prints every view's median and spread; on failure the outer views' images go
/// beside `at` as `…-view{i}`.
pub fn assert_depth_parallax(quilt: &Image, at: &Path, cols: u32, max: i32, what: &str) -> ParallaxReport {
    let (report, _, failures) = depth_parallax(quilt, cols, max, what);
    if !failures.is_empty() {
        let images = write_outer_views(quilt, at, cols);
        panic!("{what}: {}\n{report:.2?}\n{images}", failures.join("; "));
    }
    report
}

/// What `assert_depth_parallax` measures, without failing: the per-view report (printed), the
/// mirror errors per pair from the outside in, and what is wrong (empty when nothing is).
pub fn depth_parallax(quilt: &Image, cols: u32, max: i32, what: &str) -> (ParallaxReport, Vec<f64>, Vec<String>) {
    let centre = cols / 2;
    let views = quilt_shifts(quilt, (cols, 1), centre, max);
    let report: ParallaxReport = views.iter().map(|v| (v.median(), v.spread(), v.count())).collect();
    for (i, (m, s, n)) in report.iter().enumerate() {
        eprintln!("{what}: view {i}: shift median {m:.2} px, spread {s:.2} px over {n} blocks");
    }
    let mirror: Vec<f64> = (0..centre)
        .map(|i| mirror_error(&views[i as usize], &views[(cols - 1 - i) as usize]))
        .collect();
    eprintln!("{what}: mirror error (median |left + right|) per pair from the outside in: {mirror:.2?} px");
    let failures = parallax_failures(&report, &mirror);
    (report, mirror, failures)
}

/// What is wrong with the measured parallax (`mirror`: per pair from the outside in).
fn parallax_failures(report: &ParallaxReport, mirror: &[f64]) -> Vec<String> {
    let (cols, centre) = (report.len(), report.len() / 2);
    let spread = |i: usize| report[i].1;
    let mut failures = Vec::new();
    if !(spread(0) > 1.0 && spread(cols - 1) > 1.0) {
        failures.push("the outer views move as a whole (spread of block shifts ≤ 1 px): no depth".to_string());
    }
    let grows = (1..=centre)
        .all(|d| spread(centre + d) > spread(centre + d - 1) && spread(centre - d) > spread(centre - d + 1));
    if !grows {
        failures.push("the spread does not grow with the distance from the centre".to_string());
    }
    if let Some(e) = mirror.iter().find(|e| e.is_nan() || **e > MIRROR_PX) {
        failures.push(format!(
            "left and right views do not mirror (median |left + right| {e:.2} px)"
        ));
    }
    failures
}

/// The outermost views against the centre, as failure images beside `at`.
fn write_outer_views(quilt: &Image, at: &Path, cols: u32) -> String {
    let centre = tile(quilt, cols, 1, cols / 2);
    let written: Vec<String> = [0, cols - 1]
        .iter()
        .map(|&i| {
            let view = tile(quilt, cols, 1, i);
            let diff = diff_image(&centre, &view, 0);
            write_failure_images(&suffixed(at, &format!("-view{i}")), &centre, &view, &diff)
        })
        .collect();
    written.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A textured image, and it moved `dx` px to the right.
    fn textured(w: u32, h: u32, shift: impl Fn(u32) -> i32) -> Image {
        let pattern = |x: i32, y: u32| {
            let (x, y) = (x as f64, y as f64);
            (128.0 + 60.0 * (0.7 * x + 0.3 * y).sin() + 50.0 * (0.19 * x - 0.41 * y).sin()) as u8
        };
        let mut rgb = Vec::new();
        for y in 0..h {
            for x in 0..w {
                rgb.extend([pattern(x as i32 - shift(y), y); 3]);
            }
        }
        Image {
            width: w,
            height: h,
            rgb,
        }
    }

    #[test]
    fn a_slide_has_no_spread_and_depth_has() {
        let centre = textured(200, 64, |_| 0);
        let slide = block_shifts(&centre, &textured(200, 64, |_| 6), 20);
        assert!(slide.count() > 10);
        assert!(
            (slide.median() - 6.0).abs() < 0.05 && slide.spread() < 0.05,
            "{} {}",
            slide.median(),
            slide.spread()
        );
        // The top half moves 6 px, the bottom half -3 px.
        let depth = block_shifts(&centre, &textured(200, 64, |y| if y < 32 { 6 } else { -3 }), 20);
        assert!((depth.spread() - 9.0).abs() < 0.1, "{}", depth.spread());
        let mirrored = block_shifts(&centre, &textured(200, 64, |y| if y < 32 { -6 } else { 3 }), 20);
        assert!(mirror_error(&depth, &mirrored) < 0.1);
        assert!(mirror_error(&depth, &slide) > 2.0);
    }
    /// glmark2 terrain before the fix: ±20 px with 0.1 px of spread.
    #[test]
    fn a_slide_fails_and_depth_passes() {
        let slide = vec![
            (-20.0, 0.1, 50),
            (-10.0, 0.07, 50),
            (0.0, 0.03, 50),
            (10.0, 0.07, 50),
            (20.0, 0.1, 50),
        ];
        let failures = parallax_failures(&slide, &[0.02, 0.02]);
        assert!(
            failures.len() == 1 && failures[0].contains("as a whole"),
            "{failures:?}"
        );
        let depth = vec![
            (-1.3, 22.0, 50),
            (-0.7, 11.0, 50),
            (0.0, 0.03, 50),
            (0.7, 11.0, 50),
            (1.4, 22.1, 50),
        ];
        assert!(parallax_failures(&depth, &[0.06, 0.05]).is_empty());
        assert_eq!(parallax_failures(&depth, &[2.5, 0.05]).len(), 1, "not mirrored");
        let flat_left = vec![
            (0.0, 0.5, 50),
            (0.0, 0.6, 50),
            (0.0, 0.03, 50),
            (0.7, 11.0, 50),
            (1.4, 22.1, 50),
        ];
        assert_eq!(
            parallax_failures(&flat_left, &[0.5, 0.5]).len(),
            2,
            "no depth on the left, no growth"
        );
    }
}
