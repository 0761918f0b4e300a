//! Helpers shared by the integration tests: locating the built layer, launcher and sample
//! apps, running them headless with a time limit (plainly or under the layer), checking what
//! they said (`gl_errors`: GL errors reported), and comparing images (`image`, `compare`).

mod compare;
mod disparity;
mod gl_errors;
mod image;
mod parallax;
mod region;
mod xserver;
pub use compare::*;
pub use disparity::*;
pub use gl_errors::*;
pub use image::*;
pub use parallax::*;
pub use region::*;
pub use xserver::*;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Mutex;

/// Longest any single program run may take before the test fails (llvmpipe on 2 cores).
pub const RUN_TIMEOUT_S: u32 = 180;

pub fn launcher() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_holoinject"))
}

pub fn layer_lib() -> PathBuf {
    launcher().with_file_name("libholoinject.so")
}

/// A sample app from `tests/apps`, built into the same profile directory by `scripts/test.sh`.
pub fn app(name: &str) -> PathBuf {
    let p = launcher().with_file_name(name);
    assert!(
        p.exists(),
        "{} missing: build the sample apps first (`cargo build --workspace --release`, done by scripts/test.sh)",
        p.display()
    );
    p
}

/// A fresh, empty directory for one test. Tests of this binary run in parallel, so each name
/// may be asked for once per run: a second request is a bug (two tests sharing files).
/// Where `temp_dir(test)` is, without creating or emptying it (a later step of a test reads
/// what an earlier one left there).
pub fn temp_path(test: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(test)
}

pub fn temp_dir(test: &str) -> PathBuf {
    static GIVEN: Mutex<BTreeSet<String>> = Mutex::new(BTreeSet::new());
    let fresh = GIVEN.lock().unwrap_or_else(|e| e.into_inner()).insert(test.to_string());
    assert!(
        fresh,
        "temp_dir(\"{test}\") asked for twice: give each test its own name"
    );
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(test);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn require_display() {
    assert!(
        std::env::var_os("DISPLAY").is_some(),
        "GLX tests need an X server: run the tests through scripts/test.sh (it starts Xvfb)"
    );
}

/// Runs `program args…` under `timeout`, with extra environment, and returns its output.
pub fn run(program: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new("timeout");
    cmd.arg(RUN_TIMEOUT_S.to_string())
        .arg(program)
        .args(args)
        .envs(env.iter().copied());
    cmd.env("ALSOFT_DRIVERS", "null");
    cmd.output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", program.display()))
}

/// Runs `holoinject run LAYER… -- PROGRAM ARGS…` (a sample app's path or a name in `$PATH`).
pub fn under_layer(layer: &[&str], program: impl AsRef<Path>, args: &[&str], env: &[(&str, &str)]) -> Output {
    let program = program.as_ref().to_str().expect("program path is UTF-8");
    let mut all = vec!["run"];
    all.extend_from_slice(layer);
    all.extend(["--", program]);
    all.extend_from_slice(args);
    run(&launcher(), &all, env)
}

/// The launcher options that dump frame `frame` into `dump` and end the program after it.
pub fn dump_and_exit_at<'a>(dump: &'a Path, frame: &'a str) -> [&'a str; 6] {
    let dump = dump.to_str().expect("dump path is UTF-8");
    ["--dump", dump, "--dump-frames", frame, "--exit-after", frame]
}

pub fn assert_success(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what} failed ({}):\nstdout: {}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The layer announced itself (it does at `--log info` and below).
pub fn assert_layer_loaded(out: &Output) {
    assert!(
        stderr(out).contains("holoinject 0.1.0 active"),
        "layer not loaded:\n{}",
        stderr(out)
    );
}

/// The sample apps check `glGetError` after their first frame: the layer must not add errors.
pub fn assert_no_gl_error(out: &Output) {
    assert!(
        !stderr(out).contains("GL error"),
        "GL error under the layer:\n{}",
        stderr(out)
    );
}

/// The run failed with exactly one line on stderr, containing `needle`, and no panic report.
pub fn assert_one_line_failure(out: &Output, needle: &str, what: &str) {
    let err = stderr(out);
    assert!(!out.status.success(), "{what} accepted");
    assert_eq!(err.lines().count(), 1, "{what}: {err}");
    assert!(
        err.contains(needle) && !err.contains("panicked"),
        "{what}: `{needle}` not in {err}"
    );
}
