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

/// The multi-pass sample apps' scene (tests/apps `multipass.rs`: a floor, a ring of cubes
/// around a floating one, a row of pillars 15.5 units from the eye), at its default
/// convergence (the scene centre, 10.73), with the outermost view moving 48 px at infinity:
/// the pillars lie ~15 px behind the screen in the outermost view, the front cubes within a
/// pixel or two of it.
const MULTIPASS_RIG: [&str; 10] = [
    "--quilt",
    "3x1",
    "--tile",
    "320x240",
    "--output",
    "quilt",
    "--convergence",
    "10.73",
    "--depthiness",
    "0.3",
];
/// The comfortable range of the depth-of-field runs: ±2 px kept, compressed towards 6 px;
/// the blur starts at 2 px behind and reaches its full radius, 6 px, at 6 px.
const DOF_RANGE: [&str; 2] = ["--depth-remap", "2,2,6,6"];
/// Background: blocks whose outermost-view shift without the remap is at least this far
/// behind the screen (px). 8 px is remapped to 4.4 px, a blur radius of 3.6 px.
const FAR_PX: f64 = 8.0;
/// Foreground: blocks within this of the screen, or in front of it (px): inside the range.
const NEAR_PX: f64 = 1.0;
/// A background block must lose at least this share of its detail (mean gradient magnitude;
/// the median over the far blocks). Not more: a far object's silhouette against the clear
/// colour stays crisp (nothing is blurred where nothing was drawn, and the clear contributes
/// no taps), so blocks on a pillar's top against the sky keep most of their gradient. On the
/// control (`shadowmap`, the same scene drawn into the window) the median far block keeps
/// 77 %, and all far blocks together 80 %.
const FAR_MAX_KEPT: f64 = 0.85;
/// A foreground block keeps at least this share (the median over the near blocks: a near
/// block on a cube's edge can hold background pixels, which are blurred; the median block is
/// untouched, 100 % on the control).
const NEAR_MIN_KEPT: f64 = 0.98;

/// A 3x1 quilt of multi-pass sample app `program` (OSMesa, frame 3) under the rig and `comfort`.
fn multipass(program: &str, name: &str, comfort: &[&str]) -> (Image, std::path::PathBuf) {
    let mut layer: Vec<&str> = MULTIPASS_RIG.to_vec();
    layer.extend_from_slice(comfort);
    let args = ["--backend", "osmesa", "--size", "320x240", "--frames", "3"];
    dumped(&format!("dof-{program}-{name}"), &layer, program, &args, "3")
}

/// Mean |∂x| + |∂y| (levels per pixel and channel) over 16x16 `blocks` (top-left corners) of
/// a tile: what a blur lowers.
fn gradient(t: &Image, blocks: &[(u32, u32)]) -> f64 {
    let level = |x: u32, y: u32, c: u32| f64::from(t.rgb[((y * t.width + x) * 3 + c) as usize]);
    let (mut sum, mut n) = (0.0, 0.0);
    for &(x0, y0) in blocks {
        for y in y0..(y0 + SHIFT_BLOCK).min(t.height - 1) {
            for x in x0..(x0 + SHIFT_BLOCK).min(t.width - 1) {
                for c in 0..3 {
                    let v = level(x, y, c);
                    sum += (level(x + 1, y, c) - v).abs() + (level(x, y + 1, c) - v).abs();
                    n += 1.0;
                }
            }
        }
    }
    sum / n
}

/// The depth of field on `program`'s scene: the regions come from the scene itself, as exact
/// renders it without the remap: the outermost view's shift of each textured 16x16 block of
/// the centre view (`block_shifts`, positive = behind the screen in the rightmost view). Far
/// blocks (≥ `FAR_PX` behind) must lose detail under `--dof on` against the same remap
/// without it, near blocks (≤ `NEAR_PX`) must not. Blocks are measured in the centre view
/// (the blur reads the outermost view's disparity in every view, and the centre view is the
/// same image with and without the remap). Detail is the mean |∂x| + |∂y| of a block; the
/// share a block keeps is its detail with `--dof on` over its detail without; the median over
/// far blocks must be at most `FAR_MAX_KEPT`, over near blocks at least `NEAR_MIN_KEPT`.
/// Returns (far kept, near kept, far blocks, near blocks) after printing them.
fn dof_on(program: &str, how: &str) -> (f64, f64, usize, usize) {
    let (depth, _) = multipass(program, "depth", &[]);
    let (sharp, _) = multipass(program, "sharp", &DOF_RANGE);
    let (blurred, at) = multipass(program, "dof", &[&DOF_RANGE[..], &["--dof", "on"]].concat());
    let view = |q: &Image, i| tile(q, 3, 1, i);
    let shifts = block_shifts(&view(&depth, 1), &view(&depth, 2), 40);
    let origins = block_origins(&view(&depth, 1), 40);
    let pick = |keep: &dyn Fn(f64) -> bool| -> Vec<(u32, u32)> {
        origins
            .iter()
            .zip(&shifts.shifts)
            .filter(|(_, s)| s.is_some_and(keep))
            .map(|(o, _)| *o)
            .collect()
    };
    let far = pick(&|s| s >= FAR_PX);
    let near = pick(&|s| s <= NEAR_PX);
    let (c_sharp, c_blurred) = (view(&sharp, 1), view(&blurred, 1));
    let kept = |blocks: &[(u32, u32)]| gradient(&c_blurred, blocks) / gradient(&c_sharp, blocks);
    // Per block: the share of its mean gradient the blur keeps; the median over each region.
    let per_block = |blocks: &[(u32, u32)]| {
        let mut r: Vec<f64> = blocks.iter().map(|b| kept(std::slice::from_ref(b))).collect();
        r.sort_by(f64::total_cmp);
        r
    };
    let (far_r, near_r) = (per_block(&far), per_block(&near));
    let (far_kept, near_kept) = (quantile(&far_r, 0.5), quantile(&near_r, 0.5));
    let changed = pixels_off(&sharp, &blurred, 0) as f64 / f64::from(sharp.width * sharp.height);
    eprintln!(
        "{program} ({how}): {} blocks matched, {} far (≥ {FAR_PX} px behind), {} near (≤ {NEAR_PX} px); \
         --dof on keeps a median {:.1} % of a far block's mean gradient (all far blocks: {:.2} -> {:.2} levels) \
         and {:.1} % of a near block's ({:.2} -> {:.2}); {:.2} % of the quilt's pixels changed; per block, far \
         {far_r:.2?}, near {near_r:.2?}",
        shifts.count(),
        far.len(),
        near.len(),
        100.0 * far_kept,
        gradient(&c_sharp, &far),
        gradient(&c_blurred, &far),
        100.0 * near_kept,
        gradient(&c_sharp, &near),
        gradient(&c_blurred, &near),
        100.0 * changed,
    );
    assert!(
        far.len() >= 8 && near.len() >= 8,
        "{program}: {} far and {} near blocks: the scene lacks the depth the test needs ({})",
        far.len(),
        near.len(),
        at.display()
    );
    assert!(
        far_kept <= FAR_MAX_KEPT,
        "{program} ({how}), --depth-remap 2,2,6,6 --dof on: the background beyond the comfortable range \
         keeps {:.1} % of its detail (median far block) (at most {:.0} % may stay; {:.2} % of the quilt's pixels changed at \
         all): a viewer sees the far pillars as sharp, and as doubled by the display, as without depth \
         of field ({})",
        100.0 * far_kept,
        100.0 * FAR_MAX_KEPT,
        100.0 * changed,
        at.display()
    );
    assert!(
        near_kept >= NEAR_MIN_KEPT,
        "{program} ({how}), --dof on: the foreground within the comfortable range keeps only {:.1} % of \
         its detail (median near block) (at least {:.0} % must): a viewer sees the cubes at the screen plane blurred, which \
         the display shows sharp ({})",
        100.0 * near_kept,
        100.0 * NEAR_MIN_KEPT,
        at.display()
    );
    (far_kept, near_kept, far.len(), near.len())
}

/// A composited renderer: `framebuffers` draws its scene into its own framebuffer (colour
/// texture, depth renderbuffer) and copies it to the window with a full-screen sharpen pass,
/// so framebuffer 0 holds only the quad's depth. The blur must still find the background.
#[test]
fn depth_of_field_blurs_the_background_of_a_composited_scene() {
    dof_on(
        "framebuffers",
        "scene in its own framebuffer, composited by a full-screen pass",
    );
}

/// The control: the same scene drawn straight into framebuffer 0 (`shadowmap`: the shadow
/// map is a depth-only pass of its own, the lit scene goes to the window), where the blur reads
/// the scene's depth directly. It shows the measure works where the depth of field does.
#[test]
fn depth_of_field_blurs_the_background_of_a_directly_drawn_scene() {
    dof_on("shadowmap", "scene drawn into the window");
}

/// The edge fade on the multi-pass scene, composited (`framebuffers`) and drawn into the
/// window (`shadowmap`): the floor runs into both borders in front of the screen plane, so
/// both must fade it in the bands and nowhere else, and the composited scene as the direct
/// one (measured: the same 23,412 px; the sharpen pass of the composite may move a few).
/// Framebuffer 0 of the composite holds the full-screen quad's depth, not the scene's: the
/// fade read it and faded the whole band, sky included (56,152 px), before it read the
/// disparity record and, where nothing recorded, the scene framebuffer's depth.
#[test]
fn edge_fade_works_on_a_composited_scene() {
    let band = 40;
    let mut changed = Vec::new();
    for program in ["shadowmap", "framebuffers"] {
        let (plain, _) = multipass(program, "fade-plain", &[]);
        let (faded, at) = multipass(program, "fade-on", &["--edge-fade", "40"]);
        let mut n = 0;
        for view in 0..3 {
            let (a, b) = (tile(&plain, 3, 1, view), tile(&faded, 3, 1, view));
            let cols = changed_columns(&a, &b);
            assert!(
                cols.iter().all(|&x| x < band || x >= a.width - band),
                "{program} view {view}: columns outside the bands changed: {cols:?} ({})",
                at.display()
            );
            n += pixels_off(&a, &b, 0);
        }
        eprintln!("{program}: --edge-fade 40 changed {n} px over the three views");
        changed.push(n);
    }
    let (direct, composited) = (changed[0], changed[1]);
    assert!(
        direct > 500,
        "the direct scene barely faded ({direct} px): the test sees nothing"
    );
    assert!(
        (composited as f64 - direct as f64).abs() <= 0.1 * direct as f64,
        "the composited scene faded {composited} px where the same scene drawn into the window fades {direct}: \
         the fade does not see the scene's depth through the composite"
    );
}
