//! `--mode auto --frame-budget MS` on the sample apps (OSMesa: no display needed): budgets
//! are chosen from `exact` and `synth` frame times measured in the same test, so they are
//! reachable whatever this machine's speed and load.

use crate::util::*;

const QUILT: [&str; 6] = ["--output", "quilt", "--quilt", "5x1", "--tile", "320x240"];

/// The layer's own median frame time (ms) of `app` over `frames` frames in `mode`, and its log.
fn frame_time(app_name: &str, mode: &[&str], frames: &str) -> (f64, String) {
    let mut options = vec!["--log", "info", "--exit-after", frames, "--mode"];
    options.extend_from_slice(mode);
    options.extend(QUILT);
    let args = ["--backend", "osmesa", "--size", "320x240", "--frames", frames];
    let out = under_layer(&options, app(app_name), &args, &[]);
    assert_success(&out, &format!("{app_name} --mode {mode:?}"));
    assert_layer_loaded(&out);
    let log = stderr(&out);
    assert!(!log.contains("holoinject: warn"), "{log}");
    let ms = log
        .lines()
        .filter_map(|l| l.split("frame time: median ").nth(1))
        .filter_map(|r| r.split(" ms").next()?.parse::<f64>().ok())
        .next_back()
        .unwrap_or_else(|| panic!("no frame time in:\n{log}"));
    (ms, log)
}

/// The K changes (`auto: frame F: K a → b`) of an auto run: (frame, to).
fn changes(log: &str) -> Vec<(u64, u32)> {
    log.lines()
        .filter_map(|l| {
            let rest = l.split("auto: frame ").nth(1)?;
            let (frame, rest) = rest.split_once(": K ")?;
            let to = rest.split(" → ").nth(1)?.split(' ').next()?;
            Some((frame.parse().ok()?, to.parse().ok()?))
        })
        .collect()
}

/// The status lines (`auto: K k: median M ms over frames A-B`): (k, ms, first frame).
fn statuses(log: &str) -> Vec<(u32, f64, u64)> {
    log.lines()
        .filter_map(|l| {
            let rest = l.split("auto: K ").nth(1)?;
            let (k, rest) = rest.split_once(": median ")?;
            let (ms, rest) = rest.split_once(" ms over frames ")?;
            let first = rest.split('-').next()?;
            Some((k.parse().ok()?, ms.parse().ok()?, first.parse().ok()?))
        })
        .collect()
}

/// `bloom` (a multi-pass pipeline: every view's HDR pass and blur chain cost more than a
/// warp) with a budget halfway between synth and exact: auto settles on a K in between, and
/// the run's median frame time (every frame after warm-up, the probes of the ends included)
/// holds the budget within 10 % (its dead band is 5 %; the machine's load moves the rest).
/// It swung between neighbouring K on a loaded machine until a K left for going over the
/// budget was backed off (`auto::tests::runs_of_cheap_frames_do_not_pull_k_back_up_each_time`):
/// at most three changes after the two probes.
#[test]
fn auto_holds_a_budget_between_synth_and_exact() {
    // Twice each, alternating, the faster run of each kept: one run can meet a burst of
    // other work (seen with the other tests of the suite running beside it).
    let (mut exact, mut synth) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..2 {
        exact = exact.min(frame_time("bloom", &["exact"], "20").0);
        synth = synth.min(frame_time("bloom", &["synth"], "20").0);
    }
    assert!(
        synth < exact * 0.8,
        "bloom: synth {synth:.1} ms is not faster than exact {exact:.1} ms"
    );
    let budget = (exact + synth) / 2.0;
    let budget_arg = format!("{budget:.1}");
    let (ms, log) = frame_time("bloom", &["auto", "--frame-budget", &budget_arg], "70");
    // Regression: at a change of K the swap's depth copy came from the next frame's views
    // (not yet drawn), the deep scene looked flat, and auto stayed at K = 1 for good.
    assert!(!log.contains("under the synthesis threshold"), "{log}");
    let changes = changes(&log);
    assert!(
        (2..=5).contains(&changes.len()),
        "auto measures synth and exact, then chooses, and stays: {changes:?}\n{log}"
    );
    let (last_change, k) = *changes.last().unwrap();
    assert!(
        (1..5).contains(&k),
        "budget {budget:.1} ms (exact {exact:.1}, synth {synth:.1}): K {k}\n{log}"
    );
    if let Some(&(sk, _, _)) = statuses(&log).iter().rfind(|s| s.2 > last_change) {
        assert_eq!(sk, k, "{log}");
    }
    assert!(
        ms <= budget * 1.10,
        "median {ms:.1} ms against a budget of {budget:.1} ms (exact {exact:.1}, synth {synth:.1})\n{log}"
    );
}

/// `cubes` on a software rasteriser: warping costs more than rendering (README "Speed on a
/// software rasterizer"), so exact is both the fastest and the best, and auto ends there
/// whatever the budget between them.
#[test]
fn auto_ends_at_exact_where_exact_is_the_fastest() {
    let (exact, _) = frame_time("cubes", &["exact"], "30");
    let (synth, _) = frame_time("cubes", &["synth"], "30");
    let budget = format!("{:.1}", (exact + synth) / 2.0);
    let (_, log) = frame_time("cubes", &["auto", "--frame-budget", &budget], "40");
    let changes = changes(&log);
    assert_eq!(
        changes.last().map(|c| c.1),
        Some(5),
        "exact {exact:.1} ms, synth {synth:.1} ms:\n{log}"
    );
}

/// A scene without disparity runs K = 1 whatever the budget: nothing is measured, nothing
/// changes. `cubes` with depthiness 0 (its depth is there, its views do not differ), and
/// `lines`, which has no perspective camera.
#[test]
fn auto_keeps_one_view_for_a_flat_scene() {
    let (_, log) = frame_time("cubes", &["auto", "--frame-budget", "60000", "--depthiness", "0"], "30");
    assert!(changes(&log).is_empty(), "{log}");
    assert!(log.contains("auto: K 1: median"), "{log}");
    let (_, log) = frame_time("lines", &["auto", "--frame-budget", "60000"], "30");
    assert!(changes(&log).is_empty(), "{log}");
}
