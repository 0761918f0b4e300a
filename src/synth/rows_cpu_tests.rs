use super::*;

fn settings() -> Settings {
    Settings {
        px: (10.0, 0.0),
        threshold: 0.5,
        reversed: false,
        far_bias: 1.0 / 16384.0,
        count_holes: true,
        second_fills_holes: true,
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
    let src: Vec<SrcPixel> = (0..w * h)
        .map(|i| SrcPixel {
            color: (i as u32).wrapping_mul(2_654_435_761),
            depth: ((i * 7919) % 101) as f32 / 101.0,
            parallax: ((i * 7919) % 101) as f32 / 101.0 - 0.3,
        })
        .collect();
    let targets: Vec<TargetParams> = [-1.0f32, -0.4, 0.3, 0.9]
        .iter()
        .map(|&du| TargetParams {
            du: [du, du],
            src: [0, 0],
            two: false,
        })
        .collect();
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
    let src: Vec<SrcPixel> = (0..w * h)
        .map(|i| SrcPixel {
            color: (i as u32).wrapping_mul(2_246_822_519),
            depth: ((i * 31) % 17) as f32 / 17.0,
            parallax: ((i * 31) % 17) as f32 / 17.0 - 0.5,
        })
        .collect();
    let targets: Vec<TargetParams> = [-0.7f32, 0.5]
        .iter()
        .map(|&du| TargetParams {
            du: [du, du],
            src: [0, 0],
            two: false,
        })
        .collect();
    let mut warped = vec![OutPixel::default(); w * h * 2];
    let a = warp(&src, Output::Warped(&mut warped), (w, h), &targets, &settings(), 2);
    for flipped in [false, true] {
        let mut pixels = vec![0u32; w * h * 2];
        let b = warp(
            &src,
            Output::Colour {
                pixels: &mut pixels,
                flipped,
            },
            (w, h),
            &targets,
            &settings(),
            2,
        );
        assert_eq!(a, b);
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
