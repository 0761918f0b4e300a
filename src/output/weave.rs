//! CPU reference of the native lenticular weave (DESIGN §4); `glsl-patches/lenticular.frag`
//! is the same mapping, line for line, so this file is what the GPU pass is checked against.
//!
//! Conventions: `(x, y)` is an output pixel in GL window coordinates (y counted from the
//! bottom, like `gl_FragCoord - 0.5`); `u, v` are its centre in [0, 1]. Per colour channel:
//! `phase = (u + dx + (v + dy) * tilt) * pitch' - center`, `f = fract(phase)`,
//! `view = (invView ? 1 - f : f) * N`. Classic panels use `(dx, dy) = (slot * subp, 0)`, where
//! the sub-pixel slot is the channel, R and B swapped by `flipSubp` (panels with BGR stripes).
//! Gen3 panels replace `(dx, dy)` by the offsets of the pixel's sub-pixel cell (below).
//!
//! Gen3 cells, as Looking Glass Bridge's shader does it (`lent_lent.glsl` mappings, also in
//! the public `@lookingglass/webxr` shader): the cell of a pixel is chosen by `CellPatternMode`
//! from its integer position, y bottom-up: 0: cell 0; 1: checkerboard `(x + y) % 2`;
//! 2: `y % 4`; 3: `(y + 2 * (x % 2)) % 4`; 4: `x % 2`; then taken modulo the number of cells.
//! The offsets are in pixels, divided by screenW / screenH (done in `weave_params`), and the
//! y offset is scaled by tilt with `v`. They name colours, so `flipSubp` does not apply to them.
//!
//! View `k` is taken to sit at position `k`: `Nearest` samples `floor(view)`, `BlendNext`
//! mixes it with the next view, `Gaussian` weighs views by their distance to `view`. Views are
//! never wrapped from N-1 to 0: the two ends of the view cone are the most different images.

pub use crate::config::WeaveFilter as Filter;
use crate::config::calibration::WeaveParams;

/// The largest `f32` below 1: `fract` can round up to 1 and `1 - fract` is 1 at 0.
const ONE_BELOW: f32 = 0.999_999_94;
/// Gaussian taps reach at most this many views either side (the shader's loop bound).
pub const MAX_GAUSSIAN_RADIUS: i32 = 8;
const MAX_TAPS: usize = 2 * MAX_GAUSSIAN_RADIUS as usize + 2;

/// The Gen3 cell of pixel `(x, y)`, `None` on a classic panel.
pub fn cell_index(params: &WeaveParams, x: u32, y: u32) -> Option<usize> {
    if params.cells.is_empty() {
        return None;
    }
    let cell = match params.cell_pattern {
        1 => (x + y) % 2,
        2 => y % 4,
        3 => (y + 2 * (x % 2)) % 4,
        4 => x % 2,
        _ => 0,
    };
    Some(cell as usize % params.cells.len())
}

/// `(dx, dy)` of channel `ch` of pixel `(x, y)`, in `u, v` units.
pub fn subpixel_offset(params: &WeaveParams, x: u32, y: u32, ch: usize) -> (f32, f32) {
    match cell_index(params, x, y) {
        Some(cell) => (params.cells[cell][2 * ch], params.cells[cell][2 * ch + 1]),
        None => {
            let slot = if params.flip_subp { 2 - ch } else { ch };
            (slot as f32 * params.subp, 0.0)
        }
    }
}

/// The fractional view, in [0, N), seen through channel `ch` of output pixel `(x, y)`.
pub fn view_for(params: &WeaveParams, x: u32, y: u32, width: u32, height: u32, ch: usize) -> f32 {
    let u = (x as f32 + 0.5) / width as f32;
    let v = (y as f32 + 0.5) / height as f32;
    let (dx, dy) = subpixel_offset(params, x, y, ch);
    let phase = (u + dx + (v + dy) * params.tilt) * params.pitch - params.center;
    let f = phase - phase.floor();
    let f = if params.inv_view { 1.0 - f } else { f };
    f.clamp(0.0, ONE_BELOW) * params.view_count as f32
}

/// The views a filter reads for fractional view `view` of `n`, with weights summing to 1;
/// returns how many of `taps` are filled.
pub fn taps(view: f32, n: u32, filter: Filter, taps: &mut [(u32, f32); MAX_TAPS]) -> usize {
    let last = n.saturating_sub(1);
    let k0 = (view as u32).min(last);
    match filter {
        Filter::Nearest => {
            taps[0] = (k0, 1.0);
            1
        }
        Filter::BlendNext => {
            let t = view - k0 as f32;
            taps[0] = (k0, 1.0 - t);
            taps[1] = ((k0 + 1).min(last), t);
            2
        }
        Filter::Gaussian { sigma } => gaussian_taps(view, k0, last, sigma, taps),
    }
}

fn gaussian_taps(view: f32, k0: u32, last: u32, sigma: f32, taps: &mut [(u32, f32); MAX_TAPS]) -> usize {
    let radius = ((3.0 * sigma).ceil() as i32).clamp(1, MAX_GAUSSIAN_RADIUS);
    let (mut count, mut total) = (0, 0.0);
    for k in (k0 as i32 - radius)..=(k0 as i32 + radius + 1) {
        if k < 0 || k > last as i32 {
            continue;
        }
        let d = view - k as f32;
        let w = (-d * d / (2.0 * sigma * sigma)).exp();
        taps[count] = (k as u32, w);
        total += w;
        count += 1;
    }
    if total.is_nan() || total <= 1e-20 {
        // A sigma far below one view: every weight underflowed; that is Nearest.
        taps[0] = (k0, 1.0);
        return 1;
    }
    taps[..count].iter_mut().for_each(|t| t.1 /= total);
    count
}

/// A quilt as the weave reads it: top-down RGB, view `i` at column `i % cols` and row
/// `i / cols` counted from the bottom; tiles of `width / cols` x `height / rows` pixels, any
/// leftover columns at the right and rows at the top unused (as GL's bottom-left origin has it).
struct Quilt<'a> {
    rgb: &'a [u8],
    width: u32,
    height: u32,
    cols: u32,
    tile_w: u32,
    tile_h: u32,
}

impl Quilt<'_> {
    /// Channel `ch` of view `view` at tile coordinates `(u, v)`, nearest texel.
    fn texel(&self, view: u32, u: f32, v: f32, ch: usize) -> f32 {
        let tx = ((u * self.tile_w as f32) as u32).min(self.tile_w - 1);
        let ty = ((v * self.tile_h as f32) as u32).min(self.tile_h - 1);
        let qx = (view % self.cols) * self.tile_w + tx;
        let qy_from_bottom = (view / self.cols) * self.tile_h + ty;
        let row = (self.height - 1 - qy_from_bottom) as usize;
        f32::from(self.rgb[(row * self.width as usize + qx as usize) * 3 + ch])
    }
}

/// Weaves a quilt into a top-down RGB image of `out_w x out_h` for the display in `params`.
#[allow(clippy::too_many_arguments)]
pub fn weave_cpu(
    quilt_rgb: &[u8],
    quilt_w: u32,
    quilt_h: u32,
    cols: u32,
    rows: u32,
    params: &WeaveParams,
    filter: Filter,
    out_w: u32,
    out_h: u32,
) -> Vec<u8> {
    assert!(
        quilt_rgb.len() >= quilt_w as usize * quilt_h as usize * 3,
        "quilt too short"
    );
    assert!(
        cols >= 1 && rows >= 1 && quilt_w >= cols && quilt_h >= rows,
        "bad quilt layout"
    );
    assert!(
        (1..=cols * rows).contains(&params.view_count),
        "views do not fit the quilt"
    );
    let quilt = Quilt {
        rgb: quilt_rgb,
        width: quilt_w,
        height: quilt_h,
        cols,
        tile_w: quilt_w / cols,
        tile_h: quilt_h / rows,
    };
    let mut out = vec![0u8; out_w as usize * out_h as usize * 3];
    let line = out_w as usize * 3;
    if line == 0 {
        return out;
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let band = (out_h as usize).div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        for (i, chunk) in out.chunks_mut(band * line).enumerate() {
            let quilt = &quilt;
            scope.spawn(move || {
                for (j, pixels) in chunk.chunks_exact_mut(line).enumerate() {
                    let y = out_h - 1 - (i * band + j) as u32;
                    weave_row(quilt, params, filter, (out_w, out_h), y, pixels);
                }
            });
        }
    });
    out
}

fn weave_row(q: &Quilt, params: &WeaveParams, filter: Filter, size: (u32, u32), y: u32, out: &mut [u8]) {
    let (w, h) = size;
    let v = (y as f32 + 0.5) / h as f32;
    let mut tap_buf = [(0u32, 0f32); MAX_TAPS];
    for x in 0..w {
        let u = (x as f32 + 0.5) / w as f32;
        for ch in 0..3 {
            let view = view_for(params, x, y, w, h, ch);
            let n = taps(view, params.view_count, filter, &mut tap_buf);
            let value: f32 = tap_buf[..n].iter().map(|&(k, wt)| wt * q.texel(k, u, v, ch)).sum();
            out[x as usize * 3 + ch] = (value + 0.5).clamp(0.0, 255.0) as u8;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::calibration::{DevicePreset, preset_names};

    /// Binary fractions throughout, so every step below is exact in f32.
    fn simple() -> WeaveParams {
        WeaveParams {
            pitch: 2.0,
            tilt: 0.5,
            subp: 0.125,
            center: 0.25,
            inv_view: false,
            flip_subp: false,
            view_count: 8,
            cell_pattern: 0,
            cells: Vec::new(),
        }
    }

    fn views(p: &WeaveParams, x: u32, y: u32) -> [f32; 3] {
        std::array::from_fn(|ch| view_for(p, x, y, 4, 2, ch))
    }

    #[test]
    fn classic_views_by_hand() {
        // Output 4x2. Pixel (1, 0): u = 1.5/4 = 0.375, v = 0.5/2 = 0.25, v*tilt = 0.125.
        //   R: (0.375 + 0     + 0.125) * 2 - 0.25 = 0.75 -> fract 0.75 -> view 6
        //   G: (0.375 + 0.125 + 0.125) * 2 - 0.25 = 1.0  -> fract 0    -> view 0
        //   B: (0.375 + 0.25  + 0.125) * 2 - 0.25 = 1.25 -> fract 0.25 -> view 2
        assert_eq!(views(&simple(), 1, 0), [6.0, 0.0, 2.0]);
        // Pixel (3, 1): u = 0.875, v = 0.75, v*tilt = 0.375.
        //   R: 1.25 * 2 - 0.25 = 2.25 -> 2;  G: 1.375 * 2 - 0.25 = 2.5 -> 4;  B: 3 - 0.25 -> 6
        assert_eq!(views(&simple(), 3, 1), [2.0, 4.0, 6.0]);
    }

    #[test]
    fn flags_change_views_as_designed() {
        // invView: 1 - fract. Pixel (1, 0) fracts 0.75, 0, 0.25 -> 0.25, 1 (held below 1), 0.75.
        let inv = WeaveParams {
            inv_view: true,
            ..simple()
        };
        let [r, g, b] = views(&inv, 1, 0);
        assert_eq!((r, b), (2.0, 6.0));
        assert!(g < 8.0 && g > 7.999, "{g}");
        // flipSubp: R reads the sub-pixel slot of B and B that of R; G stays.
        let flip = WeaveParams {
            flip_subp: true,
            ..simple()
        };
        assert_eq!(views(&flip, 1, 0), [2.0, 0.0, 6.0]);
        // flipImageX negates tilt and subp (weave_params does it): pixel (1, 0):
        //   R: (0.375 - 0.125) * 2 - 0.25 = 0.25 -> 2;  G: (0.375 - 0.125 - 0.125) * 2 - 0.25 = 0
        //   B: (0.375 - 0.25 - 0.125) * 2 - 0.25 = -0.25 -> fract 0.75 -> 6
        let mirrored = WeaveParams {
            tilt: -0.5,
            subp: -0.125,
            ..simple()
        };
        assert_eq!(views(&mirrored, 1, 0), [2.0, 0.0, 6.0]);
    }

    #[test]
    fn gen3_cells_replace_the_subpixel_term() {
        // Pattern 4: cell = x % 2. Offsets [Rx, Ry, Gx, Gy, Bx, By] in u, v units.
        let p = WeaveParams {
            cell_pattern: 4,
            cells: vec![[0.125, 0.0, 0.0, 0.25, -0.125, 0.0], [0.0, 0.0, 0.0, 0.0, 0.125, 0.5]],
            flip_subp: true, // colour-named offsets: no swap
            ..simple()
        };
        // Pixel (0, 0), cell 0: u = 0.125, v = 0.25.
        //   R: (0.125 + 0.125 + 0.25 * 0.5) * 2 - 0.25 = 0.5 -> 4
        //   G: (0.125 + (0.25 + 0.25) * 0.5) * 2 - 0.25 = 0.5 -> 4
        //   B: (0.125 - 0.125 + 0.125) * 2 - 0.25 = 0 -> 0
        assert_eq!(views(&p, 0, 0), [4.0, 4.0, 0.0]);
        // Pixel (1, 0), cell 1: u = 0.375. R, G: 0.75 -> 6.
        //   B: (0.375 + 0.125 + (0.25 + 0.5) * 0.5) * 2 - 0.25 = 1.5 -> 4
        assert_eq!(views(&p, 1, 0), [6.0, 6.0, 4.0]);
    }

    #[test]
    fn cell_patterns_follow_bridge() {
        let at = |pattern, x, y| {
            let p = WeaveParams {
                cell_pattern: pattern,
                cells: vec![[0.0; 6]; 4],
                ..simple()
            };
            cell_index(&p, x, y).unwrap()
        };
        assert_eq!([at(0, 3, 5), at(1, 3, 5), at(1, 2, 5), at(2, 9, 6)], [0, 0, 1, 2]);
        assert_eq!([at(3, 1, 1), at(3, 0, 3), at(4, 7, 2), at(4, 6, 3)], [3, 3, 1, 0]);
        let two = WeaveParams {
            cell_pattern: 2,
            cells: vec![[0.0; 6]; 2],
            ..simple()
        };
        assert_eq!(cell_index(&two, 0, 3), Some(1)); // 3 % 4 = 3, then mod 2 cells
        assert_eq!(cell_index(&simple(), 0, 3), None);
    }

    #[test]
    fn filters_weigh_neighbouring_views() {
        let mut t = [(0, 0.0); MAX_TAPS];
        let n = taps(2.7, 8, Filter::Nearest, &mut t);
        assert_eq!(&t[..n], &[(2, 1.0)]);
        let n = taps(2.25, 8, Filter::BlendNext, &mut t);
        assert_eq!(&t[..n], &[(2, 0.75), (3, 0.25)]);
        // The last view has no next: it keeps all the weight, never wrapping to view 0.
        let n = taps(7.5, 8, Filter::BlendNext, &mut t);
        assert_eq!(&t[..n], &[(7, 0.5), (7, 0.5)]);
        let n = taps(3.0, 8, Filter::Gaussian { sigma: 0.5 }, &mut t);
        let w = |k: u32| t[..n].iter().find(|tap| tap.0 == k).map_or(0.0, |tap| tap.1);
        assert!((w(2) - w(4)).abs() < 1e-6 && w(3) > w(2) && w(2) > w(1));
        assert!((t[..n].iter().map(|tap| tap.1).sum::<f32>() - 1.0).abs() < 1e-5);
        // Views below 0 are skipped and the rest renormalised.
        let n = taps(0.0, 8, Filter::Gaussian { sigma: 0.5 }, &mut t);
        assert_eq!(t[..n].iter().map(|tap| tap.0).collect::<Vec<_>>(), [0, 1, 2, 3]);
        assert!(t[0].1 > t[1].1 && (t[..n].iter().map(|tap| tap.1).sum::<f32>() - 1.0).abs() < 1e-5);
        let n = taps(5.5, 8, Filter::Gaussian { sigma: 1e-6 }, &mut t);
        assert_eq!(&t[..n], &[(5, 1.0)]);
    }

    /// Flat colour per view: every channel alone tells the view (R and G monotonic, B a
    /// permutation), and the hue-like ramp makes the woven stripes readable by eye.
    fn view_colour(i: u32) -> [u8; 3] {
        [(20 + 3 * i) as u8, (235 - 3 * i) as u8, (i * 67 % 256) as u8]
    }

    /// Quilt of flat tiles, top-down, view i at column i % cols, row i / cols from the bottom.
    fn flat_quilt(cols: u32, rows: u32, tile: u32) -> Vec<u8> {
        let (w, h) = (cols * tile, rows * tile);
        let mut rgb = vec![0; (w * h * 3) as usize];
        for (i, px) in rgb.chunks_exact_mut(3).enumerate() {
            let (x, y_down) = (i as u32 % w, i as u32 / w);
            let view = (rows - 1 - y_down / tile) * cols + x / tile;
            px.copy_from_slice(&view_colour(view));
        }
        rgb
    }

    #[test]
    fn weave_samples_the_views_by_hand() {
        // 8 views in 4x2 tiles of 1 pixel: the top quilt row holds views 4..7.
        let quilt = flat_quilt(4, 2, 1);
        assert_eq!(&quilt[..3], &view_colour(4));
        let out = weave_cpu(&quilt, 4, 2, 4, 2, &simple(), Filter::Nearest, 4, 2);
        // Pixel (1, 0) is the bottom row, i.e. the second row of the top-down image.
        let px = |x: usize, row: usize| &out[(row * 4 + x) * 3..][..3];
        assert_eq!(px(1, 1), [view_colour(6)[0], view_colour(0)[1], view_colour(2)[2]]);
        assert_eq!(px(3, 0), [view_colour(2)[0], view_colour(4)[1], view_colour(6)[2]]);
        let blend = weave_cpu(&quilt, 4, 2, 4, 2, &simple(), Filter::BlendNext, 4, 2);
        assert_eq!(&blend[..], &out[..], "views land on whole numbers: no blending here");
    }

    /// Every preset woven at its native resolution into `target/test-patterns/<device>.png`.
    #[test]
    fn device_test_patterns() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-patterns");
        std::fs::create_dir_all(&dir).unwrap();
        let names = preset_names();
        // Checking and PNG encoding are serial: two devices at a time keep both cores busy.
        let (first, second) = names.split_at(names.len() / 2);
        std::thread::scope(|s| {
            for half in [first, second] {
                let dir = &dir;
                s.spawn(move || half.iter().for_each(|name| device_test_pattern(name, dir)));
            }
        });
    }

    fn device_test_pattern(name: &str, dir: &std::path::Path) {
        let device = DevicePreset::get(name).unwrap();
        let (cal, q) = (&device.calibration, device.quilt);
        let params = cal.weave_params(q.columns * q.rows);
        // Flat tiles make the tile size irrelevant to the result: keep the quilt small.
        let quilt = flat_quilt(q.columns, q.rows, 2);
        let (w, h) = (cal.screen_w, cal.screen_h);
        let (qw, qh) = (q.columns * 2, q.rows * 2);
        let out = weave_cpu(&quilt, qw, qh, q.columns, q.rows, &params, Filter::Nearest, w, h);
        check_pattern(name, &params, &out, w, h);
        crate::output::png::write_rgb(&dir.join(format!("{name}.png")), w, h, &out).unwrap();
    }

    fn check_pattern(name: &str, params: &WeaveParams, out: &[u8], w: u32, h: u32) {
        for (i, px) in out.chunks_exact(3).enumerate() {
            let (x, y) = (i as u32 % w, h - 1 - i as u32 / w);
            for (ch, &value) in px.iter().enumerate() {
                let view = view_for(params, x, y, w, h, ch) as u32;
                assert_eq!(value, view_colour(view)[ch], "{name}: pixel ({x}, {y}) ch {ch}");
            }
        }
    }
}
