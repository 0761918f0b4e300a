//! `--mode auto --frame-budget MS` on the sample apps (OSMesa: no display needed), asserting
//! only what does not depend on this machine's speed or load. Which K a run ends at does
//! (issue 21: on a busy machine the budget test failed and K changed nine times in 70
//! frames), so how K follows costs, holds a budget and keeps still under load that comes and
//! goes is asserted where the test writes the costs (`multiview::auto::control::tests`).
//! Here: auto measures both ends and then chooses, its changes are held apart by the frame
//! count, and a frame it renders at K is the frame `hybrid:K` renders, bit for bit.

use crate::util::*;
use holoinject::multiview::fast::auto::HOLD;
use std::path::Path;

const QUILT: [&str; 6] = ["--output", "quilt", "--quilt", "5x1", "--tile", "320x240"];
const VIEWS: u32 = 5;

/// `app` for `frames` frames under the layer with `layer` options and the quilt, its last
/// frame dumped into `dump` when given: the layer's log.
fn run_app(app_name: &str, layer: &[&str], frames: &str, dump: Option<&Path>) -> String {
    let mut options = vec!["--log", "info", "--exit-after", frames];
    options.extend_from_slice(layer);
    options.extend(QUILT);
    if let Some(dump) = dump {
        options.extend(["--dump", dump.to_str().unwrap(), "--dump-frames", frames]);
    }
    let args = ["--backend", "osmesa", "--size", "320x240", "--frames", frames];
    let out = under_layer(&options, app(app_name), &args, &[]);
    assert_success(&out, &format!("{app_name} {layer:?}"));
    assert_layer_loaded(&out);
    let log = stderr(&out);
    assert!(!log.contains("holoinject: warn"), "{log}");
    log
}

/// The layer's median frame time (ms) in its log.
fn median_ms(log: &str) -> f64 {
    log.lines()
        .filter_map(|l| l.split("frame time: median ").nth(1))
        .filter_map(|r| r.split(" ms").next()?.parse::<f64>().ok())
        .next_back()
        .unwrap_or_else(|| panic!("no frame time in:\n{log}"))
}

/// The K changes (`auto: frame F: K a → b`) of an auto run: (frame, from, to).
fn changes(log: &str) -> Vec<(u64, u32, u32)> {
    log.lines()
        .filter_map(|l| {
            let rest = l.split("auto: frame ").nth(1)?;
            let (frame, rest) = rest.split_once(": K ")?;
            let (from, rest) = rest.split_once(" → ")?;
            let to = rest.split(' ').next()?;
            Some((frame.parse().ok()?, from.parse().ok()?, to.parse().ok()?))
        })
        .collect()
}

/// The status lines (`auto: K k: median M ms over frames A-B`): (k, first frame).
fn statuses(log: &str) -> Vec<(u32, u64)> {
    log.lines()
        .filter_map(|l| {
            let rest = l.split("auto: K ").nth(1)?;
            let (k, rest) = rest.split_once(": median ")?;
            let first = rest.split_once(" ms over frames ")?.1.split('-').next()?;
            Some((k.parse().ok()?, first.parse().ok()?))
        })
        .collect()
}

/// The fixed mode that renders K views.
fn mode_of(k: u32) -> String {
    match k {
        1 => "synth".into(),
        VIEWS => "exact".into(),
        k => format!("hybrid:{k}"),
    }
}

/// `app` under `--mode auto` for `frames` frames at `budget` ms, the convergence fixed at
/// `convergence` (auto-convergence smooths over frames, and which frames give it the centre
/// view's depth depends on K: the same frame would then differ by the K history).
fn assert_auto_renders_the_k_it_chose(test: &str, app_name: &str, budget: f64, convergence: &str, frames: u64) {
    let dir = temp_dir(test);
    let n = frames.to_string();
    let budget = format!("{budget:.1}");
    let auto = [
        "--mode",
        "auto",
        "--frame-budget",
        &budget,
        "--convergence",
        convergence,
    ];
    let log = run_app(app_name, &auto, &n, Some(&dir.join("auto")));
    // Regression: at a change of K the swap's depth copy came from the next frame's views
    // (not yet drawn), the deep scene looked flat, and auto stayed at K = 1 for good.
    assert!(!log.contains("under the synthesis threshold"), "{log}");
    let changes = changes(&log);
    let first = log.lines().find(|l| l.contains("auto: frame"));
    assert!(
        changes.first().is_some_and(|&(_, from, to)| (from, to) == (1, VIEWS))
            && first.is_some_and(|l| l.contains("measuring exact")),
        "auto measures synth, then exact: {changes:?}\n{log}"
    );
    assert!(
        changes
            .iter()
            .all(|&(_, from, to)| (1..=VIEWS).contains(&from) && (1..=VIEWS).contains(&to))
    );
    for w in changes[1..].windows(2) {
        assert!(
            w[1].0 - w[0].0 >= u64::from(HOLD),
            "changes closer than {HOLD} frames: {changes:?}\n{log}"
        );
    }
    // A change at the end of frame F renders from frame F + 1 on.
    let k = changes.iter().rfind(|c| c.0 < frames).map_or(1, |c| c.2);
    let last_change = changes.last().map_or(0, |c| c.0);
    if let Some(&(sk, _)) = statuses(&log).iter().rfind(|s| s.1 > last_change) {
        assert_eq!(sk, changes.last().unwrap().2, "{log}");
    }
    let fixed = ["--mode", &mode_of(k), "--convergence", convergence];
    run_app(app_name, &fixed, &n, Some(&dir.join("fixed")));
    let mut dumps: Vec<_> = std::fs::read_dir(dir.join("auto"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dumps.sort();
    assert!(!dumps.is_empty(), "nothing dumped in {}", dir.display());
    eprintln!("{test}: budget {budget} ms, frame {frames} at K {k}: changes {changes:?}");
    for auto_png in dumps {
        assert_identical(&dir.join("fixed").join(auto_png.file_name().unwrap()), &auto_png);
    }
}

/// `bloom`: a multi-pass pipeline, every view's HDR pass and blur chain costing more than a
/// warp, so K in between is worth choosing. The budget is set halfway between synth and
/// exact as this machine measures them, so that most runs end at a K in between; nothing
/// asserted depends on it.
#[test]
fn auto_on_bloom_renders_the_k_it_chose() {
    let exact = median_ms(&run_app("bloom", &["--mode", "exact"], "20", None));
    let synth = median_ms(&run_app("bloom", &["--mode", "synth"], "20", None));
    assert_auto_renders_the_k_it_chose("auto_bloom", "bloom", (exact + synth) / 2.0, "9", 70);
}

/// `cubes` on a software rasteriser: warping costs more than rendering (README "Speed on a
/// software rasterizer"), so most runs end at exact.
#[test]
fn auto_on_cubes_renders_the_k_it_chose() {
    assert_auto_renders_the_k_it_chose("auto_cubes", "cubes", 100.0, "15.6", 40);
}

/// A scene without disparity runs K = 1 whatever the budget: nothing is measured, nothing
/// changes. `cubes` with depthiness 0 (its depth is there, its views do not differ). (`lines`
/// was the second case while its globe, blended without depth writes, left neither depth nor
/// a record; it records now, and is a scene with disparity.)
#[test]
fn auto_keeps_one_view_for_a_flat_scene() {
    let flat = ["--mode", "auto", "--frame-budget", "60000", "--depthiness", "0"];
    let log = run_app("cubes", &flat, "30", None);
    assert!(changes(&log).is_empty(), "{log}");
    assert!(log.contains("auto: K 1: median"), "{log}");
}
