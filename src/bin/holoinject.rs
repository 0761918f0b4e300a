//! The launcher: parse, check, set the environment, `exec`. All option knowledge lives in
//! `holoinject::config` so the layer and the launcher cannot disagree.

#[path = "holoinject/checks.rs"]
mod checks;
#[path = "holoinject/doctor.rs"]
mod doctor;
#[path = "holoinject/probe.rs"]
mod probe;
#[path = "holoinject/probe_context.rs"]
mod probe_context;
#[path = "holoinject/quilt.rs"]
mod quilt;

use holoinject::config::cli::{self, Launch};
use holoinject::config::preset;
use std::ffi::{CString, OsString};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};

fn main() {
    if let Err(e) = run() {
        eprintln!("holoinject: error: {}", holoinject::config::one_line(&e));
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<OsString> = std::env::args_os().skip(1).collect();
    match args.first().and_then(|a| a.to_str()) {
        Some("run") if args.get(1).is_some_and(|a| a == "--help" || a == "-h") => print_help(),
        Some("run") => launch(cli::parse_run(&args[1..])?),
        Some("presets") => list_presets(),
        Some("quilt") => quilt::run(&args[1..]),
        Some("doctor") => doctor::run(&args[1..]),
        Some("__probe") => probe::run(&args[1..]),
        Some("ctl") => ctl(&args[1..]),
        Some("--version" | "-V") => {
            println!("holoinject {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Some("--help" | "-h" | "help") | None => print_help(),
        Some(other) => Err(format!(
            "unknown command `{other}`; usage: holoinject run [OPTIONS] -- PROGRAM [ARGS…] | holoinject ctl …"
        )),
    }
}

/// `holoinject ctl …`: one request to a running program's layer (README "Live controls").
fn ctl(args: &[OsString]) -> Result<(), String> {
    let args: Vec<String> = args.iter().map(|a| a.to_string_lossy().into_owned()).collect();
    let reply = holoinject::control::client::ctl(&args, &|k| std::env::var(k).ok())?;
    print!("{reply}");
    Ok(())
}

fn print_help() -> Result<(), String> {
    print!("{}", cli::help());
    Ok(())
}

fn launch(mut plan: Launch) -> Result<(), String> {
    let lib = layer_library()?;
    let program = find_program(&plan.program)?;
    absolutise_dump_dir(&mut plan)?;
    absolutise_record_path(&mut plan)?;
    absolutise_preset_path(&mut plan)?;
    let preset = chosen_preset(&plan, &program);
    cli::check_combinations(&plan, &|k| std::env::var(k).ok(), preset.as_ref().map(|c| &c.preset))?;
    let preload = cli::ld_preload_with(std::env::var_os("LD_PRELOAD").as_deref(), &lib.to_string_lossy());
    if plan.dry_run {
        if let Some(c) = &preset {
            println!("# preset {} (by {})", c.preset.source, c.reason);
        }
        println!("LD_PRELOAD={preload}");
        for (k, v) in &plan.env {
            println!("{k}={v}");
        }
        let words: Vec<String> = std::iter::once(program.as_os_str())
            .chain(plan.args.iter().map(|a| a.as_os_str()))
            .map(|w| shell_quote(&w.to_string_lossy()))
            .collect();
        println!("{}", words.join(" "));
        return Ok(());
    }
    let err = std::process::Command::new(&program)
        .args(&plan.args)
        .envs(plan.env.iter().map(|(k, v)| (k, v)))
        .env("LD_PRELOAD", preload)
        .exec();
    Err(format!("cannot run {}: {err}", program.display()))
}

/// `$HOLOINJECT_LIB`, else `libholoinject.so` beside this executable; it must load, or the
/// program would run without the layer and only a loader warning would say so.
fn layer_library() -> Result<PathBuf, String> {
    let path = match std::env::var_os("HOLOINJECT_LIB") {
        Some(p) => PathBuf::from(p),
        None => {
            let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
            exe.with_file_name("libholoinject.so")
        }
    };
    let path = path.canonicalize().map_err(|e| {
        format!(
            "layer library {}: {e} (build it with `cargo build --release`, or set HOLOINJECT_LIB)",
            path.display()
        )
    })?;
    let c = CString::new(path.as_os_str().as_encoded_bytes()).map_err(|_| "layer path contains NUL".to_string())?;
    // SAFETY: loading our own library locally only to prove it loads; it has no constructors.
    let handle = unsafe { libc::dlopen(c.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
    if handle.is_null() {
        // SAFETY: dlerror returns a static, NUL-terminated message after a failed dlopen.
        let why = unsafe { std::ffi::CStr::from_ptr(libc::dlerror()) }
            .to_string_lossy()
            .into_owned();
        return Err(format!("layer library {} cannot be loaded: {why}", path.display()));
    }
    Ok(path)
}

fn find_program(program: &OsString) -> Result<PathBuf, String> {
    let p = Path::new(program);
    let candidates: Vec<PathBuf> = if p.components().count() > 1 {
        vec![p.to_path_buf()]
    } else {
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())
            .map(|d| d.join(p))
            .collect()
    };
    let found = candidates.into_iter().find(|c| {
        c.metadata()
            .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    });
    found.ok_or_else(|| format!("program `{}` not found or not executable", p.display()))
}

/// The program may change directory, so the layer gets an absolute dump path, checked
/// writable now rather than failing silently at the first frame.
fn absolutise_dump_dir(plan: &mut Launch) -> Result<(), String> {
    let Some((_, dir)) = plan.env.iter_mut().find(|(k, _)| k == "HOLOINJECT_DUMP") else {
        return Ok(());
    };
    let path = std::path::absolute(dir.as_str()).map_err(|e| format!("--dump {dir}: {e}"))?;
    std::fs::create_dir_all(&path).map_err(|e| format!("--dump {}: cannot create: {e}", path.display()))?;
    let probe = path.join(".holoinject-write-test");
    std::fs::write(&probe, b"").map_err(|e| format!("--dump {}: not writable: {e}", path.display()))?;
    let _ = std::fs::remove_file(probe);
    *dir = path.to_string_lossy().into_owned();
    Ok(())
}

/// As for `--dump`: the video's directory must exist and be writable now, and the path must
/// survive the program changing directory.
fn absolutise_record_path(plan: &mut Launch) -> Result<(), String> {
    let Some((_, file)) = plan.env.iter_mut().find(|(k, _)| k == "HOLOINJECT_RECORD") else {
        return Ok(());
    };
    let path = std::path::absolute(file.as_str()).map_err(|e| format!("--record {file}: {e}"))?;
    let dir = path.parent().unwrap_or(Path::new("/"));
    let probe = dir.join(".holoinject-write-test");
    std::fs::write(&probe, b"").map_err(|e| format!("--record {file}: cannot write into {}: {e}", dir.display()))?;
    let _ = std::fs::remove_file(probe);
    *file = path.to_string_lossy().into_owned();
    Ok(())
}

/// The preset the layer will pick, for `--dry-run`. Problems with it are the layer's to report
/// (once, when the program starts): an explicit `--preset` was already checked as an option.
fn chosen_preset(plan: &Launch, program: &Path) -> Option<preset::Chosen> {
    let env = |k: &str| std::env::var(k).ok();
    let chosen = match plan.get("preset") {
        Some(spec) => preset::load_spec(spec, &env),
        None if std::env::var_os("HOLOINJECT_PRESET").is_some() => return None,
        None => {
            let names: Vec<String> = [program.as_os_str(), plan.program.as_os_str()]
                .iter()
                .filter_map(|p| Path::new(p).file_name().and_then(|n| n.to_str()).map(str::to_string))
                .collect();
            preset::for_program(&names, &env)
        }
    };
    chosen.ok().flatten()
}

/// A preset given as a relative path must still be found after the program changes directory.
fn absolutise_preset_path(plan: &mut Launch) -> Result<(), String> {
    let Some((_, spec)) = plan.env.iter_mut().find(|(k, _)| k == "HOLOINJECT_PRESET") else {
        return Ok(());
    };
    if spec.contains('/') || spec.ends_with(".toml") {
        let path = std::path::absolute(spec.as_str()).map_err(|e| format!("--preset {spec}: {e}"))?;
        *spec = path.to_string_lossy().into_owned();
    }
    Ok(())
}

fn list_presets() -> Result<(), String> {
    let env = |k: &str| std::env::var(k).ok();
    if let Some(dir) = preset::user_dir(&env) {
        println!(
            "your presets: {} (win over bundled ones of the same name)",
            dir.display()
        );
    }
    println!("bundled presets (chosen by program name, or with --preset NAME):");
    for name in preset::bundled_names() {
        if let Ok(Some(c)) = preset::load_spec(name, &|_| None) {
            let set: Vec<String> = c.preset.values.iter().map(|(k, v)| format!("{k}={v}")).collect();
            println!("  {name:<14} for {:<40} {}", c.preset.matches.join(", "), set.join(" "));
        }
    }
    Ok(())
}

fn shell_quote(s: &str) -> String {
    if !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c)) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}
