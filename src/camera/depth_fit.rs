//! A depth model read off what a program draws, for programs whose projection the layer
//! cannot read (a matrix assembled in ways the shader analysis does not follow, a
//! projection split across shader objects as Wine's wined3d does).
//!
//! The exact shift does not need the projection, and neither does the disparity record: each
//! recorded pixel holds `p = 1 - c/w` for the convergence `c` it was drawn with, so its eye
//! distance is `w = c / (1 - p)`. The depth buffer at the same pixel holds `z_ndc = -a + b/w`
//! for the projection's depth terms `(a, b)` (`DepthRange`). A straight-line fit of `z_ndc`
//! against `1/w` over the recorded pixels gives `(a, b)`, the model that auto-convergence, the
//! warps and the comfort pass need. Pixels the fit does not explain (a HUD drawn at `w == 1`
//! records 0; a draw with a projection of its own) are dropped as outliers.

use super::projection::DepthRange;

/// Fewer recorded pixels than this at distinct depths say too little to fit.
const MIN_SAMPLES: usize = 256;
/// The share of candidate pixels the fit must explain.
const MIN_INLIERS: f64 = 0.8;
/// `1/w` must span this ratio: a scene at one distance fixes `z` but not how it changes.
const MIN_SPREAD: f64 = 1.05;
/// Residuals (NDC) below this are agreement: a 24-bit depth buffer's step is 1.2e-7, a
/// 16-bit one's 3e-5, float records add their own rounding.
const FLOOR_RESIDUAL: f64 = 4e-5;

/// A fitted depth model and how many pixels support it.
#[derive(Clone, Copy, Debug)]
pub struct Fitted {
    pub range: DepthRange,
    pub inliers: usize,
    pub candidates: usize,
}

/// Fits the depth model to `(p, d)`: the recorded parallax and the window depth (0..1, the
/// [-1,1] clip convention) of each recorded pixel, drawn with convergence `c`. `None` when
/// the pixels do not determine it (too few, one distance, no straight line through most).
pub fn fit(samples: impl Iterator<Item = (f32, f32)>, c: f64) -> Option<Fitted> {
    if !(c.is_finite() && c > 0.0) {
        return None;
    }
    // p == 0 exactly is what an orthographic or w == 1 draw records (a HUD); p -> 1 is
    // infinity; depth 0 and 1 are the clears.
    let points: Vec<(f64, f64)> = samples
        .filter(|&(p, d)| p.is_finite() && p != 0.0 && p < 1.0 - 1e-6 && d > 0.0 && d < 1.0)
        .map(|(p, d)| ((1.0 - f64::from(p)) / c, 2.0 * f64::from(d) - 1.0))
        .collect();
    if points.len() < MIN_SAMPLES {
        return None;
    }
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &(x, _)| (lo.min(x), hi.max(x)));
    if !(lo > 0.0 && hi / lo >= MIN_SPREAD) {
        return None;
    }
    // Most pixels are the scene; a weapon or a HUD at the far end of 1/w would pull a plain
    // least-squares line: the line most pixels agree with is found first (pairs of pixels
    // spread over the frame), then refined over those that agree with it.
    let mut line = consensus(&points)?;
    let mut keep = Vec::new();
    for _ in 0..2 {
        keep = points.iter().map(|&p| agrees(line, p)).collect();
        line = least_squares(&points, &keep)?;
    }
    let inliers = keep.iter().filter(|k| **k).count();
    if (inliers as f64) < MIN_INLIERS * points.len() as f64 {
        return None;
    }
    let range = plausible(DepthRange { a: -line.0, b: line.1 })?;
    Some(Fitted {
        range,
        inliers,
        candidates: points.len(),
    })
}

/// Pairs tried for the consensus line, and the most pixels each is checked against.
const PAIRS: usize = 256;
const CHECKED: usize = 16_384;

/// Whether `(x, y)` lies on `line` within the record's and the depth buffer's rounding: a
/// recorded `p` near 1 (far away) leaves few bits in `1 - p`, hence the relative term.
fn agrees((i, s): (f64, f64), (x, y): (f64, f64)) -> bool {
    (y - (i + s * x)).abs() <= FLOOR_RESIDUAL + 1e-3 * (s * x).abs()
}

/// The line through two of `points` that most of the others agree with.
fn consensus(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len();
    let stride = n.div_ceil(CHECKED).max(1);
    let x_max = points.iter().fold(0.0f64, |m, p| m.max(p.0));
    let mut best: Option<((f64, f64), usize)> = None;
    for k in 0..PAIRS {
        // Deterministic spread: the same frame gives the same fit.
        let (a, b) = (points[(k * 7919) % n], points[(k * 104_729 + n / 2) % n]);
        if (a.0 - b.0).abs() < 1e-3 * x_max {
            continue;
        }
        let s = (b.1 - a.1) / (b.0 - a.0);
        let line = (a.1 - s * a.0, s);
        let votes = points.iter().step_by(stride).filter(|&&p| agrees(line, p)).count();
        if best.is_none_or(|(_, v)| votes > v) {
            best = Some((line, votes));
        }
    }
    best.map(|(line, _)| line)
}

/// `y = i + s·x` over the kept points, centred for precision.
fn least_squares(points: &[(f64, f64)], keep: &[bool]) -> Option<(f64, f64)> {
    let kept = || points.iter().zip(keep).filter(|(_, k)| **k).map(|(p, _)| *p);
    let n = kept().count() as f64;
    if n < 2.0 {
        return None;
    }
    let (mx, my) = kept().fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x / n, sy + y / n));
    let (sxy, sxx) = kept().fold((0.0, 0.0), |(sxy, sxx), (x, y)| {
        (sxy + (x - mx) * (y - my), sxx + (x - mx) * (x - mx))
    });
    if sxx <= 0.0 {
        return None;
    }
    let s = sxy / sxx;
    Some((my - s * mx, s))
}

/// A perspective depth model with a positive near plane; a far plane the fit cannot tell from
/// infinity (beyond 1e7 near planes, or past it by rounding) is made infinite.
fn plausible(mut r: DepthRange) -> Option<DepthRange> {
    let near = r.near();
    if !(near.is_finite() && near > 0.0) {
        return None;
    }
    let far = r.far();
    if !(far.is_finite() && far > near && far < 1e7 * near) {
        if (r.a + 1.0).abs() > 1e-3 {
            return None;
        }
        r.a = -1.0;
    }
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a pixel at eye distance `w` records and holds in a 24-bit depth buffer.
    fn pixel(r: DepthRange, c: f64, w: f64) -> (f32, f32) {
        let d = ((-r.a + r.b / w) + 1.0) / 2.0;
        let d = (d * 16_777_215.0).round() / 16_777_215.0;
        ((1.0 - c / w) as f32, d as f32)
    }

    fn distances(n: usize, lo: f64, hi: f64) -> impl Iterator<Item = f64> {
        (0..n).map(move |i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
    }

    #[test]
    fn a_frustum_comes_back_from_its_pixels() {
        for (n, f, c) in [(0.5, 100.0, 8.0), (0.01, 5000.0, 3.0), (2.0, 40.0, 1.0)] {
            let r = DepthRange::frustum(n, f);
            let got = fit(distances(4000, n * 1.5, f * 0.8).map(|w| pixel(r, c, w)), c).expect("a fit");
            assert!((got.range.near() - n).abs() / n < 2e-3, "near {n}: {:?}", got.range);
            assert!((got.range.far() - f).abs() / f < 2e-2, "far {f}: {:?}", got.range);
            assert_eq!(got.inliers, got.candidates);
        }
    }

    #[test]
    fn a_hud_and_a_second_projection_are_outliers() {
        let (r, c) = (DepthRange::frustum(0.5, 100.0), 8.0);
        let scene = distances(3000, 1.0, 60.0).map(|w| pixel(r, c, w));
        // A HUD records 0 (dropped before the fit); a weapon drawn with near 0.05 disagrees.
        let hud = std::iter::repeat_n((0.0f32, 0.0001f32), 2000);
        let weapon = distances(400, 0.1, 0.6).map(|w| pixel(DepthRange::frustum(0.05, 100.0), c, w));
        let got = fit(scene.chain(hud).chain(weapon), c).expect("a fit");
        assert!((got.range.near() - 0.5).abs() < 1e-3, "{:?}", got.range);
        assert_eq!(got.candidates, 3400);
        assert_eq!(got.inliers, 3000);
    }

    #[test]
    fn an_infinite_far_plane_stays_infinite() {
        let r = DepthRange { a: -1.0, b: -0.2 };
        let got = fit(distances(3000, 0.3, 500.0).map(|w| pixel(r, 5.0, w)), 5.0).expect("a fit");
        assert!(got.range.far().is_infinite(), "{:?}", got.range);
        assert!((got.range.near() - 0.1).abs() < 1e-4, "{:?}", got.range);
    }

    #[test]
    fn one_distance_or_too_few_pixels_say_nothing() {
        let r = DepthRange::frustum(0.5, 100.0);
        assert!(fit(std::iter::repeat_n(pixel(r, 8.0, 10.0), 5000), 8.0).is_none());
        assert!(fit(distances(100, 1.0, 50.0).map(|w| pixel(r, 8.0, w)), 8.0).is_none());
        assert!(fit(distances(3000, 1.0, 50.0).map(|w| pixel(r, 8.0, w)), 0.0).is_none());
    }
}
