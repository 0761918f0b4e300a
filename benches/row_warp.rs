//! The row warp's CPU scan (`--rows-on cpu`) over a synthetic scene shaped like the sample
//! apps' (a sloping floor, boxes in front of it, a far wall): one 420x560 source, 47 targets
//! spread as an 8x6 quilt's are, on one thread and on every core. Compare its time per target
//! with `../shared/tools/fill-floor` (`copy + gl_FragDepth` per view) on the same machine.

use criterion::{Criterion, criterion_group, criterion_main};
use holoinject::synth::rows_cpu::{self, Output, Settings, SrcPixel, TargetParams};

const TILE: (usize, usize) = (420, 560);

/// Depth and parallax of a scene of boxes over a floor and a wall (parallax 0 at the screen,
/// 1 at infinity), colours a texture-like pattern.
fn scene() -> Vec<SrcPixel> {
    let (w, h) = TILE;
    let boxes = [
        (40, 60, 120, 200, 0.35f32),
        (180, 300, 90, 160, 0.5),
        (300, 380, 250, 420, 0.25),
    ];
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let floor = 0.6 + 0.3 * y as f32 / h as f32;
            let mut depth = if y > h / 3 { floor } else { 0.95 };
            for &(x0, x1, y0, y1, d) in &boxes {
                if (x0..x1).contains(&x) && (y0..y1).contains(&y) {
                    depth = d + 0.0004 * (x - x0) as f32;
                }
            }
            let parallax = (depth - 0.55) * 1.6;
            let color = (x as u32 * 2_654_435_761) ^ (y as u32 * 40_503) | 0xff00_0000;
            out.push(SrcPixel { color, depth, parallax });
        }
    }
    out
}

/// Asteroids' shape: small rocks near the screen over a background at infinity, so that
/// every rock opens a disocclusion as wide as the background's shift.
fn rocks() -> Vec<SrcPixel> {
    let (w, h) = TILE;
    let mut out: Vec<SrcPixel> = (0..w * h)
        .map(|i| SrcPixel {
            color: (i as u32).wrapping_mul(2_246_822_519) | 0xff00_0000,
            depth: 1.0,
            parallax: 1.0,
        })
        .collect();
    let mut seed = 7u32;
    for _ in 0..400 {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let (cx, cy, r) = (
            (seed >> 8) as usize % w,
            (seed >> 16) as usize % h,
            4 + (seed >> 24) as usize % 14,
        );
        let depth = 0.3 + (seed % 97) as f32 / 200.0;
        for y in cy.saturating_sub(r)..(cy + r).min(h) {
            for x in cx.saturating_sub(r)..(cx + r).min(w) {
                let (dx, dy) = (x as f32 - cx as f32, y as f32 - cy as f32);
                if dx * dx + dy * dy < (r * r) as f32 {
                    let z = depth + 0.002 * (dx * dx + dy * dy).sqrt();
                    out[y * w + x] = SrcPixel {
                        color: seed | 0xff00_0000,
                        depth: z,
                        parallax: z - 0.5,
                    };
                }
            }
        }
    }
    out
}

fn targets() -> Vec<TargetParams> {
    (0..48)
        .filter(|&i| i != 24)
        .map(|i| {
            let du = (i as f32 - 24.0) / 47.0;
            TargetParams {
                du: [du, du],
                src: [0, 0],
                two: false,
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let targets = targets();
    let settings = Settings {
        px: (40.0, 0.0),
        threshold: 1.0,
        reversed: false,
        far_bias: 1.0 / 16384.0,
        count_holes: false,
        second_fills_holes: true,
        guard: 0,
    };
    let mut pixels = vec![0u32; TILE.0 * TILE.1 * targets.len()];
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("row warp, 47 targets of 420x560");
    group.sample_size(10);
    for ((name, sources), threads) in [("boxes", scene()), ("rocks", rocks())]
        .iter()
        .flat_map(|s| [(s, 1), (s, cores)])
    {
        group.bench_function(format!("{name}, {threads} thread(s)"), |b| {
            b.iter(|| {
                let out = Output::Colour {
                    pixels: &mut pixels,
                    flipped: true,
                    ready: &mut |_, _| {},
                };
                rows_cpu::warp(sources, out, TILE, &targets, &settings, threads)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
