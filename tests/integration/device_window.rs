//! `--present device`: the layer's own window sits exactly on the monitor, shows the weave
//! pixel for pixel, and the program's window shows the preview. Xvfb cannot fake a second
//! monitor here (`xrandr --setmonitor` without an output is ignored), so the "monitor" is a
//! rectangle of one wide screen given with `--monitor`, as a user of an undetected unit would.

use crate::util::*;
use holoinject::config::calibration::DevicePreset;
use holoinject::output::weave::{Filter, weave_cpu};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The portrait's panel (1536x2048) to the right of a 1920-wide desk monitor.
const SCREEN: &str = "3456x2048x24";
const MONITOR: &str = "1536x2048+1920+0";

/// cubes under the layer on `display`, frozen (every frame draws frame 0, convergence fixed:
/// the frame on screen is the frame dumped), until killed.
fn frozen_cubes(display: &str, dump: &Path, layer: &[&str], backend: &str) -> Child {
    let mut args = vec![
        "run",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-frames",
        "3",
        "--convergence",
        "19",
    ];
    args.extend_from_slice(layer);
    let app = app("cubes");
    args.extend(["--", app.to_str().unwrap(), "--backend", backend, "--size", "420x560"]);
    args.extend(["--freeze", "0", "--frames", "0"]);
    Command::new(launcher())
        .args(&args)
        .env("DISPLAY", display)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("launcher")
}

/// Waits for frame 3's dumps and two more frames, so the device window shows a frame after
/// the dumped one (identical: the scene is frozen).
fn wait_for_frame_3(child: &mut Child, dump: &Path) {
    let start = Instant::now();
    let done = |f: &str| dump.join(f).exists();
    while !(done("f000003_out.png") && done("f000003_qs8x6a0.75.png")) {
        if let Ok(Some(status)) = child.try_wait() {
            panic!("cubes ended ({status}) before frame 3: {}", finish(child));
        }
        assert!(
            start.elapsed() < Duration::from_secs(RUN_TIMEOUT_S as u64),
            "no frame 3"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    std::thread::sleep(Duration::from_secs(3));
}

fn finish(child: &mut Child) -> String {
    let _ = child.kill();
    let mut err = String::new();
    use std::io::Read;
    child.stderr.take().map(|mut e| e.read_to_string(&mut err));
    let _ = child.wait();
    err
}

/// Under `backend`, the device window is exactly on the monitor and shows the weave of the
/// frame on screen.
fn device_window_shows_the_weave(backend: &str) {
    let x = Xvfb::start(SCREEN);
    let dump = temp_dir(&format!("device_window_{backend}"));
    let layer = [
        "--device",
        "portrait",
        "--weave-filter",
        "nearest",
        "--monitor",
        MONITOR,
        "--log",
        "info",
    ];
    let mut cubes = frozen_cubes(&x.display, &dump, &layer, backend);
    wait_for_frame_3(&mut cubes, &dump);
    let conn = XConn::open(&x.display);
    let windows = conn.top_levels();
    let grab = conn.grab(1920, 0, 1536, 2048);
    let err = finish(&mut cubes);
    let ours: Vec<_> = windows
        .iter()
        .filter(|w| w.name == "holoinject: Looking Glass")
        .collect();
    assert_eq!(ours.len(), 1, "one device window among {windows:?}\n{err}");
    assert_eq!(ours[0].geometry, MONITOR, "{err}");
    assert!(ours[0].override_redirect && ours[0].viewable, "{:?}", ours[0]);
    assert!(err.contains("--present device: on --monitor 1536x2048+1920+0"), "{err}");

    // The layer's own weave of that frame, shown 1:1 (a NEAREST blit of equal size, or the
    // read-back pixels themselves): every channel equal.
    let native = read_png(&dump.join("f000003_native.png"));
    let at = dump.join("grab.png");
    assert_within(
        &native,
        &grab,
        &at,
        EXACT,
        &format!("{backend}: device window against the layer's weave"),
    );

    // The CPU reference weave of the dumped quilt (`output::weave::weave_cpu`): every channel
    // equal. Measured so on Mesa 22.3 llvmpipe for GLX, EGL and OSMesa; another driver may
    // pick the next view where a phase lands within float rounding of a view boundary, which
    // `output_modes::native_nearest_matches_cpu_weave` allows for 0.1% of channels.
    let quilt = read_png(&dump.join("f000003_qs8x6a0.75.png"));
    let params = DevicePreset::get("portrait").unwrap().calibration.weave_params(48);
    let cpu = weave_cpu(
        &quilt.rgb,
        quilt.width,
        quilt.height,
        8,
        6,
        &params,
        Filter::Nearest,
        1536,
        2048,
    );
    let cpu = Image {
        width: 1536,
        height: 2048,
        rgb: cpu,
    };
    let (max, fraction) = difference(&cpu.rgb, &grab.rgb);
    eprintln!(
        "{backend}: grab vs CPU weave: {:.5}% of channels differ, by at most {max}",
        fraction * 100.0
    );
    assert_within(
        &cpu,
        &grab,
        &at,
        EXACT,
        &format!("{backend}: device window against the CPU weave"),
    );
}

#[test]
fn glx_device_window_sits_on_the_monitor_and_shows_the_weave() {
    device_window_shows_the_weave("glx");
}

#[test]
fn egl_device_window_sits_on_the_monitor_and_shows_the_weave() {
    device_window_shows_the_weave("egl");
}

#[test]
fn osmesa_device_window_sits_on_the_monitor_and_shows_the_weave() {
    device_window_shows_the_weave("osmesa");
}

#[test]
fn preview_off_leaves_the_programs_window_black() {
    let x = Xvfb::start(SCREEN);
    let dump = temp_dir("device_preview_off");
    let layer = ["--device", "portrait", "--monitor", MONITOR, "--preview", "off"];
    let mut cubes = frozen_cubes(&x.display, &dump, &layer, "glx");
    wait_for_frame_3(&mut cubes, &dump);
    finish(&mut cubes);
    let out = read_png(&dump.join("f000003_out.png"));
    assert!(
        out.rgb.iter().all(|&c| c == 0),
        "--preview off: the window is not black"
    );
    assert!(has_content(&dump.join("f000003_native.png")), "no weave made");
}

#[test]
fn no_looking_glass_is_one_line_and_the_programs_window_shows_the_weave() {
    require_display();
    let dump = temp_dir("device_absent");
    let mut options = dump_and_exit_at(&dump, "2").to_vec();
    options.extend(["--device", "portrait"]);
    let out = under_layer(
        &options,
        app("cubes"),
        &["--backend", "glx", "--size", "420x560", "--frames", "2"],
        &[],
    );
    assert_success(&out, "cubes with no Looking Glass");
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("--present device")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains("no Looking Glass connected") && lines[0].contains("program's window"),
        "{err}"
    );
    // The weave in the program's window, fitted: not the preview.
    let (shown, native) = (
        read_png(&dump.join("f000002_out.png")),
        read_png(&dump.join("f000002_native.png")),
    );
    assert_eq!((shown.width, native.width), (420, 1536));
}

#[test]
fn a_quilt_on_an_egl_device_is_one_line_and_the_programs_window() {
    let x = Xvfb::start(SCREEN);
    let dump = temp_dir("device_egl_quilt");
    let layer = [
        "--device",
        "portrait",
        "--monitor",
        MONITOR,
        "--present",
        "device",
        "--output",
        "quilt",
    ];
    let mut cubes = frozen_cubes(&x.display, &dump, &layer, "egl");
    wait_for_frame_3(&mut cubes, &dump);
    let windows = XConn::open(&x.display).top_levels();
    let err = finish(&mut cubes);
    assert_eq!(err.matches("--present device").count(), 1, "{err}");
    assert!(err.contains("presenting in the program's window"), "{err}");
    assert!(!windows.iter().any(|w| w.name.starts_with("holoinject")), "{windows:?}");
    assert_eq!(read_png(&dump.join("f000003_out.png")).width, 420);
}

/// A bad `--monitor` at run time: one line each, the weave in the program's window.
fn device_refused(test: &str, monitor: &str, needles: &[&str]) {
    require_display();
    let dump = temp_dir(test);
    let mut options = dump_and_exit_at(&dump, "2").to_vec();
    options.extend(["--device", "portrait", "--monitor", monitor]);
    let out = under_layer(
        &options,
        app("cubes"),
        &["--backend", "glx", "--size", "420x560", "--frames", "2"],
        &[],
    );
    assert_success(&out, test);
    let err = stderr(&out);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("--present device") || l.contains("--monitor"))
        .collect();
    assert_eq!(lines.len(), 1, "{err}");
    for n in needles {
        assert!(lines[0].contains(n), "`{n}` not in {err}");
    }
}

#[test]
fn a_monitor_named_wrong_is_one_line_listing_the_monitors() {
    // Xvfb's one monitor is named `screen`.
    device_refused(
        "device_monitor_typo",
        "DP-9",
        &["--monitor DP-9: no such monitor", "connected: screen"],
    );
}

#[test]
fn a_monitor_of_another_size_than_the_calibration_is_one_line() {
    device_refused(
        "device_monitor_size",
        "1000x800+0+0",
        &["is 1000x800 but the calibration of portrait is for 1536x2048"],
    );
}
