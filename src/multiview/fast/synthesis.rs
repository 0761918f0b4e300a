//! The fast modes in the quilt: at the warp point (`plan`), the rendered views' tiles and
//! the scene's depth are handed to `synth`, which fills every other tile.
//!
//! Depth comes from where the main camera drew this frame (DESIGN §5): the quilt's own
//! depth when it draws to framebuffer 0, else the matching layer of the scene framebuffer's
//! shadow (a post-processed scene reaches framebuffer 0 through a full-screen composite
//! whose depth means nothing). Colour always comes from the quilt tile: what the view shows.

use crate::gl::depth_copy;
use crate::gl::guard::{StateGuard, get_i};
use crate::gl::*;
use crate::log::{self, Level};
use crate::multiview::Multiview;
use crate::synth::{Job, ParallaxModel, Source, Target};
use std::sync::atomic::AtomicBool;

static FAILED: AtomicBool = AtomicBool::new(false);
static ANNOUNCED: AtomicBool = AtomicBool::new(false);
static UNSUPPORTED: AtomicBool = AtomicBool::new(false);
static FLAT: AtomicBool = AtomicBool::new(false);

/// The mode this context runs in: the one asked for, or exact (said once) where the
/// synthesis passes cannot run.
pub fn mode_for(settings: &crate::config::ViewSettings, info: crate::gl::GlInfo) -> crate::config::Mode {
    use crate::config::Mode;
    if settings.mode == Mode::Exact || crate::synth::Synthesizer::supported(info) {
        return settings.mode;
    }
    log::once(
        &UNSUPPORTED,
        Level::Warn,
        format_args!(
            "--mode {:?} needs desktop OpenGL 4.3 (compute shaders); this context is {}{}.{}: every view is rendered exactly",
            settings.mode,
            if info.es { "OpenGL ES " } else { "OpenGL " },
            info.major,
            info.minor
        ),
    );
    Mode::Exact
}

/// At the swap: a frame whose scene was drawn but never reached a warp point is warped
/// now; a measured frame is compared and logged.
pub fn end_frame(gl: &Gl, mv: &mut Multiview, frame: u64) {
    mv.scene.ended_view = Some(mv.plan.nearest(mv.camera.rig.centre()));
    if mv.plan.synthesise && !mv.plan.warped {
        if mv.plan.scene_dirty {
            warp_at(gl, mv, true);
        } else {
            copy_flat(gl, mv);
        }
    }
    if let (Some(m), Some(t)) = (mv.measure.as_mut(), mv.target.as_ref())
        && let Some(e) = m.compare(gl, mv.info, t, &mv.plan.rendered)
    {
        let worst = e.worst().unwrap_or((0, f64::INFINITY));
        let holes = match mv.synth.hole_fraction(gl) {
            Some(h) if !e.views.is_empty() => format!("; holes filled {:.2}% of their pixels", h * 100.0),
            _ => String::new(),
        };
        log::info(format_args!(
            "measure-error: frame {frame}: {} synthesised views against exact: PSNR mean {:.2} dB, worst {:.2} dB (view {}){holes}",
            e.views.len(),
            e.mean(),
            worst.1,
            worst.0
        ));
    }
    mv.synth.forget_capture();
    super::reuse::plan_next_frame(mv, frame + 1);
    let measured = mv
        .settings
        .measure_error
        .as_ref()
        .is_some_and(|f| f.contains(frame + 1));
    super::auto::end_frame(mv, frame);
    mv.plan.new_frame(measured && mv.measure.is_some());
    super::guard::end_frame(mv, frame);
}

/// This frame's warp, still to come, writes every pixel's colour and depth of every tile it
/// synthesises, whatever was there (the row warp's resolve, depth test ALWAYS; a frame with
/// nothing view-dependent copies colour and depth): a clear of those tiles before it is
/// wasted. Not under the grid and per-pixel warps (depth-tested into the tile), `--reuse`
/// (kept views fill tiles their own way), nor on frames that render every view.
pub fn overwrites_tiles(mv: &Multiview) -> bool {
    let rows = mv.settings.synth_warp == crate::config::SynthWarp::Rows && !mv.plan.per_pixel;
    mv.plan.synthesise && !mv.plan.warped && !mv.plan.all && rows && !mv.settings.reuse && !mv.failed
}

/// Synthesises every view the plan does not render, now, and marks the frame warped.
pub fn warp(gl: &Gl, mv: &mut Multiview) {
    warp_at(gl, mv, false);
}

/// `warp`; `at_swap`: the frame ends here, so the program draws nothing more into it.
fn warp_at(gl: &Gl, mv: &mut Multiview, at_swap: bool) {
    mv.plan.mark_warped();
    if let Some(m) = mv.measure.as_mut().filter(|_| mv.plan.all)
        && let Some(t) = &mv.target
    {
        m.keep_reference(gl, mv.info, t);
    }
    let reused = super::reuse::at_warp(gl, mv);
    let result = try_warp(gl, mv, &reused.filled, at_swap);
    if result.is_ok() {
        super::reuse::move_kept(gl, mv, &reused.moved);
    }
    if let Err(e) = result {
        log::once(
            &FAILED,
            Level::Warn,
            format_args!("view synthesis failed ({e}); every view is rendered exactly from now on"),
        );
        mv.plan = super::plan::ViewPlan::new(crate::config::Mode::Exact, mv.plan.views());
        mv.auto = None;
    }
}

/// A frame that drew nothing view-dependent into framebuffer 0 (a 2D program, a menu, a
/// desktop of windows) has no disparity: every view shows what the rendered ones show, so
/// each other tile is a copy of its nearest rendered tile (colour and depth, for the comfort
/// pass). Without it those tiles keep whatever was there, black on the first frame.
fn copy_flat(gl: &Gl, mv: &mut Multiview) {
    let Some(t) = mv.target.as_ref().filter(|_| !mv.failed) else {
        return;
    };
    if t.samples > 0 {
        // Multisampled blits between two places of one buffer are not portable: the warp
        // copies a flat frame as well.
        warp(gl, mv);
        return;
    }
    mv.plan.mark_warped();
    log::once(
        &FLAT,
        Level::Info,
        format_args!(
            "synthesis: a frame with nothing view-dependent in the window: its rendered views are copied into the others"
        ),
    );
    let layout = t.layout;
    let mask = COLOR_BUFFER_BIT | if t.depth != 0 { DEPTH_BUFFER_BIT } else { 0 };
    let _guard = StateGuard::new(gl, mv.info)
        .framebuffers()
        .caps(&[SCISSOR_TEST, FRAMEBUFFER_SRGB]);
    // SAFETY: blits between disjoint tiles of the quilt, a framebuffer of ours; bindings,
    // scissor and sRGB are restored by the guard.
    unsafe {
        gl.Disable(SCISSOR_TEST);
        gl.Disable(FRAMEBUFFER_SRGB);
        gl.BindFramebuffer(READ_FRAMEBUFFER, t.fbo);
        gl.BindFramebuffer(DRAW_FRAMEBUFFER, t.fbo);
        // Framebuffer 0's read and draw buffers are the app's choice: ours for the copy.
        let (read, draw) = (get_i(gl, READ_BUFFER) as GLenum, get_i(gl, DRAW_BUFFER0) as GLenum);
        gl.ReadBuffer(COLOR_ATTACHMENT0);
        gl.DrawBuffer(COLOR_ATTACHMENT0);
        for v in (0..layout.views()).filter(|&v| !mv.plan.renders(v)) {
            let [x, y, w, h] = layout.tile_rect(mv.plan.nearest(v));
            let [dx, dy, _, _] = layout.tile_rect(v);
            gl.BlitFramebuffer(x, y, x + w, y + h, dx, dy, dx + w, dy + h, mask, NEAREST);
        }
        gl.ReadBuffer(read);
        gl.DrawBuffer(draw);
    }
}

/// The rendered views' scene depth, copied now for this frame's warp: called when the scene
/// tracker sees the scene's depth about to be drawn over or cleared (with auto-convergence's
/// copy), so the warp gets the main camera's depth even when the program reuses the scene's
/// framebuffer for a later pass.
pub fn capture_depth(gl: &Gl, mv: &mut Multiview) {
    if !mv.plan.synthesise || mv.plan.warped {
        return;
    }
    let (Some(layout), Some(quilt)) = (mv.layout(), mv.quilt_fbo()) else {
        return;
    };
    let (depth_fbo, depth_rect) = depth_source(mv, quilt);
    let guard = guard_now(mv);
    let tile = (layout.tile_w as i32, layout.tile_h as i32);
    let depths: Vec<(u32, Vec<crate::synth::Part>)> = mv
        .plan
        .rendered
        .iter()
        .enumerate()
        .map(|(slot, &r)| {
            let band = super::guard::source_strips(layout, guard, slot);
            (
                depth_fbo(r),
                crate::synth::parts(depth_rect(r), band, tile, guard as i32),
            )
        })
        .collect();
    drop((depth_fbo, depth_rect));
    let source = depths.first().map_or(quilt, |d| d.0);
    let format = mv.scene.described(source).map_or_else(
        || {
            let _guard = StateGuard::new(gl, mv.info).framebuffers();
            depth_copy::describe(gl, mv.info, source)
        },
        Ok,
    );
    let Ok(format) =
        format.map_err(|e| log::debug(format_args!("synthesis: the scene's depth is not captured early: {e}")))
    else {
        return;
    };
    if format.multisampled {
        return;
    }
    let grid = mv.settings.synth_warp == crate::config::SynthWarp::Grid && !mv.plan.per_pixel;
    let info = mv.info;
    let mut synth = std::mem::take(&mut mv.synth);
    synth.capture_depth(gl, info, &depths, (tile, guard as i32, format.format, grid));
    mv.synth = synth;
}

/// `kept`: views already filled (from the `--reuse` history).
fn try_warp(gl: &Gl, mv: &mut Multiview, kept: &[u32], at_swap: bool) -> Result<(), String> {
    let (Some(layout), Some(quilt)) = (mv.layout(), mv.quilt_fbo()) else {
        return Ok(());
    };
    let rig = mv.camera.rig;
    // Without a perspective camera seen yet there is no disparity to warp by: the rendered
    // view is shown in every tile until there is.
    let model = mv
        .camera
        .last_depth
        .and_then(|d| ParallaxModel::new(d, rig.convergence));
    let (depth_fbo, depth_rect) = depth_source(mv, quilt);
    let format = {
        let _guard = StateGuard::new(gl, mv.info).framebuffers();
        depth_copy::describe(gl, mv.info, depth_fbo(mv.plan.rendered[0]))?
    };
    if format.multisampled {
        return Err("the scene's depth is multisampled".into());
    }
    let guard = guard_now(mv);
    let mut sources: Vec<Source> = mv
        .plan
        .rendered
        .iter()
        .enumerate()
        .map(|(slot, &r)| Source {
            u: rig.u(r),
            color: (quilt, layout.tile_rect(r)),
            depth: (depth_fbo(r), depth_rect(r)),
            record: None,
            guard: super::guard::source_strips(layout, guard, slot),
        })
        .collect();
    drop((depth_fbo, depth_rect));
    for (s, rec) in sources.iter_mut().zip(records(gl, mv, &layout)) {
        s.record = rec;
    }
    let index = |v: u32| mv.plan.rendered.iter().position(|&r| r == v).unwrap_or(0);
    let targets: Vec<Target> = (0..layout.views())
        .filter(|&i| !mv.plan.rendered.contains(&i) && !kept.contains(&i))
        .map(|i| {
            let (l, r) = mv.plan.neighbours(i);
            let near = if i.abs_diff(l) <= i.abs_diff(r) { (l, r) } else { (r, l) };
            Target {
                u: rig.u(i),
                rect: layout.tile_rect(i),
                sources: [index(near.0), index(near.1)],
            }
        })
        .collect();
    let job = Job {
        dest_fbo: quilt,
        sources: &sources,
        targets: &targets,
        tile: (layout.tile_w as i32, layout.tile_h as i32),
        guard: guard as i32,
        depth_format: format.format,
        model: model.unwrap_or(ParallaxModel::FLAT),
        depthiness: if model.is_some() { rig.depthiness } else { 0.0 },
        focus: rig.focus,
        remap: crate::multiview::quilt::comfort::remap_pixels(mv),
        threshold: mv.settings.synth_threshold,
        rows: mv.settings.synth_warp == crate::config::SynthWarp::Rows,
        gather: mv.settings.synth_warp == crate::config::SynthWarp::Gather,
        rows_on_cpu: match mv.settings.rows_on {
            crate::config::RowsOn::Auto => None,
            crate::config::RowsOn::Gpu => Some(false),
            crate::config::RowsOn::Cpu => Some(true),
        },
        count_holes: mv.measure.is_some() && mv.plan.all,
        second_fills_holes: !mv.settings.reuse,
        per_pixel: mv.plan.per_pixel,
        direct: direct_color(mv, at_swap),
    };
    if !ANNOUNCED.swap(true, std::sync::atomic::Ordering::Relaxed) {
        let how = if job.per_pixel {
            "splatted per pixel, holes filled by pull-push".to_string()
        } else if job.gather {
            format!(
                "gathered pixel by pixel from their source rows (neighbouring pixels as one \
                 piece unless their disparities differ by more than {} px)",
                job.threshold
            )
        } else if job.rows {
            format!(
                "warped row by row (neighbouring pixels as one piece unless their disparities \
                 differ by more than {} px)",
                job.threshold
            )
        } else {
            format!(
                "warped by an adaptive quad grid (cells 32 px down to 1 px, split above {} px of \
                 disparity range)",
                job.threshold
            )
        };
        log::info(format_args!(
            "synthesis: {} of {} views rendered, the others {how}",
            sources.len(),
            layout.views(),
        ));
    }
    let info = mv.info;
    let mut synth = std::mem::take(&mut mv.synth);
    let result = synth.warp(gl, info, &job);
    mv.synth = synth;
    result
}

/// The guard band the warp reads this frame: the one the frame drew (`fast::guard`), under
/// the row warp with the depth in the quilt (a scene shadow has no band).
fn guard_now(mv: &Multiview) -> u32 {
    let rows = mv.settings.synth_warp == crate::config::SynthWarp::Rows && !mv.plan.per_pixel;
    if rows && mv.scene_shadow().is_none() {
        mv.guard
    } else {
        0
    }
}

/// Where the row warp, when the CPU runs it, may upload the synthesised tiles' colour itself,
/// skipping the pass that puts colour and depth into them (a full-tile pass per view): when
/// nothing reads their depth this frame. At the swap the program draws nothing more; of the
/// layer's own readers of the quilt's depth, the comfort pass, `--reuse`'s history and
/// `--dump-disparity` are off, and a measured frame keeps its exact path. The quilt must be
/// single-sampled `RGBA8` (or sRGB with a linear view) for its bytes to be the upload's.
fn direct_color(mv: &Multiview, at_swap: bool) -> Option<crate::synth::DirectColor> {
    let t = mv.target.as_ref()?;
    let readers = mv.settings.comfort.post_pass() || mv.settings.reuse || crate::config::settings().dump_disparity;
    let rows = mv.settings.synth_warp == crate::config::SynthWarp::Rows && !mv.plan.per_pixel;
    let rgba8 = t.samples == 0 && (t.color_format == RGBA8 || (t.color_format == SRGB8_ALPHA8 && t.sampled != t.color));
    (at_swap && rows && rgba8 && !readers && !mv.plan.all).then_some(crate::synth::DirectColor {
        texture: t.sampled,
        height: t.layout.height() as i32,
        flipped: t.layout.flipped,
    })
}

/// Where each rendered view's disparity record is read (`replay::record` says when there is
/// one).
fn records(
    gl: &Gl,
    mv: &mut Multiview,
    layout: &crate::multiview::quilt::layout::QuiltLayout,
) -> Vec<Option<(u32, [i32; 4])>> {
    let rendered = mv.plan.rendered.clone();
    let flipped = mv.scene_shadow().is_some_and(|s| s.presented_flipped);
    rendered
        .iter()
        .map(|&r| {
            let rec = crate::multiview::quilt::record::source(gl, mv, r, layout.tile_rect(r));
            // A shadow's record is read like its depth: in the window's orientation.
            rec.map(|(fbo, [x, y, w, h])| {
                if flipped {
                    (fbo, [x, y + h, w, -h])
                } else {
                    (fbo, [x, y, w, h])
                }
            })
        })
        .collect()
}

/// The framebuffer and rectangle holding view `r`'s scene depth, as functions of `r`.
fn depth_source(mv: &Multiview, quilt: u32) -> (impl Fn(u32) -> u32 + '_, impl Fn(u32) -> [i32; 4] + '_) {
    let shadow = mv.scene_shadow();
    let layout = mv.layout();
    let fbo = move |r: u32| match shadow {
        Some(s) => s.views.get(r as usize).copied().unwrap_or(quilt),
        None => quilt,
    };
    let rect = move |r: u32| match (shadow, layout) {
        (Some(s), _) => s.scene_rect(),
        (None, Some(l)) => l.tile_rect(r),
        (None, None) => [0, 0, 1, 1],
    };
    (fbo, rect)
}
