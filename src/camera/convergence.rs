//! Auto-convergence: put the zero-parallax plane where the scene is, so it sits on the
//! display's surface and the rest spreads in front and behind.
//!
//! The estimate is the harmonic mean of eye distances over the centre view's covered pixels
//! (background at the far plane excluded). The harmonic mean weighs near content more, which
//! keeps the nearest objects — the ones that would otherwise pop out uncomfortably — close to
//! the plane. It is smoothed over frames so camera cuts do not make the depth jump.

use super::projection::DepthRange;

/// Weight of a new frame's estimate in the running value.
const SMOOTHING: f64 = 0.2;

/// Harmonic mean of eye distance over `depths` (window depth in 0..1, default [-1,1] NDC).
pub fn estimate(depths: &[f32], range: DepthRange) -> Option<f64> {
    let (mut sum_inv, mut n) = (0.0f64, 0usize);
    for &d in depths {
        if d >= 1.0 || d <= 0.0 {
            continue;
        }
        let w = range.w_of_ndc(2.0 * d as f64 - 1.0);
        if w.is_finite() && w > 0.0 {
            sum_inv += 1.0 / w;
            n += 1;
        }
    }
    (n > 0 && sum_inv > 0.0).then(|| n as f64 / sum_inv)
}

/// Relative distance from the estimate within which the running value holds still.
const HOLD: f64 = 1e-3;

/// Exponential smoothing; the first estimate is taken as is. Within `HOLD` of the estimate
/// the value stops moving: a still scene would otherwise change the rig (and so every view
/// but the centre) by ever smaller amounts for some 160 frames, and `--reuse` keeps views
/// only while the rig is unchanged. A 0.1% change of convergence moves a pixel by a small
/// fraction of a pixel.
pub fn smooth(previous: Option<f64>, new: f64) -> f64 {
    previous.map_or(new, |p| {
        if (new - p).abs() <= HOLD * p.abs() {
            p
        } else {
            p + SMOOTHING * (new - p)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_mean_of_known_depths() {
        let (n, f) = (0.1f64, 100.0f64);
        let range = DepthRange {
            a: -(f + n) / (f - n),
            b: -2.0 * f * n / (f - n),
        };
        let window_depth = |w: f64| ((-range.a + range.b / w) * 0.5 + 0.5) as f32;
        let depths = [window_depth(2.0), window_depth(6.0), 1.0];
        let c = estimate(&depths, range).unwrap();
        assert!((c - 3.0).abs() < 1e-3, "{c}");
        assert_eq!(estimate(&[1.0, 1.0], range), None);
        assert_eq!(smooth(Some(2.0), 4.0), 2.4);
        assert_eq!(smooth(Some(2.0), 2.001), 2.0, "holds within 0.1%");
    }
}
