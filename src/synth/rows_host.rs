//! The row warp on this process's threads (`--rows-on cpu`, and `auto` under a software
//! rasteriser): the packed sources mapped, the scan of `rows_cpu` run over them, and the
//! result either written into the warped storage for the resolve pass or, where nothing
//! reads the synthesised tiles' depth this frame (`Job::direct`), uploaded as colour straight
//! into the quilt's texture: no fragment pass at all for those tiles.
//!
//! Why: under llvmpipe the GPU is this machine's CPU. Its compute passes run every storage
//! load and store one lane at a time in a bounds-checked loop, and a fragment pass that
//! copies what a compute pass made costs a full-tile pass of its own (issue 23: rows 2.3-4.3
//! floors, the resolve one more). The same scan written for the CPU, with its output
//! uploaded by `glTexSubImage2D` from client memory (Mesa's memcpy path), costs less than
//! that pass alone.

use super::Job;
use super::pass::Pass;
use super::profile::Profile;
use super::rows_cpu::{self, OutPixel, Output, SrcPixel};
use crate::gl::types::GLbitfield;
use crate::gl::*;

/// The row warp's storage (`rows::RowTargets`), as the scan reads and writes it.
pub struct Storage {
    pub tile: (i32, i32),
    /// Source columns beyond each side of a tile (the guard band) in the packed sources.
    pub guard: i32,
    pub sources: usize,
    pub count: usize,
    /// The sources packed per pixel (`SrcPixel`), and the warped targets (`OutPixel`).
    pub packed: u32,
    pub warped: u32,
    /// The hole counter.
    pub holes: u32,
    /// How far a gap's fill is pushed back (depth units), as the shader's.
    pub fill_bias: f32,
}

/// What the scan left.
pub enum Done {
    /// Colour and depth in the warped storage: the resolve pass puts them into the tiles.
    Warped,
    /// Colour in the tiles already (`Job::direct`): nothing more to do.
    InTiles,
}

/// The scan of every target of `job` from the packed sources in `out` (waits for the
/// packing passes); `colour`: scratch kept between frames for the direct upload; `band`: what
/// the sources' guard band held (`rows_cpu::band_differs`), added to.
pub fn warp(
    pass: &Pass,
    out: &Storage,
    job: &Job,
    (colour, band): (&mut Vec<u32>, &mut Option<(u64, u64)>),
    profile: &mut Profile,
) -> Result<Done, String> {
    let gl = pass.gl;
    let tile = (job.tile.0.max(0) as usize, job.tile.1.max(0) as usize);
    let pixels = tile.0 * tile.1;
    if out.tile != job.tile || out.guard != job.guard || out.count < job.targets.len() {
        return Err("its storage does not fit the job".into());
    }
    let targets = params(job);
    let settings = settings(job, out.fill_bias);
    let threads = threads();
    let n_src = (tile.0 + 2 * job.guard.max(0) as usize) * tile.1 * out.sources;
    let direct = job.direct.filter(|d| d.height >= job.tile.1);
    if direct.is_some() {
        colour.resize(pixels * targets.len(), 0);
    }
    // SAFETY: our own buffers, mapped whole for the length they were made with (`fits`
    // holds) and unmapped before returning; ARRAY_BUFFER is restored by the caller's guard.
    // The slices do not outlive the mappings.
    let holes = unsafe {
        gl.MemoryBarrier(BUFFER_UPDATE_BARRIER_BIT);
        let src = Mapped::new(gl, out.packed, n_src * size_of::<SrcPixel>(), MAP_READ_BIT);
        let sources = src.slice::<SrcPixel>(n_src).ok_or("its sources could not be mapped")?;
        if job.guard > 0 {
            let (d, n) = rows_cpu::band_differs(sources, tile, job.guard as usize);
            let (d0, n0) = band.unwrap_or((0, 0));
            *band = Some((d0 + d, n0 + n));
        }
        let holes = match direct {
            Some(d) => {
                let unpack = crate::gl::unpack::UnpackState::neutral(gl);
                gl.ActiveTexture(TEXTURE0);
                gl.BindTexture(TEXTURE_2D, d.texture);
                let mut ready = |k: usize, pixels: &[u32]| upload(gl, job, d, k, pixels);
                let output = Output::Colour {
                    pixels: colour,
                    flipped: d.flipped,
                    ready: &mut ready,
                };
                let holes = rows_cpu::warp(sources, output, tile, &targets, &settings, threads);
                unpack.restore(gl);
                holes
            }
            None => {
                let n_out = pixels * targets.len();
                let dst = Mapped::new(gl, out.warped, n_out * size_of::<OutPixel>(), MAP_WRITE_BIT);
                let warped = dst
                    .slice_mut::<OutPixel>(n_out)
                    .ok_or("its output could not be mapped")?;
                let holes = rows_cpu::warp(sources, Output::Warped(warped), tile, &targets, &settings, threads);
                dst.unmap()?;
                holes
            }
        };
        src.unmap()?;
        holes.ok_or("its storage does not hold what the targets name, or a thread failed")?
    };
    set_holes(gl, out, holes);
    // With direct colour the uploads ran inside the scan, as each target was made.
    profile.lap(if direct.is_some() { "rows+upload" } else { "rows" });
    if direct.is_none() {
        return Ok(Done::Warped);
    }
    Ok(Done::InTiles)
}

/// The threads the scan runs on, asked once: `available_parallelism` reads the process's
/// cgroup files on Linux, not a thing to do every frame inside the program.
fn threads() -> usize {
    static THREADS: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Each target's camera offsets from its sources, as the shader's `Target`.
fn params(job: &Job) -> Vec<rows_cpu::TargetParams> {
    job.targets
        .iter()
        .map(|t| {
            let [preferred, second] = t.sources;
            let du = |j: usize| (t.u - job.sources[j].u) as f32;
            rows_cpu::TargetParams {
                du: [du(second), du(preferred)],
                src: [second, preferred],
                two: second != preferred,
            }
        })
        .collect()
}

/// The shader's uniforms.
fn settings(job: &Job, bias: f32) -> rows_cpu::Settings {
    let px = job.tile.0 as f64 / 2.0;
    rows_cpu::Settings {
        px: ((job.depthiness * px) as f32, (job.focus * px) as f32),
        threshold: job.threshold as f32,
        reversed: job.model.reversed,
        far_bias: if job.model.reversed { -bias } else { bias },
        count_holes: job.count_holes,
        second_fills_holes: job.second_fills_holes,
        guard: job.guard.max(0) as usize,
    }
}

/// The hole counter the compute pass would have left.
fn set_holes(gl: &Gl, out: &Storage, holes: u64) {
    let count = holes.min(u64::from(u32::MAX)) as u32;
    // SAFETY: four bytes into our own counter; ARRAY_BUFFER is restored by the caller's guard.
    unsafe {
        gl.BindBuffer(ARRAY_BUFFER, out.holes);
        gl.BufferSubData(ARRAY_BUFFER, 0, 4, [count].as_ptr().cast());
    }
}

/// Target `k`'s colour into its tile of the quilt's texture (bound on unit 0, the unpack
/// state neutral), rows as it stores them.
fn upload(gl: &Gl, job: &Job, d: super::DirectColor, k: usize, pixels: &[u32]) {
    let (w, h) = job.tile;
    let Some(t) = job.targets.get(k) else { return };
    if pixels.len() < (w.max(0) * h.max(0)) as usize {
        return;
    }
    let [x, y, ..] = t.rect;
    let y = if d.flipped { d.height - y - h } else { y };
    // SAFETY: `pixels` holds the tile's `w * h` pixels (checked), read as tight rows from
    // client memory (the caller made the unpack state neutral); the texture is bound by the
    // caller, whose guard restores the binding.
    unsafe { gl.TexSubImage2D(TEXTURE_2D, 0, x, y, w, h, RGBA, UNSIGNED_BYTE, pixels.as_ptr().cast()) };
}

/// One of our buffers mapped through ARRAY_BUFFER; unmapped by `unmap` (or on drop, when an
/// early return leaves it mapped).
struct Mapped<'a> {
    gl: &'a Gl,
    buffer: u32,
    ptr: *mut core::ffi::c_void,
}

impl<'a> Mapped<'a> {
    /// # Safety
    /// `buffer` is ours and holds at least `bytes` bytes.
    unsafe fn new(gl: &'a Gl, buffer: u32, bytes: usize, access: GLbitfield) -> Mapped<'a> {
        // SAFETY: as the caller promises; ARRAY_BUFFER is restored by the caller's guard.
        let ptr = unsafe {
            gl.BindBuffer(ARRAY_BUFFER, buffer);
            gl.MapBufferRange(ARRAY_BUFFER, 0, bytes as isize, access)
        };
        Mapped { gl, buffer, ptr }
    }

    /// The mapping as `n` values of `T`, when it is there and aligned for them.
    ///
    /// # Safety
    /// The mapping holds `n` values of `T`, and nothing else writes it meanwhile.
    unsafe fn slice<T>(&self, n: usize) -> Option<&[T]> {
        let ok = !self.ptr.is_null() && (self.ptr as usize).is_multiple_of(align_of::<T>());
        // SAFETY: as the caller promises.
        ok.then(|| unsafe { std::slice::from_raw_parts(self.ptr.cast(), n) })
    }

    /// # Safety
    /// As `slice`, and nothing else reads or writes it meanwhile.
    #[allow(clippy::mut_from_ref)]
    unsafe fn slice_mut<T>(&self, n: usize) -> Option<&mut [T]> {
        let ok = !self.ptr.is_null() && (self.ptr as usize).is_multiple_of(align_of::<T>());
        // SAFETY: as the caller promises.
        ok.then(|| unsafe { std::slice::from_raw_parts_mut(self.ptr.cast(), n) })
    }

    fn unmap(mut self) -> Result<(), String> {
        let intact = self.release();
        if intact {
            Ok(())
        } else {
            Err("its storage was lost while mapped".into())
        }
    }

    fn release(&mut self) -> bool {
        if self.ptr.is_null() {
            return true;
        }
        self.ptr = core::ptr::null_mut();
        // SAFETY: unmapping our own buffer, mapped by `new`.
        unsafe {
            self.gl.BindBuffer(ARRAY_BUFFER, self.buffer);
            self.gl.UnmapBuffer(ARRAY_BUFFER) == TRUE
        }
    }
}

impl Drop for Mapped<'_> {
    fn drop(&mut self) {
        self.release();
    }
}
