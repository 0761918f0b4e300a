//! The row warp run by the CPU (`--rows-on cpu`, and `auto` under a software rasteriser):
//! the scan of `glsl-patches/synth_rows.comp`, step for step, over the same storage, mapped.
//! Under llvmpipe the CPU is the GPU, and its compute shaders run every storage load and
//! store one lane at a time in a bounds-checked loop: the scan written for the CPU does the
//! same work for a fraction of the instructions (issue 23: the row pass alone was 2.3-4.3
//! times the floor pass; the whole warp is now 1.3-1.9).
//!
//! Kept in step with the shader: a change to one is a change to both. The unit tests hold the
//! scan bit-identical to the shader's order of steps (`reference` in the tests), and
//! `rows_on_cpu::row_warp_on_the_cpu_matches_the_compute_pass` compares their quilts.

mod row;

use row::*;
pub use row::{OutPixel, Settings, SrcPixel, TargetParams};

/// Where the warped rows go.
pub enum Output<'a> {
    /// Colour and marked depth per target pixel, targets one after another, rows bottom-up:
    /// what the resolve pass puts into the tiles.
    Warped(&'a mut [OutPixel]),
    /// Colour alone (RGBA8), targets one after another, each target's rows top-down when
    /// `flipped`: uploaded into the tiles as it is, where nothing reads their depth. `ready`
    /// is called on the calling thread with each target (its index and pixels) as soon as it
    /// is made, in any order: its upload overlaps the other threads' scans.
    Colour {
        pixels: &'a mut [u32],
        flipped: bool,
        ready: Ready<'a>,
    },
}

impl Output<'_> {
    fn len(&self) -> usize {
        match self {
            Output::Warped(o) => o.len(),
            Output::Colour { pixels, .. } => pixels.len(),
        }
    }
}

/// Every target's rows from `sources` (layer after layer of `tile` pixels widened by the
/// guard band on both sides, `s.guard`, rows bottom-up) into `out`, on up to `threads` threads taking the next target as they finish one; the
/// pixels left filled over holes when counted. `None` when the storage does not hold what
/// the targets name, or a thread failed.
pub fn warp<'o>(
    sources: &[SrcPixel],
    out: Output<'o>,
    tile: (usize, usize),
    targets: &[TargetParams],
    s: &Settings,
    threads: usize,
) -> Option<u64> {
    let (width, height) = tile;
    let layer = width * height;
    let src_width = width + 2 * s.guard;
    let layers = sources.len() / (src_width * height).max(1);
    if width == 0
        || height == 0
        || out.len() < layer * targets.len()
        || targets.iter().any(|t| t.src.iter().any(|&j| j >= layers))
    {
        return None;
    }
    let (jobs, mut ready): (Vec<Dst>, Option<Ready>) = match out {
        Output::Warped(o) => (
            o[..layer * targets.len()].chunks_mut(layer).map(Dst::Warped).collect(),
            None,
        ),
        Output::Colour { pixels, flipped, ready } => (
            pixels[..layer * targets.len()]
                .chunks_mut(layer)
                .map(|c| Dst::Colour(c, flipped))
                .collect(),
            Some(ready),
        ),
    };
    let queue = std::sync::Mutex::new(jobs.into_iter().enumerate());
    let next = || queue.lock().ok().and_then(|mut q| q.next());
    // Each row made in `row_out` first: the scan reads back what it wrote, and a row's worth
    // stays in the cache.
    let make = |t: &TargetParams, dst: &mut Dst, row_out: &mut [OutPixel], lands: &mut Lands| {
        let mut holes = 0;
        for y in 0..height {
            let mut scanner = Row {
                out: row_out,
                width,
                s,
                first_scan: true,
                second: false,
            };
            holes += scanner.run(t, lands, |j| &sources[(j * height + y) * src_width..][..src_width]);
            dst.put_row(y, height, width, row_out);
        }
        holes
    };
    // One thread's share: targets from the queue until it is empty, each handed to `made`.
    let work = |made: &mut dyn FnMut(usize, Dst<'o>)| {
        let (mut row_out, mut lands) = (vec![OutPixel::default(); width], Lands::default());
        let mut holes = 0;
        while let Some((k, mut dst)) = next() {
            holes += make(&targets[k], &mut dst, &mut row_out, &mut lands);
            made(k, dst);
        }
        holes
    };
    let (tx, rx) = std::sync::mpsc::channel::<(usize, &[u32])>();
    std::thread::scope(|scope| {
        let others: Vec<_> = (1..threads.clamp(1, 64).min(targets.len()))
            .map(|_| {
                let tx = tx.clone();
                scope.spawn(move || {
                    work(&mut |k, dst| {
                        if let Dst::Colour(c, _) = dst {
                            // The receiver outlives every sender (scope).
                            let _ = tx.send((k, &*c));
                        }
                    })
                })
            })
            .collect();
        drop(tx);
        let holes = work(&mut |k, dst| {
            if let (Some(ready), Dst::Colour(c, _)) = (ready.as_mut(), dst) {
                ready(k, c);
                for (k, c) in rx.try_iter() {
                    ready(k, c);
                }
            }
        });
        if let Some(ready) = ready.as_mut() {
            for (k, c) in rx.iter() {
                ready(k, c);
            }
        }
        let theirs: Option<u64> = others.into_iter().map(|h| h.join().ok()).sum();
        theirs.map(|t| t + holes)
    })
}

/// How many of the guard band's pixels (`guard` columns each side of every source row, the
/// sources laid out as `warp` reads them) differ from the tile's border pixel of their row and
/// side by more than a few levels in a channel, and how many there are: a band whose pixels
/// are all the border's own (a plain background around the scene) shows nothing the warp's
/// stretch of the border would not.
pub fn band_differs(sources: &[SrcPixel], (width, height): (usize, usize), guard: usize) -> (u64, u64) {
    const LEVELS: i32 = 4;
    let sw = width + 2 * guard;
    let differ =
        |a: u32, b: u32| (0..4).any(|c| ((a >> (8 * c) & 0xff) as i32 - (b >> (8 * c) & 0xff) as i32).abs() > LEVELS);
    let (mut d, mut n) = (0u64, 0u64);
    if width == 0 || guard == 0 {
        return (0, 0);
    }
    for row in sources
        .chunks_exact(sw)
        .take(sources.len() / sw.max(1) / height.max(1) * height)
    {
        let (left, right) = (row[guard].color, row[guard + width - 1].color);
        d += row[..guard].iter().filter(|p| differ(p.color, left)).count() as u64;
        d += row[guard + width..].iter().filter(|p| differ(p.color, right)).count() as u64;
        n += 2 * guard as u64;
    }
    (d, n)
}

/// `Output::Colour`'s `ready`.
type Ready<'a> = &'a mut dyn FnMut(usize, &[u32]);

/// One target's part of `Output`.
enum Dst<'a> {
    Warped(&'a mut [OutPixel]),
    Colour(&'a mut [u32], bool),
}

impl Dst<'_> {
    /// Row `y` (bottom-up).
    fn put_row(&mut self, y: usize, height: usize, width: usize, row: &[OutPixel]) {
        match self {
            Dst::Warped(o) => o[y * width..][..width].copy_from_slice(row),
            Dst::Colour(c, flipped) => {
                let y = if *flipped { height - 1 - y } else { y };
                for (d, p) in c[y * width..][..width].iter_mut().zip(row) {
                    *d = p.color;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
