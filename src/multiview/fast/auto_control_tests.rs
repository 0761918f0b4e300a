//! The controller against cost sequences written here: a cost model per K, noise, and the
//! loads a shared machine puts on it (spikes, alternation, runs of load that come and go, a
//! lasting step), so what a loaded machine does to K is tested without one.

use super::*;

const N: u32 = 9;

/// A scene with something to fill at every K (holes need every view).
fn deep() -> SceneNeeds {
    SceneNeeds {
        range_px: 40.0,
        holes_per_u: 1.0,
    }
}

/// Deterministic noise in ±`amp` (fraction), from a linear congruential sequence.
struct Noise(u64, f64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        1.0 + self.1 * (((self.0 >> 33) as f64 / (1u64 << 31) as f64) * 2.0 - 1.0)
    }
}

/// Runs `frames` frames with frame time `cost(k, frame)`; the K sequence.
fn run(c: &mut Controller, frames: u32, noise: &mut Noise, cost: impl Fn(u32, u32) -> f64) -> Vec<u32> {
    let mut ks = vec![];
    for f in 0..frames {
        let ms = cost(c.k(), f) * noise.next();
        c.frame(Some(ms));
        ks.push(c.k());
    }
    ks
}

/// A heavy scene: replaying a view costs 20 ms, warping one from one source 3 ms, a grid 2 ms.
fn heavy(k: u32) -> f64 {
    let (a, r, g, w) = (10.0, 20.0, 2.0, 3.0);
    match k {
        N => a + r * N as f64,
        1 => a + r + g + w * (N - 1) as f64,
        _ => a + (r + g) * k as f64 + 2.0 * w * (N - k) as f64,
    }
}

fn changes(ks: &[u32]) -> usize {
    ks.windows(2).filter(|w| w[0] != w[1]).count()
}

#[test]
fn converges_to_the_most_views_that_fit() {
    // heavy: K=4 → 10 + 88 + 30 = 128 ms, K=5 → 10 + 110 + 24 = 144 ms.
    let mut c = Controller::new(N, 135.0, 1.0);
    c.scene(deep());
    let ks = run(&mut c, 80, &mut Noise(1, 0.0), |k, _| heavy(k));
    assert_eq!(*ks.last().unwrap(), 4, "{ks:?}");
    assert!(ks[..20].contains(&N), "exact is measured first: {ks:?}");
    assert!(changes(&ks[40..]) == 0, "settled: {ks:?}");
}

#[test]
fn does_not_oscillate_under_noise() {
    // The budget 3 % above K = 4's cost: ±8 % noise crosses it on many frames.
    let mut c = Controller::new(N, heavy(4) * 1.03, 1.0);
    c.scene(deep());
    let ks = run(&mut c, 300, &mut Noise(7, 0.08), |k, _| heavy(k));
    assert!(changes(&ks[60..]) <= 2, "{:?}", &ks[60..]);
    assert!(matches!(ks.last(), Some(3 | 4)), "{ks:?}");
}

#[test]
fn steps_down_when_costs_grow_and_up_when_they_fall() {
    let mut c = Controller::new(N, 135.0, 1.0);
    c.scene(deep());
    let scale = |f: u32| if (100..200).contains(&f) { 1.6 } else { 1.0 };
    let ks = run(&mut c, 300, &mut Noise(3, 0.02), |k, f| heavy(k) * scale(f));
    assert_eq!(ks[99], 4, "{ks:?}");
    // 1.6 × heavy: K=2 costs 1.6 × 98 = 157 ms: only K=1 (1.6 × 56 = 90 ms) fits.
    assert_eq!(ks[199], 1, "{:?}", &ks[100..200]);
    assert_eq!(ks[299], 4, "{:?}", &ks[200..]);
    for k in &ks[100..200] {
        assert!(*k <= 4);
    }
}

#[test]
fn a_flat_scene_runs_synth_whatever_the_budget() {
    let mut c = Controller::new(N, 10_000.0, 1.0);
    c.scene(SceneNeeds {
        range_px: 0.4,
        holes_per_u: 0.0,
    });
    let ks = run(&mut c, 50, &mut Noise(5, 0.05), |k, _| heavy(k));
    assert!(ks.iter().all(|&k| k == 1), "{ks:?}");
    // It turns deep: the budget allows every view.
    c.scene(deep());
    let ks = run(&mut c, 50, &mut Noise(5, 0.05), |k, _| heavy(k));
    assert_eq!(*ks.last().unwrap(), N, "{ks:?}");
}

#[test]
fn exact_when_it_is_the_fastest() {
    // A cheap scene on a software rasteriser: warping costs more than rendering.
    let cheap = |k: u32| match k {
        N => 40.0,
        1 => 200.0,
        _ => 200.0 + 40.0 * k as f64,
    };
    let mut c = Controller::new(N, 120.0, 1.0);
    c.scene(deep());
    let ks = run(&mut c, 40, &mut Noise(9, 0.05), |k, _| cheap(k));
    assert_eq!(*ks.last().unwrap(), N, "{ks:?}");
    assert_eq!(changes(&ks), 1, "only the probe of exact: {ks:?}");
    // Nothing fits 10 ms: the fastest.
    let mut c = Controller::new(N, 10.0, 1.0);
    let ks = run(&mut c, 40, &mut Noise(9, 0.05), |k, _| cheap(k));
    assert_eq!(*ks.last().unwrap(), N, "{ks:?}");
}

#[test]
fn k_grows_only_as_far_as_the_holes_call_for() {
    // Holes of 0.5 % of a tile per unit offset: K = 1 leaves 0.5 % in the outer views, K = 3
    // (farthest view 0.5 from a rendered one) 0.25 %, K = 4 (views 0, 3, 5, 8: one view,
    // 0.25, away) 0.125 %: enough, and cheaper than more.
    let mut c = Controller::new(N, 10_000.0, 1.0);
    c.scene(SceneNeeds {
        range_px: 12.0,
        holes_per_u: 0.005,
    });
    let ks = run(&mut c, 60, &mut Noise(2, 0.02), |k, _| heavy(k));
    assert_eq!(*ks.last().unwrap(), 4, "{ks:?}");
}

#[test]
fn hybrid_costs_are_predicted_from_the_ends_then_from_measured_ones() {
    let mut c = Controller::new(N, 1.0, 1.0);
    assert_eq!(c.predict(5), None);
    c.costs[0] = Some(100.0);
    c.costs[(N - 1) as usize] = Some(180.0);
    assert_eq!(c.predict(5), Some(140.0));
    c.costs[2] = Some(150.0);
    assert_eq!(c.predict(5), Some(170.0));
    c.costs[6] = Some(190.0);
    assert_eq!(c.predict(5), Some(170.0));
}

/// 400 frames of a 5-view scene costing `costs` by K against a 100 ms budget, each frame
/// scaled by `noise` and by `load(frame)`: the K sequence.
fn five_views(costs: [f64; 5], mut noise: Noise, load: impl Fn(u32) -> f64) -> Vec<u32> {
    drive(costs, 400, |f| noise.next() * load(f)).0
}

/// `frames` frames of a 5-view scene costing `costs` by K against a 100 ms budget, each frame
/// scaled by `load(frame)`: the K in force after each frame, and each frame's time.
fn drive(costs: [f64; 5], frames: u32, mut load: impl FnMut(u32) -> f64) -> (Vec<u32>, Vec<f64>) {
    let mut c = Controller::new(5, 100.0, 1.0);
    c.scene(deep());
    (0..frames)
        .map(|f| {
            let ms = costs[(c.k() - 1) as usize] * load(f);
            c.frame(Some(ms));
            (c.k(), ms)
        })
        .unzip()
}

#[test]
fn a_k_that_went_over_the_budget_is_not_retried_at_once() {
    // Measured on bloom 5x1 with the row warp (issue 12): K = 3 sits a few per cent over the
    // budget, K = 2 under it, frame times spread ±12 %. The controller swung 2 ↔ 3 every few
    // frames: a noisy run of K = 2's frames scaled K = 3's estimate back under the budget.
    // Every 17th frame a spike, as the machine's other work steals a core.
    let spike = |f: u32| if f.is_multiple_of(17) { 1.3 } else { 1.0 };
    let ks = five_views([60.0, 84.0, 104.0, 124.0, 140.0], Noise(11, 0.12), spike);
    assert!(changes(&ks[60..]) <= 3, "{:?}", &ks[60..]);
    assert_eq!(*ks.last().unwrap(), 2, "{ks:?}");
}

#[test]
fn runs_of_cheap_frames_do_not_pull_k_back_up_each_time() {
    // The machine's load comes and goes: every 40 frames, 10 frames cost 20 % less, enough
    // to make K = 3 look affordable from K = 2 and to be measured over the budget once the
    // run ends. Without the back-off it went 2 → 3 → 2 in every run (20 changes).
    let load = |f: u32| if f % 40 < 10 { 0.8 } else { 1.0 };
    let ks = five_views([60.0, 84.0, 110.0, 124.0, 140.0], Noise(4, 0.03), load);
    assert!(changes(&ks[60..]) <= 6, "{:?}", &ks[60..]);
    assert_eq!(*ks.last().unwrap(), 2, "{ks:?}");
}

/// A 5-view scene whose cost is a line in K. At the 100 ms budget K = 2 (80 ms) has the most
/// views that fit; 32 % more load takes it over the budget's band, 5 % less makes K = 3 look
/// affordable: both happen all the time on a shared machine.
const LINE: [f64; 5] = [60.0, 80.0, 100.0, 120.0, 140.0];
/// The frame by which both ends have been measured and K = 2 chosen, without load.
const SETTLED: u32 = 20;

/// The frames at whose end K changed.
fn change_frames(ks: &[u32]) -> Vec<usize> {
    (1..ks.len()).filter(|&i| ks[i] != ks[i - 1]).collect()
}

/// `LINE` under no load until `SETTLED`, then under `load`: K must stay 2 throughout.
fn assert_keeps_k(what: &str, load: impl Fn(u32) -> f64) {
    let (ks, _) = drive(LINE, 400, |f| if f < SETTLED { 1.0 } else { load(f) });
    let settled = &ks[SETTLED as usize - 1..];
    assert!(settled.iter().all(|&k| k == 2), "{what}: {settled:?}");
}

#[test]
fn a_load_that_alternates_does_not_change_k() {
    // Every other frame 60 % slower (over the band) or 10 % faster (K = 3 looks affordable):
    // the median of five flips every frame.
    assert_keeps_k("1.6 / 1", |f| if f % 2 == 1 { 1.6 } else { 1.0 });
    assert_keeps_k("1 / 0.9", |f| if f % 2 == 1 { 1.0 } else { 0.9 });
    assert_keeps_k("1.6 / 0.9", |f| if f % 2 == 1 { 1.6 } else { 0.9 });
}

#[test]
fn spikes_do_not_change_k() {
    // One or two frames three times slower in every seven (a core taken by another process).
    assert_keeps_k("spikes", |f| if f % 7 < 1 + (f / 7) % 2 { 3.0 } else { 1.0 });
    assert_keeps_k("dips", |f| if f % 7 < 1 + (f / 7) % 2 { 0.5 } else { 1.0 });
}

#[test]
fn load_that_comes_and_goes_in_short_runs_does_not_change_k() {
    // Four frames 60 % slower in every twelve: the median is over the band on four frames in
    // a row, one short of the call. (With a call of 3 frames, K went 2 → 1 in the first run.)
    assert_keeps_k("runs of 4 slow frames", |f| if f % 12 < 4 { 1.6 } else { 1.0 });
    // Twelve frames 10 % faster in every forty: K = 3 looks affordable on twelve frames in a
    // row, three short of the call. (It went 2 → 3 in the first run, 3 → 2 after it.)
    assert_keeps_k("runs of 12 fast frames", |f| if f % 40 < 12 { 0.9 } else { 1.0 });
}

#[test]
fn a_lasting_rise_lowers_k_within_seven_frames() {
    // From frame 100 on, every frame 60 % slower: the median of five is over from the third
    // such frame, and the call lasts `OVER_FRAMES`: K goes down at the end of frame 106.
    let (ks, _) = drive(LINE, 200, |f| if f < 100 { 1.0 } else { 1.6 });
    let down = 100 + RECENT / 2 + OVER_FRAMES as usize - 1;
    assert_eq!(down, 106);
    assert!(ks[SETTLED as usize..down].iter().all(|&k| k == 2), "{ks:?}");
    // 1.6 × LINE: nothing fits, K = 1 is the fastest.
    assert!(ks[down..].iter().all(|&k| k == 1), "{:?}", &ks[down..]);
}

#[test]
fn a_lasting_fall_raises_k_within_seventeen_frames() {
    // 25 % slower until frame 100: K = 1 (75 ms) is all that fits. Then unloaded: K = 2's
    // estimate falls to 80 ms from the third frame on, and the call lasts `BETTER_FRAMES`.
    let (ks, _) = drive(LINE, 200, |f| if f < 100 { 1.25 } else { 1.0 });
    let up = 100 + RECENT / 2 + BETTER_FRAMES as usize - 1;
    assert_eq!(up, 116);
    assert!(ks[SETTLED as usize..up].iter().all(|&k| k == 1), "{ks:?}");
    assert!(ks[up..].iter().all(|&k| k == 2), "{:?}", &ks[up..]);
}

#[test]
fn changes_are_held_apart_under_any_load() {
    // The load of the machine (6 to 9 on 2 cores): each frame 1 to 3 times slower at
    // random, in runs of random length. After the probes, no two changes closer than `HOLD`.
    let mut held = 0;
    for seed in 1..40 {
        let (mut noise, mut run, mut level) = (Noise(seed, 1.0), 0, 1.0);
        let (ks, _) = drive(LINE, 600, |_| {
            if run == 0 {
                (run, level) = ((noise.next() * 15.0) as u32, 1.0 + noise.next());
            }
            run = run.saturating_sub(1);
            level * (1.0 + 0.5 * (noise.next() - 1.0))
        });
        // The first change is to exact, to measure it; the hold starts when it is left.
        let at = change_frames(&ks);
        for w in at.get(1..).unwrap_or_default().windows(2) {
            assert!(w[1] - w[0] >= HOLD as usize, "seed {seed}: changes at {at:?}");
            held += 1;
        }
    }
    assert!(
        held >= 20,
        "only {held} pairs of changes: the load moves K too little to test the hold"
    );
}

#[test]
fn a_steady_random_load_does_not_make_k_flap() {
    // Each frame 1 to 3 times slower at random (the load, without runs): the load does
    // not change, nor should K once chosen. K changed 9 times in 70 frames on bloom.
    for seed in 1..40 {
        let mut noise = Noise(seed, 1.0);
        let (ks, _) = drive(LINE, 400, |_| 1.0 + noise.next());
        let at = change_frames(&ks);
        let revisits = at.windows(2).filter(|w| ks[w[1]] == ks[w[0] - 1]).count();
        assert!(at.len() <= 4 && revisits <= 1, "seed {seed}: changes at {at:?}: {ks:?}");
    }
}

#[test]
fn holds_a_budget_between_synth_and_exact() {
    // What the bloom integration test asserted against the machine's clock, now against
    // costs written here: bloom 5x1 (issue 12's figures), a budget halfway between synth
    // and exact, frame times spread ±12 %, and once the ends are measured, 4 frames 50 %
    // slower in every 25. K settles in between and stays, and the median frame time after
    // the ends were measured keeps the budget within the current K's band.
    let costs = [60.0, 84.0, 104.0, 124.0, 140.0];
    let mut noise = Noise(21, 0.12);
    let (ks, ms) = drive(costs, 400, |f| {
        noise.next() * if f >= SETTLED && f % 25 < 4 { 1.5 } else { 1.0 }
    });
    let k = *ks.last().unwrap();
    assert!((2..5).contains(&k), "{ks:?}");
    assert_eq!(changes(&ks[SETTLED as usize..]), 0, "{ks:?}");
    let mut after = ms[SETTLED as usize..].to_vec();
    after.sort_by(f64::total_cmp);
    let median = after[after.len() / 2];
    assert!(median <= 100.0 * (1.0 + OVER), "median {median:.1} ms: {ks:?}");
}
