//! Real programs from Debian packages under the layer in pass-through (`--output mono`).
//!
//! Their animation follows the wall clock, so "identical with and without the layer" is made
//! deterministic the way the issue suggests: record an apitrace once, replay it plainly with
//! glretrace's own snapshots, replay it again under the layer with our dumps, and compare the
//! same frame bit for bit. A replay alone does not make frame N one moment of the animation:
//! the recording samples the clock, and a loaded machine recorded glmark2's pulsar flat again
//! at frame 1500 (issue 21). So programs are recorded under a steady clock
//! (`real_programs/steady_clock.c`: each reading on the main thread is 1/60 s after the
//! last), and frame N of a recording is the same scene on any machine. glmark2 itself (which
//! `dlopen`s libGL `RTLD_LOCAL`) is also run directly to prove the dlopen/dlsym path is
//! hooked. Every replay under the layer reports no GL error that the plain replay of the same
//! trace does not (`assert_no_added_gl_errors`).

use crate::util::*;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod fbo_truth;
mod hdr;
mod jellyfish;
mod minetest;
mod sky_box;
mod weapon;
mod window_like;

/// `real_programs/steady_clock.c`, built once per test run with `cc` (the linker Rust uses).
fn steady_clock() -> &'static Path {
    static LIB: OnceLock<PathBuf> = OnceLock::new();
    LIB.get_or_init(|| {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/integration/real_programs/steady_clock.c");
        let lib = Path::new(env!("CARGO_TARGET_TMPDIR")).join("steady_clock.so");
        let (src, out) = (src.to_str().unwrap(), lib.to_str().unwrap());
        let flags = [
            "-shared", "-fPIC", "-O2", "-Wall", "-Wextra", "-Werror", "-o", out, src, "-ldl",
        ];
        assert_success(&run(Path::new("cc"), &flags, &[]), "cc steady_clock.c");
        lib
    })
}

/// Runs the rest of its arguments with `$0` added to `LD_PRELOAD` after what is there:
/// `apitrace trace` sets `LD_PRELOAD` to its own wrapper for the program it starts.
const PRELOAD_TOO: &str = r#"LD_PRELOAD="$LD_PRELOAD:$0" exec "$@""#;

/// Records `program` with apitrace, under the steady clock, for `seconds` (or until it
/// exits), until the trace holds `frames` frames. `timeout` signals the whole process group;
/// apitrace's own signal handler in the traced program has been seen to hang under load, so a
/// KILL follows 5 s later (glretrace replays truncated traces). On a loaded machine a program
/// can spend a short recording just starting (glxgears recorded nothing in 1.5 s during a
/// full test run; chromium-bsu 6 s short of 60 frames beside `stress-ng --cpu 4`): then it is
/// recorded again for four times as long. Which frames there are depends on the machine;
/// what each one shows does not.
fn record(dir: &Path, name: &str, api: &str, program: &[&str], seconds: &str, frames: u32) -> PathBuf {
    require_display();
    let trace = dir.join(format!("{name}.trace"));
    let longer = seconds
        .parse::<f64>()
        .map_or(seconds.to_string(), |s| format!("{}", s * 4.0));
    let clock = steady_clock().to_str().unwrap();
    let mut recorded = 0;
    for limit in [seconds, longer.as_str()] {
        let mut args = vec!["-k", "5", limit, "apitrace", "trace", "--api", api, "-o"];
        args.extend([trace.to_str().unwrap(), "sh", "-c", PRELOAD_TOO, clock]);
        args.extend_from_slice(program);
        let _ = std::fs::remove_file(&trace);
        record_once(&args);
        recorded = frames_in(&trace);
        if recorded >= frames {
            return trace;
        }
    }
    panic!(
        "apitrace recorded {recorded} of {frames} frames of {program:?} in {longer} s \
         (is apitrace installed? scripts/setup-debian.sh)"
    );
}

/// `timeout ARGS…` in a process group of its own, its output discarded, and whatever of the
/// group outlives it killed: a traced program whose apitrace signal handler hung kept running
/// after `timeout` had killed its child, holding the test's output pipe open (a CI run waited
/// on winduprobot for 12 minutes).
fn record_once(args: &[&str]) {
    use std::os::unix::process::CommandExt;
    use std::process::{Command, Stdio};
    let child = Command::new("timeout")
        .args(args)
        .env("ALSOFT_DRIVERS", "null")
        .process_group(0)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn();
    if let Ok(mut c) = child {
        let _ = c.wait();
        let group = format!("-{}", c.id());
        let _ = Command::new("kill")
            .args(["-KILL", "--", &group])
            .stderr(Stdio::null())
            .status();
    }
}

/// The frames of a trace (`apitrace info`), 0 when there is none.
fn frames_in(trace: &Path) -> u32 {
    let out = run(Path::new("apitrace"), &["info", trace.to_str().unwrap()], &[]);
    let info = String::from_utf8_lossy(&out.stdout);
    info.split("\"FramesCount\":")
        .nth(1)
        .and_then(|r| r.split([',', '\n', '}']).next()?.trim().parse().ok())
        .unwrap_or(0)
}

/// Frame `frame` (from 1) of a plain replay, as glretrace's own snapshot, and what the
/// replay said on stderr (its GL errors).
fn plain_snapshot(dir: &Path, retrace: &str, trace: &Path, frame: u32) -> (PathBuf, String) {
    let snaps = dir.join("plain");
    std::fs::create_dir_all(&snaps).unwrap();
    let prefix = format!("{}/", snaps.display());
    let out = run(
        Path::new(retrace),
        &["--call-nos=false", "-s", &prefix, trace.to_str().unwrap()],
        &[MESA_DEBUG_ENV],
    );
    assert_success(&out, retrace);
    (snaps.join(format!("{:010}.png", frame - 1)), stderr(&out))
}

/// The same frame replayed under the layer, as the layer's dump, and the replay's stderr.
fn injected_dump(dir: &Path, retrace: &str, trace: &Path, frame: u32) -> (PathBuf, String) {
    let dump = dir.join("injected");
    let n = frame.to_string();
    let mut options = vec!["--output", "mono", "--log", "info"];
    options.extend(dump_and_exit_at(&dump, &n));
    let out = under_layer(&options, retrace, &[trace.to_str().unwrap()], &[MESA_DEBUG_ENV]);
    assert_success(&out, "replay under the layer");
    assert_layer_loaded(&out);
    (dump.join(format!("f{frame:06}_out.png")), stderr(&out))
}

fn assert_replay_identical(test: &str, api: &str, retrace: &str, program: &[&str], seconds: &str, frame: u32) {
    let dir = temp_dir(test);
    let trace = record(&dir, test, api, program, seconds, frame);
    let (expected, plain_err) = plain_snapshot(&dir, retrace, &trace, frame);
    let (actual, layer_err) = injected_dump(&dir, retrace, &trace, frame);
    assert!(
        has_content(&expected),
        "frame {frame} of {test} is blank; pick a later frame"
    );
    assert_no_added_gl_errors(&plain_err, &layer_err, test);
    assert_identical(&expected, &actual);
}

/// Block search range (px): the outer view moves 20 px at infinity (depthiness 0.1 in a
/// 400-px tile) and content at half the convergence distance as far the other way.
const PARALLAX_SEARCH: i32 = 40;

/// Frame `frame` of a replay under the layer as a 5x1 quilt, with the layer's own
/// auto-convergence: its centre tile must be the plain frame bit for bit (the quilt is drawn
/// where and as the window is; before issue 11, llvmpipe's rounding after the tile's offset
/// and in a bottom-up framebuffer moved 1-7 pixels in glmark2's scenes and 277 in
/// chromium-bsu, by one level), and the side views must show depth: per-block
/// shifts that spread over more than a pixel in the outer views, more the further from the
/// centre, and mirrored between left and right (`assert_depth_parallax`). A scene seen at the
/// wrong convergence slides as a whole (no spread); one at a sensible convergence has near
/// and far content moving opposite ways. Returns the layer's auto-convergence log line.
fn assert_replay_quilt(test: &str, api: &str, retrace: &str, program: &[&str], seconds: &str, frame: u32) -> String {
    replay_quilt(test, api, retrace, program, seconds, frame, QuiltChecks::ALL)
}

/// What `replay_quilt` asserts of the quilt besides the GL errors (always checked).
#[derive(Clone, Copy)]
struct QuiltChecks {
    /// The side views show depth (`assert_depth_parallax`).
    parallax: bool,
}

impl QuiltChecks {
    const ALL: QuiltChecks = QuiltChecks { parallax: true };
}

/// `assert_replay_quilt` with a choice of checks: scenes drawn flat (2D compositing) have no
/// parallax to check.
fn replay_quilt(
    test: &str,
    api: &str,
    retrace: &str,
    program: &[&str],
    seconds: &str,
    frame: u32,
    checks: QuiltChecks,
) -> String {
    let dir = temp_dir(test);
    let trace = record(&dir, test, api, program, seconds, frame);
    let (plain_png, plain_err) = plain_snapshot(&dir, retrace, &trace, frame);
    let plain = read_png(&plain_png);
    let dump = dir.join("quilt");
    let n = frame.to_string();
    // Auto-convergence even where a preset pins it (glxgears, es2gears, chromium-bsu): the
    // depth it finds is what these tests are about.
    let mut options = vec!["--quilt", "5x1", "--depthiness", "0.1", "--convergence", "auto"];
    options.extend(["--log", "info"]);
    options.extend(dump_and_exit_at(&dump, &n));
    let out = under_layer(&options, retrace, &[trace.to_str().unwrap()], &[MESA_DEBUG_ENV]);
    assert_success(&out, "replay under the layer");
    let err = stderr(&out);
    assert_no_added_gl_errors(&plain_err, &err, test);
    let convergence = err
        .lines()
        .filter(|l| l.contains("auto-convergence"))
        .collect::<Vec<_>>()
        .join("\n");
    eprintln!("{test}: {convergence}");
    let aspect =
        holoinject::multiview::quilt::layout::QuiltLayout::new((5, 1), None, (plain.width, plain.height)).file_tag();
    let quilt_png = dump.join(format!("f{frame:06}_{aspect}.png"));
    let quilt = read_png(&quilt_png);
    let centre = tile(&quilt, 5, 1, 2);
    let what = format!("{test}: centre tile against the plain frame");
    assert_within(&plain, &centre, &suffixed(&quilt_png, "-centre"), EXACT, &what);
    if checks.parallax {
        assert_depth_parallax(&quilt, &quilt_png, 5, PARALLAX_SEARCH, test);
    }
    convergence
}

/// ES has no depth read-back: the convergence comes through the layer's colour pass and
/// lands on the gears, as glxgears' does with `glReadPixels` (38.8 measured in both; the
/// gears sit 40 in front of the camera, near 5, far 60).
#[test]
fn es2gears_quilt_has_parallax_and_exact_centre() {
    let line = assert_replay_quilt("es2gears_quilt", "egl", "eglretrace", &["es2gears_x11"], "1.5", 10);
    assert!(line.contains("colour pass"), "{line}");
    let c: f64 = line
        .split("scene at ")
        .nth(1)
        .and_then(|r| r.split(' ').next()?.parse().ok())
        .unwrap();
    assert!((35.0..42.0).contains(&c), "{line}");
}

/// glmark2 scenes, each run for its own length (`duration=S` or `nframes=N`) and seen at
/// frame `$frame`.
macro_rules! glmark2_quilt_tests {
    ($($name:ident: $bench:literal at $frame:expr;)*) => {$(
        #[test]
        fn $name() {
            let prog = ["glmark2", "-s", "400x300", "-b", $bench];
            assert_replay_quilt(stringify!($name), "gl", "glretrace", &prog, "20", $frame);
        }
    )*};
}

/// glmark2 scenes that render through their own framebuffers: `shadow` (a depth-only shadow
/// map drawn once, then the lit scene) and `desktop` (2D windows composited through FBOs).
#[test]
fn glmark2_shadow_fbo_quilt() {
    let prog = ["glmark2", "-s", "400x300", "-b", "shadow:duration=0.5"];
    assert_replay_quilt("glmark2_shadow_fbo_quilt", "gl", "glretrace", &prog, "20", 8);
}

/// `terrain`: noise and height maps through a chain of FBOs with mipmaps
/// (`glGenerateMipmapEXT`), the terrain into its own FBO, a depth-of-field blur, then a
/// full-screen composite onto the screen. Regression: auto-convergence read framebuffer 0's
/// depth, which at the swap holds the composite's quad (w = 2·near = 4), so every view slid
/// as a flat picture (outer views: shifts of ±20 px, spread 0.1 px); the scene's depth is in
/// the framebuffer the camera draws into.
#[test]
fn glmark2_terrain_fbo_quilt() {
    let prog = ["glmark2", "-s", "400x300", "-b", "terrain:nframes=8"];
    let line = assert_replay_quilt("glmark2_terrain_fbo_quilt", "gl", "glretrace", &prog, "60", 6);
    assert!(
        line.contains("from framebuffer") && !line.contains("from framebuffer 0"),
        "{line}"
    );
    let trace = temp_path("glmark2_terrain_fbo_quilt").join("glmark2_terrain_fbo_quilt.trace");
    terrain_synth_matches_exact(&trace);
    terrain_rendered_view_mipmapped_alone(&trace);
}

/// Under `--mode synth` only the rendered view's layers of terrain's mipmapped framebuffer
/// textures are filtered when it calls `glGenerateMipmapEXT` (blits per level: Mesa mipmaps a
/// texture view's whole array; the whole chain of 48 layers was most of a synthesised view's
/// cost). Its blur samples those levels, so the rendered view must be the exact quilt's own,
/// bit for bit; a level left unfiltered or filtered otherwise shows in the blur.
fn terrain_rendered_view_mipmapped_alone(trace: &Path) {
    let dir = trace.parent().unwrap();
    let quilt = |mode: &str| {
        let dump = dir.join(format!("mip-{mode}"));
        let mut options = vec!["--mode", mode, "--quilt", "5x1", "--tile", "200x150"];
        options.extend(dump_and_exit_at(&dump, "6"));
        let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &[]);
        assert_success(&out, &format!("terrain under --mode {mode}"));
        let png = dumped_quilt(&dump, 6);
        (read_png(&png), png)
    };
    let ((exact, _), (synth, png)) = (quilt("exact"), quilt("synth"));
    let what = "terrain synth: the rendered centre view against exact's";
    assert_within(
        &tile(&exact, 5, 1, 2),
        &tile(&synth, 5, 1, 2),
        &suffixed(&png, "-centre"),
        EXACT,
        what,
    );
}

/// The same trace under `--mode synth`: terrain draws a full-screen pass into its scene
/// framebuffer after the terrain, so at the warp point that framebuffer's depth is the pass's
/// (0.5 everywhere). Regression: the warp read it there, every pixel moved by hundreds of
/// pixels and the synthesised views were stretched border pixels (15.4 dB against exact);
/// the depth is now copied when the scene tracker sees it about to be drawn over (37.8 dB
/// measured at 3x3 of 200x150; 30 dB leaves room for other frames of the animation).
fn terrain_synth_matches_exact(trace: &Path) {
    let options = [
        "--mode",
        "synth",
        "--quilt",
        "3x3",
        "--tile",
        "200x150",
        "--log",
        "info",
        "--measure-error",
        "every:5",
        "--exit-after",
        "6",
    ];
    let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &[]);
    assert_success(&out, "terrain under --mode synth");
    let err = stderr(&out);
    let line = err
        .lines()
        .find(|l| l.contains("measure-error: frame 5"))
        .unwrap_or_else(|| panic!("no measured frame:\n{err}"));
    let mean: f64 = line
        .split("PSNR mean ")
        .nth(1)
        .and_then(|r| r.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(mean >= 30.0, "{line}");
}

/// The quilt `--dump` wrote into `dump` for `frame`.
fn dumped_quilt(dump: &Path, frame: u32) -> PathBuf {
    let prefix = format!("f{frame:06}_qs");
    std::fs::read_dir(dump)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with(&prefix)))
        .unwrap_or_else(|| panic!("no quilt dumped in {}", dump.display()))
}

/// 2D windows composited through FBOs: no depth to show, so only the centre is checked.
#[test]
fn glmark2_desktop_fbo_quilt_centre() {
    let prog = ["glmark2", "-s", "400x300", "-b", "desktop:duration=0.5"];
    let checks = QuiltChecks { parallax: false };
    replay_quilt("glmark2_desktop_fbo_quilt", "gl", "glretrace", &prog, "20", 8, checks);
    flat_frame_fills_every_view_in_synth(&temp_path("glmark2_desktop_fbo_quilt"));
}

/// The same trace under `--mode synth`: nothing in the frame depends on the view, so there is
/// no warp point, and every view must show what the rendered one shows. Regression: the views
/// that are not rendered were left as they were (black: 14 of 15 views in the disparity sweep).
fn flat_frame_fills_every_view_in_synth(dir: &Path) {
    let trace = dir.join("glmark2_desktop_fbo_quilt.trace");
    let dump = dir.join("synth");
    let mut options = vec!["--mode", "synth", "--quilt", "5x1", "--log", "info"];
    options.extend(dump_and_exit_at(&dump, "8"));
    let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &[]);
    assert_success(&out, "desktop under --mode synth");
    let quilt_png = dumped_quilt(&dump, 8);
    let quilt = read_png(&quilt_png);
    let centre = tile(&quilt, 5, 1, 2);
    for v in [0, 1, 3, 4] {
        let what = format!("desktop synth: view {v} against the rendered centre view");
        assert_within(
            &centre,
            &tile(&quilt, 5, 1, v),
            &suffixed(&quilt_png, &format!("-{v}")),
            EXACT,
            &what,
        );
    }
}

/// `refract`: the scene's depth drawn into a framebuffer with an unsized `GL_DEPTH_COMPONENT`
/// texture of `GL_UNSIGNED_INT` (32 bits on Mesa), sampled by the refraction pass.
/// Regression: the layers of that texture were 24-bit, and every depth blit between them and
/// the app's texture was `GL_INVALID_OPERATION` (10 in a 3x3 replay).
///
/// The centre tile is not asserted: chained refraction lookups amplify the last bit of the
/// varyings, and the rewritten vertex shader compiles differently, so the centre view is
/// not the plain frame inside the bunny (measured in three recordings: 3,906 to 5,612 of
/// 120,000 pixels off by more than one level, the tolerance being 60; PSNR 35-36 dB; a
/// separate fix of the rewrite is under way). Its figures are printed; the errors and the
/// parallax are asserted.
#[test]
fn glmark2_refract_fbo_quilt() {
    let prog = ["glmark2", "-s", "400x300", "-b", "refract:nframes=24"];
    // The centre view is bit-exact since the quilt is stored like the window (it was 35 dB).
    replay_quilt(
        "glmark2_refract_fbo_quilt",
        "gl",
        "glretrace",
        &prog,
        "20",
        12,
        QuiltChecks::ALL,
    );
}

// `texture` and `pulsar` start flat (a crate's front face; quads squashed into a band a few
// pixels tall, their height growing as sin(t/3.6)) and change with time; their depth shows
// only later. Each scene runs a fixed number of frames (so that the frame seen exists however
// slowly the machine records) and, under the steady clock, frame N is N/60 s into it
// whatever the machine's speed: texture and pulsar are seen at 1 s and 3 s (measured: outer-
// view spreads of 6.3 / 6.1 px and 3.1 / 3.1 px; pulsar at frame 3 has none). Recorded by
// the wall clock, frame 1500 of pulsar was flat on a loaded machine (issue 21: the quads are
// flat again whenever sin(t/3.6) is near 0, at t = 11.3 s). The pulsar's quads are textured
// so that blocks match.
glmark2_quilt_tests! {
    glmark2_build_quilt: "build:use-vbo=true:nframes=24" at 12;
    glmark2_texture_quilt: "texture:nframes=60" at 60;
    glmark2_shading_quilt: "shading:shading=phong:nframes=24" at 12;
    glmark2_bump_quilt: "bump:bump-render=normals:nframes=24" at 12;
    glmark2_pulsar_quilt: "pulsar:texture=true:nframes=180" at 180;
}

#[test]
fn glxgears_passthrough_is_pixel_identical() {
    assert_replay_identical("glxgears", "gl", "glretrace", &["glxgears"], "1.5", 10);
}

#[test]
fn es2gears_passthrough_is_pixel_identical() {
    assert_replay_identical("es2gears", "egl", "eglretrace", &["es2gears_x11"], "1.5", 10);
}

#[test]
fn glmark2_scene_passthrough_is_pixel_identical() {
    let prog = ["glmark2", "-s", "400x300", "-b", "shading:shading=phong:duration=0.5"];
    assert_replay_identical("glmark2_phong", "gl", "glretrace", &prog, "20", 12);
}

#[test]
fn glmark2_dlopen_rtld_local_is_hooked() {
    require_display();
    let dir = temp_dir("glmark2_dlopen");
    let dump = dir.join("d");
    let mut options = vec!["--log", "debug"];
    options.extend(dump_and_exit_at(&dump, "5"));
    let out = under_layer(&options, "glmark2", &["-s", "320x240", "-b", "build:duration=5"], &[]);
    assert_success(&out, "glmark2 under the layer");
    let err = stderr(&out);
    assert!(
        err.contains("glXSwapBuffers) -> hook"),
        "glmark2's dlsym of glXSwapBuffers did not reach us:\n{err}"
    );
    assert!(has_content(&dump.join("f000005_out.png")));
}

/// Fixed-function programs: glxgears (display lists, lighting) and the chromium-bsu shooter
/// (SDL, blended textured sprites, perspective camera).
#[test]
fn glxgears_quilt_has_parallax_and_exact_centre() {
    assert_replay_quilt("glxgears_quilt", "gl", "glretrace", &["glxgears"], "1.5", 30);
}

#[test]
fn chromium_bsu_quilt_has_parallax_and_exact_centre() {
    assert_replay_quilt(
        "chromium_bsu_quilt",
        "gl",
        "glretrace",
        &["/usr/games/chromium-bsu"],
        "6",
        60,
    );
}

/// Regression: an ES context on a window with a 32-bit depth buffer (glmark2-es2) got a
/// `GL_DEPTH_COMPONENT32` quilt, which ES cannot render to, and lost multiview. Both glmark2
/// flavours now run FBO-heavy scenes under a quilt without a single layer error or warning,
/// and without a GL error their plain runs do not have (Mesa reports every one: the quilt
/// asked the stencil size of windows without stencil, an error at every start).
#[test]
fn es_window_with_32bit_depth_gets_a_quilt() {
    require_display();
    for program in ["glmark2", "glmark2-es2"] {
        let args = [
            "-s",
            "320x240",
            "-b",
            "build:duration=0.2",
            "-b",
            "shadow:duration=0.2",
            "-b",
            "refract:duration=0.2",
            "-b",
            "desktop:duration=0.2",
        ];
        let plain = run(Path::new(program), &args, &[MESA_DEBUG_ENV]);
        assert_success(&plain, program);
        let out = under_layer(&["--quilt", "3x3", "--log", "warn"], program, &args, &[MESA_DEBUG_ENV]);
        assert_success(&out, program);
        let err = stderr(&out);
        assert!(
            !err.contains("holoinject: error") && !err.contains("holoinject: warn"),
            "{program}:\n{err}"
        );
        assert_no_added_gl_errors(&stderr(&plain), &err, program);
    }
}

/// The quilt of an ES context cannot have a 32-bit window's depth format (no 32-bit
/// normalised depth in ES: the quilt's is float), and a depth blit between the two is an
/// error. When the layer gives up, the frame's depth goes back to the window through a pass
/// instead (regression: `GL_INVALID_OPERATION in glBlitFramebuffer(depth attachment format
/// mismatch)` at the hand-back).
#[test]
fn es_window_with_32bit_depth_gets_its_depth_back_without_error() {
    require_display();
    let args = ["-s", "320x240", "-b", "build:duration=0.3"];
    let env = [MESA_DEBUG_ENV, ("HOLOINJECT_TEST_FAIL", "eglSwapBuffers")];
    let out = under_layer(&["--quilt", "3x3", "--log", "info"], "glmark2-es2", &args, &env);
    assert_success(&out, "glmark2-es2");
    let err = stderr(&out);
    assert!(err.contains("depth copied by a pass"), "{err}");
    assert_no_added_gl_errors("", &err, "glmark2-es2 handed back");
}

/// Contexts destroyed and re-created (glmark2 probes with one context, destroys it and makes
/// its benchmark context) leave nothing behind in the layer: after a destruction at most the
/// one context still in use is tracked.
#[test]
fn destroyed_contexts_are_not_kept() {
    require_display();
    let scenes = [
        "build:duration=0.1",
        "texture:duration=0.1",
        "shading:duration=0.1",
        "bump:duration=0.1",
        "pulsar:duration=0.1",
    ];
    let mut args = vec!["-s", "160x120"];
    for s in &scenes {
        args.extend(["-b", s]);
    }
    let out = under_layer(&["--quilt", "2x1", "--log", "info"], "glmark2", &args, &[]);
    assert_success(&out, "glmark2");
    let err = stderr(&out);
    let tracked: Vec<usize> = err
        .lines()
        .filter_map(|l| l.split(" destroyed (").nth(1))
        .filter_map(|t| t.split_whitespace().next()?.parse().ok())
        .collect();
    assert!(!tracked.is_empty(), "no context was destroyed:\n{err}");
    assert!(tracked.iter().all(|&n| n <= 1), "contexts pile up: {tracked:?}");
}

/// Three cubes at different depths, as a Wavefront OBJ (f3d ships no sample model).
fn write_cubes_obj(path: &Path) {
    let mut obj = String::new();
    for (k, (cx, cy, cz, s)) in [(-1.5, 0.0, 0.0, 0.6), (0.0, 0.0, -2.0, 0.8), (1.5, 0.3, 1.0, 0.5)]
        .into_iter()
        .enumerate()
    {
        for (dx, dy, dz) in (0..8).map(|i| ([-1.0, 1.0][i >> 2], [-1.0, 1.0][(i >> 1) & 1], [-1.0, 1.0][i & 1])) {
            obj += &format!("v {} {} {}\n", cx + dx * s, cy + dy * s, cz + dz * s);
        }
        for f in [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ] {
            let [a, b, c, d] = f.map(|i| i + 1 + 8 * k);
            obj += &format!("f {a} {b} {c} {d}\n");
        }
    }
    std::fs::write(path, obj).unwrap();
}

/// A VTK interaction log (`f3d --interaction-test-play`): the left button held while the
/// mouse wiggles by a pixel, so every event renders a frame with the model barely turned.
fn write_wiggle_events(path: &Path, frames: usize) {
    let mut log = String::from("# StreamVersion 1.1\nLeftButtonPressEvent 160 120 0 0 0 0 0\n");
    for i in 0..frames {
        log += &format!("MouseMoveEvent {} 120 0 0 0 0 0\n", 159 + 2 * (i % 2));
    }
    log += "LeftButtonReleaseEvent 160 120 0 0 0 0 0\n";
    std::fs::write(path, log).unwrap();
}

/// Pixels brighter than `background` by more than a few levels: the lit faces of the model.
/// (Darker ones are left out: f3d's first frame has a black band where its window grew after
/// the first draw.)
fn model_pixels(img: &Image, background: &[u8]) -> usize {
    let lit = |p: &[u8]| p.iter().zip(background).all(|(a, b)| *a > b.saturating_add(8));
    img.rgb.chunks(3).filter(|p| lit(p)).count()
}

/// Regression (issue 11): f3d (VTK 9.1) with SSAO re-attaches its render targets for every
/// pass and detaches them after it; the layer re-made the shadows each time, so the quilt
/// showed the background only, and logged "shadowed" for the same framebuffer every frame.
/// Now, over 100 frames of the user turning the model (f3d on an Xvfb window, no trace
/// needed: the scene is static): every tile of frames 1 and 100 shows the model (at least
/// half the model pixels of the pass-through frame), outer views shift further than inner
/// ones, left and right mirror each other, and each framebuffer is logged shadowed once.
#[test]
fn f3d_ssao_quilt_shows_the_model_in_every_view() {
    require_display();
    let dir = temp_dir("f3d_ssao");
    let (model, events) = (dir.join("cubes.obj"), dir.join("wiggle.log"));
    write_cubes_obj(&model);
    write_wiggle_events(&events, 110);
    let f3d = |layer: &[&str], dump: &Path, frames: &str, last: &str| {
        let mut options = layer.to_vec();
        options.extend([
            "--dump",
            dump.to_str().unwrap(),
            "--dump-frames",
            frames,
            "--exit-after",
            last,
        ]);
        let play = format!("--interaction-test-play={}", events.display());
        let args = ["--ssao", "--resolution", "320,240", &play, model.to_str().unwrap()];
        let out = under_layer(&options, "f3d", &args, &[]);
        assert_success(&out, "f3d under the layer");
        out
    };
    f3d(&["--output", "mono"], &dir.join("plain"), "1", "1");
    let plain = read_png(&dir.join("plain/f000001_out.png"));
    let background = plain.rgb[..3].to_vec();
    let expected = model_pixels(&plain, &background);
    assert!(expected > 2000, "f3d drew no model ({expected} pixels)");
    let layer = [
        "--quilt",
        "3x3",
        "--depthiness",
        "0.1",
        "--convergence",
        "0.01",
        "--log",
        "info",
    ];
    let out = f3d(&layer, &dir.join("quilt"), "1,100", "100");
    let aspect =
        holoinject::multiview::quilt::layout::QuiltLayout::new((3, 3), None, (plain.width, plain.height)).file_tag();
    for frame in [1, 100] {
        let png = dir.join(format!("quilt/f{frame:06}_{aspect}.png"));
        let quilt = read_png(&png);
        let found: Vec<usize> = (0..9)
            .map(|i| model_pixels(&tile(&quilt, 3, 3, i), &background))
            .collect();
        eprintln!("f3d frame {frame}: model pixels per view {found:?}, pass-through {expected}");
        assert!(
            found.iter().all(|&n| n * 2 >= expected),
            "frame {frame}: a view lacks the model: {found:?} vs {expected}\n{}",
            png.display()
        );
        assert_parallax_grows(&quilt, &png, (3, 3), 4, &[5, 6, 7, 8], 40, "f3d right views");
        assert_parallax_grows(&quilt, &png, (3, 3), 4, &[3, 2, 1, 0], 40, "f3d left views");
        let centre = tile(&quilt, 3, 3, 4);
        let [left, right] = [0, 8].map(|i| horizontal_shift(&centre, &tile(&quilt, 3, 3, i), 40));
        assert!(
            (left + right).abs() <= 1,
            "frame {frame}: outer views do not mirror: {left} and {right} px"
        );
    }
    assert_shadowed_once(&stderr(&out));
}

/// Each framebuffer is announced as shadowed at most once (f3d deletes its passes'
/// framebuffers after its first frame and makes new ones: each new name is announced once).
fn assert_shadowed_once(log: &str) {
    let mut seen = std::collections::BTreeMap::<&str, usize>::new();
    for l in log.lines().filter(|l| l.contains(" shadowed with ")) {
        let fbo = l.split_whitespace().nth(3).unwrap_or("?");
        *seen.entry(fbo).or_default() += 1;
    }
    eprintln!("framebuffers shadowed (announcements): {seen:?}");
    assert!(!seen.is_empty(), "nothing shadowed:\n{log}");
    assert!(seen.values().all(|&n| n == 1), "shadowed more than once: {seen:?}");
}
