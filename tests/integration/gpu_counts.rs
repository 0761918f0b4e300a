//! `--gpu-counts`: what a frame asks of the GPU, counted by the layer (draws the driver is
//! given, fragment and compute invocations from pipeline-statistics queries, bytes read back).
//! The counts must follow from the mode: exact hands the driver every draw once per view,
//! synth once, plus the layer's own passes.

use crate::util::*;

struct Counts {
    app: u64,
    submitted: u64,
    own: u64,
    fragments: u64,
    compute: u64,
    read_back: u64,
}

fn number(line: &str, after: &str) -> u64 {
    let rest = line
        .split(after)
        .nth(1)
        .unwrap_or_else(|| panic!("no `{after}` in: {line}"));
    let n: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    n.parse()
        .unwrap_or_else(|_| panic!("no number after `{after}` in: {line}"))
}

/// Cubes at 5x3 of 160x120 for 14 frames (the last four counted) in `mode`.
fn counts(mode: &str, extra: &[&str]) -> Counts {
    let mut layer = vec![
        "--log", "info", "--output", "quilt", "--quilt", "5x3", "--tile", "160x120", "--mode", mode,
    ];
    layer.extend(["--gpu-counts", "--exit-after", "14"]);
    layer.extend_from_slice(extra);
    let out = under_layer(
        &layer,
        app("cubes"),
        &["--backend", "osmesa", "--size", "160x120", "--frames", "14"],
        &[],
    );
    assert_success(&out, &format!("cubes --mode {mode}"));
    let err = stderr(&out);
    let line = err
        .lines()
        .find(|l| l.contains("gpu counts: per frame"))
        .unwrap_or_else(|| panic!("no gpu counts line under --mode {mode}:\n{err}"));
    assert!(line.contains("median over 4 frames"), "{line}");
    Counts {
        app: number(line, "app draws "),
        submitted: number(line, "draws submitted "),
        own: number(line, "layer's own "),
        fragments: number(line, "fragments "),
        compute: number(line, "compute invocations "),
        read_back: number(line, "bytes read back "),
    }
}

#[test]
fn exact_submits_every_draw_once_per_view_and_synth_once() {
    let exact = counts("exact", &[]);
    assert!(exact.app > 0 && exact.fragments > 0, "exact counted nothing");
    assert_eq!(
        exact.submitted - exact.own,
        15 * exact.app,
        "exact: one replay per view"
    );
    assert_eq!(exact.compute, 0, "exact runs no compute pass");
    let synth = counts("synth", &["--synth-warp", "rows", "--guard-band", "off"]);
    assert_eq!(synth.app, exact.app, "the same frames of the same program");
    assert_eq!(synth.submitted - synth.own, synth.app, "synth renders one view");
    // The guard band's two strips per rendered view are two more draws of each draw of the
    // scene (cubes draws nothing but its scene).
    let band = counts("synth", &["--synth-warp", "rows", "--guard-band", "8"]);
    assert_eq!(band.submitted - band.own, 3 * band.app, "synth with a guard band");
    assert!(
        synth.compute > 0,
        "the row warp is a compute pass: {} invocations",
        synth.compute
    );
    assert!(synth.own > exact.own, "synth's passes are the layer's own");
}

#[test]
fn a_dumped_quilt_counts_as_read_back() {
    let dir = temp_dir("gpu_counts_dump");
    let plain = counts("exact", &[]);
    let dumped = counts("exact", &["--dump", dir.to_str().unwrap()]);
    let quilt_bytes = 5 * 160 * 3 * 120 * 4;
    assert!(
        dumped.read_back >= plain.read_back + quilt_bytes,
        "dumping every frame reads the quilt back: {} bytes against {} without",
        dumped.read_back,
        plain.read_back
    );
}

/// Auto-convergence reads back a quarter of the scene's rows (depth, 4 bytes a pixel, and the
/// disparity record, 8), not all of them: what a GPU stalls for at every swap. A fixed
/// convergence reads nothing. The estimate from those rows is asserted elsewhere
/// (`convergence`).
#[test]
fn auto_convergence_reads_a_quarter_of_the_rows() {
    let auto = counts("synth", &[]);
    let fixed = counts("synth", &["--convergence", "5"]);
    assert_eq!(fixed.read_back, 0, "a fixed convergence reads nothing back");
    let rows = 120_u64.div_ceil(4);
    assert!(
        auto.read_back > 0 && auto.read_back <= 160 * rows * (4 + 8),
        "auto-convergence read {} bytes a frame: more than {} rows of 160 pixels",
        auto.read_back,
        rows
    );
}
