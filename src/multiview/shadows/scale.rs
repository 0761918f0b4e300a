//! The resolution of layered images (`--fbo-scale`).
//!
//! A view shown in a 256x256 tile gains nothing from off-screen passes drawn at the program's
//! 800x600: on llvmpipe those layers are most of the frame time. With `tile` (or a factor)
//! every layer of a shadowed framebuffer is smaller than the app's object by the same factors
//! `(sx, sy)`, and everything the app addresses in pixels of that framebuffer is mapped into
//! it: viewport, scissor, blit rectangles, `gl_FragCoord` (through the same uniform that maps
//! it back from tiles), reads (the centre layer, scaled back up). Sampling with normalised
//! coordinates needs nothing; `textureSize` answers the layer's size, so kernels written in
//! texels (blur steps of `1 / textureSize`) keep their size in texels, as they would if the
//! window were the tile. Programs whose integer texel addressing cannot be mapped (see
//! `shader::fragcoord::pixel_addressing`, `downscale`) keep their framebuffers' layers at the
//! app's size.
//!
//! Only images whose size follows the window's are scaled: the window's size, a chain of
//! halvings of it (bloom's and blur's mip-like chains), rounded either way, or a doubling or
//! quadrupling of it (a pass drawn supersampled: glmark2's refract draws its distance map at
//! twice the window, which at the tile's size is twice the tile, as the program itself does
//! when run at that size). An image of a
//! size of its own (a 256x256 luminance target, a 1x1 average, a 2048² shadow map, a lookup
//! table) is not part of the picture's resolution: scaling it would change what the program
//! computes (OpenArena's auto-exposure went dark), so its framebuffer keeps the app's size.
//!
//! The factors are fixed per image when it is made: a later window resize changes what new
//! images get, and each shadow maps with its own images' factors.

use crate::config::FboScale;

/// Halvings of the window an image may be and still count as following it (1/64: below, a
/// chain ends in a few pixels that are the program's reduction, not its picture).
const MAX_HALVINGS: u32 = 6;
/// Doublings of the window (4x: supersampling beyond that is a size chosen for its own sake).
const MAX_DOUBLINGS: u32 = 2;

/// Factors from the app's framebuffer pixels to its layers' (each in (0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerScale {
    pub sx: f64,
    pub sy: f64,
}

impl LayerScale {
    pub const ONE: LayerScale = LayerScale { sx: 1.0, sy: 1.0 };

    /// The factors `setting` gives for a `window`-sized program shown in `tile`-sized views.
    pub fn new(setting: FboScale, window: (u32, u32), tile: (u32, u32)) -> LayerScale {
        let fit = |t: u32, w: u32| (f64::from(t) / f64::from(w.max(1))).min(1.0);
        match setting {
            FboScale::Window => LayerScale::ONE,
            FboScale::Tile => LayerScale {
                sx: fit(tile.0, window.0),
                sy: fit(tile.1, window.1),
            },
            FboScale::Factor(f) => LayerScale { sx: f, sy: f },
        }
    }

    /// Whether an image of `size` follows a window of `window`: the window's size divided by
    /// 2^k (k ≤ MAX_HALVINGS), rounded down or up, or multiplied by 2^k (k ≤ MAX_DOUBLINGS),
    /// in both directions with the same k.
    pub fn follows_window(size: (i32, i32), window: (u32, u32)) -> bool {
        let halves = |v: i32, w: u32, k: u32| {
            let (w, d) = (i64::from(w), 1i64 << k);
            let v = i64::from(v);
            v == w / d || v == (w + d - 1) / d
        };
        let doubles = |v: i32, w: u32, k: u32| i64::from(v) == i64::from(w) << k;
        (0..=MAX_HALVINGS).any(|k| halves(size.0, window.0, k) && halves(size.1, window.1, k))
            || (1..=MAX_DOUBLINGS).any(|k| doubles(size.0, window.0, k) && doubles(size.1, window.1, k))
    }

    pub fn is_one(self) -> bool {
        self == LayerScale::ONE
    }

    /// The layer size for an app image of `(w, h)`: `ceil(size * s)`, at least 1 (a product
    /// that is an integer up to rounding, 600 * (256/600), stays that integer).
    pub fn size(self, (w, h): (i32, i32)) -> (i32, i32) {
        let up = |v: i32, s: f64| ((f64::from(v) * s - 1e-6).ceil() as i32).max(1);
        (up(w, self.sx), up(h, self.sy))
    }

    /// A rectangle `[x, y, w, h]` in app pixels, in layer pixels as floats (viewports).
    pub fn rect_f(self, r: [i32; 4]) -> [f32; 4] {
        let (sx, sy) = (self.sx as f32, self.sy as f32);
        [r[0] as f32 * sx, r[1] as f32 * sy, r[2] as f32 * sx, r[3] as f32 * sy]
    }

    /// A rectangle `[x, y, w, h]` in app pixels, as the layer pixels it covers (scissors:
    /// every pixel partly inside stays in).
    pub fn rect_out(self, r: [i32; 4]) -> [i32; 4] {
        let lo = |v: i32, s: f64| (f64::from(v) * s + 1e-6).floor() as i32;
        let hi = |v: i32, s: f64| (f64::from(v) * s - 1e-6).ceil() as i32;
        let (x0, y0) = (lo(r[0], self.sx), lo(r[1], self.sy));
        let (x1, y1) = (hi(r[0] + r[2], self.sx), hi(r[1] + r[3], self.sy));
        [x0, y0, (x1 - x0).max(0), (y1 - y0).max(0)]
    }

    /// Blit corners `[x0, y0, x1, y1]` in app pixels, rounded to the nearest layer pixel
    /// (both ends of a same-size blit between two layers of one scale stay the same size).
    pub fn corners(self, c: [i32; 4]) -> [i32; 4] {
        let r = |v: i32, s: f64| (f64::from(v) * s).round() as i32;
        [r(c[0], self.sx), r(c[1], self.sy), r(c[2], self.sx), r(c[3], self.sy)]
    }

    /// The `holoinject_fragcoord` value that maps a layer's `gl_FragCoord` back to the app's
    /// pixels.
    pub fn fragcoord(self) -> [f32; 4] {
        [0.0, 0.0, (1.0 / self.sx) as f32, (1.0 / self.sy) as f32]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_maps_the_window_to_the_tile_and_never_upscales() {
        let s = LayerScale::new(FboScale::Tile, (800, 600), (256, 256));
        assert_eq!(s.size((800, 600)), (256, 256));
        assert_eq!(s.size((400, 300)), (128, 128));
        assert_eq!(s.size((801, 600)), (257, 256));
        assert_eq!(LayerScale::new(FboScale::Tile, (200, 100), (256, 256)), LayerScale::ONE);
        assert!(LayerScale::new(FboScale::Window, (800, 600), (256, 256)).is_one());
    }

    #[test]
    fn images_follow_the_window_by_halvings_and_doublings_only() {
        let w = (800, 600);
        for size in [
            (800, 600),
            (400, 300),
            (200, 150),
            (100, 75),
            (50, 38),
            (50, 37),
            (25, 19),
            (13, 10),
            (1600, 1200),
            (3200, 2400),
        ] {
            assert!(LayerScale::follows_window(size, w), "{size:?}");
        }
        // Fixed sizes: a luminance target, a 1x1 average, a shadow map, mixed halvings and
        // doublings, a doubling past 4x.
        for size in [
            (256, 256),
            (128, 128),
            (1, 1),
            (2048, 2048),
            (400, 600),
            (1600, 600),
            (1601, 1200),
            (6400, 4800),
            (799, 600),
        ] {
            assert!(!LayerScale::follows_window(size, w), "{size:?}");
        }
        assert!(LayerScale::follows_window((961, 541), (1921, 1081)));
        assert!(LayerScale::follows_window((960, 540), (1921, 1081)));
    }

    #[test]
    fn factor_halves() {
        let s = LayerScale::new(FboScale::Factor(0.5), (800, 600), (256, 256));
        assert_eq!(s.size((800, 600)), (400, 300));
        assert_eq!(s.size((1, 1)), (1, 1));
        assert_eq!(s.rect_f([0, 0, 800, 600]), [0.0, 0.0, 400.0, 300.0]);
        assert_eq!(s.rect_out([1, 1, 3, 3]), [0, 0, 2, 2]);
        assert_eq!(s.corners([0, 0, 800, 600]), [0, 0, 400, 300]);
        assert_eq!(s.fragcoord(), [0.0, 0.0, 2.0, 2.0]);
    }
}
