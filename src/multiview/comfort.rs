//! The comfort remap's uniforms for this frame's rig: the settings are read on every draw
//! and warp (`ViewSettings::comfort`), so a change takes effect at once.

use super::Multiview;
use crate::camera::comfort::{DepthRemap, REMAP_OFF};

/// Tile pixels of the outermost view's disparity per unit of parallax `1 - c/w`.
pub fn pixels_per_parallax(mv: &Multiview) -> f64 {
    let tile_w = mv.layout().map_or(0, |l| l.tile_w);
    mv.camera.rig.depthiness * tile_w as f64 / 2.0
}

/// `holoinject_comfort` of the injected shift: the remap in units of parallax, or off.
pub fn remap_uniform(mv: &Multiview) -> [f32; 4] {
    mv.settings
        .comfort
        .remap
        .and_then(|r| r.scaled(pixels_per_parallax(mv)))
        .map_or(REMAP_OFF, |r| r.uniform())
}

/// The remap in tile pixels, as the warps apply it to the outermost view's disparity, or off.
pub fn remap_pixels(mv: &Multiview) -> [f32; 4] {
    mv.settings
        .comfort
        .remap
        .as_ref()
        .map_or(REMAP_OFF, DepthRemap::uniform)
}
