//! The comfort remap `R` of DESIGN §3 (Agus et al., eq. 1), on the outermost view's disparity.
//!
//! A light-field display is sharp only near its screen plane. `R` leaves the disparity `x`
//! of the outermost view (tile pixels; positive behind the screen) alone on the comfortable
//! range `[-F, B]` and compresses it beyond, towards `-D_F` in front and `D_B` behind. Every
//! view keeps its share `u_i` of it, so views stay evenly spaced and the centre view never
//! moves.
//!
//! ## Which form, and why not the printed one
//! The paper prints, for the side beyond `B`, `B + (z - B) / (1 + (z - B)/(D_B - B))` but
//! applies it where `z < B` with `D_B` a positive distance: there `z - B < 0`, the
//! denominator reaches zero at `z = 2B - D_B` and the curve flips sign (a pole, not an
//! asymptote). Evaluated on the side it is meant for (`t = z - B ≥ 0`) the same rational
//! saturation is what we want: value `B` and slope 1 at the join (`C¹`), strictly increasing,
//! `D_B` as `t → ∞`. We write it `D_B - g²/(t + g)`, `g = D_B - B`, which is the same
//! function but gives `D_B` rather than `∞/∞ = NaN` at `t = ∞`, and mirror it in front of
//! `-F`. A rational tail approaches its asymptote like `1/t`, slower than an exponential
//! one: far content keeps more of its ordering, which is the paper's point of leaving most of
//! the depth perception intact.
//!
//! ## Where it runs
//! The same function is GLSL in `glsl-patches/depth_remap.glsl`: the injected view shift
//! calls it per vertex (`x += w·u_i·R(s(1 - c/w)) + h_i·w`), the synthesis warps per pixel.
//! The shift works in units of parallax `p = 1 - c/w`, so the CPU hands it `R` rescaled by
//! the pixels per unit of parallax ([`DepthRemap::scaled`]); the warps work in pixels.

pub use crate::config::comfort::DepthRemap;

/// `R` and its rescaling (the type is the settings', `config::comfort`; the function is here).
impl DepthRemap {
    /// `R(x)`. Never NaN unless `x` is (then 0: the screen plane).
    pub fn apply(&self, x: f64) -> f64 {
        if x > self.back {
            let g = self.back_limit - self.back;
            self.back_limit - g * (g / ((x - self.back) + g))
        } else if x < -self.front {
            let g = self.front_limit - self.front;
            -(self.front_limit - g * (g / ((-self.front - x) + g)))
        } else if x.is_nan() {
            0.0
        } else {
            x
        }
    }

    /// `x ↦ R(k·x)/k` as a remap of the same form, for `x` in units `k` times smaller (`k`
    /// pixels per unit of parallax); `None` when `k` is zero or not finite (no disparity to
    /// remap). A negative `k` (depthiness < 0, views mirrored) swaps front and back.
    pub fn scaled(&self, k: f64) -> Option<DepthRemap> {
        if k == 0.0 || !k.is_finite() {
            return None;
        }
        let a = k.abs();
        let (f, b, df, db) = (self.front / a, self.back / a, self.front_limit / a, self.back_limit / a);
        Some(if k > 0.0 {
            DepthRemap {
                front: f,
                back: b,
                front_limit: df,
                back_limit: db,
                tile_w: None,
            }
        } else {
            DepthRemap {
                front: b,
                back: f,
                front_limit: db,
                back_limit: df,
                tile_w: None,
            }
        })
    }

    /// The GLSL `vec4 r` of `holoinject_remap(x, r)`.
    pub fn uniform(&self) -> [f32; 4] {
        [self.front, self.back, self.front_limit, self.back_limit].map(|v| v as f32)
    }
}

/// `float holoinject_remap(float x, vec4 r)`: `R` in GLSL, for the injected shift and the
/// synthesis passes.
pub const GLSL: &str = include_str!("../../glsl-patches/depth_remap.glsl");

/// `source` with [`GLSL`] inserted after its first line (`#version`).
pub fn with_glsl(source: &str) -> String {
    let (version, rest) = source.split_once('\n').unwrap_or((source, ""));
    format!("{version}\n{GLSL}{rest}")
}

/// The value of the remap uniform that turns it off (`r.z <= 0`).
pub const REMAP_OFF: [f32; 4] = [0.0; 4];

#[cfg(test)]
#[path = "comfort_tests.rs"]
mod tests;
