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

/// Relative size of a translation that counts as none. A rotation alone leaves it exactly
/// zero, but games rarely build the sky's transform that way: Extreme Tux Racer loads its
/// view matrix (translation `-R·eye`) and then `glTranslated(eye)` for the sky, and the two
/// cancel only to GL's f32 round-off, a few ulps of the eye's distance from the world's
/// origin: 4e-6 of the box at 100 units, up to 3e-4 at 3,000 (its longest courses;
/// measured in a trace, modelled for the rest). 1e-6 missed every such sky after the
/// race's first metres. What an app translates by on purpose is further off: a large scene
/// moved by a thousandth of its size is still a translation.
const NO_TRANSLATION: f64 = 4e-4;

/// Whether a fixed-function draw under `projection` and `modelview` (column-major) is
/// attached to the camera: its origin is the eye, and it has either a rotation of its own or
/// no depth writes.
pub fn camera_attached(projection: &[f32; 16], modelview: &[f32; 16], depth_writes: impl FnOnce() -> bool) -> bool {
    origin_at_eye(&[*projection, *modelview]) && (!identity_rotation(&to_f64(modelview)) || !depth_writes())
}

/// Whether a shader draw whose `gl_Position` is the product of `chain` (column-major, in
/// multiplication order) is attached to the camera: its origin is the eye and, when the
/// projection's place in the chain is known, the model-view after it is a rotation of its
/// own (an identity model-view is eye-space geometry: a program's depth writes do not tell
/// its passes apart, so they are not asked).
pub fn chain_attached(chain: &[[f32; 16]], projection: Option<usize>) -> bool {
    if !origin_at_eye(chain) {
        return false;
    }
    match projection {
        Some(j) if j + 1 < chain.len() => !identity_rotation(&product(&chain[j + 1..])),
        Some(_) => false,
        None => true,
    }
}

/// The draw's origin is the eye: `T·(0,0,0,1)`, the last column of the whole transform, has
/// no x, y or w. Tested on the product rather than on the model-view alone, since programs
/// also move the camera inside the projection matrix (xscreensaver's `gflux`: `glFrustum`
/// then `glTranslatef(0, 0, -4)` in `GL_PROJECTION`), and `P·(0,0,0,1)` has no x, y or w
/// for every perspective projection, off-centre, reversed or infinite.
fn origin_at_eye(chain: &[[f32; 16]]) -> bool {
    if chain.is_empty() {
        return false;
    }
    let t = product(chain);
    if t.iter().any(|v| !v.is_finite()) {
        return false;
    }
    let scale = t[..12].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let origin = t[12].abs().max(t[13].abs()).max(t[15].abs());
    scale > 0.0 && origin <= NO_TRANSLATION * scale
}

fn to_f64(m: &[f32; 16]) -> [f64; 16] {
    m.map(f64::from)
}

fn product(chain: &[[f32; 16]]) -> [f64; 16] {
    use glam::DMat4;
    chain
        .iter()
        .fold(DMat4::IDENTITY, |acc, m| acc * DMat4::from_cols_array(&to_f64(m)))
        .to_cols_array()
}

fn identity_rotation(m: &[f64; 16]) -> bool {
    let scale = (0..3)
        .flat_map(|c| (0..3).map(move |r| m[c * 4 + r].abs()))
        .fold(0.0, f64::max);
    (0..3).all(|c| (0..3).all(|r| (m[c * 4 + r] - if c == r { scale } else { 0.0 }).abs() <= 1e-6 * scale))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};

    fn cols(m: Mat4) -> [f32; 16] {
        m.to_cols_array()
    }

    fn perspective() -> [f32; 16] {
        cols(Mat4::perspective_rh_gl(1.0, 1.5, 0.1, 100.0))
    }

    #[test]
    fn a_rotation_alone_is_attached_whatever_the_depth_writes() {
        let p = perspective();
        let sky = cols(Mat4::from_rotation_x(0.4) * Mat4::from_rotation_y(1.3));
        assert!(camera_attached(&p, &sky, || true));
        assert!(camera_attached(&p, &sky, || false));
        // Scaled (a dome drawn at radius 500) is still attached, under any perspective.
        let dome = cols(Mat4::from_rotation_y(0.2) * Mat4::from_scale(Vec3::splat(500.0)));
        assert!(camera_attached(&p, &dome, || true));
        let reversed_infinite = cols(Mat4::perspective_infinite_reverse_rh(0.5, 1.0, 1e-4));
        assert!(camera_attached(&reversed_infinite, &dome, || true));
    }

    #[test]
    fn a_translated_draw_is_not_attached() {
        let p = perspective();
        let world = cols(Mat4::from_rotation_x(0.4) * Mat4::from_translation(Vec3::new(0.0, -5.0, -12.0)));
        assert!(!camera_attached(&p, &world, || false));
        // A small translation of a large scene is still a translation.
        let far = cols(Mat4::from_scale(Vec3::splat(1e4)) * Mat4::from_translation(Vec3::new(1e-3, 0.0, 0.0)));
        assert!(!camera_attached(&p, &far, || false));
    }

    /// Extreme Tux Racer's sky at frame 240 of a recorded race: the view matrix as loaded
    /// (`glLoadMatrixd`, kept in f32 by GL), then `glTranslated(eye)` multiplied in f32, as
    /// GL does. The translations cancel to 3.8e-6, not to zero.
    #[test]
    fn a_sky_translated_back_to_the_eye_in_f32_is_attached() {
        let view: [f64; 16] = [
            0.9999999899433455,
            -4.850606486041612e-05,
            0.0001332684167445536,
            0.0,
            0.0,
            0.939691877479772,
            0.3420221855355897,
            0.0,
            -0.0001418213990547369,
            -0.3420221820959908,
            0.9396918680296152,
            0.0,
            -45.20640719235146,
            7.011277405905325,
            92.07712093322687,
            1.0,
        ];
        // The eye as the game holds it in f64, rounded to the f32 that glTranslated passes on.
        let eye = [45.19447585507766f64, -38.08085856849373, -84.13252061079893].map(|v| v as f32);
        let eye = Vec3::from_array(eye);
        let sky = Mat4::from_cols_array(&view.map(|v| v as f32)) * Mat4::from_translation(eye);
        let residual = sky.w_axis.truncate().abs().max_element();
        assert!(residual > 1e-6, "{residual}: the f32 product cancels exactly here");
        let p = perspective();
        assert!(camera_attached(&p, &cols(sky), || false));
        // The same sky 3,000 units from the origin (its longest courses), at the round-off
        // modelled there: 3e-4 of the box's size.
        let mut far = cols(sky);
        far[12] = 3e-4;
        assert!(camera_attached(&p, &far, || false));
    }

    #[test]
    fn a_camera_moved_inside_the_projection_is_not_the_eye() {
        // gflux: glFrustum, then glTranslatef(0, 0, -4) on GL_PROJECTION; rotations alone in
        // GL_MODELVIEW.
        let (n, f) = (2.0, 6.0);
        let frustum = Mat4::from_cols_array(&[
            n,
            0.0,
            0.0,
            0.0, //
            0.0,
            n / 0.8,
            0.0,
            0.0,
            0.0,
            0.0,
            -(f + n) / (f - n),
            -1.0,
            0.0,
            0.0,
            -2.0 * f * n / (f - n),
            0.0,
        ]);
        let p = cols(frustum * Mat4::from_translation(Vec3::new(0.0, 0.0, -4.0)));
        let spin = cols(Mat4::from_rotation_x(0.3) * Mat4::from_rotation_z(0.8));
        assert!(!camera_attached(&p, &spin, || false));
    }

    #[test]
    fn eye_space_geometry_under_identity_is_scene_unless_it_writes_no_depth() {
        let (p, identity) = (perspective(), cols(Mat4::IDENTITY));
        assert!(!camera_attached(&p, &identity, || true));
        assert!(camera_attached(&p, &identity, || false));
    }

    #[test]
    fn a_chain_is_attached_by_its_model_view() {
        let p = perspective();
        let sky_view = cols(Mat4::from_rotation_y(0.7) * Mat4::from_rotation_x(0.2));
        let model = cols(Mat4::from_scale(Vec3::splat(50.0)));
        assert!(chain_attached(&[p, sky_view, model], Some(0)));
        let world_view = cols(Mat4::from_rotation_y(0.7) * Mat4::from_translation(Vec3::new(3.0, -2.0, 9.0)));
        assert!(!chain_attached(&[p, world_view, model], Some(0)));
        // Eye-space geometry under the projection alone.
        assert!(!chain_attached(&[p], Some(0)));
        assert!(!chain_attached(&[p, cols(Mat4::IDENTITY)], Some(0)));
    }

    #[test]
    fn a_single_mvp_is_attached_when_its_last_column_has_no_x_y_or_w() {
        let p = Mat4::from_cols_array(&perspective());
        let sky = cols(p * Mat4::from_rotation_y(2.0));
        assert!(chain_attached(&[sky], None));
        let world = cols(p * Mat4::from_rotation_y(2.0) * Mat4::from_translation(Vec3::new(0.0, 0.0, -4.0)));
        assert!(!chain_attached(&[world], None));
        assert!(!chain_attached(&[], None));
    }

    #[test]
    fn degenerate_matrices_are_not_attached() {
        let p = perspective();
        assert!(!camera_attached(&p, &[0.0; 16], || false));
        let mut nan = cols(Mat4::IDENTITY);
        nan[0] = f32::NAN;
        assert!(!camera_attached(&p, &nan, || false));
        assert!(!camera_attached(&[0.0; 16], &cols(Mat4::from_rotation_y(0.3)), || {
            false
        }));
    }
}
