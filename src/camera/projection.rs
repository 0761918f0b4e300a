//! What a tracked matrix (P, VP or MVP, column-major as uploaded) says about the projection,
//! in f64.
//!
//! For any affine model-view `A`, `row3(P·A) = row3(P)·A`, so an orthographic projection
//! keeps `row3 = (0,0,0,1)` whatever is multiplied on its right: that test is robust for P, VP
//! and MVP alike. Near/far need the projection itself; with `P = [.. ; 0 0 a b ; 0 0 -1 0]`,
//! `n = b/(a-1)`, `f = b/(a+1)` ([-1,1] depth), and reversed-Z shows as `a > 0`.

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProjectionKind {
    Perspective,
    Orthographic,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    pub kind: ProjectionKind,
    /// Present when depth can be linearised (a perspective P·A with A rigid or uniformly
    /// scaled).
    pub depth: Option<DepthRange>,
    /// Horizontal focal scale `Fx` (P[0][0] of the bare projection), when recoverable.
    pub fx: Option<f64>,
    /// Why a perspective matrix gave no depth model (reported once per program).
    pub issue: Option<DepthIssue>,
}

/// What keeps a perspective matrix's depth from being linearised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthIssue {
    /// Row 3 or row 2 is (nearly) zero: no projection can be read from it.
    Degenerate,
    /// Row 2 is not parallel to row 3 in xyz: an oblique near plane, or a transform applied
    /// after the projection. (Any affine model-view keeps them parallel: `row2(P·A) =
    /// -a·row3(P·A) + b·e3`, shear and non-uniform scale included.)
    ObliqueOrPostProjection,
    /// Depth is fine, but the model-view is not rigid or uniformly scaled (shear, non-uniform
    /// scale), so the focal length `Fx` cannot be read off the product.
    NonRigidModelView,
}

impl std::fmt::Display for DepthIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            DepthIssue::Degenerate => "degenerate matrix (row 2 or 3 is zero)",
            DepthIssue::ObliqueOrPostProjection => "oblique near plane or a transform after the projection",
            DepthIssue::NonRigidModelView => "shear or non-uniform scale in the model-view (focal length unknown)",
        })
    }
}

/// Eye-space depth model of a bare perspective projection: `z_ndc = a + b / (-z_eye)` after
/// normalising row3 to (0,0,-1,0), i.e. `w = b / (z_ndc - a)`... stored as the matrix terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthRange {
    pub a: f64,
    pub b: f64,
}

impl DepthRange {
    /// The depth terms of `glFrustum(.., near, far)` (as `classify` reads them).
    pub fn frustum(near: f64, far: f64) -> DepthRange {
        DepthRange {
            a: -(far + near) / (far - near),
            b: -2.0 * far * near / (far - near),
        }
    }

    /// Eye distance `w` of a fragment with NDC depth `z_ndc` (window depth `d` maps to
    /// `2d-1` under the default [-1,1] clip control).
    pub fn w_of_ndc(&self, z_ndc: f64) -> f64 {
        // z_clip = a*z_eye + b, w = -z_eye  =>  z_ndc = -a + b/w  =>  w = b / (z_ndc + a)
        self.b / (z_ndc + self.a)
    }

    pub fn near(&self) -> f64 {
        self.b / (self.a - 1.0)
    }

    pub fn far(&self) -> f64 {
        if (self.a + 1.0).abs() < 1e-12 {
            f64::INFINITY
        } else {
            self.b / (self.a + 1.0)
        }
    }
}

const EPS: f64 = 1e-6;

/// Classifies a column-major 4x4 matrix; `None` when it is not a projection we recognise
/// (degenerate, or a model-view matrix: row3 = (0,0,0,1) *and* no scaling of w... we cannot
/// tell those from an orthographic projection, so callers only pass matrices that feed
/// gl_Position first in the chain).
pub fn classify(m: &[f32; 16]) -> Option<Projection> {
    let m: [f64; 16] = m.map(f64::from);
    let row3 = [m[3], m[7], m[11], m[15]];
    if row3.iter().any(|v| !v.is_finite()) {
        return None;
    }
    if row3[0].abs() < EPS && row3[1].abs() < EPS && row3[2].abs() < EPS && (row3[3] - 1.0).abs() < EPS {
        return Some(Projection {
            kind: ProjectionKind::Orthographic,
            depth: None,
            fx: None,
            issue: None,
        });
    }
    let depth = depth_model(&m);
    let fx = depth.and_then(|_| focal_x(&m));
    Some(Projection {
        kind: ProjectionKind::Perspective,
        depth: depth.ok(),
        fx: fx.ok(),
        issue: fx.err(),
    })
}

/// `Fx` of P in P·A (A rigid, scale s): row0 = Fx·s·r0 + cx·s·r2 and row3 = -s·r2, so the
/// part of row0 orthogonal to row3, divided by |row3|, is Fx — exact for off-centre frusta.
/// With A rigid the same holds for row1 with `Fy·s·r1`, and r0 ⊥ r1: parts of row0 and row1
/// that are not orthogonal give a shear or non-uniform scale away.
fn focal_x(m: &[f64; 16]) -> Result<f64, DepthIssue> {
    let q = [m[3], m[7], m[11]];
    let qq: f64 = q.iter().map(|v| v * v).sum();
    let reject = |r: [f64; 3]| {
        let along = (r[0] * q[0] + r[1] * q[1] + r[2] * q[2]) / qq;
        [r[0] - along * q[0], r[1] - along * q[1], r[2] - along * q[2]]
    };
    let (x, y) = (reject([m[0], m[4], m[8]]), reject([m[1], m[5], m[9]]));
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    if dot(x, y).abs() > 1e-6 * (dot(x, x) * dot(y, y)).sqrt() {
        return Err(DepthIssue::NonRigidModelView);
    }
    let fx = (dot(x, x) / qq).sqrt();
    if fx.is_finite() && fx > 0.0 {
        Ok(fx)
    } else {
        Err(DepthIssue::Degenerate)
    }
}

/// The depth model of a perspective matrix P·A for any rigid (or uniformly scaled) model-view
/// A: then `row2 = -a·row3 + (0,0,0,b)`, so `z_ndc = -a + b/w` with the clip w the shader
/// sees. The xyz part of row2 must be parallel to row3's; otherwise (shear, non-uniform
/// scale) the depth cannot be linearised, and the reason is returned.
fn depth_model(m: &[f64; 16]) -> Result<DepthRange, DepthIssue> {
    let q = [m[3], m[7], m[11]];
    let r = [m[2], m[6], m[10]];
    let qq: f64 = q.iter().map(|v| v * v).sum();
    let rr: f64 = r.iter().map(|v| v * v).sum();
    if qq < EPS * EPS || rr == 0.0 || !rr.is_finite() {
        return Err(DepthIssue::Degenerate);
    }
    let a = -(r[0] * q[0] + r[1] * q[1] + r[2] * q[2]) / qq;
    let residual: f64 = (0..3).map(|i| (r[i] + a * q[i]).powi(2)).sum();
    if residual > 1e-8 * rr {
        return Err(DepthIssue::ObliqueOrPostProjection);
    }
    let b = m[14] + a * m[15];
    if a.is_finite() && b.is_finite() && b != 0.0 {
        Ok(DepthRange { a, b })
    } else {
        Err(DepthIssue::Degenerate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn perspective(fovy: f64, aspect: f64, n: f64, f: f64) -> [f32; 16] {
        crate::camera::matrix::perspective(fovy, aspect, n, Some(f), false).map(|v| v as f32)
    }

    #[test]
    fn recovers_near_far_and_linearises() {
        let p = classify(&perspective(60.0, 1.5, 0.1, 100.0)).unwrap();
        assert_eq!(p.kind, ProjectionKind::Perspective);
        let d = p.depth.unwrap();
        assert!((d.near() - 0.1).abs() < 1e-5 && (d.far() - 100.0).abs() < 0.05, "{d:?}");
        // A point 7 units away: z_ndc = -a + b/7.
        let z = -d.a + d.b / 7.0;
        assert!((d.w_of_ndc(z) - 7.0).abs() < 1e-9);
    }

    #[test]
    fn orthographic_is_detected_through_model_view() {
        let ortho = [
            2. / 640.,
            0.,
            0.,
            0.,
            0.,
            2. / 480.,
            0.,
            0.,
            0.,
            0.,
            -1.,
            0.,
            -1.,
            -1.,
            0.,
            1.,
        ];
        assert_eq!(classify(&ortho).unwrap().kind, ProjectionKind::Orthographic);
    }

    #[test]
    fn depth_model_survives_a_rigid_view_and_uniform_scale() {
        let p = perspective(50.0, 1.0, 0.5, 200.0);
        // View: rotate 30° about y, translate, scale 2 (column-major).
        let (c, s) = (30f32.to_radians().cos(), 30f32.to_radians().sin());
        let v = [
            2.0 * c,
            0.,
            -2.0 * s,
            0.,
            0.,
            2.0,
            0.,
            0.,
            2.0 * s,
            0.,
            2.0 * c,
            0.,
            1.0,
            -2.0,
            -9.0,
            1.0,
        ];
        let mut mvp = [0f32; 16];
        for col in 0..4 {
            for row in 0..4 {
                mvp[col * 4 + row] = (0..4).map(|k| p[k * 4 + row] * v[col * 4 + k]).sum();
            }
        }
        let proj = classify(&mvp).unwrap();
        let d = proj.depth.unwrap();
        assert!(
            (proj.fx.unwrap() - p[0] as f64).abs() < 1e-4,
            "fx {:?} vs {}",
            proj.fx,
            p[0]
        );
        // A point: clip w and z from the matrix, then linearise z back to w.
        let x = [0.3f64, -0.2, 0.7, 1.0];
        let clip = |row: usize| (0..4).map(|k| mvp[k * 4 + row] as f64 * x[k]).sum::<f64>();
        let (z, w) = (clip(2), clip(3));
        assert!((d.w_of_ndc(z / w) - w).abs() < 1e-3 * w, "{} vs {w}", d.w_of_ndc(z / w));
    }

    #[test]
    fn sheared_model_view_is_not_linearised() {
        let mut m = perspective(50.0, 1.0, 0.5, 200.0);
        m[2] += 0.3; // row 2 no longer parallel to row 3
        m[3] = 0.2;
        let p = classify(&m).unwrap();
        assert!(p.depth.is_none());
        assert_eq!(p.issue, Some(DepthIssue::ObliqueOrPostProjection));
    }

    /// `P·M` column-major, both column-major.
    fn mul(p: &[f32; 16], m: &[f64; 16]) -> [f32; 16] {
        let mut out = [0f32; 16];
        for c in 0..4 {
            for r in 0..4 {
                out[c * 4 + r] = (0..4).map(|k| p[k * 4 + r] as f64 * m[c * 4 + k]).sum::<f64>() as f32;
            }
        }
        out
    }

    #[test]
    fn non_rigid_model_views_keep_depth_but_report_the_focal_length() {
        let p = perspective(50.0, 1.0, 0.5, 200.0);
        let exact = classify(&p).unwrap();
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        // Model space stretched along y, then rolled: x and y mix. (A stretch along the
        // camera's own axes is indistinguishable from another projection's Fx/Fy.)
        #[rustfmt::skip]
        let roll_after_stretch = [c, s, 0.0, 0.0,  -2.0 * s, 2.0 * c, 0.0, 0.0,  0.0, 0.0, 1.0, 0.0,  4.0, -1.0, -30.0, 1.0];
        #[rustfmt::skip]
        let shear = [1.0, 0.0, 0.0, 0.0,  0.7, 1.0, 0.0, 0.0,  0.0, 0.0, 1.0, 0.0,  0.0, 0.0, -20.0, 1.0];
        for m in [roll_after_stretch, shear] {
            let got = classify(&mul(&p, &m)).unwrap();
            let (d, e) = (got.depth.unwrap(), exact.depth.unwrap());
            assert!(
                (d.a - e.a).abs() < 1e-5 && (d.b - e.b).abs() < 1e-5 * e.b.abs(),
                "{d:?} vs {e:?}"
            );
            assert_eq!(got.issue, Some(DepthIssue::NonRigidModelView));
            assert_eq!(got.fx, None);
        }
        #[rustfmt::skip]
        let rigid = [c, 0.0, -s, 0.0,  0.0, 1.0, 0.0, 0.0,  s, 0.0, c, 0.0,  4.0, -1.0, -30.0, 1.0];
        let got = classify(&mul(&p, &rigid)).unwrap();
        assert_eq!(got.issue, None);
        assert!((got.fx.unwrap() - exact.fx.unwrap()).abs() < 1e-5);
    }

    #[test]
    fn degenerate_matrices_are_reported() {
        let p = perspective(50.0, 1.0, 0.5, 200.0);
        let mut flat = p;
        (0..4).for_each(|c| flat[c * 4 + 2] = 0.0);
        assert_eq!(classify(&flat).unwrap().issue, Some(DepthIssue::Degenerate));
        let mut nan_row2 = p;
        nan_row2[10] = f32::INFINITY;
        assert_eq!(classify(&nan_row2).unwrap().issue, Some(DepthIssue::Degenerate));
    }

    #[test]
    fn nan_is_refused() {
        let mut m = perspective(60.0, 1.0, 0.1, 10.0);
        m[3] = f32::NAN;
        assert!(classify(&m).is_none());
    }
}
