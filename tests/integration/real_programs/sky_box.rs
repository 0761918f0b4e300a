//! A real game's camera-centred sky box at infinity (DESIGN §3): Extreme Tux Racer (Debian's
//! `extremetuxracer`) draws its sky as a unit cube under the view matrix followed by
//! `glTranslated(eye)`, depth writes off, before the course, the trees and Tux.
//!
//! The game is driven to a race by pressing Return until the screen shows snow (player,
//! event, cup, "Race!"), recorded with apitrace for a few seconds more, and the trace's
//! last frame is replayed under the layer as a 3x3 quilt (exact mode), with the rule and
//! with `--sky-at-infinity off`. Only the sky draw differs between the two replays, so the
//! pixels where an outer view differs between them are the sky that view shows: its shift
//! against the centre view must be infinity's, `depthiness · tile_w / 2` px, mirrored
//! between views 0 and 8, and must not be with the rule off.
//!
//! Two things stand between the packaged game and a trace, both handled by a small
//! preloaded library built here (`SHIM`): Debian's apitrace 11.1 keeps the count of the last
//! `glLockArraysEXT` after `glUnlockArraysEXT` (fixed upstream later) and copies that many
//! vertices from the game's next small stack array, which faults; the game is told the
//! extension is absent (a hint: the same pictures). And the game finds its settings through
//! `getpwuid`, not `$HOME`; the shim answers with `$HOME`, so the run has its own settings
//! (`OPTIONS`) and leaves the user's alone.

use crate::util::*;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const ETR: &str = "/usr/games/etr";
const SCREEN: (u32, u32) = (640, 480);
const DEPTHINESS: f64 = 0.13;
const CONVERGENCE: &str = "10";
/// Search range of the sky's shift (px): infinity is 41.6 px here; with the rule off the
/// unit box's shift is many times that and varies over the box.
const SEARCH: i32 = 64;
const BLOCK: u32 = 16;

/// The game's settings, all on one line (it reads every setting from each line, taking the
/// default for those absent from it, so the last line decides): full screen at the Xvfb
/// screen's size, 5 frames a second at most (a short trace: the race's clock is the wall
/// clock), full detail, silent.
const OPTIONS: &str = "[fullscreen] 1 [res_type] 0 [framerate] 5 [detail_level] 3 \
                       [sound_volume] 0 [music_volume] 0 [language] 0\n";

const SHIM: &str = r#"
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pwd.h>
#include <stdlib.h>
#include <string.h>
typedef void (*fn)(void);
typedef fn (*getproc)(const unsigned char *);
static int locks(const char *n) { return !strcmp(n, "glLockArraysEXT") || !strcmp(n, "glUnlockArraysEXT"); }
static fn lookup(const char *which, const unsigned char *n) {
    if (locks((const char *)n)) return 0;
    getproc next = (getproc)dlsym(RTLD_NEXT, which);
    return next ? next(n) : 0;
}
fn glXGetProcAddressARB(const unsigned char *n) { return lookup("glXGetProcAddressARB", n); }
fn glXGetProcAddress(const unsigned char *n) { return lookup("glXGetProcAddress", n); }
struct passwd *getpwuid(uid_t uid) {
    static struct passwd copy;
    struct passwd *(*next)(uid_t) = (struct passwd *(*)(uid_t))dlsym(RTLD_NEXT, "getpwuid");
    struct passwd *p = next(uid);
    const char *home = getenv("HOME");
    if (!p || !home) return p;
    copy = *p;
    copy.pw_dir = (char *)home;
    return &copy;
}
"#;

fn build_shim(dir: &Path) -> PathBuf {
    let (src, lib) = (dir.join("etr-shim.c"), dir.join("etr-shim.so"));
    std::fs::write(&src, SHIM).unwrap();
    let out = Command::new("cc")
        .args(["-shared", "-fPIC", "-O2", "-o"])
        .arg(&lib)
        .arg(&src)
        .arg("-ldl")
        .output()
        .expect("cc (the C compiler Rust links with)");
    assert_success(&out, "building the preload shim");
    lib
}

/// apitrace's GLX wrapper, preloaded by hand so that the shim comes before it.
fn glxtrace() -> PathBuf {
    std::fs::read_dir("/usr/lib")
        .unwrap()
        .flatten()
        .map(|d| d.path().join("apitrace/wrappers/glxtrace.so"))
        .find(|p| p.exists())
        .expect("apitrace's glxtrace.so (scripts/setup-debian.sh installs apitrace)")
}

/// The race (or its intro) is on screen: the lower third is snow, where every menu is blue.
fn racing(x: &XConn) -> bool {
    let img = x.grab(0, (SCREEN.1 * 2 / 3) as i32, SCREEN.0, SCREEN.1 / 3);
    let red = img.rgb.iter().step_by(3).map(|&v| f64::from(v)).sum::<f64>();
    red / f64::from(img.width * img.height) > 170.0
}

fn signal(child: &Child, sig: &str) {
    let _ = Command::new("kill").args([sig, &child.id().to_string()]).status();
}

/// Records the game from its start, through the menus, to `after` past the moment the race
/// shows on screen. Returns the trace and the number of frames it holds.
fn record_race(dir: &Path, xvfb: &Xvfb, after: Duration) -> (PathBuf, u32) {
    let home = dir.join("home");
    std::fs::create_dir_all(home.join(".etr")).unwrap();
    std::fs::write(home.join(".etr/options"), OPTIONS).unwrap();
    let preload = format!("{}:{}", build_shim(dir).display(), glxtrace().display());
    let trace = dir.join("etr.trace");
    let log = std::fs::File::create(dir.join("etr.log")).unwrap();
    let mut game = Command::new(ETR)
        .env("DISPLAY", &xvfb.display)
        .env("HOME", &home)
        .env("LD_PRELOAD", &preload)
        .env("TRACE_FILE", &trace)
        .env("ALSOFT_DRIVERS", "null")
        .env("SDL_AUDIODRIVER", "dummy")
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .expect("extremetuxracer (scripts/setup-debian.sh installs it)");
    let x = XConn::open(&xvfb.display);
    let start = Instant::now();
    let mut raced = None;
    while raced.is_none() && start.elapsed() < Duration::from_secs(150) {
        std::thread::sleep(Duration::from_secs(2));
        if let Ok(Some(status)) = game.try_wait() {
            panic!(
                "the game ended before the race ({status}): {}",
                dir.join("etr.log").display()
            );
        }
        if racing(&x) {
            raced = Some(start.elapsed());
        } else {
            let _ = Command::new("xdotool")
                .args(["key", "Return"])
                .env("DISPLAY", &xvfb.display)
                .status();
        }
    }
    let Some(raced) = raced else {
        signal(&game, "-KILL");
        let _ = game.wait();
        panic!("no race on screen after 150 s of Return presses");
    };
    std::thread::sleep(after);
    // apitrace's handler writes the trace out on SIGTERM.
    signal(&game, "-TERM");
    let end = Instant::now();
    while game.try_wait().ok().flatten().is_none() && end.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(200));
    }
    let _ = game.kill();
    let _ = game.wait();
    let frames = trace_frames(&trace);
    eprintln!(
        "etr: race on screen after {:.1} s; {frames} frames recorded ({} MB)",
        raced.as_secs_f64(),
        std::fs::metadata(&trace).map(|m| m.len() >> 20).unwrap_or(0)
    );
    (trace, frames)
}

/// `apitrace info`'s frame count.
fn trace_frames(trace: &Path) -> u32 {
    let out = run(Path::new("apitrace"), &["info", trace.to_str().unwrap()], &[]);
    assert_success(&out, "apitrace info");
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .find_map(|l| l.trim().strip_prefix("\"FramesCount\":"))
        .and_then(|v| v.trim().trim_end_matches(',').parse().ok())
        .unwrap_or_else(|| panic!("no frame count in {text}"))
}

/// Frame `frame` of the trace replayed under the layer as a 3x3 quilt, and the layer's log.
fn replay(dir: &Path, xvfb: &Xvfb, trace: &Path, frame: u32, rule: &str) -> (Image, String) {
    let dump = dir.join(format!("sky-{rule}"));
    let n = frame.to_string();
    let depthiness = DEPTHINESS.to_string();
    let tile = format!("{}x{}", SCREEN.0, SCREEN.1);
    let mut options = vec![
        "--quilt", "3x3", "--tile", &tile, "--output", "quilt", "--mode", "exact",
    ];
    options.extend(["--depthiness", &depthiness, "--convergence", CONVERGENCE]);
    options.extend(["--sky-at-infinity", rule, "--log", "info"]);
    options.extend(dump_and_exit_at(&dump, &n));
    let out = under_layer(
        &options,
        "glretrace",
        &[trace.to_str().unwrap()],
        &[("DISPLAY", &xvfb.display)],
    );
    assert_success(&out, "the trace replayed under the layer");
    let err = stderr(&out);
    assert!(!err.contains("holoinject: error"), "{err}");
    let aspect = holoinject::multiview::quilt::layout::QuiltLayout::new((3, 3), None, SCREEN).file_tag();
    (read_png(&dump.join(format!("f{frame:06}_{aspect}.png"))), err)
}

fn level(img: &Image, x: u32, y: u32, c: u32) -> i32 {
    i32::from(img.rgb[((y * img.width + x) * 3 + c) as usize])
}

/// The blocks of `view` (top-left corners) that show the sky: nearly all their pixels differ
/// from `other`, the same view with the other rule (nothing but the sky moves between the
/// two), and they have texture to match. Blocks within `SEARCH` of the sides are left out.
fn sky_blocks(view: &Image, other: &Image) -> Vec<(u32, u32)> {
    let mut blocks = Vec::new();
    for y0 in (0..view.height - BLOCK + 1).step_by(BLOCK as usize) {
        for x0 in (SEARCH as u32..view.width - BLOCK - SEARCH as u32 + 1).step_by(BLOCK as usize) {
            let (mut differ, mut texture) = (0, 0);
            for y in y0..y0 + BLOCK {
                for x in x0..x0 + BLOCK {
                    let d: i32 = (0..3)
                        .map(|c| (level(view, x, y, c) - level(other, x, y, c)).abs())
                        .sum();
                    differ += i32::from(d > 12);
                    if x + 1 < x0 + BLOCK {
                        texture += (0..3)
                            .map(|c| (level(view, x + 1, y, c) - level(view, x, y, c)).abs())
                            .sum::<i32>();
                    }
                }
            }
            let textured = f64::from(texture) / f64::from(BLOCK * (BLOCK - 1) * 3) >= 2.0;
            if differ * 10 >= (BLOCK * BLOCK * 9) as i32 && textured {
                blocks.push((x0, y0));
            }
        }
    }
    blocks
}

/// The shift (px, from the centre view to `view`) that best maps `blocks` of `view` onto the
/// centre, summed over all of them: the integer best and a sub-pixel estimate (a parabola
/// through the best three).
fn shift_of(centre: &Image, view: &Image, blocks: &[(u32, u32)]) -> (i32, f64) {
    let sad = |dx: i32| -> f64 {
        let mut e = 0i64;
        for &(x0, y0) in blocks {
            for y in y0..y0 + BLOCK {
                for x in x0..x0 + BLOCK {
                    let xc = (x as i32 + dx) as u32;
                    e += (0..3)
                        .map(|c| i64::from((level(view, x, y, c) - level(centre, xc, y, c)).abs()))
                        .sum::<i64>();
                }
            }
        }
        e as f64
    };
    let errors: Vec<f64> = (-SEARCH..=SEARCH).map(sad).collect();
    let best = (0..errors.len())
        .min_by(|&a, &b| errors[a].total_cmp(&errors[b]))
        .unwrap();
    let mut sub = best as f64;
    if best > 0 && best + 1 < errors.len() {
        let (l, e0, r) = (errors[best - 1], errors[best], errors[best + 1]);
        let curvature = l - 2.0 * e0 + r;
        if curvature > 0.0 {
            sub += 0.5 * (l - r) / curvature;
        }
    }
    // The view's content at x is the centre's at x + dx: the view moved it by -dx.
    (SEARCH - best as i32, SEARCH as f64 - sub)
}

/// The sky's shift from the centre to views 0 and 8 of `quilt`, the sky being where they
/// differ from `other`'s, and how many blocks of sky each view had.
fn sky_shifts(quilt: &Image, other: &Image) -> [((i32, f64), usize); 2] {
    let centre = tile(quilt, 3, 3, 4);
    [0, 8].map(|i| {
        let view = tile(quilt, 3, 3, i);
        let blocks = sky_blocks(&view, &tile(other, 3, 3, i));
        (shift_of(&centre, &view, &blocks), blocks.len())
    })
}

/// Extreme Tux Racer's sky moves as infinity in every view, within half a pixel: the integer
/// search finds the rounded disparity of infinity, mirrored between the outer views, and its
/// sub-pixel estimate is within 0.5 px of it. With `--sky-at-infinity off` it does not.
#[test]
fn extreme_tux_racer_sky_is_at_infinity() {
    require_display();
    assert!(
        Path::new(ETR).exists(),
        "{ETR} missing: scripts/setup-debian.sh installs extremetuxracer"
    );
    let dir = temp_dir("etr_sky");
    let xvfb = Xvfb::start(&format!("{}x{}x24", SCREEN.0, SCREEN.1));
    let (trace, frames) = record_race(&dir, &xvfb, Duration::from_secs(4));
    // The last frame may be cut short by the end of the recording.
    let frame = frames - 1;
    let (on, on_log) = replay(&dir, &xvfb, &trace, frame, "on");
    let (off, off_log) = replay(&dir, &xvfb, &trace, frame, "off");
    assert!(on_log.contains("put at infinity"), "the rule never applied:\n{on_log}");
    assert!(!off_log.contains("put at infinity"), "{off_log}");
    assert_eq!(
        tile(&on, 3, 3, 4).rgb,
        tile(&off, 3, 3, 4).rgb,
        "the centre view depends on the rule"
    );

    let rule_moved = |i| tile(&on, 3, 3, i).rgb != tile(&off, 3, 3, i).rgb;
    assert!(
        rule_moved(0) && rule_moved(8),
        "frame {frame}'s outer views are the same with the rule and without: its sky was not \
         taken as camera-attached ({})",
        dir.display()
    );

    let infinity = DEPTHINESS * f64::from(SCREEN.0) / 2.0;
    let expected = [-infinity.round() as i32, infinity.round() as i32];
    let with = sky_shifts(&on, &off);
    let without = sky_shifts(&off, &on);
    eprintln!(
        "etr frame {frame}: infinity ±{infinity:.2} px; sky (views 0, 8) with the rule {:?}, off {:?} \
         (integer, sub-pixel; blocks)",
        with, without
    );
    let where_ = dir.join("sky-on");
    for ((shift, blocks), want) in with.iter().zip(expected) {
        assert!(
            *blocks >= 20,
            "only {blocks} blocks of sky in frame {frame}: pick a frame with more sky ({})",
            where_.display()
        );
        assert_eq!(
            shift.0,
            want,
            "sky shift {with:?}, infinity ±{infinity:.2} ({})",
            where_.display()
        );
        assert!(
            (shift.1.abs() - infinity).abs() <= 0.5,
            "sky shift {with:?}, infinity ±{infinity:.2} ({})",
            where_.display()
        );
    }
    assert_eq!(with[0].0.0, -with[1].0.0, "the outer views do not mirror: {with:?}");
    for ((shift, blocks), want) in without.iter().zip(expected) {
        assert!(*blocks >= 20, "only {blocks} blocks of sky with the rule off");
        assert_ne!(
            shift.0, want,
            "--sky-at-infinity off: the sky still moves as infinity ({without:?})"
        );
    }
    // A passing run leaves the dumps, not the trace (about 100 MB).
    let _ = std::fs::remove_file(&trace);
}
