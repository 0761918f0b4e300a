//! The user's tools around a run: `--record` (the quilt video, checked frame by frame against
//! the quilts the layer dumped for the same frames), `holoinject quilt` (the offline weave,
//! checked against the layer's own native output) and `holoinject doctor`.

use crate::util::*;
use holoinject::output::quilt_file;
use std::path::Path;
use std::process::Command;

fn as_image(q: quilt_file::RgbImage) -> Image {
    Image {
        width: q.width,
        height: q.height,
        rgb: q.rgb,
    }
}

fn mean_psnr(a: &Image, b: &Image, cols: u32, rows: u32) -> f64 {
    let p = tile_psnr(a, b, cols, rows);
    p.iter().map(|v| v.min(99.0)).sum::<f64>() / p.len() as f64
}

fn video_frames(path: &Path) -> u64 {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries", "stream=nb_read_frames", "-of", "csv=p=0"])
        .arg(path)
        .output()
        .expect("ffprobe runs (apt install ffmpeg)");
    String::from_utf8_lossy(&out.stdout)
        .trim()
        .parse()
        .expect("ffprobe counted frames")
}

/// H.264 (x264 ultrafast, crf 18, 4:2:0) of the cubes quilt against the dumped PNG: measured
/// 34.7 and 34.6 dB mean tile PSNR (first, last frame); frames 12 and 40 of the animation,
/// 23.8 dB apart. 30 dB passes a faithful encode and fails a wrong, flipped or shifted frame.
const VIDEO_PSNR_DB: f64 = 30.0;

#[test]
fn recording_holds_the_dumped_quilts() {
    let dir = temp_dir("recording_quilts");
    let dump = dir.join("dump");
    let video = dir.join("cubes.mp4");
    let layer = [
        "--quilt",
        "3x2",
        "--record",
        video.to_str().unwrap(),
        "--dump",
        dump.to_str().unwrap(),
        "--dump-frames",
        "12,40",
        "--exit-after",
        "40",
        "--log",
        "info",
    ];
    let out = under_layer(
        &layer,
        app("cubes"),
        &["--backend", "egl", "--size", "320x240", "--frames", "50"],
        &[],
    );
    assert_success(&out, "cubes recording");
    // The name gets the Looking Glass tag, and the user is told.
    let named = dir.join("cubes_qs3x2a1.3333.mp4");
    assert!(stderr(&out).contains(named.to_str().unwrap()), "{}", stderr(&out));
    assert!(!video.exists());
    // The rate is measured over frames 1..=11; frames 12..=40 are recorded, less those the
    // summary says were dropped (a busy machine). The first is never dropped (the queue is
    // empty), nor the last two (still being read back at the end, handed over waiting).
    let err = stderr(&out);
    let dropped: u64 = err
        .split_once("; ")
        .and_then(|_| err.split(" of 29 frames dropped").next())
        .and_then(|head| head.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no drop count in the summary:\n{err}"));
    let frames = video_frames(&named);
    assert_eq!(frames, 29 - dropped, "{err}");
    let first = as_image(quilt_file::load(&named, Some(0)).unwrap());
    let last = as_image(quilt_file::load(&named, Some(frames - 1)).unwrap());
    let q12 = read_png(&dump.join("f000012_qs3x2a1.3333.png"));
    let q40 = read_png(&dump.join("f000040_qs3x2a1.3333.png"));
    let (p_first, p_last) = (mean_psnr(&q12, &first, 3, 2), mean_psnr(&q40, &last, 3, 2));
    let p_other = mean_psnr(&q40, &first, 3, 2);
    eprintln!(
        "video against dumps: first {p_first:.2} dB, last {p_last:.2} dB, first against frame 40 {p_other:.2} dB"
    );
    assert!(
        p_first >= VIDEO_PSNR_DB && p_last >= VIDEO_PSNR_DB,
        "{p_first} {p_last}"
    );
    assert!(p_other < VIDEO_PSNR_DB, "frames 12 and 40 should differ: {p_other}");
}

#[test]
fn recording_without_an_encoder_is_one_line_and_the_program_runs() {
    let dir = temp_dir("recording_no_encoder");
    // A PATH with `timeout` (used to run the program) and no ffmpeg.
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink("/usr/bin/timeout", bin.join("timeout")).unwrap();
    let video = dir.join("x.mp4");
    let layer = [
        "--record",
        video.to_str().unwrap(),
        "--exit-after",
        "15",
        "--quilt",
        "2x1",
    ];
    let path = bin.to_str().unwrap();
    let out = under_layer(
        &layer,
        app("cubes"),
        &["--backend", "egl", "--size", "64x64", "--frames", "30"],
        &[("PATH", path)],
    );
    assert_success(&out, "cubes with --record and no ffmpeg");
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("holoinject")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].contains("--record") && lines[0].contains("ffmpeg"), "{err}");
    assert!(
        std::fs::read_dir(&dir)
            .unwrap()
            .all(|e| !e.unwrap().file_name().to_string_lossy().ends_with(".mp4"))
    );
}

#[test]
fn offline_weave_equals_the_layers_native_output() {
    let dir = temp_dir("offline_weave");
    let dump = dir.join("dump");
    let mut layer = dump_and_exit_at(&dump, "2").to_vec();
    layer.extend(["--device", "portrait"]);
    let out = under_layer(
        &layer,
        app("cubes"),
        &["--backend", "egl", "--size", "420x560", "--frames", "2"],
        &[],
    );
    assert_success(&out, "cubes native");
    let woven = dir.join("woven.png");
    let quilt = dump.join("f000002_qs8x6a0.75.png");
    let tool = run(
        &launcher(),
        &[
            "quilt",
            quilt.to_str().unwrap(),
            "--device",
            "portrait",
            "--out",
            woven.to_str().unwrap(),
        ],
        &[],
    );
    assert_success(&tool, "holoinject quilt");
    assert!(tool.stdout.is_empty());
    let native = dump.join("f000002_native.png");
    // Both use the default filter (blend): as in output_modes::native_blend_matches_cpu_weave,
    // the GPU may round a mix of two views one level apart from the CPU, and a phase within
    // float rounding of a view boundary may pick the other pair (under 0.1% of channels).
    assert_channels_close(&read_png(&native), &read_png(&woven), &woven, 2, 0.001, "offline weave");
}

#[test]
fn offline_weave_refuses_unknown_layouts_and_devices() {
    let dir = temp_dir("offline_weave_bad");
    let png = dir.join("plain.png");
    holoinject::output::png::write_rgb(&png, 4, 2, &[0; 24]).unwrap();
    let out_png = dir.join("o.png");
    let weave = |extra: &[&str]| {
        let mut args = vec!["quilt", png.to_str().unwrap(), "--out", out_png.to_str().unwrap()];
        args.extend_from_slice(extra);
        run(&launcher(), &args, &[])
    };
    let r = weave(&["--device", "portrait"]);
    assert_one_line_failure(&r, "--quilt CxR", "a quilt without a layout");
    let r = weave(&["--quilt", "4x2", "--device", "nope"]);
    assert_one_line_failure(&r, "--device nope", "an unknown device");
    let r = weave(&["--quilt", "4x2", "--device", "go"]);
    assert_success(&r, "a 4x2 quilt of 1-pixel tiles");
    assert_eq!(read_png(&out_png).width, 1440);
}

#[test]
fn doctor_passes_here_and_names_what_breaks() {
    require_display();
    let ok = run(&launcher(), &["doctor", "--device", "portrait", "--", "glxgears"], &[]);
    let text = String::from_utf8_lossy(&ok.stdout).into_owned();
    assert_success(&ok, &format!("doctor on this machine:\n{text}"));
    for check in [
        "layer:",
        "glx:",
        "egl:",
        "osmesa:",
        "calibration:",
        "program:",
        "preload:",
        "record:",
    ] {
        assert!(
            text.lines().any(|l| l.starts_with("ok") && l.contains(check)),
            "{check} not ok:\n{text}"
        );
    }
    // A missing layer library, and a device that does not exist: non-zero, the line named.
    let missing = run(
        &launcher(),
        &["doctor"],
        &[("HOLOINJECT_LIB", "/nonexistent/libholoinject.so")],
    );
    let text = String::from_utf8_lossy(&missing.stdout).into_owned();
    assert!(!missing.status.success(), "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("fail  layer:") && l.contains("fix:")),
        "{text}"
    );
    let bad = run(&launcher(), &["doctor", "--device", "nope"], &[]);
    let text = String::from_utf8_lossy(&bad.stdout).into_owned();
    assert!(!bad.status.success(), "{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("fail")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(fails[0].starts_with("fail  calibration: --device nope"), "{text}");
    assert!(stderr(&bad).contains("1 check(s) failed"), "{}", stderr(&bad));
    // Xvfb has no Looking Glass: a warning; a monitor named by its rectangle is checked
    // against the panel; one that does not exist fails.
    let fake = run(
        &launcher(),
        &["doctor", "--device", "portrait", "--monitor", "1536x2048+1920+0"],
        &[],
    );
    let text = String::from_utf8_lossy(&fake.stdout).into_owned();
    assert_success(&fake, &text);
    assert!(
        text.contains("ok    display: Looking Glass at --monitor 1536x2048+1920+0"),
        "{text}"
    );
    let other = run(
        &launcher(),
        &["doctor", "--device", "portrait", "--monitor", "1920x1080+0+0"],
        &[],
    );
    let text = String::from_utf8_lossy(&other.stdout).into_owned();
    assert!(
        text.contains("warn  display:") && text.contains("1536x2048 panel"),
        "{text}"
    );
    let typo = run(&launcher(), &["doctor", "--monitor", "HDMI-9"], &[]);
    let text = String::from_utf8_lossy(&typo.stdout).into_owned();
    assert!(
        !typo.status.success() && text.contains("fail  display: --monitor HDMI-9"),
        "{text}"
    );
}

#[test]
fn recording_to_a_bad_name_or_place_is_refused_in_one_line() {
    let r = run(&launcher(), &["run", "--record", "run.png", "--", "true"], &[]);
    assert_one_line_failure(&r, "--record run.png", "a PNG as the video");
    let r = run(
        &launcher(),
        &["run", "--record", "/nonexistent/run.mp4", "--", "true"],
        &[],
    );
    assert_one_line_failure(&r, "cannot write into /nonexistent", "a missing directory");
}
