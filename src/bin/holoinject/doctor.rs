//! `holoinject doctor [--device NAME|PATH] [-- PROGRAM [ARGS…]]`: is this machine ready?
//! One line per check on stdout, `ok`, `warn` or `fail`, the finding, and after `fix:` what
//! to do. Exit status 0 unless a check failed, i.e. only when a real run would work.
//!
//! The GL checks run this executable's hidden `__probe` mode as a child per back-end (GLX,
//! EGL, OSMesa): a context made the way programs make it, whatever is installed, and a driver
//! crash costs one line, not the report. The preload check renders a small scene twice with
//! `__probe osmesa --draw`: once plainly, once under the layer as a 3x1 quilt; the quilt's
//! centre view must be the plain image (the centre camera is the program's own) and its side
//! views must differ from it (the parallax is there).

use super::checks::{self, Status};
use std::ffi::OsString;
use std::path::{Path, PathBuf};

pub const USAGE: &str = "usage: holoinject doctor [--device NAME|PATH] [--monitor NAME|WxH+X+Y] [-- PROGRAM [ARGS…]]";

#[derive(Default)]
struct Report {
    failed: usize,
}

impl Report {
    fn line(&mut self, status: Status, check: &str, finding: &str, fix: Option<&str>) {
        self.failed += usize::from(status == Status::Fail);
        let fix = fix.map(|f| format!("; fix: {f}")).unwrap_or_default();
        println!("{:<5} {check}: {finding}{fix}", status.word());
    }
}

struct Args {
    device: Option<String>,
    /// As `run --monitor`: the monitor to check instead of the one found by its EDID name.
    monitor: Option<String>,
    program: Option<OsString>,
}

fn parse_args(args: &[OsString]) -> Result<Args, String> {
    let mut a = Args {
        device: None,
        monitor: None,
        program: None,
    };
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        match arg.to_str() {
            Some("--device") => {
                a.device = Some(
                    it.next()
                        .and_then(|v| v.to_str())
                        .ok_or("--device needs a value")?
                        .into(),
                )
            }
            Some(s) if s.starts_with("--device=") => a.device = Some(s["--device=".len()..].into()),
            Some("--monitor") => {
                a.monitor = Some(
                    it.next()
                        .and_then(|v| v.to_str())
                        .ok_or("--monitor needs a value")?
                        .into(),
                )
            }
            Some("--") => {
                a.program = it.next().cloned();
                break;
            }
            Some(s) if !s.starts_with('-') => {
                a.program = Some(arg.clone());
                break;
            }
            _ => return Err(format!("unknown argument {}; {USAGE}", arg.to_string_lossy())),
        }
    }
    Ok(a)
}

pub fn run(args: &[OsString]) -> Result<(), String> {
    let a = parse_args(args)?;
    let mut r = Report::default();
    let lib = check_layer(&mut r);
    for backend in ["glx", "egl", "osmesa"] {
        check_backend(&mut r, backend);
    }
    check_monitor(&mut r, a.device.as_deref(), a.monitor.as_deref());
    check_calibration(&mut r, a.device.as_deref());
    if let Some(p) = &a.program {
        check_program(&mut r, p);
    }
    match &lib {
        Some(lib) => check_preload(&mut r, lib),
        None => r.line(Status::Fail, "preload", "not tried: no layer library", None),
    }
    check_encoder(&mut r);
    if r.failed > 0 {
        return Err(format!(
            "{} check(s) failed: a run would not work as it should",
            r.failed
        ));
    }
    Ok(())
}

fn check_layer(r: &mut Report) -> Option<PathBuf> {
    match crate::layer_library() {
        Ok(p) => {
            r.line(Status::Ok, "layer", &format!("{} loads", p.display()), None);
            Some(p)
        }
        Err(e) => {
            let fix = "build it (`cargo build --release`) or point HOLOINJECT_LIB at libholoinject.so";
            r.line(Status::Fail, "layer", &e, Some(fix));
            None
        }
    }
}

fn check_backend(r: &mut Report, backend: &str) {
    if backend == "glx" && std::env::var_os("DISPLAY").is_none() {
        let fix = "run doctor inside your X session (GLX programs need one)";
        return r.line(Status::Warn, "glx", "no X display ($DISPLAY unset)", Some(fix));
    }
    let out = match checks::run_probe(&[backend]) {
        Ok(out) => out,
        Err(e) => {
            let (status, fix) = checks::probe_failure(backend, &e);
            return r.line(status, backend, &e, Some(fix));
        }
    };
    let info = checks::GlReport::parse(&out);
    for (status, finding, fix) in info.findings() {
        r.line(status, backend, &finding, fix);
    }
}

/// Whether a Looking Glass is connected, where, and whether it matches `--device`.
fn check_monitor(r: &mut Report, device: Option<&str>, chosen: Option<&str>) {
    use holoinject::output::monitor;
    let fix = "plug the Looking Glass in (HDMI or DisplayPort, and its USB-C power) and turn it on, or name it with --monitor NAME|WxH+X+Y";
    if std::env::var_os("DISPLAY").is_none() {
        return r.line(
            Status::Warn,
            "display",
            "no X display ($DISPLAY unset): cannot look for a Looking Glass",
            Some(fix),
        );
    }
    let monitors = match monitor::detect() {
        Ok(m) => m,
        Err(e) => {
            return r.line(
                Status::Warn,
                "display",
                &format!("cannot list monitors: {e}"),
                Some(fix),
            );
        }
    };
    let picked =
        match chosen.map(|c| holoinject::config::parse::monitor(c).and_then(|s| monitor::select(&s, &monitors))) {
            Some(Ok(m)) => Some(m),
            Some(Err(e)) => {
                return r.line(
                    Status::Fail,
                    "display",
                    &e,
                    Some("`xrandr --listmonitors` names the monitors"),
                );
            }
            None => monitor::find_looking_glass(&monitors).cloned(),
        };
    let Some(lkg) = picked.as_ref() else {
        let seen: Vec<String> = monitors.iter().map(|m| m.describe()).collect();
        let finding = format!("no Looking Glass connected (monitors: {})", seen.join(", "));
        return r.line(Status::Warn, "display", &finding, Some(fix));
    };
    let model = lkg
        .device_preset()
        .map(|p| format!(", model {}", p.name))
        .unwrap_or_default();
    let by = if chosen.is_some() { " (by --monitor)" } else { "" };
    let finding = format!("Looking Glass at {}{model}{by}", lkg.describe());
    let size = (lkg.geometry.w, lkg.geometry.h);
    let panel = device
        .and_then(|d| holoinject::config::device::load(d).ok())
        .map(|d| (d.calibration.screen_w, d.calibration.screen_h));
    match panel {
        Some(p) if p != size => {
            let mismatch = format!("{finding}, but --device is a {}x{} panel", p.0, p.1);
            r.line(
                Status::Warn,
                "display",
                &mismatch,
                Some("set the monitor to the panel's native mode, or give this unit's visual.json as --device"),
            )
        }
        _ => r.line(Status::Ok, "display", &finding, None),
    }
}

fn check_calibration(r: &mut Report, device: Option<&str>) {
    let found = checks::visual_json_candidates();
    match device {
        Some(d) => match holoinject::config::device::load(d) {
            Ok(dev) => {
                let c = &dev.calibration;
                let from = if d.contains('/') || d.ends_with(".json") { "file" } else { "preset in presets/devices/" };
                let finding = format!(
                    "--device {d}: {} ({from}), {}x{} panel, default quilt {}x{}",
                    dev.name, c.screen_w, c.screen_h, dev.quilt.columns, dev.quilt.rows
                );
                r.line(Status::Ok, "calibration", &finding, None);
            }
            Err(e) => r.line(Status::Fail, "calibration", &format!("--device {d}: {e}"), Some("give a preset name from presets/devices/ or the path of your unit's visual.json")),
        },
        None => match found.first() {
            Some(p) => r.line(
                Status::Warn,
                "calibration",
                &format!("no --device; your unit's calibration is at {}", p.display()),
                Some(&format!("run with --device {} for --output native", p.display())),
            ),
            None => r.line(
                Status::Warn,
                "calibration",
                "no --device and no visual.json found (Bridge's Locations folder, the unit's USB drive): quilt output only",
                Some("plug the Looking Glass in (its drive holds LKG_calibration/visual.json) or use --device with a preset name, e.g. --device portrait"),
            ),
        },
    }
}

fn check_program(r: &mut Report, program: &OsString) {
    let path = match crate::find_program(program) {
        Ok(p) => p,
        Err(e) => return r.line(Status::Fail, "program", &e, Some("give its path, or install it")),
    };
    let env = |k: &str| std::env::var(k).ok();
    let names: Vec<String> = [path.as_os_str(), program.as_os_str()]
        .iter()
        .filter_map(|p| Path::new(p).file_name().and_then(|n| n.to_str()).map(str::to_string))
        .collect();
    let finding = match holoinject::config::preset::for_program(&names, &env) {
        Ok(Some(c)) => format!("{}: preset {} (by {})", path.display(), c.preset.source, c.reason),
        Ok(None) => format!("{}: no preset matches; the defaults apply", path.display()),
        Err(e) => return r.line(Status::Fail, "preset", &e, Some("fix the preset file named")),
    };
    r.line(Status::Ok, "program", &finding, None);
}

fn check_preload(r: &mut Report, lib: &Path) {
    match checks::preload_quilt(lib) {
        Ok(finding) => r.line(Status::Ok, "preload", &finding, None),
        Err((status, e)) => r.line(
            status,
            "preload",
            &e,
            Some("run `holoinject run --log debug --quilt 3x1 -- PROGRAM` and report the log"),
        ),
    }
}

fn check_encoder(r: &mut Report) {
    match holoinject::output::encoder::find_ffmpeg() {
        Ok(p) => r.line(
            Status::Ok,
            "record",
            &format!("--record encodes with {}", p.display()),
            None,
        ),
        Err(e) => r.line(
            Status::Warn,
            "record",
            &format!("--record: {e}"),
            Some("apt install ffmpeg"),
        ),
    }
}
