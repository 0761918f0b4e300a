//! The guard band (`--guard-band`, issue 23): the columns just beyond each side of a rendered
//! view, rendered for the warp alone.
//!
//! A synthesised view sees a little past its source's edges: without those columns the row
//! warp can only stretch the source's border pixel over them (on Neverball-like scenes 16–33 %
//! of the outer views' squared error lay in their outer 5 % of columns). So while the scene is
//! drawn, every draw into framebuffer 0 is replayed into two strips per rendered view besides
//! its tile, in room the quilt keeps beyond its tiles (`QuiltLayout::guard`): the same view
//! with its image moved by the strip's width (`x_ndc ± 2g/W`, the per-view image shift `h` of
//! DESIGN §3), so the strip shows the columns `[-g, 0)` or `[W, W + g)` of that view. The warp
//! reads them as part of the source row; the tiles themselves are drawn exactly as before.
//!
//! Only where it is right and cheap: the row warp, a single-sampled quilt, the main camera
//! drawing into framebuffer 0 (a composited scene's passes run in the app's framebuffers,
//! whose shadows have no room beside their layers), and no more rendered views than the room
//! has slots. Draws that are not seen through the camera (a clear, a full-screen quad behind
//! the scene) keep their geometry, so a strip holds the tile's own border columns there,
//! except what they compute from the camera's matrices (a sky drawn as a full-screen quad
//! that un-projects each pixel), which gets the strip's move.

use crate::config::{GuardBand, Mode, SynthWarp, ViewSettings};
use crate::multiview::Multiview;
use crate::multiview::quilt::layout::{QuiltLayout, intersect};
use std::cell::Cell;
use std::time::Instant;

/// The share of the frame `auto` lets the strips take: each is one more draw of everything
/// the rendered view draws (a program of 5,000 draws a frame runs 10,000 more per rendered
/// view, which no border is worth), and one outer view's border is worth little more.
const AUTO_LIMIT: f64 = 0.10;
/// The share of the band's pixels under which `auto` finds it plain: the border's own colour.
const PLAIN: f64 = 0.005;
/// Frames the share is measured over before `auto` judges it, and frames it then stays off.
const JUDGE_AFTER: u32 = 4;
const RETRY_AFTER: u64 = 300;
/// The process's first frames link programs and make resources: not timed.
const WARM_UP: u64 = 5;

/// What the strips cost: the time inside their draw calls (the calls' own work: submission,
/// and on a software rasteriser the vertex shading; their few pixels are rasterised later),
/// as a share of the frame, smoothed over frames.
#[derive(Debug, Default)]
pub struct Meter {
    /// Seconds in strip draws this frame (the replay holds `Multiview` shared).
    pub spent: Cell<f64>,
    last_end: Option<Instant>,
    share: f64,
    frames: u32,
    /// `auto` found the band too dear: off before this frame.
    off_until: u64,
    /// Its width and its cost were said at `info`.
    shown: bool,
    told: bool,
    /// Of the band's pixels the warps read: those that differ from their row's border pixel,
    /// and all (`synth::Synthesizer::take_band_seen`), over the frames measured.
    seen: (u64, u64),
}

impl Meter {
    /// Times one strip's draw.
    pub fn time(&self, draw: impl FnOnce()) {
        let start = Instant::now();
        draw();
        self.spent.set(self.spent.get() + start.elapsed().as_secs_f64());
    }
}

/// At a frame's end: the strips' cost and content measured, and the band of the next frame
/// decided (`mv.guard`). `auto` drops a band that costs more than `AUTO_LIMIT` of the frame,
/// or whose pixels are the border's own (under `PLAIN` of them differ: a plain background
/// around the scene, where the band costs its warp and strips for nothing), said at `info`,
/// and tries again `RETRY_AFTER` frames later.
pub fn end_frame(mv: &mut Multiview, frame: u64) {
    let now = Instant::now();
    let seen = mv.synth.take_band_seen();
    let m = &mut mv.guard_meter;
    let spent = m.spent.replace(0.0);
    if let Some(last) = m.last_end.filter(|_| mv.guard > 0 && frame > WARM_UP) {
        let share = (spent / now.duration_since(last).as_secs_f64().max(1e-6)).min(1.0);
        m.share = if m.frames == 0 {
            share
        } else {
            0.8 * m.share + 0.2 * share
        };
        m.frames += 1;
        if let Some((d, n)) = seen {
            m.seen = (m.seen.0 + d, m.seen.1 + n);
        }
    }
    m.last_end = Some(now);
    let auto = mv.settings.guard_band == GuardBand::Auto;
    let judged = m.frames >= JUDGE_AFTER;
    // (Seen only where the CPU scans: a compute pass's sources are not read back for it.)
    let differing = (m.seen.1 > 0).then(|| m.seen.0 as f64 / m.seen.1 as f64);
    let content = differing.map_or(String::new(), |d| {
        format!(
            "; {:.1} % of its pixels differ from the tile's border pixel of their row",
            d * 100.0
        )
    });
    let dear = m.share > AUTO_LIMIT;
    let plain = differing.is_some_and(|d| d < PLAIN);
    if judged && !m.told && !(auto && (dear || plain)) {
        m.told = true;
        crate::log::info(format_args!(
            "guard band: its strips take {:.1} % of the frame{content}",
            m.share * 100.0
        ));
    }
    if auto && judged && (dear || plain) {
        let mut why = Vec::new();
        if dear {
            why.push(format!(
                "more than {:.0} %: every draw of the scene is drawn twice more per rendered view",
                AUTO_LIMIT * 100.0
            ));
        }
        if plain {
            why.push("the band shows nothing the border's own pixels stretched would not".to_string());
        }
        let why = why.join("; ");
        crate::log::info(format_args!(
            "guard band: its strips take {:.1} % of the frame{content} ({why}): off, tried again in {RETRY_AFTER} frames",
            m.share * 100.0
        ));
        m.off_until = frame + RETRY_AFTER;
        m.frames = 0;
        m.share = 0.0;
        m.seen = (0, 0);
    }
    let off = auto && frame < m.off_until;
    let g = if off { 0 } else { width(mv) };
    if g != mv.guard {
        let first = g > 0 && !std::mem::replace(&mut mv.guard_meter.shown, true);
        let level = if first {
            crate::log::Level::Info
        } else {
            crate::log::Level::Debug
        };
        crate::log::at(
            level,
            format_args!(
                "guard band: {g} columns each side of the rendered views from frame {}",
                frame + 1
            ),
        );
        mv.guard = g;
    }
}

/// Columns per side the quilt keeps room for under `settings` in `mode`.
pub fn room(settings: &ViewSettings, mode: Mode, tile_w: u32) -> u32 {
    let warps_rows =
        matches!(mode, Mode::Synth | Mode::Hybrid(_) | Mode::Auto) && settings.synth_warp == SynthWarp::Rows;
    match settings.guard_band {
        _ if !warps_rows => 0,
        GuardBand::Off => 0,
        GuardBand::Auto => auto_cap(tile_w),
        GuardBand::Columns(n) => n,
    }
}

/// The widest band `auto` draws: a quarter of the tile (105 columns of a 420-pixel tile; a
/// sky at infinity moves that far in the outer views of a deep rig), past which most of a
/// synthesised view would come from the band anyway.
fn auto_cap(tile_w: u32) -> u32 {
    (tile_w / 4).max(4)
}

/// The band this frame draws, columns per side (0: none), decided at its start so that every
/// draw and the warp agree.
pub fn width(mv: &Multiview) -> u32 {
    let Some(t) = mv.target.as_ref() else { return 0 };
    let l = t.layout;
    let possible = l.guard > 0
        && t.samples == 0
        && mv.plan.synthesise
        && !mv.plan.per_pixel
        && !mv.failed
        && mv.settings.synth_warp == SynthWarp::Rows
        && mv.plan.rendered.len() as u32 <= l.guard_slots()
        && mv.scene.tracker.target == Some(0);
    if !possible {
        return 0;
    }
    match mv.settings.guard_band {
        GuardBand::Off => 0,
        GuardBand::Columns(n) => n.min(l.guard),
        GuardBand::Auto => {
            let rig = mv.camera.rig;
            // The furthest a synthesised view is from a source it is made from.
            let du = (0..l.views())
                // (Not `renders`: a measured frame renders every view, and synthesises them.)
                .filter(|i| !mv.plan.rendered.contains(i))
                .map(|i| {
                    let (a, b) = mv.plan.neighbours(i);
                    (rig.u(i) - rig.u(a)).abs().max((rig.u(i) - rig.u(b)).abs())
                })
                .fold(0.0, f64::max);
            // Disparity du (s p + f) in NDC over the background's parallax, 0 to 1.
            let ndc = du * (rig.depthiness + rig.focus).abs().max(rig.focus.abs());
            let px = ndc * l.tile_w as f64 / 2.0;
            if px.is_finite() && px >= 0.5 {
                ((px.min(f64::from(u32::MAX / 2)).ceil() as u32) + 1).min(l.guard)
            } else {
                0
            }
        }
    }
}

/// The band the draw or clear being replayed now reaches: this frame's, while the scene is
/// drawn (before the warp point), else 0.
pub fn drawn_now(mv: &Multiview) -> u32 {
    if mv.plan.synthesise && !mv.plan.warped {
        mv.guard
    } else {
        0
    }
}

/// One strip of one rendered view as a draw reaches it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripDraw {
    pub view: u32,
    pub viewport: [i32; 4],
    pub scissor: [i32; 4],
    /// The image shift added to the view's (NDC) for the strip's columns: applied to the
    /// geometry of draws seen through the camera (`shifted`), and to the camera matrices a
    /// screen-space pass un-projects with (a sky drawn as a full-screen quad) whatever its
    /// geometry.
    pub dh: f32,
    pub shifted: bool,
    /// Where window pixel (0, 0) of the view is in the quilt for this strip (the origin the
    /// program's `gl_FragCoord` is mapped from).
    pub origin: (i32, i32),
}

/// The strips a draw with the app's `viewport` (and `scissor` when the test is on) reaches,
/// each handed to `draw`: both of every rendered view's, `shifted` when the draw is seen
/// through the camera. A strip the app's scissor keeps away from (it does not reach that side
/// of the window) is left out. (A callback, not a list: this runs for every draw.)
pub fn strip_draws(
    mv: &Multiview,
    layout: QuiltLayout,
    g: u32,
    (viewport, scissor): ([i32; 4], Option<[i32; 4]>),
    shifted: bool,
    mut draw: impl FnMut(StripDraw),
) {
    if g == 0 {
        return;
    }
    for (slot, &r) in mv.plan.rendered.iter().enumerate() {
        let (ox, oy) = layout.origin(r);
        let tile = layout.tile_rect(r);
        let vp = layout.map_rect(r, viewport);
        let sc = scissor.map(|s| intersect(layout.map_rect(r, s), tile));
        for (side, strip) in layout.guard_strips(slot as u32, g).into_iter().enumerate() {
            let left = side == 0;
            let (sx, sy) = (strip[0], strip[1]);
            // The strip shows the view's columns [-g, 0) or [W, W + g) (shifted), or the tile's
            // own first or last g columns (unshifted): the same move of the viewport both ways.
            let tx = if left { sx - ox } else { sx - ox - tile[2] + g as i32 };
            let ty = sy - oy;
            let reaches = match sc {
                None => true,
                Some(s) if left => s[2] > 0 && s[0] <= tile[0],
                Some(s) => s[2] > 0 && s[0] + s[2] >= tile[0] + tile[2],
            };
            if !reaches || vp[2] <= 0 {
                continue;
            }
            let scissor = match sc {
                None => strip,
                Some(s) => intersect(strip, [strip[0], s[1] + ty, strip[2], s[3]]),
            };
            let px = if left { g as i32 } else { -(g as i32) };
            let moved = if shifted { px } else { 0 };
            draw(StripDraw {
                view: r,
                viewport: [vp[0] + tx, vp[1] + ty, vp[2], vp[3]],
                scissor,
                dh: 2.0 * px as f32 / vp[2] as f32,
                shifted,
                origin: (ox + tx + moved, oy + ty),
            });
        }
    }
}

/// Where each rendered view's band is (`synth::Source::guard`), slot by slot.
pub fn source_strips(layout: QuiltLayout, g: u32, slot: usize) -> Option<[[i32; 4]; 2]> {
    (g > 0).then(|| layout.guard_strips(slot as u32, g))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mv(views: (u32, u32)) -> (Multiview, QuiltLayout) {
        let settings = ViewSettings {
            quilt: views,
            mode: Mode::Synth,
            ..ViewSettings::default()
        };
        let layout = QuiltLayout::new(views, Some((100, 50)), (200, 100)).with_guard(8);
        let info = crate::gl::GlInfo::parse("4.5 (Core Profile) Mesa");
        (Multiview::new(info, settings, (200, 100)), layout)
    }

    fn draws(mv: &Multiview, l: QuiltLayout, scissor: Option<[i32; 4]>, shifted: bool) -> Vec<StripDraw> {
        let mut out = Vec::new();
        strip_draws(mv, l, 6, ([0, 0, 200, 100], scissor), shifted, |d| out.push(d));
        out
    }

    #[test]
    fn the_room_is_beside_the_tiles_a_pair_of_strips_per_row() {
        let l = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100)).with_guard(8);
        assert_eq!((l.width(), l.storage_width(), l.guard_slots()), (300, 316, 2));
        assert_eq!(l.guard_strips(1, 5), [[300, 50, 5, 50], [308, 50, 5, 50]]);
        assert_eq!(l.guard_strips(0, 20)[0][2], 8, "never wider than the room");
        let none = QuiltLayout::new((3, 2), Some((100, 50)), (200, 100));
        assert_eq!((none.storage_width(), none.guard_slots()), (300, 0));
        let edge = QuiltLayout::new((1, 1), Some((16384, 8)), (16384, 8)).with_guard(8);
        assert_eq!(edge.storage_width(), 16384, "no room past the largest texture");
    }

    #[test]
    fn a_strip_shows_the_columns_beyond_its_side_of_the_view() {
        let (mv, l) = mv((3, 1));
        let draws = draws(&mv, l, None, true);
        assert_eq!(draws.len(), 2);
        let (ox, _) = l.origin(1);
        let [left, right] = [draws[0], draws[1]];
        let [ls, rs] = l.guard_strips(0, 6);
        // Left: window column -6 (NDC shifted right by 6 px of the 100 px viewport) at the
        // strip's first column.
        assert_eq!(left.scissor, ls);
        assert!((left.dh - 0.12).abs() < 1e-6);
        let column = |d: &StripDraw, x_view: f32| {
            // A view column's NDC, shifted, through the strip's viewport.
            let ndc = 2.0 * (x_view + 0.5) / 100.0 - 1.0 + d.dh;
            (ndc + 1.0) / 2.0 * d.viewport[2] as f32 + d.viewport[0] as f32 - 0.5
        };
        assert!((column(&left, -6.0) - ls[0] as f32).abs() < 1e-3);
        assert!((column(&right, 100.0) - rs[0] as f32).abs() < 1e-3);
        assert_eq!(
            left.origin.0,
            ls[0] + 6,
            "gl_FragCoord at the strip's start is column -6"
        );
        assert_eq!(right.origin.0, rs[0] - 100);
        // Unshifted, the strips hold the tile's own border columns.
        let flat = super::tests::draws(&mv, l, None, false);
        assert_eq!(flat[0].viewport, left.viewport);
        assert_eq!((flat[0].dh, flat[0].shifted), (left.dh, false));
        assert_eq!(flat[0].origin.0, ls[0]);
        let _ = ox;
    }

    #[test]
    fn a_scissor_away_from_a_side_leaves_its_strip_alone() {
        let (mv, l) = mv((3, 1));
        let middle = draws(&mv, l, Some([50, 0, 100, 100]), true);
        assert!(middle.is_empty());
        let left_half = draws(&mv, l, Some([0, 20, 100, 40]), true);
        assert_eq!(left_half.len(), 1);
        let [ls, _] = l.guard_strips(0, 6);
        assert_eq!(
            left_half[0].scissor,
            [ls[0], 10, 6, 20],
            "the scissor's rows, in the strip"
        );
    }
}
