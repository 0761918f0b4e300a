//! The comfort effects on a real scene (README "Comfort"): `asteroids`, a field of rocks from
//! 0.1 to 100 units, frozen on its first frame, with the convergence fixed so that runs with
//! and without an effect see the same rig.

use crate::util::*;

const GRID: (u32, u32) = (3, 1);
/// Outermost-view disparity at infinity: depthiness 0.3 in 320-px tiles is 48 px.
const RIG: [&str; 10] = [
    "--quilt",
    "3x1",
    "--tile",
    "320x240",
    "--output",
    "quilt",
    "--convergence",
    "20",
    "--depthiness",
    "0.3",
];

fn quilt(test: &str, name: &str, comfort: &[&str]) -> (Image, std::path::PathBuf) {
    let mut layer: Vec<&str> = RIG.to_vec();
    layer.extend_from_slice(comfort);
    let args = [
        "--backend",
        "egl",
        "--size",
        "320x240",
        "--draws",
        "1500",
        "--freeze",
        "0",
    ];
    dumped(&format!("{test}-{name}"), &layer, "asteroids", &args, "2")
}

/// The 3x1 quilt `program` (a sample app) shows at `frame` under `layer`.
fn dumped(dir: &str, layer: &[&str], program: &str, args: &[&str], frame: &str) -> (Image, std::path::PathBuf) {
    let dir = temp_dir(dir);
    let mut layer: Vec<&str> = layer.to_vec();
    layer.extend(dump_and_exit_at(&dir, frame));
    let out = under_layer(&layer, app(program), args, &[]);
    assert_success(&out, program);
    assert_no_gl_error(&out);
    let at = dir.join(format!("f{frame:0>6}_qs3x1a1.3333.png"));
    (read_png(&at), at)
}

/// The 90th percentile of |shift| of the matched blocks of the outermost view (view 0)
/// against the centre (the largest is no measure: among hundreds of look-alike rocks a few
/// blocks match the wrong one), and how many blocks matched.
fn outer_disparity(q: &Image) -> (f64, usize) {
    let shifts = block_shifts(&tile(q, GRID.0, GRID.1, 1), &tile(q, GRID.0, GRID.1, 0), 60);
    let mut found: Vec<f64> = shifts.shifts.iter().flatten().map(|s| s.abs()).collect();
    found.sort_by(f64::total_cmp);
    (quantile(&found, 0.9), found.len())
}

#[test]
fn remap_keeps_the_centre_view_and_bounds_the_outer_disparity() {
    let (off, _) = quilt("remap", "off", &[]);
    // Comfortable up to 4 px either side; nothing beyond 10 px behind or 8 px in front.
    let (on, at) = quilt("remap", "on", &["--depth-remap", "4,4,8,10"]);
    let centre = |q: &Image| tile(q, GRID.0, GRID.1, 1).rgb;
    assert!(centre(&off) == centre(&on), "the centre view changed: {}", at.display());
    let (max_off, n_off) = outer_disparity(&off);
    let (max_on, n_on) = outer_disparity(&on);
    eprintln!(
        "outer-view block shifts, 90th percentile: off {max_off:.1} px ({n_off} blocks), remapped {max_on:.1} px ({n_on} blocks)"
    );
    assert!(n_off >= 20 && n_on >= 20, "too few blocks matched to measure");
    // Without the remap the far rocks reach most of the 48 px (the test can fail).
    assert!(max_off > 20.0, "the scene has no large disparity: {max_off}");
    // The block matcher's own error is ~0.5 px (util::parallax): the asymptote plus that.
    assert!(
        max_on <= 10.5,
        "remapped disparity {max_on} px beyond D_B = 10: {}",
        at.display()
    );
}

/// Mean |∂x| of a tile's pixels, in 8-bit levels: what a blur lowers.
fn sharpness(t: &Image) -> f64 {
    let mut sum = 0.0;
    for y in 0..t.height {
        for x in 1..t.width {
            let i = ((y * t.width + x) * 3) as usize;
            sum += (0..3)
                .map(|c| (t.rgb[i + c] as f64 - t.rgb[i + c - 3] as f64).abs())
                .sum::<f64>();
        }
    }
    sum / (t.width * t.height * 3) as f64
}

fn changed_columns(a: &Image, b: &Image) -> Vec<u32> {
    (0..a.width)
        .filter(|&x| (0..a.height).any(|y| a.pixel(x, y) != b.pixel(x, y)))
        .collect()
}

#[test]
fn depth_of_field_blurs_only_behind_the_range() {
    // The remap's range is what the blur measures from; a range wider than the scene leaves
    // everything sharp, bit for bit.
    let wide = ["--depth-remap", "100,100,200,200"];
    let (plain, _) = quilt("dof", "wide", &wide);
    let (dof_wide, at) = quilt("dof", "wide-dof", &[&wide[..], &["--dof", "on"]].concat());
    assert!(plain.rgb == dof_wide.rgb, "blurred inside the range: {}", at.display());
    let narrow = ["--depth-remap", "2,2,60,60"];
    let (sharp, _) = quilt("dof", "narrow", &narrow);
    let (blurred, at) = quilt("dof", "narrow-dof", &[&narrow[..], &["--dof", "2"]].concat());
    let (s0, s1) = (sharpness(&tile(&sharp, 3, 1, 1)), sharpness(&tile(&blurred, 3, 1, 1)));
    eprintln!("centre-view sharpness (mean |dx|, levels): {s0:.3} without, {s1:.3} with --dof 2");
    // Most rocks lie behind 2 px: the blur must take a clear share of the detail away.
    assert!(s1 < 0.8 * s0, "--dof 2 barely blurred: {s0} -> {s1} ({})", at.display());
}

#[test]
fn edge_fade_touches_only_the_border_bands() {
    let base = ["--depth-remap", "2,2,60,60"];
    let (plain, _) = quilt("fade", "plain", &base);
    let (faded, at) = quilt("fade", "faded", &[&base[..], &["--edge-fade", "40"]].concat());
    for view in 0..3 {
        let cols = changed_columns(&tile(&plain, 3, 1, view), &tile(&faded, 3, 1, view));
        assert!(!cols.is_empty(), "view {view}: nothing faded ({})", at.display());
        // The band is 40 px at both borders of the 320-px tile.
        assert!(
            cols.iter().all(|&x| !(40..280).contains(&x)),
            "view {view}: columns outside the bands changed: {cols:?}"
        );
    }
}

#[test]
fn synthesis_warps_by_the_remapped_disparity() {
    let (off, _) = quilt("remap-synth", "off", &["--mode", "synth"]);
    let (max_off, _) = outer_disparity(&off);
    assert!(max_off > 20.0, "synth without the remap: {max_off} px");
    for mode in ["synth", "synth:pixel"] {
        let (on, at) = quilt("remap-synth", mode, &["--mode", mode, "--depth-remap", "4,4,8,10"]);
        let (max_on, n) = outer_disparity(&on);
        eprintln!(
            "{mode}: outer-view block shifts, 90th percentile: {max_off:.1} px off, {max_on:.1} px remapped ({n} blocks)"
        );
        // As in the exact test: the asymptote plus the matcher's error.
        assert!(
            n >= 20 && max_on <= 10.5,
            "{mode}: {max_on} px ({n} blocks): {}",
            at.display()
        );
    }
}

/// The fade and the blur read the depth the synthesis warps leave in the quilt: they work on
/// synthesised views as on rendered ones (views 0 and 2 of the 3x1 quilt are synthesised).
#[test]
fn fade_and_blur_work_on_synthesised_views() {
    for mode in ["synth", "synth:pixel"] {
        let test = format!("comfort-{}", mode.replace(':', "-"));
        let base = ["--mode", mode, "--depth-remap", "2,2,60,60"];
        let (plain, _) = quilt(&test, "plain", &base);
        let (faded, at) = quilt(&test, "faded", &[&base[..], &["--edge-fade", "40"]].concat());
        let (blurred, at_dof) = quilt(&test, "blurred", &[&base[..], &["--dof", "2"]].concat());
        for view in [0, 2] {
            let (a, b) = (tile(&plain, 3, 1, view), tile(&faded, 3, 1, view));
            let cols = changed_columns(&a, &b);
            assert!(!cols.is_empty(), "{mode} view {view}: nothing faded ({})", at.display());
            assert!(
                cols.iter().all(|&x| !(40..280).contains(&x)),
                "{mode} view {view}: columns outside the bands changed: {cols:?}"
            );
            let (s0, s1) = (sharpness(&a), sharpness(&tile(&blurred, 3, 1, view)));
            eprintln!("{mode} view {view}: sharpness {s0:.3} without, {s1:.3} with --dof 2");
            assert!(
                s1 < 0.8 * s0,
                "{mode} view {view}: barely blurred ({})",
                at_dof.display()
            );
        }
    }
}

/// `cubes --depth standard|reversed` (reversed-Z: `glClipControl(.., GL_ZERO_TO_ONE)`,
/// `GL_GREATER`, depth cleared to 0) at auto-convergence, with `comfort` (remap, blur, fade).
fn cubes_quilt(depth: &str, comfort: &[&str]) -> (Image, std::path::PathBuf) {
    let mut layer = vec!["--quilt", "3x1", "--tile", "320x240", "--output", "quilt"];
    layer.extend(["--depthiness", "0.5"]);
    layer.extend_from_slice(comfort);
    let args = [
        "--backend",
        "osmesa",
        "--size",
        "320x240",
        "--frames",
        "4",
        "--depth",
        depth,
    ];
    dumped(
        &format!("comfort-cubes-{depth}-{}", comfort.len()),
        &layer,
        "cubes",
        &args,
        "4",
    )
}

/// Reversed-Z draws the same image, so the effects must do the same to it: the window depth
/// they read is NDC depth under `GL_ZERO_TO_ONE`, not (z + 1)/2 (read as the latter, every
/// pixel looked far behind the range and the whole quilt was blurred).
#[test]
fn comfort_effects_are_the_same_under_reversed_z() {
    let on = ["--depth-remap", "2,2,40,40", "--dof", "2", "--edge-fade", "60"];
    let (standard, _) = cubes_quilt("standard", &on);
    let (reversed, at) = cubes_quilt("reversed", &on);
    let (plain, _) = cubes_quilt("standard", &[]);
    let far_off = standard
        .rgb
        .iter()
        .zip(&reversed.rgb)
        .filter(|(a, b)| a.abs_diff(**b) > 8)
        .count();
    let share = far_off as f64 / standard.rgb.len() as f64;
    eprintln!(
        "reversed-Z against standard with comfort on: {:.3} % of channels differ by more than 8 levels",
        share * 100.0
    );
    assert!(
        share < 0.01,
        "reversed-Z differs from standard in {:.2} %: {}",
        share * 100.0,
        at.display()
    );
    // The foreground stays sharp: the centre view keeps most of the unblurred detail.
    let (s, sharp) = (sharpness(&tile(&reversed, 3, 1, 1)), sharpness(&tile(&plain, 3, 1, 1)));
    assert!(
        s > 0.8 * sharp,
        "reversed-Z blurred the foreground: {s} against {sharp} unblurred"
    );
}
