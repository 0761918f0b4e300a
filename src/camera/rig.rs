//! Per-view shift parameters `k_i`, `h_i` and the convergence `c` (DESIGN §3).

/// What the injected shader gets for one view: `holoinject_view = (k, c, h, mode)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewParams {
    pub k: f32,
    pub c: f32,
    pub h: f32,
}

/// The camera rig of one frame: N views, depthiness `s`, convergence `c`, focus `f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRig {
    pub views: u32,
    pub depthiness: f64,
    pub convergence: f64,
    pub focus: f64,
}

impl ViewRig {
    /// `u_i = 2i/(N-1) - 1`; view 0 is the leftmost camera.
    pub fn u(&self, i: u32) -> f64 {
        if self.views <= 1 {
            0.0
        } else {
            2.0 * i as f64 / (self.views - 1) as f64 - 1.0
        }
    }

    pub fn params(&self, i: u32) -> ViewParams {
        let u = self.u(i);
        ViewParams {
            k: (self.depthiness * u) as f32,
            c: self.convergence as f32,
            h: (self.focus * u) as f32,
        }
    }

    /// The centre view of an odd quilt (the one `glReadPixels` and `mono` show); for an even
    /// count, the view just right of centre.
    pub fn centre(&self) -> u32 {
        self.views / 2
    }

    /// Depthiness giving `px` pixels of disparity at infinity between adjacent views in a
    /// tile `tile_w` wide: `(tile_w/2) * 2s/(N-1) = px`.
    pub fn depthiness_for_disparity(px: f64, views: u32, tile_w: u32) -> f64 {
        if views <= 1 || tile_w == 0 {
            0.0
        } else {
            px * (views - 1) as f64 / tile_w as f64
        }
    }

    /// The same shift as a projection matrix (column-major): `P'_i` of DESIGN §3, used by
    /// fixed-function replay and by the sample apps' ground truth.
    pub fn shear(&self, i: u32, p: &[f64; 16]) -> [f64; 16] {
        self.shear_moved(i, p, 0.0)
    }

    /// `shear`, the image moved by `dh` more (NDC): as view `i`'s `h + dh`.
    pub fn shear_moved(&self, i: u32, p: &[f64; 16], dh: f64) -> [f64; 16] {
        let v = self.params(i);
        let (k, h, c) = (v.k as f64, v.h as f64 + dh, v.c as f64);
        let mut out = *p;
        for col in 0..4 {
            out[col * 4] += (k + h) * p[col * 4 + 3];
        }
        out[12] -= k * c;
        out
    }

    /// How a pixel of view `i` moves in clip space when the camera's clip coordinates move by
    /// `d` (column-major, `VP_now · VP_then⁻¹`): `v ↦ m·v + t`, the shift undone, `d`, the
    /// shift redone. The shift `x' = x + (k+h)w - kc` is affine in clip space (its constant
    /// is `-kc`), so the motion is a matrix and an offset: with `L` its linear part and
    /// `s0 = (-kc, 0, 0, 0)`, `m = L·d·L⁻¹` and `t = s0 - L·d·s0`.
    pub fn clip_motion(&self, i: u32, d: &[f64; 16]) -> ([f64; 16], [f64; 4]) {
        use glam::{DMat4, DVec4};
        let v = self.params(i);
        let (kh, kc) = (v.k as f64 + v.h as f64, v.k as f64 * v.c as f64);
        let shear = |a: f64| {
            let mut l = DMat4::IDENTITY;
            l.w_axis.x = a;
            l
        };
        let (l, d) = (shear(kh), DMat4::from_cols_array(d));
        let s0 = DVec4::new(-kc, 0.0, 0.0, 0.0);
        let m = l * d * shear(-kh);
        (m.to_cols_array(), (s0 - l * d * s0).to_array())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Moving a shifted point by `clip_motion` equals shifting the moved unshifted point.
    #[test]
    fn clip_motion_is_the_motion_seen_through_the_shift() {
        let r = ViewRig { focus: 0.03, ..rig(5) };
        let d = [
            1.1, 0.1, 0.0, 0.02, -0.2, 0.9, 0.1, 0.0, 0.05, 0.0, 1.2, 0.3, 0.4, -0.3, 0.7, 1.05,
        ];
        let p = r.params(0);
        let (k, c, h) = (p.k as f64, p.c as f64, p.h as f64);
        let shift = |v: [f64; 4]| [v[0] + k * (v[3] - c) + h * v[3], v[1], v[2], v[3]];
        let mul = |m: &[f64; 16], v: [f64; 4]| -> [f64; 4] {
            std::array::from_fn(|row| (0..4).map(|col| m[col * 4 + row] * v[col]).sum())
        };
        let centre = [0.3, -0.2, 4.0, 5.0];
        let want = shift(mul(&d, centre));
        let (m, t) = r.clip_motion(0, &d);
        let moved = mul(&m, shift(centre));
        for j in 0..4 {
            assert!(
                (moved[j] + t[j] - want[j]).abs() < 1e-12,
                "{j}: {moved:?} + {t:?} != {want:?}"
            );
        }
    }

    fn rig(n: u32) -> ViewRig {
        ViewRig {
            views: n,
            depthiness: 0.2,
            convergence: 5.0,
            focus: 0.0,
        }
    }

    #[test]
    fn view_zero_is_leftmost_and_centre_is_unshifted() {
        let r = rig(9);
        assert_eq!(r.u(0), -1.0);
        assert_eq!(r.u(8), 1.0);
        assert_eq!(r.params(r.centre()).k, 0.0);
        assert_eq!(rig(1).u(0), 0.0);
    }

    #[test]
    fn shear_matches_clip_shift() {
        // gluPerspective(60°, 4/3, 0.1, 100), column-major.
        let p = crate::camera::matrix::perspective(60.0, 4.0 / 3.0, 0.1, Some(100.0), false);
        let r = ViewRig { focus: 0.01, ..rig(5) };
        let eye = [0.3, -0.2, -7.0, 1.0];
        let mul = |m: &[f64; 16]| -> [f64; 4] {
            let mut o = [0.0; 4];
            for (row, o) in o.iter_mut().enumerate() {
                *o = (0..4).map(|c| m[c * 4 + row] * eye[c]).sum();
            }
            o
        };
        for i in 0..5 {
            let clip = mul(&p);
            let v = r.params(i);
            let shifted = clip[0] + v.k as f64 * (clip[3] - v.c as f64) + v.h as f64 * clip[3];
            let sheared = mul(&r.shear(i, &p));
            assert!((shifted - sheared[0]).abs() < 1e-12);
            assert_eq!(clip[1..], sheared[1..]);
        }
    }

    #[test]
    fn plane_at_convergence_does_not_move() {
        let r = rig(7);
        for i in 0..7 {
            let v = r.params(i);
            let w = 5.0f32;
            assert!((v.k * (w - v.c)).abs() < 1e-6);
        }
    }

    #[test]
    fn default_depthiness_gives_four_pixels() {
        let s = ViewRig::depthiness_for_disparity(4.0, 48, 420);
        let adjacent = 420.0 / 2.0 * 2.0 * s / 47.0;
        assert!((adjacent - 4.0).abs() < 1e-9);
    }
}
