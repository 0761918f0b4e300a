//! `holoinject run [OPTIONS] [--] PROGRAM [ARGS…]` parsed into what to `exec`. Options come
//! from `options::OPTIONS`; each `--foo-bar V` becomes `HOLOINJECT_FOO_BAR=V`.

use super::options::{self, OptDef};
use std::ffi::{OsStr, OsString};

#[derive(Debug, PartialEq, Eq)]
pub struct Launch {
    /// `HOLOINJECT_*` variables to set, in option order.
    pub env: Vec<(String, String)>,
    pub program: OsString,
    pub args: Vec<OsString>,
    pub dry_run: bool,
}

impl Launch {
    pub fn get(&self, long: &str) -> Option<&str> {
        let name = options::find(long)?.env_name();
        self.env.iter().rev().find(|(k, _)| *k == name).map(|(_, v)| v.as_str())
    }
}

fn value_for(opt: &OptDef, inline: Option<&str>, rest: &mut std::slice::Iter<OsString>) -> Result<String, String> {
    let value = match inline {
        Some(v) => v.to_string(),
        None => rest
            .next()
            .and_then(|v| v.to_str())
            .map(str::to_string)
            .ok_or_else(|| format!("--{} needs a value ({})", opt.long, opt.value))?,
    };
    (opt.check)(&value).map_err(|e| super::one_line(&format!("--{} {value}: {e}", opt.long)))?;
    Ok(value)
}

/// Parses the arguments after `run`.
pub fn parse_run(args: &[OsString]) -> Result<Launch, String> {
    let mut launch = Launch {
        env: vec![],
        program: OsString::new(),
        args: vec![],
        dry_run: false,
    };
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let Some(text) = arg.to_str().filter(|t| t.starts_with("--")) else {
            launch.program = arg.clone();
            break;
        };
        if text == "--" {
            launch.program = it.next().cloned().unwrap_or_default();
            break;
        }
        let (name, inline) = match text[2..].split_once('=') {
            Some((n, v)) => (n, Some(v)),
            None => (&text[2..], None),
        };
        let opt =
            options::find(name).ok_or_else(|| format!("unknown option --{name} (see `holoinject run --help`)"))?;
        if opt.value.is_empty() {
            if inline.is_some() {
                return Err(format!("--{name} takes no value"));
            }
            launch.dry_run |= name == "dry-run";
            if !opt.launcher_only {
                launch.env.push((opt.env_name(), "1".into()));
            }
            continue;
        }
        let value = value_for(opt, inline, &mut it)?;
        launch.env.push((opt.env_name(), value));
    }
    if launch.program.is_empty() {
        return Err("no program given: holoinject run [OPTIONS] -- PROGRAM [ARGS…]".into());
    }
    launch.args = it.cloned().collect();
    Ok(launch)
}

/// Options that only make sense together, checked on their effective values (command line,
/// else `env`, else the preset), so the program is not started with one silently ignored.
pub fn check_combinations(
    launch: &Launch,
    env: &dyn Fn(&str) -> Option<String>,
    preset: Option<&super::preset::Preset>,
) -> Result<(), String> {
    let value = |long: &str| {
        let var = options::find(long).map(|o| o.env_name()).unwrap_or_default();
        launch
            .get(long)
            .map(str::to_string)
            .or_else(|| env(&var))
            .or_else(|| preset.and_then(|p| p.get(long)).map(str::to_string))
    };
    let reuse = value("reuse").is_some_and(|v| super::parse::switch(&v).unwrap_or(false));
    let mode = value("mode").and_then(|m| super::parse::mode(&m).ok());
    super::parse::reuse_with(reuse, mode.unwrap_or(super::Mode::Exact))
}

/// `LD_PRELOAD` with `lib` appended once, keeping what is there (entries split on ':' or ' ').
pub fn ld_preload_with(existing: Option<&OsStr>, lib: &str) -> String {
    let existing = existing.and_then(OsStr::to_str).unwrap_or("").trim();
    if existing.split([':', ' ']).any(|e| e == lib) {
        return existing.to_string();
    }
    if existing.is_empty() {
        lib.to_string()
    } else {
        format!("{existing}:{lib}")
    }
}

pub fn help() -> String {
    let mut s = String::from(
        "holoinject: show any OpenGL program in 3D on a light-field display\n\n\
         usage: holoinject run [OPTIONS] [--] PROGRAM [ARGS…]\n       holoinject presets\n       \
         holoinject doctor [--device NAME|PATH] [-- PROGRAM]   check this machine, one line per check\n       \
         holoinject quilt FILE.png|FILE.mp4 --device NAME|PATH --out OUT.png [--quilt CxR] [--frame N]\n       \
         holoinject ctl [--pid P] set KEY VALUE | get [KEY] | dump [DIR] | save-preset | list\n       \
         holoinject --version\n\n\
         Each option --foo-bar sets HOLOINJECT_FOO_BAR for the layer (libholoinject.so, found\n\
         beside this binary or at $HOLOINJECT_LIB), which is appended to LD_PRELOAD.\n\noptions:\n",
    );
    for o in options::OPTIONS {
        let head = if o.value.is_empty() {
            format!("--{}", o.long)
        } else {
            format!("--{} {}", o.long, o.value)
        };
        s.push_str(&format!("  {head:<42} {}\n", o.help));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<OsString> {
        a.iter().map(OsString::from).collect()
    }

    #[test]
    fn maps_options_to_variables_and_keeps_program_args() {
        let l = parse_run(&args(&[
            "--dump",
            "/tmp/x",
            "--exit-after=3",
            "--",
            "glxgears",
            "-info",
        ]))
        .unwrap();
        assert_eq!(
            l.env,
            vec![
                ("HOLOINJECT_DUMP".into(), "/tmp/x".into()),
                ("HOLOINJECT_EXIT_AFTER".into(), "3".into())
            ]
        );
        assert_eq!(l.program, "glxgears");
        assert_eq!(l.args, args(&["-info"]));
        assert_eq!(l.get("exit-after"), Some("3"));
    }

    #[test]
    fn program_options_after_the_program_are_not_ours() {
        let l = parse_run(&args(&["--dry-run", "prog", "--dump", "x"])).unwrap();
        assert!(l.dry_run && l.env.is_empty());
        assert_eq!(l.args, args(&["--dump", "x"]));
    }

    #[test]
    fn errors_name_the_problem() {
        let e = parse_run(&args(&["--frobnicate", "x", "prog"])).unwrap_err();
        assert!(e.contains("--frobnicate"), "{e}");
        let e = parse_run(&args(&["--quilt", "8by6", "prog"])).unwrap_err();
        assert!(e.contains("--quilt 8by6") && e.contains("CxR"), "{e}");
        let e = parse_run(&args(&["--dump", "d"])).unwrap_err();
        assert!(e.contains("no program"), "{e}");
        let e = parse_run(&args(&["--exit-after"])).unwrap_err();
        assert!(e.contains("needs a value"), "{e}");
        let e = parse_run(&args(&["--mode", "warp", "prog"])).unwrap_err();
        assert!(e.contains("--mode warp") && e.contains("expected"), "{e}");
    }

    #[test]
    fn reuse_is_a_switch_that_needs_a_fast_mode() {
        let none = |_: &str| None;
        let l = parse_run(&args(&["--reuse", "--mode", "hybrid:3", "prog"])).unwrap();
        assert_eq!(l.get("reuse"), Some("1"));
        assert!(check_combinations(&l, &none, None).is_ok());
        let l = parse_run(&args(&["--reuse", "prog"])).unwrap();
        let e = check_combinations(&l, &none, None).unwrap_err();
        assert!(e.contains("--reuse needs --mode synth or hybrid:K"), "{e}");
        let synth = |k: &str| (k == "HOLOINJECT_MODE").then(|| "synth".to_string());
        assert!(check_combinations(&l, &synth, None).is_ok());
        assert!(
            parse_run(&args(&["--reuse=1", "prog"]))
                .unwrap_err()
                .contains("takes no value")
        );
    }

    #[test]
    fn ld_preload_appends_once() {
        assert_eq!(ld_preload_with(None, "/l/h.so"), "/l/h.so");
        assert_eq!(ld_preload_with(Some(OsStr::new("a.so")), "/l/h.so"), "a.so:/l/h.so");
        assert_eq!(
            ld_preload_with(Some(OsStr::new("a.so /l/h.so")), "/l/h.so"),
            "a.so /l/h.so"
        );
    }

    #[test]
    fn help_lists_every_option() {
        let h = help();
        for o in options::OPTIONS {
            assert!(h.contains(&format!("--{}", o.long)), "--{} missing from help", o.long);
        }
    }
}
