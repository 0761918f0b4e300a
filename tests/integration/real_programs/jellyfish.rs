//! glmark2's `jellyfish`: a textured, lit jellyfish blended over a background, drawn without
//! depth writes, so the depth buffer under it holds nothing of it (the clear). `--mode exact`
//! moves it by its real eye distance (the vertex shaders' w); a fast mode that reads disparity
//! back from the depth buffer moves it as whatever lies under it. Its disparity in `--mode
//! synth`'s outermost views must be exact's, within 1 px.
//!
//! The jellyfish is found from the pictures, exactly: the background is a vertical gradient,
//! the same in every frame and constant along each row, and frame 1 of the scene shows it
//! alone (checked: every row one colour). The jellyfish is every pixel where the plain
//! replay's frame `FRAME` differs from frame 1 by more than 8 levels (the faintest edges of
//! its blended tentacles are left out: they carry no texture to match).
//!
//! On the build this test was written on it fails: 0 of 75 matched blocks agree; exact
//! shifts the jellyfish +9 px into the rightmost view, synth +17 px (it moves as the far
//! clear under it). `scripts/disparity-agreement.py` sees the same at 256x192 tiles with
//! auto-convergence (0 % agreeing blocks, -5 px against -9 px).

use super::{plain_snapshot, record};
use crate::util::*;
use std::path::Path;
use std::time::Instant;

const SCREEN: (u32, u32) = (400, 300);
/// Frame 30 of 40, as `scripts/disparity-agreement.py` looks at it: the bell and the
/// tentacles in the middle of the window.
const FRAME: u32 = 30;
const GRID: (u32, u32) = (5, 3);
/// What the layer's auto-convergence falls back to here, sqrt(near · far) = sqrt(20 · 120)
/// (nothing writes depth: no estimate), given so that every mode has the same.
const CONVERGENCE: &str = "49";
const SEARCH: i32 = 64;
/// The jellyfish's share of blocks whose synthesised shift must be within 1 px of exact's
/// in both outermost views (a block on its outline may match across a disocclusion).
const AGREE_SHARE: f64 = 0.9;

fn replay(dir: &Path, trace: &Path, mode: &str) -> Image {
    let dump = dir.join(mode);
    let n = FRAME.to_string();
    let mut options = vec![
        "--quilt", "5x3", "--output", "quilt", "--preset", "none", "--mode", mode,
    ];
    options.extend(["--convergence", CONVERGENCE, "--log", "info"]);
    options.extend(dump_and_exit_at(&dump, &n));
    let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &[]);
    assert_success(&out, &format!("jellyfish replayed under the layer, --mode {mode}"));
    let err = stderr(&out);
    assert!(!err.contains("holoinject: error"), "--mode {mode}:\n{err}");
    if mode == "synth" {
        assert!(
            err.contains("synthesis: 1 of 15 views rendered"),
            "--mode synth synthesised nothing: nothing to measure\n{err}"
        );
    }
    let aspect = holoinject::multiview::quilt::layout::QuiltLayout::new(GRID, None, SCREEN).file_tag();
    read_png(&dump.join(format!("f{FRAME:06}_{aspect}.png")))
}

/// glmark2's jellyfish moves in `--mode synth`'s outermost views as in exact's, within 1 px,
/// in at least 90 % of its blocks.
#[test]
#[ignore = "issue 22: with the record 84 % of the jellyfish's blocks are within 1 px of exact (90 % asked): where its translucent layers overlap, the last drawn is recorded, not the one whose texture shows"]
fn glmark2_jellyfish_moves_as_in_exact() {
    require_display();
    let start = Instant::now();
    let dir = temp_dir("glmark2_jellyfish");
    let size = format!("{}x{}", SCREEN.0, SCREEN.1);
    let prog = ["glmark2", "-s", &size, "-b", "jellyfish:nframes=40"];
    let trace = record(&dir, "jellyfish", "gl", &prog, "20", FRAME);
    let (frame_png, _) = plain_snapshot(&dir, "glretrace", &trace, FRAME);
    let frame = read_png(&frame_png);
    let background = read_png(&dir.join("plain/0000000000.png"));
    let flat_rows = (0..background.height).all(|y| {
        let row = &background.rgb[(y * background.width * 3) as usize..((y + 1) * background.width * 3) as usize];
        row.chunks(3).all(|p| p == &row[..3])
    });
    assert!(
        flat_rows,
        "frame 1 of jellyfish is not the bare background (a colour per row): the jellyfish \
         cannot be told from it ({})",
        dir.display()
    );
    let jellyfish = Mask::differing(&frame, &background, 8);
    eprintln!(
        "jellyfish: frame {FRAME}: the jellyfish covers {} px in {:?}",
        jellyfish.count(),
        jellyfish.bounds()
    );

    let exact = replay(&dir, &trace, "exact");
    let synth = replay(&dir, &trace, "synth");
    let found = compare_outer_views(&exact, &synth, GRID, &jellyfish, SEARCH);
    eprintln!("jellyfish, synth: {}", found.summary("synth"));
    for b in &found.matched {
        eprintln!("  block {:?}: exact {:?}, synth {:?}", b.at, b.exact, b.fast);
    }
    eprintln!("jellyfish: {:.0} s in all", start.elapsed().as_secs_f64());
    assert!(
        found.matched.len() >= 20 && found.largest_exact() >= 2,
        "exact shows too little of the jellyfish to compare ({} blocks, largest shift {} px): the \
         frame or the convergence is not what this test was written for ({})",
        found.matched.len(),
        found.largest_exact(),
        dir.display()
    );
    let (e1, f1) = found.medians(1);
    assert!(
        found.share_agreeing(1) >= AGREE_SHARE,
        "--mode synth puts glmark2's jellyfish at another depth than exact: {}; {} of its {} matched \
         blocks ({:.0} %) move within 1 px of exact, {:.0} % needed. {}. Quilts: {}",
        seen_depth("the jellyfish", "synth", e1, f1),
        found.agreeing(1),
        found.matched.len(),
        100.0 * found.share_agreeing(1),
        100.0 * AGREE_SHARE,
        found.summary("synth"),
        dir.display()
    );
    let _ = std::fs::remove_file(&trace);
}
