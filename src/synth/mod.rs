//! Image-space view synthesis (DESIGN §5): views made by warping rendered views by their
//! depth instead of replaying the app's draws.
//!
//! This module knows nothing of the app: it is handed where each rendered view's colour and
//! depth are (framebuffers and rectangles), which target tiles to fill from which of them,
//! and the depth model; it copies the sources into arrays of its own and warps them on the
//! GPU with the adaptive quad grid of Didyk et al. (2011) (`grid`):
//!
//! 1. per source: parallax `p = 1 - c/w` per pixel (`disparity`), then a min/max pyramid of
//!    it (one pass per level, cells of 2 to 32 pixels);
//! 2. per source: a compute pass per level lists the leaf cells (split while the parallax
//!    range, in pixels of the outermost target view, exceeds the threshold);
//! 3. per target: its tile's depth cleared, then one instanced draw of each source's leaves,
//!    each corner moved by its disparity, depth-tested so nearer surfaces win.
//!
//! `synth:pixel` (`pixel`) replaces steps 1 to 3 by a per-pixel splat and pull-push hole
//! filling, from the same source copies: the baseline the grid is measured against.
//!
//! Nothing here waits for the GPU or reads anything back.

pub mod disparity;
mod gather;
mod grid;
mod pass;
mod pixel;
mod profile;
mod programs;
mod pull_push;
pub mod reproject;
mod resources;
mod rows;
pub mod rows_cpu;
mod rows_host;

pub use disparity::ParallaxModel;
pub use pass::zero_to_one;

use crate::gl::GlInfo;
use crate::gl::*;
use crate::state::orphans::LayerObjects;

/// A rectangle of a source's framebuffer and where it goes in our arrays (`Source::parts`).
pub type Part = ([i32; 4], [i32; 4]);

/// A rendered view to warp from.
#[derive(Clone, Copy, Debug)]
pub struct Source {
    /// Its camera position `u` in [-1, 1] (DESIGN §3).
    pub u: f64,
    /// Framebuffer and rectangle holding its colour (colour attachment 0).
    pub color: (u32, [i32; 4]),
    /// Framebuffer and rectangle holding its depth.
    pub depth: (u32, [i32; 4]),
    /// Framebuffer (its colour attachment 0) and rectangle holding its disparity record
    /// (`shader::record`), when it was recorded.
    pub record: Option<(u32, [i32; 4])>,
    /// Where its guard band is (`Job::guard` wide): the columns just beyond its tile's left
    /// and right sides, rendered beside the tile in the same framebuffers (colour, depth and
    /// record alike).
    pub guard: Option<[[i32; 4]; 2]>,
}

impl Source {
    /// Each part of the source (`rect`, its colour's, depth's or record's rectangle, and its
    /// guard band) and where it goes in our arrays (`parts`).
    pub fn parts(&self, rect: [i32; 4], tile: (i32, i32), guard: i32) -> Vec<Part> {
        parts(rect, self.guard, tile, guard)
    }
}

/// Each part of a source (`rect`, and its guard band's strips `band`) and where it goes in our
/// arrays of `tile` between bands `guard` columns wide (the rectangle is scaled to the tile;
/// the bands are at the tile's scale).
pub fn parts(rect: [i32; 4], band: Option<[[i32; 4]; 2]>, (w, h): (i32, i32), guard: i32) -> Vec<Part> {
    let mut parts = vec![(rect, [guard, 0, w, h])];
    if let (Some([left, right]), true) = (band, guard > 0) {
        parts.push((left, [0, 0, guard, h]));
        parts.push((right, [guard + w, 0, guard, h]));
    }
    parts
}

/// A view to synthesise.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub u: f64,
    /// Its tile in the destination framebuffer.
    pub rect: [i32; 4],
    /// Indices into the sources, the preferred one first (equal when there is one).
    pub sources: [usize; 2],
}

pub struct Job<'a> {
    pub dest_fbo: u32,
    pub sources: &'a [Source],
    pub targets: &'a [Target],
    pub tile: (i32, i32),
    /// The sources' guard band (`Source::guard`), columns each side; 0: none. The row warp
    /// only.
    pub guard: i32,
    /// The sources' depth format (their copies must match it).
    pub depth_format: GLenum,
    pub model: ParallaxModel,
    pub depthiness: f64,
    pub focus: f64,
    /// The comfort remap in tile pixels of the outermost view (`camera::comfort`), or off.
    pub remap: [f32; 4],
    /// Largest parallax range of a grid cell, in pixels of the outermost target view (the
    /// row warp: the largest disparity step between neighbouring pixels on one surface).
    pub threshold: f64,
    /// Warp row by row (`rows`) instead of by the quad grid.
    pub rows: bool,
    /// Gather each target pixel (`gather`) instead of either.
    pub gather: bool,
    /// Run the row warp's scan on the CPU (`rows_cpu`): `Some` as asked, `None` where the
    /// context's renderer is a software rasteriser (`Synthesizer::software`).
    pub rows_on_cpu: Option<bool>,
    /// Count the pixels filled over holes (`Synthesizer::hole_fraction`; the row warp only,
    /// on frames measured against exact).
    pub count_holes: bool,
    /// A target's second source only fills its preferred source's holes (the row warp; off
    /// under --reuse, whose kept views fill them).
    pub second_fills_holes: bool,
    /// Splat every pixel and fill the holes (`synth:pixel`) instead of warping the grid.
    pub per_pixel: bool,
    /// Nothing reads the targets' depth this frame: a row warp run by the CPU uploads their
    /// colour straight into the destination's texture, and no pass puts colour and depth
    /// into their tiles (`DirectColor`).
    pub direct: Option<DirectColor>,
}

impl Job<'_> {
    /// The size of a source in our arrays: the tile and its guard band on both sides.
    pub fn source_size(&self) -> (i32, i32) {
        (self.tile.0 + 2 * self.guard, self.tile.1)
    }
}

/// Where a row warp run by the CPU uploads its colour: `texture`, an `RGBA8` texture (or a
/// linear view of an sRGB one) holding `dest_fbo`'s colour, `height` rows, stored top-down
/// when `flipped` (the framebuffer's y flipped, as the window's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectColor {
    pub texture: u32,
    pub height: i32,
    pub flipped: bool,
}

/// The storage in `slot`, made again (the old one deleted) unless it `fits`.
fn refit<T>(
    slot: &mut Option<T>,
    fits: impl Fn(&T) -> bool,
    create: impl FnOnce() -> T,
    delete: impl FnOnce(T),
) -> Result<&T, String> {
    if !slot.as_ref().is_some_and(fits) {
        if let Some(old) = slot.take() {
            delete(old);
        }
        *slot = Some(create());
    }
    slot.as_ref().ok_or_else(|| "no synthesis storage".to_string())
}

fn delete_programs(gl: &Gl, names: &[u32]) {
    for &p in names {
        // SAFETY: deleting a program of ours.
        unsafe { gl.DeleteProgram(p) };
    }
}

/// Per-context synthesis state: programs, working textures, a framebuffer and vertex array.
#[derive(Default)]
pub struct Synthesizer {
    programs: Option<Result<programs::Programs, String>>,
    row_programs: Option<Result<rows::RowPrograms, String>>,
    resources: Option<resources::Resources>,
    row_targets: Option<rows::RowTargets>,
    gather_programs: Option<Result<gather::GatherPrograms, String>>,
    gather_storage: Option<gather::GatherStorage>,
    fbo: u32,
    vao: u32,
    pixel: pixel::PixelSynth,
    /// Sources, depth format and guard band of the depth `capture_depth` copied for the
    /// next warp.
    captured: Option<(usize, GLenum, i32)>,
    /// Bit j: source j's disparity record is in our array (with the depth it was taken with).
    recorded: u64,
    /// The context renders on the CPU (`gl::software_renderer`), asked once.
    software: Option<bool>,
    /// The CPU row warp's colour, kept between frames (`rows_host`): a new allocation of a
    /// quilt's worth every frame would fault in every page again.
    cpu_colour: Vec<u32>,
    /// What the last CPU row warp saw of its sources' guard band (`rows_cpu::band_differs`).
    band_seen: Option<(u64, u64)>,
}

impl Synthesizer {
    /// Compute shaders and storage buffers (desktop GL 4.3) are what the grid is built with.
    pub fn supported(info: GlInfo) -> bool {
        !info.es && info.at_least(4, 3)
    }

    /// Warps every target of `job` from its sources into the destination framebuffer. All
    /// state it touches is put back.
    pub fn warp(&mut self, gl: &Gl, info: GlInfo, job: &Job) -> Result<(), String> {
        if job.sources.is_empty() || job.targets.is_empty() {
            return Ok(());
        }
        let grid = !job.rows && !job.gather && !job.per_pixel;
        let programs = match &self.programs {
            Some(Ok(p)) if p.has_grid() || !grid => *p,
            Some(Err(e)) => return Err(e.clone()),
            _ => {
                if let Some(Ok(old)) = self.programs.take() {
                    delete_programs(gl, &old.names());
                }
                let p = programs::Programs::link(gl, info, grid);
                self.programs = Some(p.clone());
                p?
            }
        };
        let gather_programs = if job.gather && !job.per_pixel {
            Some(match &self.gather_programs {
                Some(p) => p.clone()?,
                None => {
                    let p = gather::GatherPrograms::link(gl, info);
                    self.gather_programs = Some(p.clone());
                    p?
                }
            })
        } else {
            None
        };
        let row_programs = if job.rows && !job.gather && !job.per_pixel {
            Some(match &self.row_programs {
                Some(p) => p.clone()?,
                None => {
                    let p = rows::RowPrograms::link(gl, info);
                    self.row_programs = Some(p.clone());
                    p?
                }
            })
        } else {
            None
        };
        let _guard = pass::guard(gl, info);
        crate::gl::guard::neutral_pass_state(gl, info);
        let captured = self.captured.take();
        let kept = self.prepare(gl, job.source_size(), job.sources.len(), job.depth_format, grid);
        let res = self.resources.as_ref().ok_or("no resources")?;
        let depth_ready = kept && captured == Some((job.sources.len(), job.depth_format, job.guard));
        // The record is copied again even when the depth was captured early: what is drawn
        // into the scene's framebuffer after that moment (wined3d draws a game's HUD there)
        // records its own disparity, and the warp orders and moves those pixels by it.
        self.recorded = pass::copy_records(gl, self.fbo, res, job);
        let pass = pass::Pass {
            gl,
            info,
            programs: &programs,
            res,
            fbo: self.fbo,
            vao: self.vao,
            depth_ready,
            recorded: self.recorded,
        };
        if job.per_pixel {
            return self.pixel.run(gl, info, &pass, job);
        }
        let count = job.targets.len();
        let sources = job.sources.len();
        if let Some(gather_programs) = gather_programs {
            let out = refit(
                &mut self.gather_storage,
                |t| t.fits(job.tile, sources, count),
                || gather::GatherStorage::create(gl, job.tile, sources, count),
                |old| old.delete(gl),
            )?;
            return gather::run(&pass, &gather_programs, out, job);
        }
        let Some(row_programs) = row_programs else {
            return grid::run(&pass, job);
        };
        let out = refit(
            &mut self.row_targets,
            |t| t.fits((job.tile, job.guard), sources, count),
            || rows::RowTargets::create(gl, (job.tile, job.guard), sources, count),
            |old| old.delete(gl),
        )?;
        let on_cpu = job
            .rows_on_cpu
            .unwrap_or_else(|| *self.software.get_or_insert_with(|| crate::gl::software_renderer(gl)));
        rows::run(
            &pass,
            &row_programs,
            out,
            job,
            (on_cpu, &mut self.cpu_colour, &mut self.band_seen),
        )
    }

    /// Our framebuffer, vertex array and working storage for `sources` views of `tile`;
    /// whether the storage there was is kept.
    fn prepare(&mut self, gl: &Gl, tile: (i32, i32), sources: usize, depth_format: GLenum, grid: bool) -> bool {
        if self.fbo == 0 {
            // SAFETY: our own framebuffer and vertex array (per context).
            unsafe {
                gl.GenFramebuffers(1, &mut self.fbo);
                gl.GenVertexArrays(1, &mut self.vao);
            }
        }
        let fits = self
            .resources
            .as_ref()
            .is_some_and(|r| r.fits(tile, sources, depth_format, grid));
        if !fits {
            if let Some(old) = self.resources.take() {
                old.delete(gl);
            }
            self.resources = Some(resources::Resources::create(gl, tile, sources, depth_format, grid));
        }
        fits
    }

    /// The sources' depth (framebuffer and rectangle each) copied now, while it is the scene's:
    /// a program that draws over its scene depth before the warp point (a full-screen pass
    /// into the scene's framebuffer, as glmark2's `terrain` does) would otherwise hand the
    /// warp that pass's depth. The next warp of as many sources uses this copy.
    /// `depths`: each source's depth framebuffer and its parts (`Source::parts`); `guard`
    /// the band's width.
    pub fn capture_depth(
        &mut self,
        gl: &Gl,
        info: GlInfo,
        depths: &[(u32, Vec<Part>)],
        (tile, guard, depth_format, grid): ((i32, i32), i32, GLenum, bool),
    ) {
        let _guard = pass::guard(gl, info);
        crate::gl::guard::neutral_pass_state(gl, info);
        self.prepare(gl, (tile.0 + 2 * guard, tile.1), depths.len(), depth_format, grid);
        let Some(res) = self.resources.as_ref() else { return };
        for (j, (fbo, parts)) in depths.iter().enumerate() {
            pass::copy_depth(gl, self.fbo, res, j, (*fbo, parts), depth_format);
        }
        self.captured = Some((depths.len(), depth_format, guard));
    }

    /// A capture not used by the frame it was taken in is not used by the next.
    pub fn forget_capture(&mut self) {
        self.captured = None;
    }

    /// The share of the last row warp's pixels that were filled over holes (disocclusions
    /// and what comes into view beyond the edge), counted when the job asked; `None` for the
    /// other warps. Waits for the warp.
    pub fn hole_fraction(&self, gl: &Gl) -> Option<f64> {
        self.row_targets.as_ref().map(|t| t.hole_fraction(gl))
    }

    /// Of the guard band the last warps read since the previous call: its pixels that differ
    /// from the tile's border pixel of their row, and all of them (`rows_cpu::band_differs`);
    /// `None` when no CPU scan read a band.
    pub fn take_band_seen(&mut self) -> Option<(u64, u64)> {
        self.band_seen.take()
    }

    /// The last row warp's output, whose depths' sign bits mark the pixels filled over holes
    /// (`rows::RowTargets::warped`).
    pub fn hole_marks(&self) -> Option<u32> {
        self.row_targets.as_ref().map(|t| t.warped())
    }

    /// What of ours is shared with the context's share group.
    pub fn shared_objects(&self) -> LayerObjects {
        let mut o = LayerObjects::default();
        if let Some(Ok(p)) = &self.programs {
            o.programs.extend(p.names());
        }
        if let Some(Ok(p)) = &self.row_programs {
            o.programs.extend(p.names());
        }
        if let Some(Ok(p)) = &self.gather_programs {
            o.programs.extend(p.names());
        }
        if let Some(g) = &self.gather_storage {
            o.textures.extend(g.textures());
            o.buffers.extend(g.buffers());
        }
        if let Some(r) = &self.resources {
            o.textures.extend(r.textures());
            o.buffers.extend(r.buffers());
        }
        if let Some(t) = &self.row_targets {
            o.buffers.extend(t.buffers());
            o.textures.extend(t.textures());
        }
        self.pixel.shared_objects(&mut o);
        o
    }
}
