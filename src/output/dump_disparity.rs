//! `--dump-disparity`: `DIR/f{frame:06}_disparity_{tag}.png`, each view's disparity per
//! pixel in false colour, laid out like the quilt, with a legend strip below it.
//!
//! A pixel's disparity is given in pixels of the outermost view (DESIGN §3: the remapped
//! `s·(1 - c/w)` times half the tile width, plus the focus), the unit every comfort range
//! and `--depth-remap` uses, so one image reads the same at any view count. It is what the
//! fast modes, auto-convergence and the comfort pass take a pixel's disparity to be: the
//! disparity record where the view recorded it (DESIGN §5: the parallax exact mode gave the
//! draw that left the pixel), else the scene's depth where the main camera drew it
//! (`scene::convergence::view_depth`) through the scene's depth model (a pixel at the far
//! clear, a sky drawn without depth, at the far plane). Red stands in front of the screen,
//! white on it, blue behind; the darkest blue is infinity; grey is a pixel with no scene
//! depth.

use crate::camera::projection::DepthRange;
use crate::config::Settings;
use crate::gl::Gl;
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::QuiltLayout;

const LEGEND_H: usize = 28;
const NO_DEPTH: [u8; 3] = [96, 96, 96];

/// The per-pixel disparity model of one frame: outermost-view pixels of a window depth.
struct Disparity {
    model: DepthRange,
    zero_to_one: bool,
    convergence: f64,
    px_per_parallax: f64,
    focus_px: f64,
    remap: Option<crate::camera::comfort::DepthRemap>,
}

impl Disparity {
    fn of_depth(&self, d: f32) -> f64 {
        let d = f64::from(d);
        let z = if self.zero_to_one { d } else { 2.0 * d - 1.0 };
        let w = self.model.w_of_ndc(z);
        let parallax = if w.is_finite() && w > 0.0 {
            1.0 - self.convergence / w
        } else {
            1.0
        };
        self.of_parallax(parallax)
    }

    /// A recorded parallax (before the remap, as the record holds it).
    fn of_parallax(&self, parallax: f64) -> f64 {
        let px = parallax * self.px_per_parallax;
        self.remap.map_or(px, |r| r.apply(px)) + self.focus_px
    }
}

static DUMPED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

pub fn disparity(frame: u64, gl: &Gl, mv: &mut Multiview, settings: &Settings) -> Result<(), String> {
    let dir = settings.dump_dir.as_ref().ok_or("no dump directory")?;
    let target = mv.target.as_ref().ok_or("no quilt")?;
    let model = mv
        .camera
        .last_depth
        .ok_or("no perspective camera seen yet: no disparity to show")?;
    let l = target.layout;
    let rig = mv.camera.rig;
    let half = f64::from(l.tile_w) / 2.0;
    let d = Disparity {
        model,
        zero_to_one: crate::synth::zero_to_one(gl),
        convergence: rig.convergence,
        px_per_parallax: rig.depthiness * half,
        focus_px: rig.focus * half,
        remap: mv.settings.comfort.remap.map(|r| r.for_tile(l.tile_w)),
    };
    if target.samples > 0 {
        target.resolve_all(gl, mv.info, crate::gl::DEPTH_BUFFER_BIT);
    }
    let range = (rig.depthiness * half).abs().max(1.0);
    let (w, h) = (l.width() as usize, l.height() as usize);
    let mut rgb = vec![0u8; w * (h + LEGEND_H) * 3];
    let mut recorded = 0usize;
    for view in 0..l.views() {
        let Some((fbo, rect)) = crate::multiview::scene::convergence::view_depth(mv, view) else {
            paint_view(&mut rgb, l, view, None, range);
            continue;
        };
        let mut px: Vec<f64> = crate::gl::readback::read_depth(gl, mv.info, fbo, rect)
            .into_iter()
            .map(|x| d.of_depth(x))
            .collect();
        // Where the view recorded its disparity, the record's (a synthesised view's tile or
        // layer holds none: the depth its warp wrote stands).
        if let Some((record_fbo, _)) = crate::multiview::quilt::record::source(gl, mv, view, rect) {
            let rg = crate::gl::readback::read_rg(gl, mv.info, record_fbo, rect);
            for (v, r) in px.iter_mut().zip(rg.chunks_exact(2)).filter(|(_, r)| r[1] > 0.5) {
                *v = d.of_parallax(f64::from(r[0]));
                recorded += 1;
            }
        }
        if mv
            .scene_shadow()
            .is_some_and(|s| s.presented_flipped && s.views.contains(&fbo))
        {
            // Shown the way the program presents it (wined3d draws upside down).
            let row = rect[2].max(0) as usize;
            px = px.chunks(row.max(1)).rev().flatten().copied().collect();
        }
        paint_view(&mut rgb, l, view, Some(&(px, rect)), range);
    }
    crate::log::once(
        &DUMPED,
        crate::log::Level::Info,
        format_args!(
            "--dump-disparity: {:.1} % of the quilt's pixels from the disparity record, the rest from depth",
            100.0 * recorded as f64 / (w * h).max(1) as f64
        ),
    );
    legend(&mut rgb[w * h * 3..], w, range);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(format!("f{frame:06}_disparity_{}.png", l.file_tag()));
    super::png::write_rgb(&path, w as u32, (h + LEGEND_H) as u32, &rgb)
}

/// View `view`'s cell of the top-down image (view 0 bottom-left), each pixel from the
/// nearest sample of `disparities` (px, bottom-up, `rect`'s size: a scaled shadow's layer is
/// stretched to the tile), coloured over [-range, range].
fn paint_view(rgb: &mut [u8], l: QuiltLayout, view: u32, disparities: Option<&(Vec<f64>, [i32; 4])>, range: f64) {
    let (tw, th) = (l.tile_w as usize, l.tile_h as usize);
    let (col, row) = ((view % l.cols) as usize, (view / l.cols) as usize);
    let (w, h) = (l.width() as usize, l.height() as usize);
    for ty in 0..th {
        for tx in 0..tw {
            let c = match disparities {
                Some((values, r)) if !values.is_empty() => {
                    let sx = (tx * r[2] as usize / tw).min(r[2] as usize - 1);
                    let sy = (ty * r[3] as usize / th).min(r[3] as usize - 1);
                    colour(values[sy * r[2] as usize + sx], range)
                }
                _ => NO_DEPTH,
            };
            let (x, y_up) = (col * tw + tx, row * th + ty);
            let i = ((h - 1 - y_up) * w + x) * 3;
            rgb[i..i + 3].copy_from_slice(&c);
        }
    }
}

/// Diverging colours over [-range, range] px: red in front of the screen, white on it, blue
/// behind; beyond the range, the end colours.
fn colour(px: f64, range: f64) -> [u8; 3] {
    if px.is_nan() {
        return NO_DEPTH;
    }
    let t = (px / range).clamp(-1.0, 1.0);
    let fade = |a: f64, b: f64| (a + (b - a) * t.abs()).round() as u8;
    if t < 0.0 {
        [fade(255.0, 200.0), fade(255.0, 30.0), fade(255.0, 20.0)]
    } else {
        [fade(255.0, 10.0), fade(255.0, 40.0), fade(255.0, 150.0)]
    }
}

/// The colour scale across the strip, labelled at both ends and at the screen plane.
fn legend(strip: &mut [u8], w: usize, range: f64) {
    for x in 0..w {
        let c = colour((x as f64 / (w.max(2) - 1) as f64 * 2.0 - 1.0) * range, range);
        for y in 0..LEGEND_H / 2 {
            strip[(y * w + x) * 3..(y * w + x) * 3 + 3].copy_from_slice(&c);
        }
    }
    let labels = [
        (0, format!("-{range:.1} px (front)")),
        (w / 2, "0 (screen)".to_string()),
        (w, format!("+{range:.1} px (behind)")),
    ];
    for (anchor, text) in labels {
        let width = text.len() * 8;
        let x0 = anchor.saturating_sub(width / 2).min(w.saturating_sub(width));
        text_at(strip, w, x0, LEGEND_H / 2 + 3, &text);
    }
}

fn text_at(strip: &mut [u8], w: usize, x0: usize, y0: usize, text: &str) {
    for (gx, gy) in super::overlay::inked(text) {
        let (x, y) = (x0 + gx, y0 + gy);
        if x < w && y < LEGEND_H {
            strip[(y * w + x) * 3..(y * w + x) * 3 + 3].copy_from_slice(&[255, 255, 255]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Disparity {
        // A [-1, 1] projection with near 1, far 100: z_ndc = -a + b/w.
        let (n, f) = (1.0, 100.0);
        Disparity {
            model: DepthRange {
                a: -(f + n) / (f - n),
                b: -2.0 * f * n / (f - n),
            },
            zero_to_one: false,
            convergence: 10.0,
            px_per_parallax: 16.0,
            focus_px: 0.0,
            remap: None,
        }
    }

    fn window_depth(m: &Disparity, w: f64) -> f32 {
        let z = -m.model.a + m.model.b / w;
        ((z + 1.0) / 2.0) as f32
    }

    #[test]
    fn the_convergence_plane_is_zero_and_the_far_side_positive() {
        let m = model();
        assert!(m.of_depth(window_depth(&m, 10.0)).abs() < 1e-3);
        assert!(m.of_depth(window_depth(&m, 50.0)) > 0.0);
        assert!(m.of_depth(window_depth(&m, 2.0)) < 0.0);
        // The far clear is the far plane, as the warps take it.
        assert!((m.of_depth(1.0) - 16.0 * (1.0 - 10.0 / 100.0)).abs() < 1e-2);
    }

    #[test]
    fn colours_run_red_white_blue() {
        assert_eq!(colour(0.0, 10.0), [255, 255, 255]);
        assert!(colour(-10.0, 10.0)[0] > colour(-10.0, 10.0)[2]);
        assert!(colour(10.0, 10.0)[2] > colour(10.0, 10.0)[0]);
        assert_eq!(colour(f64::NAN, 10.0), NO_DEPTH);
    }
}
