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
    /// Present when the matrix is a bare perspective projection (row3 = (0,0,-s,0)).
    pub depth: Option<DepthRange>,
}

/// Eye-space depth model of a bare perspective projection: `z_ndc = a + b / (-z_eye)` after
/// normalising row3 to (0,0,-1,0), i.e. `w = b / (z_ndc - a)`... stored as the matrix terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthRange {
    pub a: f64,
    pub b: f64,
}

impl DepthRange {
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
        });
    }
    let bare = row3[0].abs() < EPS && row3[1].abs() < EPS && row3[3].abs() < EPS && row3[2] < 0.0;
    let depth = bare.then(|| {
        let s = -row3[2];
        DepthRange {
            a: m[10] / s,
            b: m[14] / s,
        }
    });
    Some(Projection {
        kind: ProjectionKind::Perspective,
        depth,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn perspective(fovy: f64, aspect: f64, n: f64, f: f64) -> [f32; 16] {
        let t = 1.0 / (fovy.to_radians() / 2.0).tan();
        [
            t / aspect,
            0.,
            0.,
            0.,
            0.,
            t,
            0.,
            0.,
            0.,
            0.,
            (f + n) / (n - f),
            -1.,
            0.,
            0.,
            2. * f * n / (n - f),
            0.,
        ]
        .map(|v| v as f32)
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
    fn nan_is_refused() {
        let mut m = perspective(60.0, 1.0, 0.1, 10.0);
        m[3] = f32::NAN;
        assert!(classify(&m).is_none());
    }
}
