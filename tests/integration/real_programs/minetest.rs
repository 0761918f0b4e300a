//! Minetest (Debian's `minetest` 5.6, with its `minetest_game`), a voxel game drawn through
//! Irrlicht: its shaders on (GLSL 1.20 per material) and off (Irrlicht's fixed-function
//! driver). Does `--mode synth` give every textured block of a real game the disparity
//! `--mode exact` gives it (issue 22, the per-pixel disparity record)?
//!
//! A world that needs no input: a fresh singleplayer world in the test's own directory
//! (`--go --world`, own `HOME`, `--config`), mapgen v7 with a fixed seed, time stopped at
//! late morning, no clouds, no waving, no sound, a 640x480 window on an Xvfb of the test's
//! own. A world mod (`holoview`) turns the new player, who spawns where the seed puts the
//! spawn (the same place on every run), towards a hill with the sea and far land behind it,
//! looks slightly down (near grass at the bottom of the picture), hides the HUD and the
//! wielded hand, stops the player's physics, and shuts the game down after `PLAY_S` seconds
//! of the server's time: the recording ends by itself, cleanly.
//!
//! The trace's last complete frame is replayed under the layer as a 5x1 quilt of 640x480
//! tiles, in `--mode exact` and `--mode synth`, same rig (fixed convergence and depthiness).
//! Both quilts must show depth as a light-field display needs it: outermost views mirrored,
//! per-block shifts that spread with depth and grow from the centre outwards
//! (`util::depth_parallax`); and synth must put ≥ 90 % of the matched textured blocks within
//! 2 px of exact's shift in both outermost views (`util::agreement`, the measure of
//! `scripts/disparity_blocks.py`).
//!
//! Why no steady clock (as `real_programs::record` uses): what a frame of Minetest shows
//! depends on its map and mesh threads (which blocks are generated and meshed by then), not
//! on the main thread's clock; and a fake clock on the main thread would speed up the
//! client's own timeouts. Within one test run the trace is fixed, so both modes see the same
//! frame; across runs the frame is the same scene once the world has loaded (a few seconds
//! of the 20 recorded), up to water's texture animation.

use crate::util::*;
use std::path::{Path, PathBuf};

const MINETEST: &str = "/usr/games/minetest";
const SCREEN: (u32, u32) = (640, 480);
const COLS: u32 = 5;
/// Irrlicht units: a node is 10. The nearest ground (bottom rows) is ~32 units from the eye,
/// the hill 100-200, the sea and far land up to the fog at 80 nodes.
const CONVERGENCE: &str = "60";
/// The outermost view moves 25.6 px at infinity in a 640-px tile; the nearest ground about
/// 22 px the other way.
const DEPTHINESS: &str = "0.08";
/// Block search (px), as `scripts/disparity-agreement.py`.
const MAX_SHIFT: i32 = 64;
/// A block is textured at this luminance standard deviation (levels), as the script.
const TEXTURE: f64 = 8.0;
/// Seconds of the server's time between the player joining and the shutdown.
const PLAY_S: u32 = 20;
const SEED: u32 = 42;

/// The client's and server's settings (`--config`).
fn config(shaders: bool) -> String {
    format!(
        "screen_w = {w}\nscreen_h = {h}\nfullscreen = false\nenable_sound = false\n\
         enable_shaders = {shaders}\ntime_speed = 0\nworld_start_time = 10000\n\
         enable_clouds = false\nmenu_clouds = false\nenable_minimap = false\n\
         enable_damage = false\ncreative_mode = true\nviewing_range = 80\n\
         node_highlighting = none\ncrosshair_alpha = 0\nfps_max = 5\nfps_max_unfocused = 5\n\
         show_debug = false\n\
         enable_waving_water = false\nenable_waving_leaves = false\nenable_waving_plants = false\n\
         mg_name = v7\nfixed_map_seed = {SEED}\nname = singleplayer\n",
        w = SCREEN.0,
        h = SCREEN.1,
    )
}

const WORLD_MT: &str = "gameid = minetest\nbackend = sqlite3\nplayer_backend = sqlite3\n\
                        auth_backend = sqlite3\nmod_storage_backend = sqlite3\n";

/// The world mod: the view, no HUD, no motion, and the end of the recording.
fn holoview_mod() -> String {
    format!(
        r#"minetest.register_on_joinplayer(function(player)
  player:hud_set_flags({{hotbar = false, healthbar = false, crosshair = false, wielditem = false,
    breathbar = false, minimap = false, minimap_radar = false}})
  player:set_physics_override({{speed = 0, jump = 0, gravity = 0, sneak = false}})
  player:set_look_horizontal(1.0)
  player:set_look_vertical(0.25)
  minetest.set_timeofday(0.45)
  minetest.log("action", "holoview: player at " .. minetest.pos_to_string(player:get_pos()))
  minetest.after({PLAY_S}, function() minetest.request_shutdown("", false, 0) end)
end)
"#
    )
}

/// Records the game with apitrace from its start to the mod's shutdown. Returns the trace and
/// the frames it holds.
fn record(dir: &Path, xvfb: &Xvfb, shaders: bool) -> (PathBuf, u32) {
    let (home, world) = (dir.join("home"), dir.join("world"));
    let holoview = world.join("worldmods/holoview");
    std::fs::create_dir_all(&home).unwrap();
    std::fs::create_dir_all(&holoview).unwrap();
    std::fs::write(world.join("world.mt"), WORLD_MT).unwrap();
    std::fs::write(holoview.join("mod.conf"), "name = holoview\n").unwrap();
    std::fs::write(holoview.join("init.lua"), holoview_mod()).unwrap();
    let conf = dir.join("minetest.conf");
    std::fs::write(&conf, config(shaders)).unwrap();
    let (trace, log) = (dir.join("minetest.trace"), dir.join("minetest.log"));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let args = [
        "-k",
        "5",
        "150",
        "apitrace",
        "trace",
        "--api",
        "gl",
        "-o",
        &s(&trace),
        MINETEST,
        "--config",
        &s(&conf),
        "--go",
        "--world",
        &s(&world),
        "--logfile",
        &s(&log),
    ];
    let home = s(&home);
    let env = [("HOME", home.as_str()), ("DISPLAY", xvfb.display.as_str())];
    // A singleplayer game serves itself on a UDP port drawn from a generator seeded with the
    // time in seconds: two games started in the same second (this test's two cases, run in
    // parallel) draw the same port and the second fails to bind. The recordings take turns,
    // and a bind failure (another Minetest on the machine) is tried again a second later.
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut attempt = 0;
    let (out, said) = loop {
        let _ = std::fs::remove_file(&log);
        let out = run(Path::new("timeout"), &args, &env);
        let said = std::fs::read_to_string(&log).unwrap_or_default();
        attempt += 1;
        if !said.contains("Failed to bind socket") || attempt == 3 {
            break (out, said);
        }
        std::thread::sleep(std::time::Duration::from_millis(1500));
    };
    assert!(
        said.contains("holoview: player at"),
        "Minetest never put the player in the world ({}):\n{said}\n{}",
        out.status,
        stderr(&out)
    );
    let frames = super::frames_in(&trace);
    eprintln!(
        "minetest (shaders {}): {frames} frames recorded ({} MB); {}",
        if shaders { "on" } else { "off" },
        std::fs::metadata(&trace).map(|m| m.len() >> 20).unwrap_or(0),
        said.lines().find(|l| l.contains("holoview")).unwrap_or("")
    );
    assert!(frames >= 20, "apitrace recorded only {frames} frames of Minetest");
    (trace, frames)
}

/// Frame `frame` of a plain replay (glretrace's snapshot) and the replay's stderr.
fn plain(dir: &Path, xvfb: &Xvfb, trace: &Path, frame: u32) -> (Image, String) {
    let snaps = dir.join("plain");
    std::fs::create_dir_all(&snaps).unwrap();
    let prefix = format!("{}/", snaps.display());
    let env = [MESA_DEBUG_ENV, ("DISPLAY", xvfb.display.as_str())];
    let args = ["--call-nos=false", "-s", &prefix, trace.to_str().unwrap()];
    let out = run(Path::new("glretrace"), &args, &env);
    assert_success(&out, "glretrace");
    (read_png(&snaps.join(format!("{:010}.png", frame - 1))), stderr(&out))
}

/// Frame `frame` replayed under the layer as the 5x1 quilt in `mode`: the quilt, its file and
/// the layer's log.
fn quilt(dir: &Path, xvfb: &Xvfb, trace: &Path, frame: u32, mode: &str) -> (Image, PathBuf, String) {
    let dump = dir.join(mode.replace(':', "-"));
    let n = frame.to_string();
    let tile = format!("{}x{}", SCREEN.0, SCREEN.1);
    let mut options = vec!["--quilt", "5x1", "--tile", &tile, "--output", "quilt", "--mode", mode];
    options.extend([
        "--depthiness",
        DEPTHINESS,
        "--convergence",
        CONVERGENCE,
        "--log",
        "info",
    ]);
    options.extend(dump_and_exit_at(&dump, &n));
    let env = [MESA_DEBUG_ENV, ("DISPLAY", xvfb.display.as_str())];
    let out = under_layer(&options, "glretrace", &[trace.to_str().unwrap()], &env);
    assert_success(&out, &format!("the Minetest trace under --mode {mode}"));
    let err = stderr(&out);
    assert!(!err.contains("holoinject: error"), "--mode {mode}:\n{err}");
    assert!(
        !err.contains("every view is rendered exactly"),
        "--mode {mode} stayed exact on Minetest (nothing synthesised to measure):\n{err}"
    );
    let aspect = holoinject::multiview::quilt::layout::QuiltLayout::new((COLS, 1), None, SCREEN).file_tag();
    let png = dump.join(format!("f{frame:06}_{aspect}.png"));
    (read_png(&png), png, err)
}

/// The outermost views' spreads of block shifts (px), left and right.
fn outer_spreads(report: &ParallaxReport) -> (f64, f64) {
    (report[0].1, report[report.len() - 1].1)
}

fn minetest_synth_matches_exact(test: &str, shaders: bool) {
    require_display();
    assert!(
        Path::new(MINETEST).exists(),
        "{MINETEST} missing: scripts/setup-debian.sh installs minetest"
    );
    let what = format!("Minetest (shaders {})", if shaders { "on" } else { "off" });
    let dir = temp_dir(test);
    let xvfb = Xvfb::start(&format!("{}x{}x24", SCREEN.0, SCREEN.1));
    let (trace, frames) = record(&dir, &xvfb, shaders);
    // The last frame may be cut short by the shutdown.
    let frame = frames - 1;
    let (plain_frame, plain_err) = plain(&dir, &xvfb, &trace, frame);
    let (exact, exact_png, exact_err) = quilt(&dir, &xvfb, &trace, frame, "exact");
    let (synth, synth_png, synth_err) = quilt(&dir, &xvfb, &trace, frame, "synth");
    assert_no_added_gl_errors(&plain_err, &exact_err, &format!("{what} exact"));
    assert_no_added_gl_errors(&plain_err, &synth_err, &format!("{what} synth"));

    let centre_off = pixels_off(&plain_frame, &tile(&exact, COLS, 1, COLS / 2), 0);
    eprintln!("{what} frame {frame}: exact's centre view differs from the plain frame in {centre_off} pixels");
    let (exact_report, exact_mirror, exact_failures) =
        depth_parallax(&exact, COLS, MAX_SHIFT, &format!("{what} exact"));
    let (synth_report, synth_mirror, synth_failures) =
        depth_parallax(&synth, COLS, MAX_SHIFT, &format!("{what} synth"));
    let a = agreement(&exact, &synth, (COLS, 1), TEXTURE, MAX_SHIFT);
    eprintln!(
        "{what} frame {frame}: synth against exact: {} of {} blocks textured, {} matched ({} not found in synth); \
         agree {:.1} % of matched ({:.1} % of textured); |Δ| median {:.1} px, p95 {:.1} px; \
         rightmost view's shifts p10..p90: exact {:.1}..{:.1} px, synth {:.1}..{:.1} px",
        a.textured,
        a.blocks,
        a.matched,
        a.not_found,
        a.agree_pct,
        a.agree_pct_textured,
        a.median_d,
        a.p95_d,
        a.exact_p10_p90.0,
        a.exact_p10_p90.1,
        a.fast_p10_p90.0,
        a.fast_p10_p90.1,
    );

    let (e0, e4) = outer_spreads(&exact_report);
    let (s0, s4) = outer_spreads(&synth_report);
    // The scene and the rig are what the rest measures: exact must show Minetest in depth.
    assert!(
        exact_failures.is_empty() && e0.min(e4) >= 8.0,
        "{what}, --mode exact: {} (outer views' block shifts spread {e0:.1} / {e4:.1} px, at least 8 \
         expected; mirror errors {exact_mirror:.2?} px): the reference itself would not show the hill in \
         front of the sea on the display, so there is nothing to compare synth with: {}",
        exact_failures.join("; "),
        exact_png.display()
    );
    assert!(
        a.matched >= 50,
        "{what}: only {} of {} textured blocks can be matched in exact's outer views: too little \
         texture to measure ({})",
        a.matched,
        a.textured,
        exact_png.display()
    );
    assert!(
        synth_failures.is_empty(),
        "{what}, --mode synth: {} (outer views' block shifts spread {s0:.1} / {s4:.1} px, exact's \
         {e0:.1} / {e4:.1}; mirror errors {synth_mirror:.2?} px): a viewer moving in front of the display \
         would see the landscape as a flat picture, where exact shows near grass, the hill and the \
         far sea at their own depths: {}",
        synth_failures.join("; "),
        synth_png.display()
    );
    assert!(
        a.agree_pct >= 90.0,
        "{what}, --mode synth puts only {:.1} % of {} matched textured blocks within 2 px of where exact \
         shows them in the outermost views (median error {:.1} px, p95 {:.1}; rightmost view's shifts \
         exact {:.1}..{:.1} px, synth {:.1}..{:.1}): on the display the grass, the hill and the sea would \
         stand at other depths than in the exact rendering, and swim as the viewer moves. \
         Quilts: {} {}",
        a.agree_pct,
        a.matched,
        a.median_d,
        a.p95_d,
        a.exact_p10_p90.0,
        a.exact_p10_p90.1,
        a.fast_p10_p90.0,
        a.fast_p10_p90.1,
        exact_png.display(),
        synth_png.display()
    );
    // A passing run leaves the quilts, not the trace.
    let _ = std::fs::remove_file(&trace);
}

/// Minetest's own shaders (`enable_shaders = true`): every material a GLSL 1.20 program.
#[test]
fn minetest_shaders_synth_disparity_matches_exact() {
    minetest_synth_matches_exact("minetest_shaders", true);
}

/// Irrlicht's fixed-function driver (`enable_shaders = false`): matrices through
/// `GL_PROJECTION`/`GL_MODELVIEW`, fog and lighting by the pipeline.
#[test]
fn minetest_fixed_function_synth_disparity_matches_exact() {
    minetest_synth_matches_exact("minetest_fixed_function", false);
}
