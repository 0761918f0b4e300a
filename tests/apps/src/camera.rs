//! Normative light-field camera model: the reference quilt is ground truth for
//! the layer, so this must match the spec formula exactly (see README).

/// Horizontal position of view `i` of `n` in [-1, 1]; view 0 is leftmost.
pub fn view_u(i: usize, n: usize) -> f32 {
    if n <= 1 {
        return 0.0;
    }
    2.0 * i as f32 / (n - 1) as f32 - 1.0
}

/// Orthographic projections (HUDs) have a constant w row and are never sheared.
pub fn is_ortho(p: &[f32; 16]) -> bool {
    p[3] == 0.0 && p[7] == 0.0 && p[11] == 0.0 && p[15] == 1.0
}

/// Column-major `p` (as uploaded to GL) sheared for view `i` of `n` with
/// depthiness `s`, convergence distance `c` and focus `f`:
/// x_clip' = x_clip + k*(w_clip - c) + h*w_clip, k = s*u, h = f*u.
pub fn sheared_projection(p: [f32; 16], i: usize, n: usize, s: f32, c: f32, f: f32) -> [f32; 16] {
    if is_ortho(&p) {
        return p;
    }
    let u = view_u(i, n);
    let (k, h) = (s * u, f * u);
    let mut q = p;
    for j in 0..4 {
        q[j * 4] += (k + h) * p[j * 4 + 3];
    }
    q[12] -= k * c;
    q
}

/// Like `sheared_projection`, but for geometry the layer treats as lying at
/// infinity (`.xyww` skyboxes: clip z == w). There the layer's shift is
/// x_clip' = x_clip + k*w_clip + h*w_clip (no -k*c term), so the reference
/// quilt must draw such geometry with P + (k + h) * e0 * row3(P).
pub fn sheared_projection_at_infinity(p: [f32; 16], i: usize, n: usize, s: f32, f: f32) -> [f32; 16] {
    // c = 0 drops exactly the -k*c*e0*e3^T term of the full shear.
    sheared_projection(p, i, n, s, 0.0, f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math;

    fn clip(p: &[f32; 16], v: [f32; 4]) -> [f32; 4] {
        let mut o = [0.0; 4];
        for (r, out) in o.iter_mut().enumerate() {
            *out = (0..4).map(|c| p[c * 4 + r] * v[c]).sum();
        }
        o
    }

    #[test]
    fn centre_view_of_odd_n_is_identity() {
        let p = math::perspective(45f32.to_radians(), 1.5, 0.1, 100.0);
        assert_eq!(sheared_projection(p, 4, 9, 0.3, 7.0, 0.2), p);
        assert_eq!(sheared_projection(p, 0, 1, 0.3, 7.0, 0.2), p);
    }

    #[test]
    fn convergence_plane_is_fixed_without_focus() {
        let p = math::perspective(45f32.to_radians(), 1.5, 0.1, 100.0);
        let c = 7.0;
        let pt = [1.3, -0.4, -c, 1.0];
        let base = clip(&p, pt);
        for i in 0..9 {
            let q = clip(&sheared_projection(p, i, 9, 0.4, c, 0.0), pt);
            assert!((q[0] / q[3] - base[0] / base[3]).abs() < 1e-6, "view {i}");
            assert_eq!(q[3], base[3]);
        }
        // and points off the plane do move
        let far = clip(&sheared_projection(p, 0, 9, 0.4, c, 0.0), [0.0, 0.0, -20.0, 1.0]);
        assert!(far[0].abs() > 1e-3);
    }

    #[test]
    fn ortho_untouched() {
        let o = math::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
        assert_eq!(sheared_projection(o, 0, 9, 0.4, 7.0, 0.3), o);
    }

    #[test]
    fn at_infinity_shifts_by_k_plus_h_times_w() {
        let p = math::perspective(60f32.to_radians(), 1.25, 0.1, 50.0);
        let (s, c, f) = (0.3, 7.0, 0.05);
        assert_eq!(sheared_projection_at_infinity(p, 2, 5, s, f), p);
        for i in 0..5 {
            let u = view_u(i, 5);
            let q = sheared_projection_at_infinity(p, i, 5, s, f);
            let full = sheared_projection(p, i, 5, s, c, f);
            for v in [[0.4, 0.2, -1.0, 1.0], [-3.0, 1.0, -9.0, 1.0]] {
                let (a, b) = (clip(&p, v), clip(&q, v));
                // x moves by (k + h) * w; y, z, w are untouched.
                assert!((b[0] - (a[0] + (s * u + f * u) * a[3])).abs() < 1e-5, "view {i}");
                assert_eq!(&b[1..], &a[1..]);
                // the full shear differs from it by exactly -k*c
                let g = clip(&full, v);
                assert!((g[0] - (b[0] - s * u * c)).abs() < 1e-5, "view {i}");
            }
        }
        let o = math::ortho(0.0, 640.0, 0.0, 480.0, -1.0, 1.0);
        assert_eq!(sheared_projection_at_infinity(o, 0, 9, 0.4, 0.3), o);
    }

    #[test]
    fn view_positions() {
        assert_eq!(view_u(0, 9), -1.0);
        assert_eq!(view_u(8, 9), 1.0);
        assert_eq!(view_u(4, 9), 0.0);
    }
}
