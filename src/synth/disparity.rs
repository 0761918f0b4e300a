//! Disparity from a depth value (DESIGN §5), prepared in f64 for the GPU's f32.
//!
//! A pixel of rendered view r at eye distance `w` lands in view i at
//! `x_ndc + (u_i - u_r)(s·p + f)`, with the parallax `p = 1 - c/w`. With the draw's depth
//! model `z_ndc = -a + b/w`, `c/w = (c/b)(z_ndc + a)`: `p` is affine in the stored depth.
//!
//! Written naively as `A + B·d` in f32, both terms reach `c/near` (1e5 for near 1e-4) and
//! cancel to O(1), losing four digits. Instead the shader forms `q = z_ndc + a` first, with
//! `a` split into two floats (`a_hi + a_lo`): `z_ndc + a_hi` is exact where it cancels
//! (Sterbenz), so `q` keeps its relative precision and `p = 1 - (c/b)·q` is as good as the
//! depth value it comes from.

use crate::camera::projection::DepthRange;

/// What the parallax shader needs: `p = 1 - scale·((z + a_hi) + a_lo)`, `z = 2d - 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParallaxModel {
    pub a_hi: f32,
    pub a_lo: f32,
    pub scale: f32,
    /// Larger window depth is nearer (reversed-Z): the depth test and clear flip.
    pub reversed: bool,
}

impl ParallaxModel {
    /// Every pixel at infinity (no depth model known): views differ by the focus only.
    pub const FLAT: ParallaxModel = ParallaxModel {
        a_hi: 0.0,
        a_lo: 0.0,
        scale: 0.0,
        reversed: false,
    };

    /// For convergence `c` and the depth model of the main camera.
    pub fn new(depth: DepthRange, c: f64) -> Option<ParallaxModel> {
        let scale = c / depth.b;
        if !scale.is_finite() || !depth.a.is_finite() {
            return None;
        }
        let a_hi = depth.a as f32;
        Some(ParallaxModel {
            a_hi,
            a_lo: (depth.a - a_hi as f64) as f32,
            scale: scale as f32,
            // z_ndc = -a + b/w grows with w when b < 0 (the usual projection).
            reversed: depth.b > 0.0,
        })
    }

    /// The shader's arithmetic, in f32 (for tests and the precision table).
    pub fn parallax_f32(&self, d: f32) -> f32 {
        let z = 2.0 * d - 1.0;
        let q = (z + self.a_hi) + self.a_lo;
        1.0 - self.scale * q
    }

    /// The window depth the far clear leaves (nothing drawn).
    pub fn far_depth(&self) -> f32 {
        if self.reversed { 0.0 } else { 1.0 }
    }
}

/// The exact parallax of window depth `d` (f64).
pub fn parallax_f64(depth: DepthRange, c: f64, d: f64) -> f64 {
    1.0 - c / depth.w_of_ndc(2.0 * d - 1.0)
}

/// Tile pixels view `i` sits from rendered view `r` for parallax `p`: `(u_i - u_r)(s·p + f)`
/// NDC, times half the tile width.
pub fn disparity_px(du: f64, s: f64, f: f64, p: f64, tile_w: u32) -> f64 {
    du * (s * p + f) * tile_w as f64 / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn perspective(near: f64, far: f64) -> DepthRange {
        // a = -(f+n)/(f-n), b = -2fn/(f-n); infinite far: a = -1, b = -2n.
        if far.is_infinite() {
            DepthRange {
                a: -1.0,
                b: -2.0 * near,
            }
        } else {
            DepthRange {
                a: -(far + near) / (far - near),
                b: -2.0 * far * near / (far - near),
            }
        }
    }

    /// Window depth of eye distance `w`, rounded to a 24-bit depth buffer.
    fn stored(depth: DepthRange, w: f64) -> f64 {
        let d = ((-depth.a + depth.b / w) + 1.0) / 2.0;
        (d * 16777215.0).round() / 16777215.0
    }

    /// Worst disparity error (outermost view, px in a 420-px tile, s = 0.1) of the f32 shader
    /// arithmetic against f64 on the same stored depth, over distances from near to far.
    pub fn worst_error_px(depth: DepthRange, c: f64, (near, far): (f64, f64)) -> f64 {
        let m = ParallaxModel::new(depth, c).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..=400 {
            let w = near * (far / near).powf(k as f64 / 400.0);
            let d = stored(depth, w);
            if !(0.0..=1.0).contains(&d) {
                continue;
            }
            let exact = parallax_f64(depth, c, d);
            let got = m.parallax_f32(d as f32) as f64;
            // Only what a tile can show: content within 10 tile widths of disparity.
            if exact.abs() * 0.1 * 210.0 > 4200.0 {
                continue;
            }
            worst = worst.max(((got - exact) * 0.1 * 210.0).abs());
        }
        worst
    }

    #[test]
    fn parallax_is_zero_at_convergence_and_one_at_infinity() {
        let d = perspective(0.1, 100.0);
        let m = ParallaxModel::new(d, 5.0).unwrap();
        let at_c = ((-d.a + d.b / 5.0) + 1.0) / 2.0;
        assert!(m.parallax_f32(at_c as f32).abs() < 1e-4);
        let inf = ParallaxModel::new(perspective(0.1, f64::INFINITY), 5.0).unwrap();
        assert!((inf.parallax_f32(1.0) - 1.0).abs() < 1e-6);
        assert!(!m.reversed && m.far_depth() == 1.0);
    }

    #[test]
    fn reversed_z_is_detected() {
        // Reversed-Z, infinite far: z_ndc = near/w (in [-1,1] terms: a = 0... b > 0).
        let r = DepthRange { a: 0.0, b: 0.1 };
        let m = ParallaxModel::new(r, 5.0).unwrap();
        assert!(m.reversed && m.far_depth() == 0.0);
    }

    /// The numbers of the README's precision table (warp column).
    #[test]
    fn f32_disparity_matches_f64_at_the_extremes() {
        // Reversed-Z with an infinite far plane, in [-1, 1] depth: z_ndc = -1 + 2n/w.
        let reversed = DepthRange { a: 1.0, b: 0.02 };
        let cases = [
            ("near 0.1, far 100", perspective(0.1, 100.0), 5.0, (0.1, 100.0)),
            ("near 1e-4, far 1e7", perspective(1e-4, 1e7), 10.0, (1e-4, 1e7)),
            (
                "near 1e-4, infinite far",
                perspective(1e-4, f64::INFINITY),
                10.0,
                (1e-4, 1e8),
            ),
            ("near 1, far 1e7, c = 1e6", perspective(1.0, 1e7), 1e6, (1.0, 1e7)),
            ("reversed-Z, near 0.01, infinite far", reversed, 10.0, (0.01, 1e6)),
        ];
        for (name, depth, c, range) in cases {
            let e = worst_error_px(depth, c, range);
            eprintln!("warp disparity error, {name}: {e:.2e} px");
            assert!(e < 0.01, "{name}: {e} px");
        }
    }

    #[test]
    fn disparity_in_pixels() {
        assert_eq!(disparity_px(1.0, 0.1, 0.0, 1.0, 400), 20.0);
        assert_eq!(disparity_px(-0.5, 0.1, 0.0, 0.0, 400), 0.0);
    }

    #[test]
    fn degenerate_models_are_refused() {
        assert!(ParallaxModel::new(DepthRange { a: -1.0, b: 0.0 }, 5.0).is_none());
    }
}
