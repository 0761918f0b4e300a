//! The programs the synthesis passes link, and which of them a warp needs: every warp starts
//! from the parallax pass; only the quad grid needs its pyramid, leaf, column and warp
//! programs, so the row and per-pixel warps skip compiling four programs.

use crate::gl::{Gl, GlInfo};

pub(super) const FULLSCREEN_VERT: &str = include_str!("../../glsl-patches/fullscreen.vert");
const PARALLAX_FRAG: &str = include_str!("../../glsl-patches/synth_parallax.frag");
const MINMAX_FRAG: &str = include_str!("../../glsl-patches/synth_minmax.frag");
const GRID_COMMON: &str = include_str!("../../glsl-patches/synth_grid_common.glsl");
const LEAVES_COMP: &str = include_str!("../../glsl-patches/synth_leaves.comp");
const COLUMNS_COMP: &str = include_str!("../../glsl-patches/synth_columns.comp");
const WARP_VERT: &str = include_str!("../../glsl-patches/synth_warp.vert");
const WARP_FRAG: &str = include_str!("../../glsl-patches/synth_warp.frag");

/// Program names; 0 for a grid program not linked.
#[derive(Clone, Copy, Debug)]
pub struct Programs {
    pub(super) parallax: u32,
    pub(super) minmax: u32,
    pub(super) leaves: u32,
    pub(super) columns: u32,
    pub(super) warp: u32,
}

/// A compute pass of the grid: `body` with the shared leaf code after its `#version` line.
fn link_grid_pass(gl: &Gl, body: &str) -> Result<u32, String> {
    let (version, rest) = body.split_once('\n').unwrap_or((body, ""));
    crate::gl::program::link_compute(gl, &format!("{version}\n{GRID_COMMON}\n{rest}"))
}

impl Programs {
    /// The parallax pass every warp uses, and with `grid` the quad grid's own passes (the
    /// row and per-pixel warps do without them: four programs fewer to compile).
    pub fn link(gl: &Gl, info: GlInfo, grid: bool) -> Result<Programs, String> {
        let parallax_frag = crate::camera::comfort::with_glsl(PARALLAX_FRAG);
        let link = |frag| crate::gl::program::link(gl, info, FULLSCREEN_VERT, frag);
        let parallax = link(&parallax_frag).map_err(|e| format!("synthesis parallax pass: {e}"))?;
        if !grid {
            return Ok(Programs {
                parallax,
                minmax: 0,
                leaves: 0,
                columns: 0,
                warp: 0,
            });
        }
        Ok(Programs {
            parallax,
            minmax: link(MINMAX_FRAG).map_err(|e| format!("synthesis pyramid pass: {e}"))?,
            leaves: link_grid_pass(gl, LEAVES_COMP).map_err(|e| format!("synthesis grid pass: {e}"))?,
            columns: link_grid_pass(gl, COLUMNS_COMP).map_err(|e| format!("synthesis column pass: {e}"))?,
            warp: crate::gl::program::link(gl, info, WARP_VERT, WARP_FRAG)
                .map_err(|e| format!("synthesis warp pass: {e}"))?,
        })
    }

    pub fn has_grid(&self) -> bool {
        self.warp != 0
    }

    pub fn names(&self) -> Vec<u32> {
        [self.parallax, self.minmax, self.leaves, self.columns, self.warp]
            .into_iter()
            .filter(|&p| p != 0)
            .collect()
    }
}
