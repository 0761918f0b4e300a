//! Screen-space passes that re-project with the camera (SSAO kernels, screen-space
//! reflections, deferred lighting that rebuilds positions from depth) draw a full-screen quad
//! but use the camera's projection — or its inverse — in their fragment shader. During view
//! i's replay those uniforms get view i's sheared projection `P'_i` (or its inverse), found by
//! value: a tracked `mat4` of the program equal to the main camera's projection.

use crate::gl::*;
use crate::multiview::Multiview;
use crate::state::AppState;

/// A uniform of the current program that holds the camera projection (or its inverse).
#[derive(Clone, Copy, Debug)]
pub struct CameraUniform {
    pub loc: i32,
    pub inverse: bool,
    pub original: [f32; 16],
}

fn close(a: &[f32; 16], b: &[f64; 16]) -> bool {
    let scale = b.iter().fold(0f64, |m, v| m.max(v.abs())).max(1e-30);
    a.iter().zip(b).all(|(x, y)| (*x as f64 - y).abs() <= 1e-5 * scale)
}

/// Fills `out` (emptied first; kept from draw to draw) with the camera-projection uniforms
/// of the current program, when it is a screen-space pass.
pub fn camera_uniforms(app: &AppState, mv: &Multiview, identity: bool, out: &mut Vec<CameraUniform>) {
    out.clear();
    let snapshot = &app.current;
    if !identity || app.program == 0 || snapshot.program != app.program || snapshot.matrices.is_empty() {
        return;
    }
    let Some(p) = mv.camera.camera_projection else { return };
    let p64 = p.map(f64::from);
    let Some(inv) = crate::camera::invert(&p64) else { return };
    out.extend(snapshot.matrices.iter().filter_map(|&(loc, m)| {
        let inverse = close(&m, &inv);
        (inverse || close(&m, &p64)).then_some(CameraUniform {
            loc,
            inverse,
            original: m,
        })
    }));
}

/// Uploads view `i`'s sheared projection (or its inverse); `None`: the app's values back.
pub fn set(gl: &Gl, app: &AppState, mv: &Multiview, uniforms: &[CameraUniform], i: Option<u32>) {
    set_moved(gl, app, mv, uniforms, i.map(|i| (i, 0.0)));
}

/// `set`, view `i`'s image moved by `dh` more (NDC: a guard band's strip).
pub fn set_moved(gl: &Gl, app: &AppState, mv: &Multiview, uniforms: &[CameraUniform], view: Option<(u32, f32)>) {
    let Some(p) = mv.camera.camera_projection else { return };
    for u in uniforms {
        let value = match view {
            None => u.original,
            Some((i, dh)) => {
                let (m, inv) = mv.sheared_camera.moved(&mv.camera.rig, &p, i, dh);
                if u.inverse { inv } else { m }
            }
        };
        // SAFETY: a uniform of the current program, through the real entry point (so our
        // tracking keeps the app's value).
        unsafe { gl.ProgramUniformMatrix4fv(app.program, u.loc, 1, FALSE, value.as_ptr()) };
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn inverse_of_a_projection() {
        let p = [
            1.5, 0., 0., 0., 0., 2.0, 0., 0., 0.1, -0.2, -1.002, -1., 0., 0., -0.2002, 0.,
        ];
        let inv = crate::camera::invert(&p).unwrap();
        for c in 0..4 {
            for r in 0..4 {
                let v: f64 = (0..4).map(|k| p[k * 4 + r] * inv[c * 4 + k]).sum();
                assert!((v - if c == r { 1.0 } else { 0.0 }).abs() < 1e-9);
            }
        }
    }
}
