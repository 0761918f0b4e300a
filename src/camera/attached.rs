//! Geometry attached to the camera is at infinity (DESIGN §3).
//!
//! A sky box or dome is drawn around the eye: its view transform is the camera's rotation
//! with no translation, so it moves with the eye and the viewer reads it as infinitely far,
//! whatever its size. Its geometric `w` is small (a unit cube), so the ordinary shift
//! `k (w - c)` would give it a large crossed disparity and stand the sky in front of the
//! whole scene (Extreme Tux Racer's kind: +74 px where the far scene moves −15 px). Such a
//! draw gets the shift of infinity, `k w`, instead.
//!
//! The one program that also draws with a translation-free view transform is one that
//! gives its vertices in eye space under an identity model-view (NeHe-era code drawing at
//! `z = -5` with `glLoadIdentity`). Those draws are scene, and they are told apart by what
//! they keep: an identity rotation *and* depth writes on. A sky seen by a camera looking
//! exactly down −z with depth writes on is the one case this gives up.

/// Relative size of a translation that counts as none: model-view matrices are built in
/// f32 from rotations, and a rotation's round-off leaves the translation exactly zero;
/// anything an app translates by on purpose is many orders above this.
const NO_TRANSLATION: f64 = 1e-6;

/// Whether a draw under `modelview` (column-major) is attached to the camera: no
/// translation, and either a rotation of its own or no depth writes.
pub fn camera_attached(modelview: &[f32; 16], depth_writes: impl FnOnce() -> bool) -> bool {
    let m = modelview.map(f64::from);
    if m.iter().any(|v| !v.is_finite()) {
        return false;
    }
    let scale = (0..3)
        .flat_map(|c| (0..3).map(move |r| m[c * 4 + r].abs()))
        .fold(0.0, f64::max);
    let perspective_free = m[3] == 0.0 && m[7] == 0.0 && m[11] == 0.0 && m[15] != 0.0;
    if scale == 0.0 || !perspective_free {
        return false;
    }
    let translation = m[12].abs().max(m[13].abs()).max(m[14].abs()) / m[15].abs();
    if translation > NO_TRANSLATION * scale {
        return false;
    }
    !identity_rotation(&m, scale) || !depth_writes()
}

fn identity_rotation(m: &[f64; 16], scale: f64) -> bool {
    (0..3).all(|c| (0..3).all(|r| (m[c * 4 + r] - if c == r { scale } else { 0.0 }).abs() <= 1e-6 * scale))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};

    fn cols(m: Mat4) -> [f32; 16] {
        m.to_cols_array()
    }

    #[test]
    fn a_rotation_alone_is_attached_whatever_the_depth_writes() {
        let sky = cols(Mat4::from_rotation_x(0.4) * Mat4::from_rotation_y(1.3));
        assert!(camera_attached(&sky, || true));
        assert!(camera_attached(&sky, || false));
        // Scaled (a dome drawn at radius 500) is still attached.
        assert!(camera_attached(
            &cols(Mat4::from_rotation_y(0.2) * Mat4::from_scale(Vec3::splat(500.0))),
            || true
        ));
    }

    #[test]
    fn a_translated_draw_is_not_attached() {
        let world = cols(Mat4::from_rotation_x(0.4) * Mat4::from_translation(Vec3::new(0.0, -5.0, -12.0)));
        assert!(!camera_attached(&world, || false));
        // A small translation of a large scene is still a translation.
        let far = cols(Mat4::from_scale(Vec3::splat(1e4)) * Mat4::from_translation(Vec3::new(1e-3, 0.0, 0.0)));
        assert!(!camera_attached(&far, || false));
    }

    #[test]
    fn eye_space_geometry_under_identity_is_scene_unless_it_writes_no_depth() {
        let identity = cols(Mat4::IDENTITY);
        assert!(!camera_attached(&identity, || true));
        assert!(camera_attached(&identity, || false));
    }

    #[test]
    fn degenerate_matrices_are_not_attached() {
        assert!(!camera_attached(&[0.0; 16], || false));
        let mut nan = cols(Mat4::IDENTITY);
        nan[0] = f32::NAN;
        assert!(!camera_attached(&nan, || false));
        let mut projective = cols(Mat4::from_rotation_y(0.3));
        projective[11] = -1.0;
        assert!(!camera_attached(&projective, || false));
    }
}
