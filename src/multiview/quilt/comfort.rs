//! The comfort remap's uniforms for this frame's rig: the settings are read on every draw
//! and warp (`ViewSettings::comfort`), so a change takes effect at once.

use crate::camera::comfort::{DepthRemap, REMAP_OFF};
use crate::multiview::Multiview;

/// Tile pixels of the outermost view's disparity per unit of parallax `1 - c/w`.
pub fn pixels_per_parallax(mv: &Multiview) -> f64 {
    mv.camera.rig.depthiness * tile_w(mv) as f64 / 2.0
}

fn tile_w(mv: &Multiview) -> u32 {
    mv.layout().map_or(0, |l| l.tile_w)
}

/// The range the fade and the depth of field measure from, in pixels of the tiles in use.
pub fn range_pixels(mv: &Multiview) -> DepthRemap {
    mv.settings.comfort.range().for_tile(tile_w(mv))
}

/// `holoinject_comfort` of the injected shift: the remap in units of parallax, or off.
pub fn remap_uniform(mv: &Multiview) -> [f32; 4] {
    mv.settings
        .comfort
        .remap
        .and_then(|r| r.for_tile(tile_w(mv)).scaled(pixels_per_parallax(mv)))
        .map_or(REMAP_OFF, |r| r.uniform())
}

/// The remap in tile pixels, as the warps apply it to the outermost view's disparity, or off.
pub fn remap_pixels(mv: &Multiview) -> [f32; 4] {
    mv.settings
        .comfort
        .remap
        .map_or(REMAP_OFF, |r| r.for_tile(tile_w(mv)).uniform())
}
