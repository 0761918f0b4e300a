//! The launcher's contract: options map to variables, bad input is one clear line and a
//! non-zero status, and the layer it preloads really loads.

use crate::util::*;

fn launch(args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    run(&launcher(), args, env)
}

fn assert_one_line_error(out: &std::process::Output, needle: &str) {
    assert_one_line_failure(out, needle, "the launcher");
    let err = stderr(out);
    assert!(err.starts_with("holoinject: error: "), "{err}");
}

#[test]
fn dry_run_prints_preload_variables_and_command() {
    let dir = temp_dir("dry_run");
    let dump = dir.join("frames");
    let out = launch(
        &[
            "run",
            "--dry-run",
            "--dump",
            dump.to_str().unwrap(),
            "--exit-after",
            "7",
            "--log",
            "debug",
            "--",
            "true",
            "a b",
        ],
        &[("LD_PRELOAD", "other.so")],
    );
    assert_success(&out, "dry run");
    let text = String::from_utf8_lossy(&out.stdout);
    let lib = layer_lib().canonicalize().unwrap();
    assert!(
        text.contains(&format!("LD_PRELOAD=other.so:{}", lib.display())),
        "{text}"
    );
    assert!(text.contains(&format!("HOLOINJECT_DUMP={}", dump.display())), "{text}");
    assert!(
        text.contains("HOLOINJECT_EXIT_AFTER=7") && text.contains("HOLOINJECT_LOG=debug"),
        "{text}"
    );
    assert!(text.lines().last().unwrap().ends_with("/true 'a b'"), "{text}");
}

#[test]
fn unknown_option_is_one_line_error() {
    assert_one_line_error(
        &launch(&["run", "--frobnicate", "--", "true"], &[]),
        "unknown option --frobnicate",
    );
}

#[test]
fn bad_quilt_syntax_is_one_line_error() {
    assert_one_line_error(&launch(&["run", "--quilt", "8by6", "--", "true"], &[]), "--quilt 8by6");
}

#[test]
fn bad_modes_are_refused_not_ignored() {
    assert_one_line_error(&launch(&["run", "--mode", "warp", "--", "true"], &[]), "--mode warp");
    assert_one_line_error(&launch(&["run", "--mode", "hybrid:0", "--", "true"], &[]), "hybrid:K");
    assert_one_line_error(
        &launch(&["run", "--synth-warp", "quads", "--", "true"], &[]),
        "rows, grid or gather",
    );
}

#[test]
fn missing_program_is_one_line_error() {
    assert_one_line_error(
        &launch(&["run", "--", "no-such-program-xyz"], &[]),
        "no-such-program-xyz",
    );
    assert_one_line_error(&launch(&["run", "--log", "info"], &[]), "no program given");
}

#[test]
fn unwritable_dump_dir_is_one_line_error() {
    let dir = temp_dir("unwritable_dump");
    let file = dir.join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let target = file.join("sub");
    assert_one_line_error(
        &launch(&["run", "--dump", target.to_str().unwrap(), "--", "true"], &[]),
        "--dump",
    );
}

#[test]
fn missing_or_unloadable_layer_library_is_detected() {
    let dir = temp_dir("bad_lib");
    let missing = dir.join("libholoinject.so");
    assert_one_line_error(
        &launch(&["run", "--", "true"], &[("HOLOINJECT_LIB", missing.to_str().unwrap())]),
        "layer library",
    );
    std::fs::write(&missing, b"not an ELF file").unwrap();
    assert_one_line_error(
        &launch(&["run", "--", "true"], &[("HOLOINJECT_LIB", missing.to_str().unwrap())]),
        "cannot be loaded",
    );
}

/// The program's environment is its own but for `LD_PRELOAD` and the layer's `HOLOINJECT_*`:
/// every process it starts inherits what the launcher adds (Wine's helpers failed at random
/// under the `MALLOC_*` tuning the launcher once added; the layer now tunes its own process).
#[test]
fn the_program_environment_gains_only_the_preload_and_our_variables() {
    let plain = run(std::path::Path::new("env"), &[], &[]);
    let under = launch(&["run", "--quilt", "3x3", "--", "env"], &[]);
    assert_success(&under, "env under the launcher");
    let lines = |o: &std::process::Output| -> std::collections::BTreeSet<String> {
        String::from_utf8_lossy(&o.stdout).lines().map(str::to_string).collect()
    };
    let (before, after) = (lines(&plain), lines(&under));
    let added: Vec<&String> = after.difference(&before).collect();
    let removed: Vec<&String> = before.difference(&after).collect();
    for line in &added {
        assert!(
            line.starts_with("LD_PRELOAD=") || line.starts_with("HOLOINJECT_"),
            "the launcher added {line} to the program's environment (added: {added:?})"
        );
    }
    assert!(
        removed.iter().all(|l| l.starts_with("LD_PRELOAD=")),
        "removed: {removed:?}"
    );
    assert!(
        added.iter().any(|l| l.starts_with("HOLOINJECT_QUILT=3x3")),
        "added: {added:?}"
    );
}

#[test]
fn program_exit_status_and_arguments_pass_through() {
    let out = launch(&["run", "--", "sh", "-c", "echo \"$0:$1\"; exit 3", "x", "y"], &[]);
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(String::from_utf8_lossy(&out.stdout), "x:y\n");
}

#[test]
fn help_documents_every_option() {
    let out = launch(&["run", "--help"], &[]);
    assert_success(&out, "help");
    let text = String::from_utf8_lossy(&out.stdout);
    for o in holoinject::config::options::OPTIONS {
        assert!(text.contains(&format!("--{}", o.long)), "--{} undocumented", o.long);
    }
}

#[test]
fn readme_documents_every_option() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    for o in holoinject::config::options::OPTIONS {
        assert!(
            readme.contains(&format!("`--{}", o.long)),
            "--{} is not documented in README.md",
            o.long
        );
    }
}

#[test]
fn readme_test_command_is_what_ci_runs() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let ci = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/.ci/run")).unwrap();
    let command = "scripts/setup-debian.sh && scripts/test.sh";
    assert!(readme.contains(command) && ci.lines().any(|l| l.trim() == command));
}

#[test]
fn presets_are_listed_and_shown_by_dry_run() {
    let out = launch(&["presets"], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    for name in ["glxgears", "es2gears", "glmark2", "chromium-bsu"] {
        assert!(text.contains(&format!("  {name} ")), "{name} missing:\n{text}");
    }
    let out = launch(&["run", "--preset", "glxgears", "--dry-run", "--", "true"], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("# preset presets/glxgears.toml (by --preset glxgears)"),
        "{text}"
    );
    assert!(text.contains("HOLOINJECT_PRESET=glxgears"), "{text}");
    // Chosen by the program's name when none is given (here a copy of `true` named glmark2-es2).
    let dir = std::env::temp_dir().join(format!("holoinject-dry-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fake = dir.join("glmark2-es2");
    std::fs::copy("/bin/true", &fake).unwrap();
    let out = launch(&["run", "--dry-run", "--", fake.to_str().unwrap()], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("# preset presets/glmark2.toml (by program name glmark2-es2)"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
