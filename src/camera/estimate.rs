//! What the layer knows of the app's main camera in one context, learned from the draws it
//! has seen (projections classified per draw, depth read back at the swap), and the view rig
//! derived from it and the settings.

use super::projection::DepthRange;
use super::rig::ViewRig;
use crate::config::{Convergence, ViewSettings};

#[derive(Clone, Debug)]
pub struct CameraEstimate {
    pub rig: ViewRig,
    /// Smoothed auto-convergence estimate (w units), once the scene has been seen.
    pub auto_convergence: Option<f64>,
    /// Depth model of the last perspective projection seen (for auto-convergence), or the
    /// one fitted to what the program draws (`depth_fitted`).
    pub last_depth: Option<DepthRange>,
    /// `last_depth` came from `depth_fit`, no projection having been read: fitted again each
    /// frame, replaced by the first projection read.
    pub depth_fitted: bool,
    /// The main camera's bare projection (row3 = (0,0,-s,0)), for screen-space passes.
    pub camera_projection: Option<[f32; 16]>,
    /// Horizontal focal scale of that projection (for `--view-cone`).
    pub last_fx: Option<f64>,
}

impl CameraEstimate {
    /// Nothing seen yet: `views` views in tiles `tile_w` pixels wide.
    pub fn new(settings: &ViewSettings, views: u32, tile_w: u32) -> CameraEstimate {
        let mut c = CameraEstimate {
            rig: ViewRig {
                views,
                depthiness: 0.0,
                convergence: 1.0,
                focus: settings.focus,
            },
            auto_convergence: None,
            last_depth: None,
            depth_fitted: false,
            camera_projection: None,
            last_fx: None,
        };
        c.update_rig(settings, views, tile_w);
        c
    }

    /// Depthiness and convergence for the current layout and scene (DESIGN §3 defaults).
    pub fn update_rig(&mut self, settings: &ViewSettings, views: u32, tile_w: u32) {
        self.rig.views = views;
        self.rig.focus = settings.focus;
        self.rig.depthiness = depthiness(settings.depthiness, settings.view_cone, self.last_fx, views, tile_w);
        self.rig.convergence = match settings.convergence {
            Convergence::Fixed(c) => c,
            Convergence::Auto => self.auto_convergence.unwrap_or_else(|| self.fallback_convergence()),
        };
    }

    /// Before the scene's depth has been seen: the geometric mean of near and far when the
    /// projection is known, else one unit.
    fn fallback_convergence(&self) -> f64 {
        self.last_depth
            .map(|d| {
                let far = if d.far().is_finite() { d.far() } else { d.near() * 1e4 };
                (d.near().max(1e-6) * far).sqrt()
            })
            .filter(|c| c.is_finite() && *c > 0.0)
            .unwrap_or(1.0)
    }
}

/// `--depthiness` as given; else from `--view-cone` (s = Fx·tan(cone/2), DESIGN §3) once
/// the projection's `Fx` is known; else 4 px between neighbouring views at infinity.
pub fn depthiness(given: Option<f64>, cone_deg: Option<f64>, fx: Option<f64>, views: u32, tile_w: u32) -> f64 {
    match (given, cone_deg, fx) {
        (Some(s), _, _) => s,
        (None, Some(cone), Some(fx)) => fx * (cone.to_radians() / 2.0).tan(),
        _ => ViewRig::depthiness_for_disparity(4.0, views, tile_w),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depthiness_from_option_cone_or_default() {
        assert_eq!(depthiness(Some(0.3), Some(40.0), Some(2.0), 48, 420), 0.3);
        let s = depthiness(None, Some(40.0), Some(2.0), 48, 420);
        assert!((s - 2.0 * 20f64.to_radians().tan()).abs() < 1e-12);
        // Cone without a known projection: the pixel default, not garbage.
        assert!((depthiness(None, Some(40.0), None, 48, 420) - 4.0 * 47.0 / 420.0).abs() < 1e-12);
    }
}
