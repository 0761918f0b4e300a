//! The scene's needs from a depth buffer whose answer is known.

use super::*;

#[test]
fn scene_needs_from_depth() {
    let (n, f) = (1.0f64, 100.0f64);
    let range = DepthRange {
        a: -(f + n) / (f - n),
        b: -2.0 * f * n / (f - n),
    };
    let window = |w: f64| ((-range.a + range.b / w) * 0.5 + 0.5) as f32;
    // 10 pixels per row: 4 at w = 2, 6 at the far plane; parallax 1 - 2/2 = 0 and 1, 20 px
    // per unit of parallax: a 20 px jump per row, half of it a hole.
    let row: Vec<f32> = (0..10).map(|i| if i < 4 { window(2.0) } else { 1.0 }).collect();
    let depths: Vec<f32> = row.iter().chain(row.iter()).copied().collect();
    let s = scene_needs(&depths, 10, range, 2.0, 20.0, 1.0).unwrap();
    assert!((s.range_px - 20.0).abs() < 1e-3, "{s:?}");
    assert!((s.holes_per_u - 20.0 / 20.0).abs() < 1e-3, "{s:?}");
    // Everything at the convergence distance: flat.
    let flat = vec![window(2.0); 20];
    let s = scene_needs(&flat, 10, range, 2.0, 20.0, 1.0).unwrap();
    assert!(s.range_px < 1e-3 && s.holes_per_u == 0.0, "{s:?}");
}
