//! Geometry attached to the camera is at infinity (DESIGN §3). `legacy --sky` draws a sky box
//! around the eye first, as fixed-function racing games do (the camera's rotation alone,
//! depth writes off); its reference quilt draws that box with the projection of infinity.
//! Under the layer the sky must move as infinity does in every view: by the depthiness
//! itself, `s · tile_w / 2` px between the centre and the outermost view, where the plain
//! shift `k (w - c)` of a unit box moves it a dozen times as far the other way.

use crate::util::*;
use std::path::Path;

const QUILT: (u32, u32) = (3, 3);
const TILE: (u32, u32) = (320, 240);
const DEPTHINESS: f64 = 0.1;
const RIG: [&str; 4] = ["--depthiness", "0.1", "--convergence", "13"];
const APP: [&str; 7] = ["--backend", "osmesa", "--size", "640x480", "--frames", "3", "--sky"];

/// The sky band of view `i`: the rows above the horizon, right of the HUD's bars.
fn sky(quilt: &Image, i: u32) -> Image {
    let t = tile(quilt, QUILT.0, QUILT.1, i);
    let (x0, x1, y0, y1) = (190u32, TILE.0 - 2, 2u32, 30u32);
    let mut rgb = Vec::new();
    for y in y0..y1 {
        let row = ((y * t.width) * 3) as usize;
        rgb.extend_from_slice(&t.rgb[row + (x0 * 3) as usize..row + (x1 * 3) as usize]);
    }
    Image {
        width: x1 - x0,
        height: y1 - y0,
        rgb,
    }
}

/// The sky's shift from the centre view to views 0 and N-1.
fn sky_shifts(quilt: &Path) -> [i32; 2] {
    let q = read_png(quilt);
    let centre = sky(&q, 4);
    [0, 8].map(|v| horizontal_shift(&centre, &sky(&q, v), 24))
}

fn injected(dir: &Path, extra: &[&str]) -> std::path::PathBuf {
    let dump = dir.join("dump");
    let mut options = vec!["--output", "quilt", "--quilt", "3x3", "--tile", "320x240"];
    options.extend(RIG);
    options.extend(extra);
    options.extend(dump_and_exit_at(&dump, "3"));
    let out = under_layer(&options, app("legacy"), &APP, &[]);
    assert_success(&out, "legacy --sky under the layer");
    assert_no_gl_error(&out);
    dump.join("f000003_qs3x3a1.3333.png")
}

#[test]
fn a_sky_box_around_the_eye_moves_as_infinity() {
    let dir = temp_dir("sky_at_infinity");
    let reference = dir.join("reference.png");
    let mut args = APP.to_vec();
    args.extend([
        "--reference-quilt",
        "3x3",
        "--tile",
        "320x240",
        "--out",
        reference.to_str().unwrap(),
    ]);
    args.extend(RIG);
    assert_success(&run(&app("legacy"), &args, &[]), "reference quilt");
    let expected = sky_shifts(&reference);
    let infinity = (DEPTHINESS * f64::from(TILE.0) / 2.0).round() as i32;
    assert!(
        expected.iter().all(|s| (s.abs() - infinity).abs() <= 1) && expected[0] == -expected[1],
        "the reference's sky moves {expected:?} px, not ±{infinity} (infinity)"
    );
    let got = sky_shifts(&injected(&dir, &[]));
    assert_eq!(
        got, expected,
        "the sky moves {got:?} px under the layer, {expected:?} in the reference"
    );
    // The rule is what puts it there: without it the unit box gets the shift of its depth.
    let off = sky_shifts(&injected(&dir.join("off"), &["--sky-at-infinity", "off"]));
    assert_ne!(
        off, expected,
        "--sky-at-infinity off: the sky still moves as infinity ({off:?} px)"
    );
}

/// `--dump-disparity` shows what the fast modes and the comfort pass take each pixel's
/// disparity to be: the sky, drawn around the eye without depth writes, at infinity, as exact
/// shows it (the disparity record: `0.1 × 160` = 16 px behind, the legend's end, `[10, 40,
/// 150]`; from depth alone it was the far clear's 13.9 px), the near floor in front of the
/// screen (red), in every view.
#[test]
fn the_disparity_dump_puts_the_sky_at_infinity_and_the_near_floor_in_front() {
    let dir = temp_dir("sky_disparity_dump");
    let dump = dir.join("dump");
    let mut options = vec![
        "--output",
        "quilt",
        "--quilt",
        "3x3",
        "--tile",
        "320x240",
        "--dump-disparity",
    ];
    options.extend(RIG);
    options.extend(dump_and_exit_at(&dump, "3"));
    let out = under_layer(&options, app("legacy"), &APP, &[]);
    assert_success(&out, "legacy --sky with --dump-disparity");
    let img = read_png(&dump.join("f000003_disparity_qs3x3a1.3333.png"));
    assert_eq!(
        (img.width, img.height),
        (960, 720 + 28),
        "quilt-sized image with a legend strip below"
    );
    for view in 0..9 {
        let (x0, y0) = ((view % 3) * 320, 720 - (view / 3 + 1) * 240);
        let sky = img.pixel(x0 + 250, y0 + 10).unwrap();
        assert_eq!(
            sky,
            [10, 40, 150],
            "view {view}: the sky is not at infinity in the dump"
        );
        let floor = img.pixel(x0 + 160, y0 + 235).unwrap();
        assert!(
            floor[0] > 200 && floor[2] < 180,
            "view {view}: the near floor is not in front ({floor:?})"
        );
    }
}

/// The same sky in `--mode synth`, whose outer views are warped from the centre view: the sky
/// writes no depth, so the depth buffer says only "far clear", which the warps take for the
/// far plane (100 here: 13.9 px, not 16). The disparity record says infinity: the sky box is
/// drawn again into the record under its own depth state (fixed function has no fragment
/// output to add), and the warp moves it as exact does, to the pixel.
#[test]
fn a_sky_box_around_the_eye_moves_as_infinity_in_synth() {
    let dir = temp_dir("sky_at_infinity_synth");
    let infinity = (DEPTHINESS * f64::from(TILE.0) / 2.0).round() as i32;
    let exact = sky_shifts(&injected(&dir.join("exact"), &[]));
    assert_eq!(exact, [-infinity, infinity], "exact: the sky moves {exact:?} px");
    let synth = sky_shifts(&injected(&dir.join("synth"), &["--mode", "synth"]));
    assert_eq!(
        synth, exact,
        "synth moves the sky {synth:?} px, exact {exact:?}: the viewer sees it at another depth in the outer views"
    );
    // The control: from depth alone the sky is at the far plane.
    let depth = sky_shifts(&injected(
        &dir.join("depth"),
        &["--mode", "synth", "--disparity-record", "off"],
    ));
    assert_ne!(
        depth, exact,
        "--disparity-record off: the sky still moves as infinity ({depth:?} px)"
    );
}
