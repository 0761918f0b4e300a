//! Per-application presets: a TOML file of option values (the launcher's long names without
//! `--`), chosen by the program's executable name or by `--preset NAME|PATH`.
//!
//! ```toml
//! # presets/glxgears.toml
//! match = ["glxgears"]        # executables it applies to (its file name is always one)
//! convergence = 40            # any option of `holoinject run --help`, same value syntax
//! view-cone = 35
//! ```
//!
//! Layering (DESIGN §2): defaults → device → preset → environment (`HOLOINJECT_*`) → CLI (the
//! launcher sets the environment). A preset's own bad fields are reported one line each,
//! naming the file and field, and skipped; a file that is not TOML is reported and skipped
//! whole. The program keeps running either way.

use super::options::{self, OptDef};
use super::preset_files::{self, candidates};
use std::path::Path;

pub use super::preset_files::{bundled_names, bundled_text, user_dir};

/// Options a preset may not set: choosing a preset, and launcher-only flags.
const NOT_IN_PRESETS: &[&str] = &["preset", "log", "dry-run"];

#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// Where it came from, as shown in messages: `presets/glxgears.toml` or the user's path.
    pub source: String,
    /// Executable names it applies to.
    pub matches: Vec<String>,
    /// `(option long name, value)` in file order, every value already checked.
    pub values: Vec<(String, String)>,
}

impl Preset {
    pub fn get(&self, long: &str) -> Option<&str> {
        self.values.iter().find(|(k, _)| k == long).map(|(_, v)| v.as_str())
    }
}

/// Parses a preset file. `Err` is one line for a file that cannot be used at all; `Ok` comes
/// with one line per field that was skipped.
pub fn parse(text: &str, source: &str) -> Result<(Preset, Vec<String>), String> {
    let table = preset_files::table(text, source)?;
    let mut preset = Preset {
        source: source.to_string(),
        matches: vec![],
        values: vec![],
    };
    let mut skipped = vec![];
    for (key, value) in &table {
        if key == "match" {
            match value
                .as_array()
                .map(|a| a.iter().map(|v| v.as_str().map(str::to_string)).collect())
            {
                Some(Some(names)) => preset.matches = names,
                _ => skipped.push(format!(
                    "{source}: field \"match\": expected a list of executable names, e.g. [\"glxgears\"]; ignored"
                )),
            }
            continue;
        }
        match field(key, value) {
            Ok(v) => preset.values.push((key.clone(), v)),
            Err(e) => skipped.push(super::one_line(&format!("{source}: field \"{key}\": {e}; ignored"))),
        }
    }
    Ok((preset, skipped))
}

fn field(key: &str, value: &toml::Value) -> Result<String, String> {
    let opt: &OptDef = options::find(key)
        .filter(|o| !NOT_IN_PRESETS.contains(&o.long))
        .ok_or_else(|| format!("unknown option (expected one of: {})", preset_keys().join(", ")))?;
    let text = match value {
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => f.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        _ => return Err("expected a string or a number".into()),
    };
    (opt.check)(&text)?;
    Ok(text)
}

/// Option names a preset may set (and `match`).
pub fn preset_keys() -> Vec<&'static str> {
    std::iter::once("match")
        .chain(
            options::OPTIONS
                .iter()
                .filter(|o| !o.launcher_only && !NOT_IN_PRESETS.contains(&o.long))
                .map(|o| o.long),
        )
        .collect()
}

/// What was chosen, for messages.
#[derive(Debug, PartialEq)]
pub struct Chosen {
    pub preset: Preset,
    /// Skipped fields (one line each).
    pub skipped: Vec<String>,
    /// Why this one: `--preset`, or the executable name that matched.
    pub reason: String,
}

/// `--preset NAME|PATH` (`none` turns automatic selection off), found by
/// `preset_files::find_spec`.
pub fn load_spec(spec: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<Option<Chosen>, String> {
    let spec = spec.trim();
    let Some((source, text)) = preset_files::find_spec(spec, env)? else {
        return Ok(None);
    };
    let (preset, skipped) = parse(&text, &source)?;
    Ok(Some(Chosen {
        preset,
        skipped,
        reason: format!("--preset {spec}"),
    }))
}

/// The preset for a program run as one of `exe_names`: a preset named like the executable,
/// else one whose `match` lists it; the user's before bundled ones. A matching file that is
/// not valid TOML is an `Err` (reported; no preset applies).
pub fn for_program(exe_names: &[String], env: &dyn Fn(&str) -> Option<String>) -> Result<Option<Chosen>, String> {
    let names: Vec<&str> = exe_names.iter().map(|n| n.as_str()).filter(|n| !n.is_empty()).collect();
    let all = candidates(env);
    let by_name = all.iter().find(|(stem, _, _)| names.contains(&stem.as_str()));
    let found = match by_name {
        Some(c) => Some((c, parse(&c.2, &c.1)?, c.0.clone())),
        None => all.iter().find_map(|c| match parse(&c.2, &c.1) {
            Ok(parsed) => {
                let hit = parsed.0.matches.iter().find(|m| names.contains(&m.as_str()))?.clone();
                Some((c, parsed, hit))
            }
            Err(_) => None,
        }),
    };
    Ok(found.map(|(_, (preset, skipped), exe)| Chosen {
        preset,
        skipped,
        reason: format!("program name {exe}"),
    }))
}

/// The names this process may be known by: its executable's and `argv[0]`'s file names.
pub fn process_names() -> Vec<String> {
    let mut names = vec![];
    if let Ok(exe) = std::fs::read_link("/proc/self/exe") {
        names.extend(exe.file_name().and_then(|n| n.to_str()).map(str::to_string));
    }
    if let Ok(cmdline) = std::fs::read("/proc/self/cmdline") {
        let argv0 = cmdline.split(|&b| b == 0).next().unwrap_or_default();
        let base = Path::new(std::str::from_utf8(argv0).unwrap_or_default())
            .file_name()
            .and_then(|n| n.to_str())
            .map(str::to_string);
        names.extend(base.filter(|b| !names.contains(b)));
    }
    names
}

/// The preset for this process: `HOLOINJECT_PRESET`, else by executable name. Problems are
/// reported through `report` (one line each), and what could not be used is left out.
pub fn for_process(env: &dyn Fn(&str) -> Option<String>, report: &mut dyn FnMut(String)) -> Option<Chosen> {
    let chosen = match env("HOLOINJECT_PRESET") {
        Some(spec) => load_spec(&spec, env).map_err(|e| format!("HOLOINJECT_PRESET={spec}: {e}")),
        None => for_program(&process_names(), env),
    };
    match chosen {
        Ok(c) => {
            if let Some(c) = &c {
                c.skipped.iter().for_each(|s| report(s.clone()));
            }
            c
        }
        Err(e) => {
            report(e);
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::preset_files::BUNDLED;
    use super::*;

    fn no_env(_: &str) -> Option<String> {
        None
    }

    #[test]
    fn every_bundled_preset_parses_cleanly_and_matches_its_name() {
        for (name, text) in BUNDLED {
            let (p, skipped) = parse(text, name).unwrap();
            assert!(skipped.is_empty(), "{name}: {skipped:?}");
            assert!(!p.values.is_empty(), "{name} sets nothing");
            let chosen = for_program(&[name.to_string()], &no_env).unwrap().unwrap();
            assert_eq!(chosen.preset.source, format!("presets/{name}.toml"));
        }
    }

    /// `presets/example.toml` documents every key a preset may set, and what it sets parses.
    #[test]
    fn the_example_preset_covers_every_key() {
        let text = include_str!("../../presets/example.toml");
        let (p, skipped) = parse(text, "presets/example.toml").unwrap();
        assert!(skipped.is_empty(), "{skipped:?}");
        assert!(p.matches.is_empty(), "the example must not apply by itself");
        for key in preset_keys() {
            let documented = text.lines().any(|l| {
                let l = l.trim_start_matches(['#', ' ']);
                l.starts_with(&format!("{key} ="))
            });
            assert!(documented, "presets/example.toml does not mention `{key}`");
        }
    }

    #[test]
    fn match_lists_select_by_other_executable_names() {
        let c = for_program(&["glmark2-es2".into()], &no_env).unwrap().unwrap();
        assert_eq!(c.preset.source, "presets/glmark2.toml");
        assert_eq!(c.reason, "program name glmark2-es2");
        assert_eq!(for_program(&["bash".into()], &no_env).unwrap(), None);
    }

    #[test]
    fn bad_fields_are_named_and_skipped() {
        let text = "quilt = \"0x0\"\ndepthines = 0.1\nview-cone = 200\ntile = \"100000x10\"\nfocus = 0.01\nmatch = 3\nlog = \"debug\"\ndevice = [1]\n";
        let (p, skipped) = parse(text, "my.toml").unwrap();
        assert_eq!(p.values, vec![("focus".to_string(), "0.01".to_string())]);
        assert_eq!(skipped.len(), 7, "{skipped:#?}");
        for (field, what) in [
            ("quilt", "1..=16384"),
            ("depthines", "unknown option"),
            ("view-cone", "(0, 180)"),
            ("tile", "1..=16384"),
            ("match", "list of executable names"),
            ("log", "unknown option"),
            ("device", "string or a number"),
        ] {
            let line = skipped
                .iter()
                .find(|s| s.contains(&format!("field \"{field}\"")))
                .unwrap();
            assert!(
                line.starts_with("my.toml: ") && line.contains(what) && !line.contains('\n'),
                "{line}"
            );
        }
    }

    /// What `cargo fuzz` (app_preset) found: values with newlines made multi-line messages.
    #[test]
    fn fuzz_regressions_give_one_line_messages() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzz/regressions/app_preset");
        let files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        assert!(!files.is_empty());
        for f in files {
            let text = String::from_utf8_lossy(&std::fs::read(&f).unwrap()).into_owned();
            match parse(&text, "p.toml") {
                Ok((_, skipped)) => assert!(
                    skipped.iter().all(|l| !l.contains('\n')),
                    "{}: {skipped:?}",
                    f.display()
                ),
                Err(e) => assert!(!e.contains('\n'), "{}: {e}", f.display()),
            }
        }
        let (_, skipped) = parse("quilt = \"\"\"3\nby3\"\"\"\n", "p.toml").unwrap();
        assert_eq!(skipped.len(), 1);
        assert!(!skipped[0].contains('\n'), "{}", skipped[0]);
    }

    #[test]
    fn malformed_toml_is_one_line_with_the_file_and_line() {
        let e = parse("quilt = \"5x9\"\ndepthiness = = 3\n", "presets/x.toml").unwrap_err();
        assert!(
            e.starts_with("presets/x.toml (line 2): not valid TOML") && !e.contains('\n'),
            "{e}"
        );
    }

    #[test]
    fn user_presets_win_and_explicit_specs_resolve() {
        let dir = std::env::temp_dir().join(format!("holoinject-preset-test-{}", std::process::id()));
        let presets = dir.join("holoinject/presets");
        std::fs::create_dir_all(&presets).unwrap();
        std::fs::write(presets.join("glxgears.toml"), "quilt = \"3x3\"\n").unwrap();
        std::fs::write(presets.join("broken.toml"), "quilt = [\n").unwrap();
        let d = dir.display().to_string();
        let env = move |k: &str| (k == "XDG_CONFIG_HOME").then(|| d.clone());
        let c = for_program(&["glxgears".into()], &env).unwrap().unwrap();
        assert_eq!(c.preset.get("quilt"), Some("3x3"));
        assert!(c.preset.source.ends_with("holoinject/presets/glxgears.toml"));
        assert!(load_spec("broken", &env).unwrap_err().contains("not valid TOML"));
        assert!(load_spec("nope", &env).unwrap_err().contains("unknown preset \"nope\""));
        assert_eq!(load_spec("none", &env).unwrap(), None);
        let path = presets.join("glxgears.toml").display().to_string();
        assert_eq!(
            load_spec(&path, &env).unwrap().unwrap().preset.get("quilt"),
            Some("3x3")
        );
        assert!(
            load_spec("/nonexistent/p.toml", &env)
                .unwrap_err()
                .starts_with("preset /nonexistent/p.toml: ")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
