//! How precise the projection estimate and the view shift are at the extremes users reach
//! (tiny near planes, huge far planes or none, reversed depth, 1°–170° fields of view,
//! cameras far from the origin), in f64 (our estimate) and in the f32 the GPU computes with.
//! `table()` is printed by `cargo test --release --lib camera::precision -- --nocapture` and
//! quoted in the README; the tests assert the bounds stated there.

use super::rig::ViewRig;

pub use super::matrix::perspective;

/// A rigid view: rotation about y by `yaw` degrees, then translation, then uniform scale.
pub fn view(yaw_deg: f64, t: [f64; 3], scale: f64) -> [f64; 16] {
    let (s, c) = yaw_deg.to_radians().sin_cos();
    [
        c * scale,
        0.,
        -s * scale,
        0.,
        0.,
        scale,
        0.,
        0.,
        s * scale,
        0.,
        c * scale,
        0.,
        t[0],
        t[1],
        t[2],
        1.,
    ]
}

pub fn mul(a: &[f64; 16], b: &[f64; 16]) -> [f64; 16] {
    let mut m = [0.0; 16];
    for c in 0..4 {
        for r in 0..4 {
            m[c * 4 + r] = (0..4).map(|k| a[k * 4 + r] * b[c * 4 + k]).sum();
        }
    }
    m
}

pub fn apply(m: &[f64; 16], p: [f64; 4]) -> [f64; 4] {
    std::array::from_fn(|r| (0..4).map(|k| m[k * 4 + r] * p[k]).sum())
}

fn apply32(m: &[f32; 16], p: [f32; 4]) -> [f32; 4] {
    std::array::from_fn(|r| (0..4).map(|k| m[k * 4 + r] * p[k]).sum())
}

/// One row of the table: worst relative error of the linearised depth `w` — estimated from the
/// exact matrix with f64 clip coordinates, and from the app's f32 matrix with the f32 clip
/// coordinates a GPU computes — and worst error of view N-1's shift in pixels of a 420-px
/// tile (f32 shader arithmetic against f64).
#[derive(Debug, Clone)]
pub struct Row {
    pub case: &'static str,
    pub depth_f64: f64,
    pub depth_f32: f64,
    pub shift_px_f32: f64,
}

fn measure(case: &'static str, p: [f64; 16], v: [f64; 16], depths: &[f64]) -> Row {
    let m = mul(&p, &v);
    // What the layer sees is the app's f32 upload: the model from the f32-rounded matrix.
    let range = classify_f64(&m.map(|x| x as f32 as f64));
    let exact = classify_f64(&m);
    let inv_v = super::matrix::invert(&v).expect("invertible view");
    let k = rig_for(depths).params(47);
    let (mut e64, mut e32, mut shift) = (0f64, 0f64, 0f64);
    for &d in depths {
        // A point straight ahead at eye distance d, in world coordinates.
        let world = point(&inv_v, d);
        let clip = apply(&m, world);
        let w = clip[3];
        e64 = e64.max((exact.w_of_ndc(clip[2] / w) - w).abs() / w);
        let c32 = apply32(&m.map(|x| x as f32), world.map(|x| x as f32));
        let w32 = range.w_of_ndc((c32[2] / c32[3]) as f64);
        e32 = e32.max((w32 - w).abs() / w);
        let x64 = clip[0] + k.k as f64 * (w - k.c as f64);
        let x32 = c32[0] + k.k * (c32[3] - k.c);
        shift = shift.max(((x32 / c32[3]) as f64 - x64 / w).abs() * 210.0);
    }
    Row {
        case,
        depth_f64: e64,
        depth_f32: e32,
        shift_px_f32: shift,
    }
}

fn classify_f64(m: &[f64; 16]) -> super::projection::DepthRange {
    // The same model as `classify`, on the exact matrix (row2 = -a·row3 + b·e3).
    let q = [m[3], m[7], m[11]];
    let qq: f64 = q.iter().map(|v| v * v).sum();
    let a = -(m[2] * q[0] + m[6] * q[1] + m[10] * q[2]) / qq;
    super::projection::DepthRange {
        a,
        b: m[14] + a * m[15],
    }
}

fn spread(near: f64, far: f64) -> Vec<f64> {
    (0..=20)
        .map(|i| near * (far / near).powf(i as f64 / 20.0))
        .map(|d| d.clamp(near * 1.001, far * 0.999))
        .collect()
}

/// One extreme setup: projection, view, and the eye distances of the test points.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: &'static str,
    pub p: [f64; 16],
    pub v: [f64; 16],
    pub depths: Vec<f64>,
}

/// The setups of the table (also run on Mesa by `tests/shift_on_mesa.rs`).
pub fn cases() -> Vec<Case> {
    let eye = view(0.0, [0.0, 0.0, 0.0], 1.0);
    vec![
        Case {
            name: "ordinary: 60°, near 0.1, far 100",
            p: perspective(60.0, 1.5, 0.1, Some(100.0), false),
            v: eye,
            depths: spread(0.1, 100.0),
        },
        Case {
            name: "near 1e-4, far 1e7",
            p: perspective(60.0, 1.5, 1e-4, Some(1e7), false),
            v: eye,
            depths: spread(1e-4, 1e7),
        },
        Case {
            name: "infinite far, near 0.01",
            p: perspective(60.0, 1.5, 0.01, None, false),
            v: eye,
            depths: spread(0.01, 1e6),
        },
        Case {
            name: "reversed-Z [0,1], near 0.01, far 1e5",
            p: perspective(60.0, 1.5, 0.01, Some(1e5), true),
            v: eye,
            depths: spread(0.01, 1e5),
        },
        Case {
            name: "reversed-Z, infinite far",
            p: perspective(60.0, 1.5, 0.01, None, true),
            v: eye,
            depths: spread(0.01, 1e6),
        },
        Case {
            name: "fov 1°",
            p: perspective(1.0, 1.5, 0.1, Some(1000.0), false),
            v: eye,
            depths: spread(0.1, 1000.0),
        },
        Case {
            name: "fov 170°",
            p: perspective(170.0, 1.5, 0.1, Some(1000.0), false),
            v: eye,
            depths: spread(0.1, 1000.0),
        },
        Case {
            name: "camera 1e6 from origin, yaw 30°, scale 3",
            p: perspective(60.0, 1.5, 0.1, Some(1000.0), false),
            v: view(30.0, [1e6, -2e5, 7e5], 3.0),
            depths: spread(0.1, 1000.0),
        },
    ]
}

pub fn table() -> Vec<Row> {
    cases()
        .into_iter()
        .map(|c| measure(c.name, c.p, c.v, &c.depths))
        .collect()
}

/// The rig every precision figure uses: 48 views, depthiness 0.45, convergence at the
/// middle test depth; view 47 (the outermost) is measured.
pub fn rig_for(depths: &[f64]) -> ViewRig {
    ViewRig {
        views: 48,
        depthiness: 0.45,
        convergence: depths[depths.len() / 2],
        focus: 0.0,
    }
}

/// Test point `j` of a case, in world coordinates: straight ahead (slightly off-axis) at eye
/// distance `d`.
pub fn point(inv_view: &[f64; 16], d: f64) -> [f64; 4] {
    apply(inv_view, [0.3 * d * 0.01, -0.2 * d * 0.01, -d, 1.0])
}

/// The stated bound (README) for depth linearised from exact clip coordinates at every
/// extreme of the table (the worst, near 1e-4 / far 1e7, is ~2e-6); what f32 clip
/// coordinates allow is recorded in the table, not bounded: it is the GPU's own precision.
pub const F64_DEPTH_BOUND: f64 = 1e-5;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::projection::{ProjectionKind, classify};
    use proptest::prelude::*;

    #[test]
    fn precision_table_within_bounds() {
        eprintln!(
            "| case | depth w rel. error, f64 | depth w rel. error, from f32 clip | view shift error (px, 420-px tile, f32) |"
        );
        eprintln!("|---|---|---|---|");
        let rows = table();
        for r in &rows {
            eprintln!(
                "| {} | {:.1e} | {:.1e} | {:.1e} |",
                r.case, r.depth_f64, r.depth_f32, r.shift_px_f32
            );
            // Linearising z/w is conditioned by far/near: exact projections stay within the
            // bound below everywhere; an ordinary one is near machine precision.
            assert!(r.depth_f64 < F64_DEPTH_BOUND, "{r:?}");
        }
        assert!(
            rows[0].depth_f64 < 1e-12 && rows[0].depth_f32 < 1e-3 && rows[0].shift_px_f32 < 0.01,
            "{:?}",
            rows[0]
        );
    }

    proptest! {
        /// Any perspective P·V with a rigid, uniformly scaled view is classified perspective,
        /// and the depth model recovered from it is P's own (a, b). Recovering b subtracts
        /// a·t_z from row2[3], so with a camera far from the origin it is only as good as
        /// f64 cancellation allows: the bound is 1e-12 relative, times the conditioning
        /// |a·t_z| / |b| (found and documented here: at t = 1e7 and near = 1e-5 that is ~1e-4).
        #[test]
        fn depth_model_holds_over_the_parameter_space(
            fovy in 0.5f64..170.0,
            aspect in 0.2f64..5.0,
            near_exp in -5.0f64..1.0,
            far_ratio_exp in 0.5f64..9.0,
            infinite in any::<bool>(),
            reversed in any::<bool>(),
            yaw in -180.0f64..180.0,
            tx in -1e7f64..1e7,
            tz in -1e7f64..1e7,
            scale_exp in -2.0f64..2.0,
        ) {
            let near = 10f64.powf(near_exp);
            let far = (!infinite).then(|| near * 10f64.powf(far_ratio_exp));
            let p = perspective(fovy, aspect, near, far, reversed);
            let v = view(yaw, [tx, 0.5 * tx, tz], 10f64.powf(scale_exp));
            let m = mul(&p, &v);
            prop_assert_eq!(classify(&m.map(|x| x as f32)).map(|c| c.kind), Some(ProjectionKind::Perspective));
            let got = classify_f64(&m);
            let (a, b) = (p[10], p[14]);
            let t_eye = m[15].abs().max(1.0);
            let cond = 1.0 + (a * t_eye).abs() / b.abs();
            prop_assert!((got.a - a).abs() <= 1e-12 * cond * (a.abs() + 1.0), "a {} vs {a}", got.a);
            prop_assert!((got.b - b).abs() <= 1e-12 * cond * b.abs(), "b {} vs {b} (cond {cond:e})", got.b);
        }

        /// The clip-space shift equals re-projecting with the sheared projection P'_i.
        #[test]
        fn shift_equals_sheared_projection(
            fovy in 0.5f64..170.0, near_exp in -5.0f64..1.0, i in 0u32..48,
            s in -1.0f64..1.0, c_exp in -3.0f64..6.0, x in -1e3f64..1e3, d_exp in -4.0f64..7.0,
        ) {
            let p = perspective(fovy, 1.3, 10f64.powf(near_exp), None, false);
            let rig = ViewRig { views: 48, depthiness: s, convergence: 10f64.powf(c_exp), focus: 0.0 };
            let point = [x, 0.0, -10f64.powf(d_exp), 1.0];
            let clip = apply(&p, point);
            let v = rig.params(i);
            let shifted = clip[0] + v.k as f64 * (clip[3] - v.c as f64);
            let sheared = apply(&rig.shear(i, &p), point)[0];
            prop_assert!((shifted - sheared).abs() <= 1e-9 * shifted.abs().max(clip[3].abs()).max(1.0));
        }

        /// Orthographic projections are never taken for perspective, whatever view follows.
        #[test]
        fn orthographic_through_any_view(w in 1.0f64..1e5, yaw in -180.0f64..180.0, t in -1e6f64..1e6) {
            let ortho = [2.0 / w, 0., 0., 0., 0., 2.0 / w, 0., 0., 0., 0., -0.001, 0., -1., -1., 0., 1.];
            let m = mul(&ortho, &view(yaw, [t, t, t], 1.0));
            prop_assert_eq!(classify(&m.map(|x| x as f32)).map(|c| c.kind), Some(ProjectionKind::Orthographic));
        }
    }
}
