//! Bad input, from the launcher and from variables set by hand: one clear line naming the
//! option, variable, file or field; the launcher refuses to start, the layer keeps the
//! program running with the default. Every row of README's bad-input table is a case here.

use crate::util::*;

fn launcher_refuses(args: &[&str], needle: &str) {
    let out = under_layer(args, "true", &[], &[]);
    assert_one_line_failure(&out, needle, &format!("{args:?}"));
}

#[test]
fn launcher_rejects_bad_values_with_one_line() {
    let dir = temp_dir("bad_values");
    let garbled = dir.join("garbled.json");
    std::fs::write(&garbled, "{ \"pitch\": { \"value\": 52.").unwrap();
    let partial = dir.join("visual.json");
    std::fs::write(&partial, r#"{"slope": {"value": -7.2}, "center": {"value": 0.1}, "DPI": {"value": 324}, "screenW": {"value": 1536}, "screenH": {"value": 2048}}"#).unwrap();
    let bad_toml = dir.join("bad.toml");
    std::fs::write(&bad_toml, "quilt = \"5x9\"\ndepthiness = = 0.1\n").unwrap();
    let cases: [(&[&str], &str); 23] = [
        (
            &["--preset", bad_toml.to_str().unwrap()],
            "bad.toml (line 2): not valid TOML",
        ),
        (&["--preset", "no-such-game"], "unknown preset \"no-such-game\""),
        (&["--preset", "/nonexistent/p.toml"], "preset /nonexistent/p.toml"),
        (&["--quilt", "0x6"], "--quilt 0x6"),
        (&["--quilt", "-8x6"], "--quilt -8x6"),
        (&["--tile", "100000x560"], "--tile 100000x560"),
        (&["--depthiness", "lots"], "--depthiness lots"),
        (&["--convergence", "-3"], "must be > 0"),
        (&["--view-cone", "200"], "--view-cone 200"),
        (&["--device", "no-such-panel"], "unknown device"),
        (&["--device", garbled.to_str().unwrap()], "garbled.json"),
        (&["--device", partial.to_str().unwrap()], "\"pitch\""),
        (&["--dump-frames", "every:0"], "--dump-frames every:0"),
        (&["--exit-after", "0"], "--exit-after 0"),
        (&["--log", "loud"], "--log loud"),
        (&["--weave-filter", "gaussian:99"], "--weave-filter gaussian:99"),
        (&["--output", "hologram"], "--output hologram"),
        (&["--monitor", "1536x2048+1920"], "--monitor 1536x2048+1920"),
        (&["--present", "screen"], "--present screen"),
        (&["--preview", "both"], "--preview both"),
        (&["--fbo-scale", "0"], "--fbo-scale 0"),
        (&["--fbo-scale", "2"], "--fbo-scale 2"),
        (&["--fbo-scale", "foo"], "--fbo-scale foo"),
    ];
    for (args, needle) in cases {
        launcher_refuses(args, needle);
    }
}

/// Variables set by hand (no launcher): the program runs to its end (status 0) and the layer
/// says once which variable it ignored.
fn layer_survives(var: &str, value: &str, needle: &str) {
    let cubes = app("cubes");
    let env = [
        ("LD_PRELOAD", layer_lib().to_str().unwrap().to_string()),
        (var, value.to_string()),
    ];
    let env: Vec<(&str, &str)> = env.iter().map(|(k, v)| (*k, v.as_str())).collect();
    let out = run(
        &cubes,
        &["--backend", "egl", "--size", "160x120", "--frames", "2"],
        &env,
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{var}={value}: program did not survive:\n{err}");
    assert_eq!(
        err.matches(needle).count(),
        1,
        "{var}={value}: `{needle}` not said exactly once:\n{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn layer_reports_bad_variables_and_keeps_running() {
    let dir = temp_dir("bad_variables");
    let file = dir.join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let unwritable = file.join("dumps");
    let cases = [
        ("HOLOINJECT_QUILT", "0x0", "HOLOINJECT_QUILT=0x0"),
        ("HOLOINJECT_TILE", "100000x100000", "HOLOINJECT_TILE=100000x100000"),
        (
            "HOLOINJECT_DEVICE",
            "/nonexistent/visual.json",
            "HOLOINJECT_DEVICE=/nonexistent/visual.json",
        ),
        ("HOLOINJECT_EXIT_AFTER", "-1", "HOLOINJECT_EXIT_AFTER=-1"),
        ("HOLOINJECT_DEPTHINESS", "NaN", "HOLOINJECT_DEPTHINESS=NaN"),
        ("HOLOINJECT_FBO_SCALE", "0", "HOLOINJECT_FBO_SCALE=0"),
        ("HOLOINJECT_QUILT", "16384x16384", "at most 1024"),
        ("HOLOINJECT_QUILT", "-3x3", "HOLOINJECT_QUILT=-3x3"),
        ("HOLOINJECT_CONVERGENCE", "1e999", "HOLOINJECT_CONVERGENCE=1e999"),
        ("HOLOINJECT_FOCUS", "\u{202e}0.1", "HOLOINJECT_FOCUS="),
        (
            "HOLOINJECT_DUMP_FRAMES",
            "every:18446744073709551616",
            "HOLOINJECT_DUMP_FRAMES=",
        ),
        ("HOLOINJECT_LOG", "loud", "HOLOINJECT_LOG: unknown level"),
        ("HOLOINJECT_DUMP", unwritable.to_str().unwrap(), "not dumped"),
    ];
    for (var, value, needle) in cases {
        layer_survives(var, value, needle);
    }
}

/// Presets found by the program's name in the user's folder: a malformed one is reported once
/// (file and line) and ignored, bad fields are reported one line each (file and field) and
/// skipped, good fields apply, and the environment still wins over the preset.
#[test]
fn app_presets_apply_and_their_problems_are_named() {
    let cubes = app("cubes");
    let lib = layer_lib().to_str().unwrap().to_string();
    let case = std::cell::Cell::new(0);
    let run_with = |preset: &str, extra: &[(&str, &str)]| {
        case.set(case.get() + 1);
        let dir = temp_dir(&format!("app_preset_{}", case.get()));
        let presets = dir.join("config/holoinject/presets");
        std::fs::create_dir_all(&presets).unwrap();
        std::fs::write(presets.join("cubes.toml"), preset).unwrap();
        let dumps = dir.join("dumps");
        let config = dir.join("config").to_str().unwrap().to_string();
        let dump = dumps.to_str().unwrap().to_string();
        let mut env = vec![
            ("LD_PRELOAD", lib.as_str()),
            ("XDG_CONFIG_HOME", config.as_str()),
            ("HOLOINJECT_DUMP", dump.as_str()),
            ("HOLOINJECT_LOG", "info"),
        ];
        env.extend_from_slice(extra);
        let out = run(
            &cubes,
            &["--backend", "egl", "--size", "160x120", "--frames", "2"],
            &env,
        );
        let quilts: Vec<String> = std::fs::read_dir(&dumps)
            .map(|d| d.filter_map(|e| e.ok()?.file_name().into_string().ok()).collect())
            .unwrap_or_default();
        (out, quilts)
    };
    let has_quilt = |quilts: &[String], grid: &str| quilts.iter().any(|q| q.contains(&format!("_qs{grid}a")));

    let (out, quilts) = run_with("quilt = \"3x2\"\nfocus = 0.01\n", &[]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("preset ") && err.contains("holoinject/presets/cubes.toml (by program name cubes)"),
        "{err}"
    );
    assert!(has_quilt(&quilts, "3x2"), "preset quilt not applied: {quilts:?}");

    let (out, quilts) = run_with("quilt = \"3x2\"\n", &[("HOLOINJECT_QUILT", "2x2")]);
    assert!(
        out.status.success() && has_quilt(&quilts, "2x2"),
        "environment did not win: {quilts:?}"
    );

    let (out, quilts) = run_with(
        "quilt = \"0x0\"\nviews = 9\ntile = \"100000x10\"\nfbo-scale = 2\nconvergence = 12\n",
        &[],
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    for field in ["quilt", "views", "tile", "fbo-scale"] {
        let needle = format!("cubes.toml: field \"{field}\"");
        assert_eq!(err.matches(&needle).count(), 1, "`{needle}` not said once:\n{err}");
    }
    assert!(
        has_quilt(&quilts, "8x6"),
        "bad quilt not replaced by the default: {quilts:?}"
    );

    let (out, quilts) = run_with("quilt = [\n", &[]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(err.matches("not valid TOML").count(), 1, "{err}");
    assert!(err.contains("cubes.toml (line "), "{err}");
    assert!(has_quilt(&quilts, "8x6"), "{quilts:?}");

    let (out, _) = run_with("quilt = \"3x2\"\n", &[("HOLOINJECT_PRESET", "no-such-game")]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(
        err.matches("HOLOINJECT_PRESET=no-such-game: unknown preset").count(),
        1,
        "{err}"
    );
}

/// Hostile values that parse but are extreme, and bytes that are not text: the program runs,
/// a too-large explicit tile is shrunk to what GL can allocate, and a non-UTF-8 variable is
/// named once.
#[test]
fn extreme_but_valid_values_and_non_utf8_bytes() {
    use std::os::unix::ffi::OsStrExt;
    let dir = temp_dir("extreme_values");
    let lib = layer_lib();
    let out = std::process::Command::new(app("cubes"))
        .args(["--backend", "egl", "--size", "160x120", "--frames", "2"])
        .env("LD_PRELOAD", &lib)
        .env("HOLOINJECT_TILE", "16384x16384")
        .env("HOLOINJECT_QUILT", "2x1")
        .env("HOLOINJECT_DUMP", &dir)
        .env("HOLOINJECT_LOG", "warn")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let quilt = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .find(|e| e.file_name().to_string_lossy().contains("_qs2x1"))
        .expect("no quilt dumped");
    let img = read_png(&quilt.path());
    assert!(
        img.width <= 16384 && img.height <= 16384 && img.width >= 8,
        "{}x{}",
        img.width,
        img.height
    );

    let out = std::process::Command::new(app("cubes"))
        .args(["--backend", "egl", "--size", "160x120", "--frames", "2"])
        .env("LD_PRELOAD", &lib)
        .env("HOLOINJECT_QUILT", std::ffi::OsStr::from_bytes(b"3x\xff3"))
        .output()
        .unwrap();
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(
        err.matches("HOLOINJECT_QUILT=3x\u{fffd}3: not valid UTF-8; ignored")
            .count(),
        1,
        "{err}"
    );
}
