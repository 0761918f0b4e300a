//! What `--output` presents, checked against independent computations from the dumped quilt:
//! the native weave against the CPU reference (`output::weave::weave_cpu`), the anaglyph
//! against Dubois' matrices applied on the CPU, `mono` against the centre tile.

use crate::util::*;
use holoinject::config::calibration::DevicePreset;
use holoinject::output::weave::{Filter, weave_cpu};
use std::path::PathBuf;

fn run_cubes(test: &str, size: &str, layer: &[&str]) -> PathBuf {
    let dir = temp_dir(test);
    let dump = dir.join("dump");
    let mut options = dump_and_exit_at(&dump, "2").to_vec();
    options.extend_from_slice(layer);
    let args = ["--backend", "egl", "--size", size, "--frames", "2"];
    assert_success(
        &under_layer(&options, app("cubes"), &args, &[]),
        "cubes under the layer",
    );
    dump
}

fn native_matches_cpu(filter_arg: &str, filter: Filter) {
    let dump = run_cubes(
        &format!("native_{}", filter_arg.replace(':', "_")),
        "420x560",
        &["--device", "portrait", "--weave-filter", filter_arg],
    );
    let quilt = read_png(&dump.join("f000002_qs8x6a0.75.png"));
    let native_png = dump.join("f000002_native.png");
    let native = read_png(&native_png);
    let device = DevicePreset::get("portrait").unwrap();
    let params = device.calibration.weave_params(48);
    assert_eq!((native.width, native.height), (1536, 2048));
    let cpu = weave_cpu(
        &quilt.rgb,
        quilt.width,
        quilt.height,
        8,
        6,
        &params,
        filter,
        native.width,
        native.height,
    );
    let cpu = Image {
        width: native.width,
        height: native.height,
        rgb: cpu,
    };
    // Nearest selects whole views: GPU and CPU must agree exactly except where a phase lands
    // within float rounding of a view boundary. Blending may also round the mix by one level.
    let max = if filter == Filter::Nearest { 255 } else { 2 };
    assert_channels_close(&cpu, &native, &native_png, max, 0.001, &format!("native {filter_arg}"));
}

#[test]
fn native_nearest_matches_cpu_weave() {
    native_matches_cpu("nearest", Filter::Nearest);
}

#[test]
fn native_blend_matches_cpu_weave() {
    native_matches_cpu("blend", Filter::BlendNext);
}

#[test]
fn mono_output_is_the_centre_tile() {
    let dump = run_cubes(
        "mono_centre",
        "320x240",
        &["--quilt", "3x3", "--output", "mono", "--depthiness", "0.1"],
    );
    // `--output mono` turns multiview off: the window shows the app's own frame, and no quilt
    // is made. The centre tile in quilt mode is checked against it in sample_apps.
    assert!(!dump.join("f000002_qs3x3a1.3333.png").exists());
    assert!(has_content(&dump.join("f000002_out.png")));
}

#[test]
fn anaglyph_applies_dubois_to_the_stereo_pair() {
    let dump = run_cubes(
        "anaglyph",
        "320x240",
        &["--quilt", "3x3", "--output", "anaglyph", "--depthiness", "0.1"],
    );
    let quilt = read_png(&dump.join("f000002_qs3x3a1.3333.png"));
    let out_png = dump.join("f000002_out.png");
    let out = read_png(&out_png);
    let (l, r) = holoinject::output::compose::stereo_pair(9);
    let (tl, tr) = (tile(&quilt, 3, 3, l), tile(&quilt, 3, 3, r));
    const LEFT: [[f32; 3]; 3] = [
        [0.456, 0.500, 0.176],
        [-0.040, -0.038, -0.016],
        [-0.015, -0.021, -0.005],
    ];
    const RIGHT: [[f32; 3]; 3] = [
        [-0.043, -0.088, -0.002],
        [0.378, 0.734, -0.018],
        [-0.072, -0.113, 1.226],
    ];
    let expected: Vec<u8> = tl
        .rgb
        .chunks(3)
        .zip(tr.rgb.chunks(3))
        .flat_map(|(a, b)| {
            (0..3).map(move |row| {
                let v: f32 = (0..3)
                    .map(|c| LEFT[row][c] * a[c] as f32 / 255.0 + RIGHT[row][c] * b[c] as f32 / 255.0)
                    .sum();
                (v.clamp(0.0, 1.0) * 255.0).round() as u8
            })
        })
        .collect();
    let expected = Image {
        width: tl.width,
        height: tl.height,
        rgb: expected,
    };
    assert_channels_close(&expected, &out, &out_png, 1, 0.05, "anaglyph");
}

#[test]
fn side_by_side_shows_the_stereo_pair() {
    let dump = run_cubes(
        "sbs",
        "320x240",
        &["--quilt", "3x3", "--output", "sbs", "--depthiness", "0.1"],
    );
    let out_png = dump.join("f000002_out.png");
    let out = read_png(&out_png);
    assert_eq!((out.width, out.height), (320, 240));
    let half = |x0: u32| Image {
        width: 160,
        height: 240,
        rgb: (0..240)
            .flat_map(|y| out.rgb[((y * 320 + x0) * 3) as usize..((y * 320 + x0 + 160) * 3) as usize].to_vec())
            .collect(),
    };
    let (left, right) = (half(0), half(160));
    assert_images_differ(&left, &right, &out_png, "both halves identical: no stereo");
    assert!(has_content(&out_png));
}

#[test]
fn unknown_device_is_one_line_error() {
    let out = run(&launcher(), &["run", "--device", "no-such-panel", "--", "true"], &[]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("unknown device") && err.contains("portrait"), "{err}");
}
