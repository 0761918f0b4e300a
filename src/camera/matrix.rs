//! 4x4 matrices as the GL API stores them (column-major `[f64; 16]`), through `glam`.

use glam::DMat4;

/// The inverse of `m`, or None when it is singular (or not finite).
pub fn invert(m: &[f64; 16]) -> Option<[f64; 16]> {
    let m = DMat4::from_cols_array(m);
    let det = m.determinant();
    (det.is_finite() && det.abs() > 1e-300).then(|| m.inverse().to_cols_array())
}

/// Column-major perspective projection; `far = None` is the infinite far plane;
/// `reversed`: reversed-Z with [0,1] depth (z_ndc = near/w).
pub fn perspective(fovy_deg: f64, aspect: f64, near: f64, far: Option<f64>, reversed: bool) -> [f64; 16] {
    let t = 1.0 / (fovy_deg.to_radians() / 2.0).tan();
    let (a, b) = match (far, reversed) {
        (Some(f), false) => ((f + near) / (near - f), 2.0 * f * near / (near - f)),
        (None, false) => (-1.0, -2.0 * near),
        (Some(f), true) => (near / (f - near), f * near / (f - near)),
        (None, true) => (0.0, near),
    };
    [t / aspect, 0., 0., 0., 0., t, 0., 0., 0., 0., a, -1., 0., 0., b, 0.]
}

/// `a * b`.
pub fn mul(a: &[f64; 16], b: &[f64; 16]) -> [f64; 16] {
    (DMat4::from_cols_array(a) * DMat4::from_cols_array(b)).to_cols_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverts_a_projection_and_refuses_a_singular_matrix() {
        let p = perspective(60.0, 1.5, 0.1, Some(100.0), false);
        let inv = invert(&p).unwrap();
        let id = mul(&p, &inv);
        for c in 0..4 {
            for r in 0..4 {
                let want = if c == r { 1.0 } else { 0.0 };
                assert!((id[c * 4 + r] - want).abs() < 1e-12, "{id:?}");
            }
        }
        assert!(invert(&[0.0; 16]).is_none());
    }
}
