//! The shared object itself: what it exports, that it stays silent on stdout, and that an
//! internal failure degrades to pass-through instead of taking the program down.

use crate::util::*;

#[test]
fn exports_exactly_the_policy_table() {
    let out = std::process::Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(layer_lib())
        .output()
        .expect("nm (binutils)");
    let text = String::from_utf8_lossy(&out.stdout);
    let mut exported: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split_whitespace().nth(2))
        .filter(|s| !s.starts_with('_'))
        .collect();
    exported.sort();
    let mut expected: Vec<String> = holoinject::hook::HOOKS
        .iter()
        .map(|h| h.name.to_string_lossy().into_owned())
        .collect();
    expected.extend(["dlopen".to_string(), "dlsym".to_string()]);
    expected.sort();
    assert_eq!(exported, expected);
}

#[test]
fn nothing_on_stdout_from_a_gl_program() {
    let dir = temp_dir("silent_stdout");
    let shot = dir.join("s.png");
    let args = ["--backend", "egl", "--size", "160x120", "--frames", "3", "--screenshot"];
    let mut args = args.to_vec();
    args.push(shot.to_str().unwrap());
    let out = under_layer(&["--quilt", "3x3", "--log", "debug"], app("cubes"), &args, &[]);
    assert_success(&out, "cubes");
    assert!(
        out.stdout.is_empty(),
        "stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(stderr(&out).contains("holoinject: debug:"), "debug log missing");
}

#[test]
fn forced_internal_error_falls_back_to_pass_through() {
    let dir = temp_dir("forced_error");
    let dump = dir.join("d");
    let cubes = app("cubes");
    let (plain, injected) = (dir.join("plain.png"), dir.join("injected.png"));
    let app_args = ["--backend", "egl", "--size", "160x120", "--frames", "4", "--screenshot"];
    let mut plain_args = app_args.to_vec();
    plain_args.push(plain.to_str().unwrap());
    assert_success(&run(&cubes, &plain_args, &[]), "plain cubes");
    let mut options = vec!["--quilt", "3x3"];
    options.extend(dump_and_exit_at(&dump, "4"));
    let mut args = app_args.to_vec();
    args.push(injected.to_str().unwrap());
    let out = under_layer(&options, &cubes, &args, &[("HOLOINJECT_TEST_FAIL", "eglSwapBuffers")]);
    assert_success(&out, "cubes with a failing swap hook");
    let err = stderr(&out);
    assert_eq!(
        err.matches("internal error in the eglSwapBuffers hook").count(),
        1,
        "{err}"
    );
    // From the failure on the layer is pass-through: frames still end, so --exit-after is
    // not honoured by the layer any more; the app ends on its own after 4 frames.
    assert!(
        !dump.join("f000004_out.png").exists(),
        "the layer kept running after failing"
    );
    // Frames after the failure are the app's own again: framebuffer 0 and unshifted shaders.
    assert_identical(&plain, &injected);
}

/// Regression: with the quilt standing in for framebuffer 0, an app asking about framebuffer
/// 0's attachments (`glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, GL_DEPTH, …)`, as
/// `HOLOAPPS_VERBOSE` makes the sample apps do) got GL_INVALID_ENUM and "depth 0". It must get
/// the window's answer and no error.
#[test]
fn default_framebuffer_queries_answer_for_the_window() {
    let cubes = app("cubes");
    let app_args = ["--backend", "egl", "--size", "160x120", "--frames", "2"];
    let plain = run(&cubes, &app_args, &[("HOLOAPPS_VERBOSE", "1")]);
    let injected = under_layer(&["--quilt", "3x3"], &cubes, &app_args, &[("HOLOAPPS_VERBOSE", "1")]);
    assert_success(&injected, "cubes under the layer");
    let first = |o: &std::process::Output| stderr(o).lines().next().unwrap_or("").to_string();
    assert!(first(&plain).contains("(depth 24, stencil 8)"), "{}", first(&plain));
    assert_eq!(first(&injected), first(&plain));
    assert_no_gl_error(&injected);
}

/// Several contexts in one share group, current on two threads at once, sharing a texture:
/// under the layer both keep working and each thread's framebuffer 0 (its centre view) is
/// its plain image.
#[test]
fn two_threads_sharing_a_texture() {
    let dir = temp_dir("two_threads");
    let tt = app("twothreads");
    let (plain, injected) = (dir.join("plain"), dir.join("injected"));
    let shot = |p: &std::path::Path| p.to_str().unwrap().to_string();
    assert_success(
        &run(&tt, &["--frames", "5", "--screenshot", &shot(&plain)], &[]),
        "plain twothreads",
    );
    let args = ["--frames", "5", "--screenshot", &shot(&injected)];
    let out = under_layer(&["--quilt", "3x3", "--log", "info"], &tt, &args, &[]);
    assert_success(&out, "twothreads under the layer");
    assert_eq!(
        stderr(&out).matches("created (share group 1)").count(),
        2,
        "{}",
        stderr(&out)
    );
    for side in ["a", "b"] {
        let p = dir.join(format!("plain-{side}.png"));
        assert!(has_content(&p));
        assert_identical(&p, &dir.join(format!("injected-{side}.png")));
    }
}

/// The `objects …` line `churn` prints: the shared GL objects alive in its share group
/// after its contexts were destroyed. Also checks the plain or injected run left the
/// screenshot of its last frame at `shot`.
fn churn_objects(layer: &[&str], cycles: u32, extra: &[&str], shot: &std::path::Path) -> String {
    let churn = app("churn");
    let cycles = cycles.to_string();
    let mut args = vec![
        "--size",
        "160x120",
        "--cycles",
        &cycles,
        "--screenshot",
        shot.to_str().unwrap(),
    ];
    args.extend(extra);
    let out = if layer.is_empty() {
        run(&churn, &args, &[])
    } else {
        under_layer(layer, &churn, &args, &[])
    };
    assert_success(&out, &format!("churn {layer:?} --cycles {cycles} {extra:?}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        stdout.starts_with("objects ") && stdout.lines().count() == 1,
        "{stdout}"
    );
    stdout.trim_end().to_string()
}

/// Contexts destroyed and re-created in one share group, a root context alive throughout:
/// the quilt, layered shadows (arrays and texture views) and pass programs the layer made in
/// each destroyed context are shared objects that outlive it, so they must be freed by the
/// share group. The shared objects left at the end are the app's own, for any cycle count;
/// and the re-created contexts' centre view is still the plain image.
#[test]
fn destroyed_contexts_leave_no_layer_objects_in_the_share_group() {
    let dir = temp_dir("context_churn");
    let quilt = ["--quilt", "3x3"];
    let anaglyph = ["--quilt", "3x3", "--output", "anaglyph"];
    let variants: [(&str, &[&str], &[&str]); 4] = [
        ("quilt", &quilt, &[]),
        ("quilt-handover", &quilt, &["--hand-over-target"]),
        ("quilt-destroy-current", &quilt, &["--destroy-current"]),
        ("anaglyph", &anaglyph, &[]),
    ];
    for (name, layer, extra) in variants {
        let mut counts = Vec::new();
        for cycles in [2, 6] {
            let (plain, injected) = (
                dir.join(format!("{name}-{cycles}-plain.png")),
                dir.join(format!("{name}-{cycles}-injected.png")),
            );
            let p = churn_objects(&[], cycles, extra, &plain);
            let i = churn_objects(layer, cycles, extra, &injected);
            println!("churn {name} --cycles {cycles}: plain `{p}`, injected `{i}`");
            if !layer.contains(&"anaglyph") {
                assert_identical(&plain, &injected);
            }
            counts.push((p, i));
        }
        let ((p2, i2), (p6, i6)) = (&counts[0], &counts[1]);
        assert_eq!(p2, p6, "{name}: the plain app's count depends on the cycles");
        assert_eq!(i2, i6, "{name}: layer objects pile up with every destroyed context");
        assert_eq!(i6, p6, "{name}: the layer left objects of its own in the share group");
    }
}

/// The layer's own uniforms never show in the app's introspection: the count, the names by
/// index (`glGetActiveUniform`, `glGetActiveUniformName`), their types (`glGetActiveUniformsiv`)
/// and the GL 4.3 interface query list exactly the app's uniforms, at the app's indices.
#[test]
fn introspection_lists_only_the_apps_uniforms() {
    for name in ["cubes", "deferred", "compat120"] {
        let exe = app(name);
        let args = ["--backend", "egl", "--size", "160x120", "--frames", "2"];
        let list = |env: &[(&str, &str)]| {
            let out = run(&exe, &args, env);
            assert_success(&out, name);
            stderr(&out)
                .lines()
                .filter(|l| l.starts_with("uniforms of program"))
                .map(str::to_string)
                .collect::<Vec<_>>()
        };
        let plain = list(&[("HOLOAPPS_LIST_UNIFORMS", "1")]);
        let lib = layer_lib().to_str().unwrap().to_string();
        let injected = list(&[
            ("HOLOAPPS_LIST_UNIFORMS", "1"),
            ("LD_PRELOAD", lib.as_str()),
            ("HOLOINJECT_QUILT", "3x3"),
        ]);
        assert!(!plain.is_empty(), "{name}: no programs listed");
        assert!(
            plain.iter().chain(&injected).all(|l| !l.contains("(inconsistent)")),
            "{injected:#?}"
        );
        // Implicit locations are the linker's to assign, and our uniform takes one: an app's
        // uniform may sit one location further (apps ask glGetUniformLocation). Within a run,
        // each name's location must agree between glGetUniformLocation and the interface query.
        for line in &injected {
            let (classic, interface) = line.split_once(" | interface: ").unwrap();
            let locs = |part: &str| -> Vec<String> {
                part.split_whitespace()
                    .filter_map(|w| w.split_once('@'))
                    .map(|(n, l)| format!("{}@{}", n.rsplit(' ').next().unwrap(), l.split(':').next().unwrap()))
                    .collect()
            };
            assert_eq!(
                locs(classic.split(": ").nth(1).unwrap_or("")),
                locs(interface),
                "{line}"
            );
        }
        let without_locations = |l: &Vec<String>| -> Vec<String> {
            l.iter()
                .map(|s| {
                    s.split_whitespace()
                        .map(|w| w.split('@').next().unwrap().to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                })
                .collect()
        };
        assert_eq!(
            without_locations(&injected),
            without_locations(&plain),
            "{name}: introspection differs under the layer"
        );
        let moved = injected.iter().zip(&plain).filter(|(a, b)| a != b).count();
        println!(
            "{name}: {} programs, the same uniforms by index, name and type as the plain run ({moved} with a location moved)",
            plain.len()
        );
    }
}

/// Regression: texture targets (which layered shadows need, Mesa refusing GL_TEXTURE_TARGET
/// queries) were recorded per context, and only where multiview was on, so a render target
/// created by `churn`'s surfaceless root context and attached to an FBO in another context
/// of its share group was "target 0x0 is not shadowed"; and they were never forgotten, so a
/// deleted cube map's name re-created as a 2D render target kept the cube map's target.
/// Each cycle's FBO must now be shadowed, the quilt's side views show parallax, and the
/// centre view is the plain image.
#[test]
fn render_targets_made_in_another_context_or_under_a_reused_name_are_shadowed() {
    let dir = temp_dir("shared_texture_targets");
    let churn = app("churn");
    // Mesa hands out fresh texture names unless this driconf option makes it reuse freed
    // ones (as NVIDIA's driver and Mesa's glthread do); `churn` warns when a name was not.
    let env = [("force_gl_names_reuse", "true")];
    let variants: [&[&str]; 3] = [
        &["--root-target"],
        &["--reuse-name"],
        &["--root-target", "--reuse-name"],
    ];
    for (v, extra) in variants.into_iter().enumerate() {
        let (plain, injected, dump) = (
            dir.join(format!("{v}-plain.png")),
            dir.join(format!("{v}-injected.png")),
            dir.join(format!("{v}-dump")),
        );
        let app_args = |shot: &std::path::Path| {
            let mut a = vec!["--size", "160x120", "--cycles", "2", "--screenshot"];
            a.push(shot.to_str().unwrap());
            a.extend(extra);
            a.into_iter().map(str::to_string).collect::<Vec<_>>()
        };
        let args = app_args(&plain);
        let out = run(&churn, &args.iter().map(String::as_str).collect::<Vec<_>>(), &env);
        assert_success(&out, &format!("plain churn {extra:?}"));
        let mut options = vec!["--quilt", "3x3", "--log", "info", "--depthiness", "0.1"];
        options.extend(["--convergence", "0.01", "--dump", dump.to_str().unwrap()]);
        options.extend(["--dump-frames", "6"]);
        let args = app_args(&injected);
        let out = under_layer(
            &options,
            &churn,
            &args.iter().map(String::as_str).collect::<Vec<_>>(),
            &env,
        );
        assert_success(&out, &format!("churn {extra:?} under the layer"));
        let err = stderr(&out);
        let shadowed = err.lines().filter(|l| l.contains(" shadowed with 9 layers")).count();
        let not = err.lines().filter(|l| l.contains("not shadowed")).count();
        println!("churn {extra:?}: {shadowed} framebuffers shadowed, {not} 'not shadowed' lines");
        assert!(!err.contains("warning: render target got texture name"), "{err}");
        assert_eq!((shadowed, not), (2, 0), "one shadow per cycle's FBO expected:\n{err}");
        assert_identical(&plain, &injected);
        // Side views shifted as the cubes' depth says (convergence at the camera: every
        // pixel moves away from the centre view, more with distance from it).
        let quilt_png = dump.join("f000006_qs3x3a1.3333.png");
        let what = format!("churn {extra:?}");
        assert_parallax_grows(&read_png(&quilt_png), &quilt_png, (3, 3), 4, &[5, 8], 20, &what);
    }
}

/// Regression: an app's synchronous KHR_debug callback that calls GL (`glGetIntegerv`,
/// `glGetError`) from inside a draw the layer replays per view deadlocked: the callback's
/// `glGetIntegerv` hook waited for the per-context multiview lock its own thread held across
/// the real draw. Re-entered hooks must pass through; the app must finish, and its callback
/// must have run once per view of each frame (inside the replay, with the lock held).
#[test]
fn debug_callback_calling_gl_inside_a_replayed_draw_does_not_deadlock() {
    use std::os::unix::process::ExitStatusExt;
    let debugcall = app("debugcall");
    let mut args = vec!["--backend", "egl", "--size", "160x120", "--frames", "3"];
    let plain = run(&debugcall, &args, &[]);
    assert_success(&plain, "plain debugcall");
    assert!(stderr(&plain).contains("debugcall: messages=3"), "{}", stderr(&plain));
    // Our own time limit, with SIGKILL: a deadlocked app never sees the SIGTERM of `run`.
    let mut cmd = std::process::Command::new("timeout");
    cmd.args(["--kill-after=5", "60"]).arg(launcher());
    args.splice(0..0, ["run", "--quilt", "3x3", "--", debugcall.to_str().unwrap()]);
    let out = cmd.args(&args).output().expect("timeout (coreutils)");
    // 124: timed out, ended by SIGTERM. SIGKILL (or 137): SIGTERM ignored, as the app's handler
    // only sets a flag its deadlocked thread never reads.
    let hung = matches!(out.status.code(), Some(124 | 137)) || out.status.signal() == Some(9);
    assert!(!hung, "hung (deadlock in the debug callback?): {}", stderr(&out));
    assert_success(&out, "debugcall under the layer");
    assert!(stderr(&out).contains("debugcall: messages=27"), "{}", stderr(&out));
}
