use super::*;

fn settings() -> Settings {
    Settings {
        px: (10.0, 0.0),
        threshold: 0.5,
        reversed: false,
        far_bias: 1.0 / 16384.0,
        count_holes: true,
        second_fills_holes: true,
        guard: 0,
    }
}

fn one(du: f32) -> [TargetParams; 1] {
    [TargetParams {
        du: [du, du],
        src: [0, 0],
        two: false,
    }]
}

/// A row of distinct colours on one plane at parallax `p`.
fn plane(width: usize, p: f32) -> Vec<SrcPixel> {
    (0..width)
        .map(|i| SrcPixel {
            color: i as u32 * 10,
            depth: 0.5,
            parallax: p,
        })
        .collect()
}

/// `n` pixels of scattered colours, depths and parallaxes (depth minus `off`), `step` apart
/// modulo `m`.
fn scrambled(n: usize, step: usize, m: usize, off: f32) -> Vec<SrcPixel> {
    (0..n)
        .map(|i| {
            let v = ((i * step) % m) as f32 / m as f32;
            SrcPixel {
                color: (i as u32).wrapping_mul(2_654_435_761),
                depth: v,
                parallax: v - off,
            }
        })
        .collect()
}

/// Targets at these camera offsets from source 0.
fn from_one_source(du: &[f32]) -> Vec<TargetParams> {
    du.iter()
        .map(|&du| TargetParams {
            du: [du, du],
            src: [0, 0],
            two: false,
        })
        .collect()
}

#[test]
fn a_whole_pixel_shift_moves_a_plane_by_that_many_pixels_and_marks_the_border() {
    let src = plane(8, 0.2);
    let mut out = vec![OutPixel::default(); 8];
    // du 1: k = 10 > 0, so the row is scanned mirrored; each pixel moves by k * p = 2.
    let holes = warp(&src, Output::Warped(&mut out), (8, 1), &one(1.0), &settings(), 1).unwrap();
    let colors: Vec<u32> = out.iter().map(|o| o.color).collect();
    assert_eq!(&colors[2..], &[0, 10, 20, 30, 40, 50]);
    assert_eq!(holes, 2, "the two columns beyond the edge are holes: {out:?}");
    assert!(out[0].depth & HOLE != 0 && out[1].depth & HOLE != 0);
    assert!(out[2..].iter().all(|o| o.depth & HOLE == 0));
}

#[test]
fn nearer_wins_over_a_farther_pixel_landing_on_it() {
    // A near pixel (parallax 0) in front of a far plane (parallax 0.3): moving the camera,
    // the far plane slides by 3 px under it, and the near one stays.
    let mut src = plane(12, 0.3);
    src[6] = SrcPixel {
        color: 999,
        depth: 0.1,
        parallax: 0.0,
    };
    let mut out = vec![OutPixel::default(); 12];
    warp(&src, Output::Warped(&mut out), (12, 1), &one(-1.0), &settings(), 1).unwrap();
    assert_eq!(out[6].color, 999, "{out:?}");
    assert_eq!(f32::from_bits(out[6].depth & !HOLE), 0.1);
}

#[test]
fn threads_make_the_same_rows() {
    let (w, h) = (37, 9);
    let src = scrambled(w * h, 7919, 101, 0.3);
    let targets = from_one_source(&[-1.0, -0.4, 0.3, 0.9]);
    let mut one_thread = vec![OutPixel::default(); w * h * 4];
    let mut three = one_thread.clone();
    let a = warp(&src, Output::Warped(&mut one_thread), (w, h), &targets, &settings(), 1);
    let b = warp(&src, Output::Warped(&mut three), (w, h), &targets, &settings(), 3);
    assert_eq!(a, b);
    assert!(one_thread == three);
}

#[test]
fn storage_smaller_than_the_targets_name_is_refused() {
    let src = plane(8, 0.1);
    let mut out = vec![OutPixel::default(); 4];
    assert_eq!(
        warp(&src, Output::Warped(&mut out), (8, 1), &one(1.0), &settings(), 1),
        None
    );
    let two = [TargetParams {
        du: [1.0, 1.0],
        src: [1, 0],
        two: true,
    }];
    let mut out = vec![OutPixel::default(); 8];
    assert_eq!(warp(&src, Output::Warped(&mut out), (8, 1), &two, &settings(), 1), None);
}

#[test]
fn colour_output_is_the_warped_colour_with_rows_turned_over_when_flipped() {
    let (w, h) = (23, 5);
    let src = scrambled(w * h, 31, 17, 0.5);
    let targets = from_one_source(&[-0.7, 0.5]);
    let mut warped = vec![OutPixel::default(); w * h * 2];
    let a = warp(&src, Output::Warped(&mut warped), (w, h), &targets, &settings(), 2);
    for flipped in [false, true] {
        let mut pixels = vec![0u32; w * h * 2];
        let mut seen = Vec::new();
        let mut ready = |k: usize, p: &[u32]| seen.push((k, p.to_vec()));
        let out = Output::Colour {
            pixels: &mut pixels,
            flipped,
            ready: &mut ready,
        };
        let b = warp(&src, out, (w, h), &targets, &settings(), 2);
        assert_eq!(a, b);
        seen.sort();
        assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), [0, 1], "each target once");
        for (k, p) in &seen {
            assert_eq!(&p[..], &pixels[k * w * h..][..w * h], "target {k} as made");
        }
        for t in 0..2 {
            for y in 0..h {
                let from = if flipped { h - 1 - y } else { y };
                let want: Vec<u32> = warped[(t * h + from) * w..][..w].iter().map(|o| o.color).collect();
                assert_eq!(
                    &pixels[(t * h + y) * w..][..w],
                    &want[..],
                    "target {t} row {y} flipped {flipped}"
                );
            }
        }
    }
}

/// The scan as the shader writes it (one step of either walk per iteration), kept to check
/// that the CPU's reordering of the same steps changes nothing.
mod reference {
    use super::super::*;

    #[allow(dead_code)]
    fn land(r: &Row, row: &[SrcPixel], i: usize, k: f32, f: f32, dir: f32) -> Landed {
        let (sw, g) = (r.width + 2 * r.s.guard, r.s.guard);
        let p = row[if dir > 0.0 { i } else { sw - 1 - i }];
        let d = dir * (k * p.parallax + f);
        let x = (i as isize - g as isize) as f32 + 0.5 + d;
        let ok = x.abs() < 1.0e6;
        Landed {
            x: if ok { x } else { -1.0e30 },
            d,
            color: p.color,
            z: p.depth,
            ok,
        }
    }

    pub fn scan(r: &mut Row, row: &[SrcPixel], du: f32) {
        let (width, thr) = (r.width, r.s.threshold);
        let (k, f) = (du * r.s.px.0, du * r.s.px.1);
        // The band's columns the shader walks, as it picks them.
        let g = band_used(k, f, r.s.guard);
        let row = &row[r.s.guard - g..];
        let s = Settings { guard: g, ..*r.s };
        let mut r = Row {
            out: &mut *r.out,
            width,
            s: &s,
            first_scan: r.first_scan,
            second: r.second,
        };
        let r = &mut r;
        let sw = width + 2 * g;
        let dir = if k > 0.0 { -1.0 } else { 1.0 };
        let mut a = land(r, row, 0, k, f, dir);
        let mut b = a;
        let mut n = land(r, row, 1.min(sw - 1), k, f, dir);
        let (mut t, mut x) = (0usize, 0usize);
        let (mut h0, mut h1) = (1.0e30f32, -1.0e30f32);
        let mut front = -1.0e30f32;
        let edge = |t: usize, b: &Landed, n: &Landed| t + 1 >= sw || !n.ok || (n.d - b.d).abs() > thr;
        for _ in 0..2 * sw + 2 {
            if x >= width {
                break;
            }
            let c = x as f32 + 0.5;
            let mut reach = b.x + if edge(t, &b, &n) { 0.5 } else { 0.0 };
            if t < sw && reach <= c {
                if t > 0 && a.ok && b.ok && b.x < front - 0.5 && b.x + 0.5 > h0 && a.x.min(b.x) < h1 + 0.5 {
                    r.over_holes(&a, &b, (b.d - a.d).abs() <= thr, c, (h0, h1), dir);
                }
                front = front.max(b.x);
                a = b;
                b = n;
                t += 1;
                if t + 1 < sw {
                    n = land(r, row, t + 1, k, f, dir);
                }
                reach = b.x + if edge(t, &b, &n) { 0.5 } else { 0.0 };
            }
            if t >= sw || reach > c {
                let gap = t > 0 && t < sw && a.ok && b.ok && (b.d - a.d).abs() > thr && c >= a.x + 0.5 && c < b.x - 0.5;
                if gap {
                    h0 = h0.min(c);
                    h1 = c;
                }
                r.emit(x, &a, &b, t == 0, t >= sw, dir);
                x += 1;
            }
        }
    }
}

/// A repeatable stream of pseudo-random numbers (xorshift32) from `seed`.
fn xorshift(mut seed: u32) -> impl FnMut() -> u32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    }
}

#[test]
fn the_scan_makes_what_the_shaders_order_of_steps_makes() {
    let width = 61;
    let mut next = xorshift(12345u32);
    let mut lands = Lands::default();
    for trial in 0..400 {
        // A guard band in every other trial: the source row is wider than the target's.
        let s = Settings {
            px: (9.0, 1.5),
            guard: (trial % 2) * 7,
            ..settings()
        };
        // Runs of planes with steps between them, some pixels far off the row (not ok).
        let mut p = 0.0f32;
        let row: Vec<SrcPixel> = (0..width + 2 * s.guard)
            .map(|i| {
                if next().is_multiple_of(7) {
                    p = (next() % 1000) as f32 / 500.0 - 1.0;
                }
                p += 0.01;
                SrcPixel {
                    color: next(),
                    depth: (p + 1.0) / 3.0,
                    parallax: if trial % 50 == 0 && i == 30 { 1.0e7 } else { p },
                }
            })
            .collect();
        let du = (next() % 2000) as f32 / 1000.0 - 1.0;
        let (mut want, mut got) = (vec![OutPixel::default(); width], vec![OutPixel::default(); width]);
        for (out, ours) in [(&mut want, false), (&mut got, true)] {
            let mut r = Row {
                out,
                width,
                s: &s,
                first_scan: true,
                second: false,
            };
            if ours {
                r.scan(&mut lands, &row, du);
            } else {
                reference::scan(&mut r, &row, du);
            }
        }
        assert_eq!(want, got, "trial {trial}, du {du}");
    }
}

#[test]
fn ceil_is_the_library_ceil() {
    for v in [
        0.0f32,
        -0.0,
        0.5,
        -0.5,
        1.0,
        -1.0,
        1.5,
        -1.5,
        419.99,
        1.0e-30,
        -1.0e-30,
        1.0e30,
        -1.0e30,
        f32::NAN,
    ] {
        assert_eq!(ceil(v), v.ceil() as i64, "{v}");
    }
}

#[test]
fn a_guard_band_shows_what_lies_beyond_the_tile_instead_of_stretching_its_border() {
    // A plane whose colour is its column, seen from a view 3 px to the left: without the band
    // the tile's first pixel stretches over the 3 columns that come into view; with it they
    // are the band's own pixels, and no pixel is filled over a hole.
    let (w, g) = (16usize, 4usize);
    let column = |x: isize| SrcPixel {
        color: (x + 100) as u32,
        depth: 0.5,
        parallax: 0.25,
    };
    let plain: Vec<SrcPixel> = (0..w as isize).map(column).collect();
    let banded: Vec<SrcPixel> = (-(g as isize)..(w + g) as isize).map(column).collect();
    let s = Settings {
        px: (12.0, 0.0),
        ..settings()
    };
    let mut out = vec![OutPixel::default(); w];
    let holes = warp(&plain, Output::Warped(&mut out), (w, 1), &one(1.0), &s, 1);
    assert_eq!(holes, Some(3), "3 columns come into view");
    assert!(out[..3].iter().all(|o| o.color == 100), "stretched: {out:?}");
    let s = Settings { guard: g, ..s };
    let holes = warp(&banded, Output::Warped(&mut out), (w, 1), &one(1.0), &s, 1);
    assert_eq!(holes, Some(0));
    let colours: Vec<u32> = out.iter().map(|o| o.color).collect();
    let want: Vec<u32> = (0..w as u32).map(|x| x + 97).collect();
    assert_eq!(colours, want, "every pixel the plane's own, 3 columns on");
}

#[test]
fn a_scan_walks_only_the_band_columns_its_target_can_see() {
    // Rows of parallax within [-1, 1]: the columns `band_used` leaves out land off the row, so
    // walking the whole band makes the same row, for every camera offset.
    let (w, guard) = (40usize, 30usize);
    let s = Settings {
        px: (9.0, 1.5),
        guard,
        ..settings()
    };
    let mut next = xorshift(99u32);
    let mut lands = Lands::default();
    for trial in 0..200 {
        let mut p = 0.0f32;
        let row: Vec<SrcPixel> = (0..w + 2 * guard)
            .map(|_| {
                if next().is_multiple_of(5) {
                    p = (next() % 2000) as f32 / 1000.0 - 1.0;
                }
                SrcPixel {
                    color: next(),
                    depth: (p + 1.0) / 3.0,
                    parallax: p,
                }
            })
            .collect();
        let du = (next() % 2000) as f32 / 1000.0 - 1.0;
        let (k, f) = (du * s.px.0, du * s.px.1);
        assert!(
            band_used(k, f, guard) < guard || du.abs() > 0.99,
            "du {du}: the band trimmed"
        );
        let (mut whole, mut trimmed) = (vec![OutPixel::default(); w], vec![OutPixel::default(); w]);
        let mut r = Row {
            out: &mut whole,
            width: w,
            s: &s,
            first_scan: true,
            second: false,
        };
        if k > 0.0 {
            r.scan_towards::<true>(&mut lands, &row, (k, f), guard);
        } else {
            r.scan_towards::<false>(&mut lands, &row, (k, f), guard);
        }
        let mut r = Row {
            out: &mut trimmed,
            width: w,
            s: &s,
            first_scan: true,
            second: false,
        };
        r.scan(&mut lands, &row, du);
        assert_eq!(whole, trimmed, "trial {trial}, du {du}");
    }
    assert_eq!(band_used(0.0, 0.0, 30), 1);
    assert_eq!(band_used(f32::NAN, 0.0, 30), 30);
    assert_eq!(band_used(5.0, 0.0, 0), 0);
}

#[test]
fn a_band_of_the_borders_own_colour_is_told_from_one_with_something_in_it() {
    let (w, h, g) = (10usize, 3usize, 4usize);
    let pixel = |color| SrcPixel {
        color,
        depth: 1.0,
        parallax: 1.0,
    };
    // Two sources: a plain background (the band as the border, give or take a level), and one
    // with an object in its left band on one row.
    let mut src: Vec<SrcPixel> = (0..2 * h * (w + 2 * g))
        .map(|i| pixel(0x0040_8020 + (i % 2) as u32))
        .collect();
    assert_eq!(band_differs(&src, (w, h), g), (0, 2 * 2 * h as u64 * g as u64));
    let sw = w + 2 * g;
    src[(h + 1) * sw + 1].color = 0x00ff_ffff;
    src[(h + 1) * sw + 2].color = 0x0040_8030;
    assert_eq!(band_differs(&src, (w, h), g).0, 2);
    assert_eq!(band_differs(&src, (w, h), 0), (0, 0));
}
