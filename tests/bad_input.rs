//! Bad input, from the launcher and from variables set by hand: one clear line naming the
//! option, variable, file or field; the launcher refuses to start, the layer keeps the
//! program running with the default. Every row of README's bad-input table is a case here.

mod util;
use util::*;

fn launcher_refuses(args: &[&str], needle: &str) {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend(["--", "true"]);
    let out = run(&launcher(), &all, &[]);
    let err = stderr(&out);
    assert!(!out.status.success(), "{args:?} accepted");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(
        err.contains(needle) && !err.contains("panicked"),
        "{args:?}: `{needle}` not in {err}"
    );
}

#[test]
fn launcher_rejects_bad_values_with_one_line() {
    let dir = temp_dir("bad_values");
    let garbled = dir.join("garbled.json");
    std::fs::write(&garbled, "{ \"pitch\": { \"value\": 52.").unwrap();
    let partial = dir.join("visual.json");
    std::fs::write(&partial, r#"{"slope": {"value": -7.2}, "center": {"value": 0.1}, "DPI": {"value": 324}, "screenW": {"value": 1536}, "screenH": {"value": 2048}}"#).unwrap();
    let cases: [(&[&str], &str); 14] = [
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
        ("HOLOINJECT_LOG", "loud", "HOLOINJECT_LOG: unknown level"),
        ("HOLOINJECT_DUMP", unwritable.to_str().unwrap(), "not dumped"),
    ];
    for (var, value, needle) in cases {
        layer_survives(var, value, needle);
    }
}
