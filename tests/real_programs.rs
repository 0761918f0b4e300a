//! Real programs from Debian packages under the layer in pass-through (`--output mono`).
//!
//! Their animation follows the wall clock, so "identical with and without the layer" is made
//! deterministic the way the issue suggests: record an apitrace once, replay it plainly with
//! glretrace's own snapshots, replay it again under the layer with our dumps, and compare the
//! same frame bit for bit. glmark2 itself (which `dlopen`s libGL `RTLD_LOCAL`) is also run
//! directly to prove the dlopen/dlsym path is hooked.

mod util;
use std::path::{Path, PathBuf};
use util::*;

/// Records `program` with apitrace for `seconds` (or until it exits).
fn record(dir: &Path, name: &str, api: &str, program: &[&str], seconds: &str) -> PathBuf {
    require_display();
    let trace = dir.join(format!("{name}.trace"));
    let mut args = vec![
        seconds,
        "apitrace",
        "trace",
        "--api",
        api,
        "-o",
        trace.to_str().unwrap(),
    ];
    args.extend_from_slice(program);
    let _ = run(Path::new("timeout"), &args, &[]);
    let size = std::fs::metadata(&trace).map(|m| m.len()).unwrap_or(0);
    assert!(
        size > 1000,
        "apitrace recorded nothing for {program:?} (is apitrace installed? scripts/setup-debian.sh)"
    );
    trace
}

/// Frame `frame` (from 1) of a plain replay, as glretrace's own snapshot.
fn plain_snapshot(dir: &Path, retrace: &str, trace: &Path, frame: u32) -> PathBuf {
    let snaps = dir.join("plain");
    std::fs::create_dir_all(&snaps).unwrap();
    let prefix = format!("{}/", snaps.display());
    let out = run(
        Path::new(retrace),
        &["--call-nos=false", "-s", &prefix, trace.to_str().unwrap()],
        &[],
    );
    assert_success(&out, retrace);
    snaps.join(format!("{:010}.png", frame - 1))
}

/// The same frame replayed under the layer, as the layer's dump.
fn injected_dump(dir: &Path, retrace: &str, trace: &Path, frame: u32) -> PathBuf {
    let dump = dir.join("injected");
    let n = frame.to_string();
    let args = [
        "run",
        "--output",
        "mono",
        "--log",
        "info",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-frames",
        &n,
        "--exit-after",
        &n,
        "--",
        retrace,
        trace.to_str().unwrap(),
    ];
    let out = run(&launcher(), &args, &[]);
    assert_success(&out, "replay under the layer");
    assert!(
        stderr(&out).contains("holoinject 0.1.0 active"),
        "layer not loaded: {}",
        stderr(&out)
    );
    dump.join(format!("f{frame:06}_out.png"))
}

fn assert_replay_identical(test: &str, api: &str, retrace: &str, program: &[&str], seconds: &str, frame: u32) {
    let dir = temp_dir(test);
    let trace = record(&dir, test, api, program, seconds);
    let expected = plain_snapshot(&dir, retrace, &trace, frame);
    let actual = injected_dump(&dir, retrace, &trace, frame);
    assert!(
        has_content(&expected),
        "frame {frame} of {test} is blank; pick a later frame"
    );
    assert_identical(&expected, &actual);
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
    let args = [
        "run",
        "--log",
        "debug",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-frames",
        "5",
        "--exit-after",
        "5",
        "--",
        "glmark2",
        "-s",
        "320x240",
        "-b",
        "build:duration=5",
    ];
    let out = run(&launcher(), &args, &[]);
    assert_success(&out, "glmark2 under the layer");
    let err = stderr(&out);
    assert!(
        err.contains("glXSwapBuffers) -> hook"),
        "glmark2's dlsym of glXSwapBuffers did not reach us:\n{err}"
    );
    assert!(has_content(&dump.join("f000005_out.png")));
}
