//! The scene's depth where the disparity record knows better (DESIGN §5: one disparity per
//! pixel). Auto-convergence and `--mode auto` read the centre view's depth through the
//! scene's depth model; a pixel the record covers is given instead the window depth that
//! model assigns its recorded parallax, so a weapon in its own depth range counts where
//! exact mode shows it, a sky at infinity as background, and a composite's quad not at all.

use crate::camera::projection::DepthRange;
use crate::gl::Gl;
use crate::multiview::Multiview;
use crate::synth::disparity::ParallaxModel;

/// Parallax at or above this is infinity: the background, as the far clear is.
const INFINITY_PARALLAX: f32 = 1.0 - 1e-6;

/// Replaces `depths` (window depth, `[-1,1]` convention, rows bottom-up) where `record`
/// (`read`, the same pixels) holds a parallax. Returns how many.
pub fn substitute(mv: &Multiview, range: DepthRange, record: &[f32], depths: &mut [f32]) -> usize {
    let Some(model) = ParallaxModel::new(range, mv.camera.rig.convergence).filter(|m| m.scale != 0.0) else {
        return 0;
    };
    let mut n = 0;
    for (d, r) in depths.iter_mut().zip(record.chunks_exact(2)) {
        // Exactly 0 is an overlay's (a HUD recorded on the screen plane when the warps need
        // it, `replay::draw`): not the scene, so the scene's depth stands there, as it does
        // when nothing recorded.
        if r[1] > 0.5 && r[0] != 0.0 {
            *d = window_depth(model, r[0]);
            n += 1;
        }
    }
    n
}

/// The record of `rect` of view `view`'s scene target, `(p, recorded)` per pixel of the rows
/// the depth copy kept, when it has one and it matches `pixels`.
pub fn read(gl: &Gl, mv: &mut Multiview, view: u32, rect: [i32; 4], pixels: usize) -> Option<Vec<f32>> {
    let (fbo, _) = crate::multiview::quilt::record::source(gl, mv, view, rect)?;
    let record = mv.scene.copy.read_record(gl, mv.info, fbo, rect);
    (record.len() == pixels * 2).then_some(record)
}

/// No projection read (`--log debug` says why per program): the depth model fitted to the
/// recorded parallax and the depth of the same pixels (`camera::depth_fit`), at the
/// convergence the frame was drawn with. Said once at `info`.
pub fn fit_depth_model(mv: &Multiview, record: &[f32], depths: &[f32]) -> Option<DepthRange> {
    let c = mv.camera.rig.convergence;
    let samples = record
        .chunks_exact(2)
        .zip(depths)
        .filter(|(r, _)| r[1] > 0.5)
        .map(|(r, &d)| (r[0], d));
    if crate::log::enabled(crate::log::Level::Trace) {
        let recorded: Vec<(f32, f32)> = samples.clone().collect();
        let (lo, hi) = recorded
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &(p, _)| {
                (lo.min(p), hi.max(p))
            });
        crate::log::trace(format_args!(
            "depth fit: {} of {} pixels recorded, parallax {lo}..{hi}, convergence {c}",
            recorded.len(),
            depths.len()
        ));
    }
    let fitted = crate::camera::depth_fit::fit(samples, c);
    match fitted {
        Some(f) => crate::log::once_for(
            ("depth-fitted", 0),
            crate::log::Level::Info,
            format_args!(
                "depth model fitted to what the program draws (no projection with the draw's depth terms was \
                 read), recorded parallax against depth at {} of {} pixels: near {:.6}, far {:.6}",
                f.inliers,
                f.candidates,
                f.range.near(),
                f.range.far()
            ),
        ),
        None => crate::log::once_for(
            ("depth-unfitted", 0),
            crate::log::Level::Debug,
            format_args!(
                "projection unknown and not yet fitted to what the program draws (too few recorded pixels, or \
                 all at one distance): auto-convergence, the warps and comfort wait for it"
            ),
        ),
    }
    fitted.map(|f| f.range)
}

/// The window depth (`[-1,1]` convention) at which the scene's model gives parallax `p`.
fn window_depth(m: ParallaxModel, p: f32) -> f32 {
    let far = if m.reversed { 0.0 } else { 1.0 };
    if !p.is_finite() || p >= INFINITY_PARALLAX {
        return far;
    }
    let z = f64::from(1.0 - p) / f64::from(m.scale) - f64::from(m.a_hi) - f64::from(m.a_lo);
    ((z + 1.0) / 2.0).clamp(0.0, 1.0) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recorded_parallax_comes_back_as_the_depth_of_its_distance() {
        let r = DepthRange::frustum(0.1, 100.0);
        let c = 5.0;
        let m = ParallaxModel::new(r, c).unwrap();
        for w in [0.2, 1.0, 5.0, 40.0] {
            let p = (1.0 - c / w) as f32;
            let d = window_depth(m, p);
            let back = r.w_of_ndc(2.0 * f64::from(d) - 1.0);
            assert!((back - w).abs() / w < 1e-4, "w {w}: came back as {back}");
        }
    }

    #[test]
    fn infinity_is_the_background_and_nothing_is_nearer_than_the_near_plane() {
        let r = DepthRange::frustum(0.1, 100.0);
        let m = ParallaxModel::new(r, 5.0).unwrap();
        assert_eq!(window_depth(m, 1.0), 1.0);
        // Beyond the far plane (a sky at 1e6) is the background too.
        assert_eq!(window_depth(m, (1.0 - 5.0 / 1e6) as f32), 1.0);
        assert_eq!(window_depth(m, -1e9), 0.0);
    }
}
