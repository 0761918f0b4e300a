//! Every exported hook survives an internal failure: for each entry point of the policy table,
//! a sample app runs under a 3x3 quilt with `HOLOINJECT_TEST_FAIL` making that hook's handler
//! panic on its first call. The app must end normally, the layer must say so once, and from
//! then on be pass-through: the app's last frame (read back by the app itself) equals its
//! plain run up to the centre-view rule (`CENTRE_VIEW`: the rewritten vertex shader, still
//! linked after the failure with a zero shift, is compiled differently, which moves some
//! varyings by a rounding in `model` and `compat120`; bit-exact for the other apps).
//!
//! Run: `xvfb-run -a cargo test --release --test integration forced_failures:: -- --nocapture`
//! (prints, per app, which hooks it reached and so were failed).

use crate::util::*;

fn policy_names() -> Vec<String> {
    let table = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/hook/policy.txt")).unwrap();
    table
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_whitespace().nth(1).map(str::to_string))
        .collect()
}

fn every_hook_fails_safely(name: &str, app_args: &[&str]) {
    // An app's switch (`--blit-to-default`, `--reattach`) names a variant of its own.
    let variant = app_args
        .last()
        .and_then(|a| a.strip_prefix("--"))
        .map_or(String::new(), |v| format!("_{v}"));
    let dir = temp_dir(&format!("forced_failures_{name}_{}{variant}", app_args[1]));
    let exe = app(name);
    let plain = dir.join("plain.png");
    let mut args: Vec<&str> = app_args.to_vec();
    let plain_arg = plain.to_str().unwrap().to_string();
    args.extend(["--screenshot", &plain_arg]);
    assert_success(&run(&exe, &args, &[]), &format!("plain {name}"));
    let lib = layer_lib().to_str().unwrap().to_string();
    let (mut reached, mut not_called) = (vec![], 0);
    for hook in policy_names() {
        let shot = dir.join(format!("{hook}.png"));
        let shot_arg = shot.to_str().unwrap().to_string();
        let mut args: Vec<&str> = app_args.to_vec();
        args.extend(["--screenshot", &shot_arg]);
        let env = [
            ("LD_PRELOAD", lib.as_str()),
            ("HOLOINJECT_QUILT", "3x3"),
            ("HOLOINJECT_TEST_FAIL", hook.as_str()),
        ];
        let out = run(&exe, &args, &env);
        let err = stderr(&out);
        assert!(
            out.status.success(),
            "{name} with a failing {hook} hook did not survive:\n{err}"
        );
        assert!(
            !err.contains("SIGSEGV") && !err.contains("aborted"),
            "{name}/{hook}:\n{err}"
        );
        let said = err.matches(&format!("internal error in the {hook} hook")).count();
        if said == 0 {
            not_called += 1;
            continue;
        }
        assert_eq!(said, 1, "{name}/{hook}: failure not reported exactly once:\n{err}");
        reached.push(hook.clone());
        assert_files_within(&plain, &shot, CENTRE_VIEW, &format!("{name}/{hook}"));
    }
    println!(
        "{name}: {} hooks failed on purpose, all survived with a pass-through last frame ({not_called} not called): {}",
        reached.len(),
        reached.join(" ")
    );
    assert!(reached.len() >= 10, "{name}: only {} hooks reached", reached.len());
}

#[test]
fn core_profile_app_survives_every_hook_failing() {
    every_hook_fails_safely("cubes", &["--backend", "egl", "--size", "160x120", "--frames", "4"]);
}

#[test]
fn glx_app_survives_every_hook_failing() {
    require_display();
    every_hook_fails_safely("cubes", &["--backend", "glx", "--size", "160x120", "--frames", "4"]);
}

#[test]
fn fixed_function_app_survives_every_hook_failing() {
    every_hook_fails_safely("legacy", &["--backend", "osmesa", "--size", "160x120", "--frames", "4"]);
}

#[test]
fn multi_pass_app_survives_every_hook_failing() {
    every_hook_fails_safely(
        "framebuffers",
        &["--backend", "egl", "--size", "160x120", "--frames", "4"],
    );
}

/// VTK's pattern: targets attached before and detached after every pass, texture parameters
/// sent again. A failure while the scene texture is detached must still hand the frame back
/// (the centre layer of its image goes into the app's texture, which the next pass samples).
#[test]
fn reattaching_app_survives_every_hook_failing() {
    every_hook_fails_safely(
        "framebuffers",
        &["--backend", "egl", "--size", "160x120", "--frames", "4", "--reattach"],
    );
}

#[test]
fn uniform_block_app_survives_every_hook_failing() {
    every_hook_fails_safely("model", &["--backend", "egl", "--size", "160x120", "--frames", "4"]);
}

#[test]
fn msaa_resolve_app_survives_every_hook_failing() {
    every_hook_fails_safely(
        "msaa",
        &[
            "--backend",
            "egl",
            "--size",
            "160x120",
            "--frames",
            "4",
            "--blit-to-default",
        ],
    );
}

#[test]
fn compat_builtins_app_survives_every_hook_failing() {
    every_hook_fails_safely(
        "compat120",
        &["--backend", "osmesa", "--size", "160x120", "--frames", "4"],
    );
}
