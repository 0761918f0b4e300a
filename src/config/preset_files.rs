//! Where a preset's text comes from: the bundled presets, the user's folder, or a path given
//! with `--preset`, and whether that text is TOML at all.
//!
//! Kept apart from `preset` because checking the `--preset` option (`options::OPTIONS`) needs
//! exactly this and no more: a preset's own fields are checked against the option table,
//! which would make the table and the preset reader each need the other. A bad field is
//! reported and skipped when the preset is applied; only a preset that cannot be found or
//! read as TOML makes the option's value wrong.

use std::path::{Path, PathBuf};

macro_rules! bundled {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_str!(concat!("../../presets/", $name, ".toml")))),*]
    };
}

/// Embedded so the layer needs no files at run time; tested programs only.
pub(super) const BUNDLED: &[(&str, &str)] = bundled!["glxgears", "es2gears", "glmark2", "chromium-bsu"];

pub fn bundled_text(name: &str) -> Option<&'static str> {
    BUNDLED.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

pub fn bundled_names() -> Vec<&'static str> {
    BUNDLED.iter().map(|(n, _)| *n).collect()
}

/// A preset file's TOML table. `Err` is one line naming the file (and line) for text that
/// is not TOML, so the whole preset is skipped.
pub fn table(text: &str, source: &str) -> Result<toml::Table, String> {
    text.parse().map_err(|e: toml::de::Error| {
        let msg = e.message().trim().replace('\n', "; ");
        let at = e
            .span()
            .map(|s| line_of(text, s.start))
            .map_or(String::new(), |l| format!(" (line {l})"));
        super::one_line(&format!("{source}{at}: not valid TOML: {msg}; preset ignored"))
    })
}

fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The user's preset folder: `$XDG_CONFIG_HOME/holoinject/presets`, else
/// `~/.config/holoinject/presets`. Its files win over bundled ones of the same name.
pub fn user_dir(env: &dyn Fn(&str) -> Option<String>) -> Option<PathBuf> {
    let base = env("XDG_CONFIG_HOME")
        .filter(|d| d.starts_with('/'))
        .map(PathBuf::from)
        .or_else(|| {
            env("HOME")
                .filter(|h| h.starts_with('/'))
                .map(|h| Path::new(&h).join(".config"))
        })?;
    Some(base.join("holoinject/presets"))
}

/// Every preset that could apply, as `(name, source, text)`: the user's first, then bundled.
pub(super) fn candidates(env: &dyn Fn(&str) -> Option<String>) -> Vec<(String, String, String)> {
    let mut out = vec![];
    if let Some(dir) = user_dir(env) {
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        files.sort();
        for path in files.into_iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
            if let (Some(stem), Ok(text)) = (
                path.file_stem().and_then(|s| s.to_str()),
                std::fs::read_to_string(&path),
            ) {
                out.push((stem.to_string(), path.display().to_string(), text));
            }
        }
    }
    for (name, text) in BUNDLED {
        out.push((name.to_string(), format!("presets/{name}.toml"), text.to_string()));
    }
    out
}

/// The text `--preset NAME|PATH` names, as `(source, text)`; `None` for `none`. `spec` is
/// already trimmed. A path when it contains '/' or ends in `.toml`, else a user or bundled
/// preset of that name.
pub fn find_spec(spec: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<Option<(String, String)>, String> {
    if spec == "none" {
        return Ok(None);
    }
    if spec.contains('/') || spec.ends_with(".toml") {
        let text = std::fs::read_to_string(spec).map_err(|e| format!("preset {spec}: {e}"))?;
        return Ok(Some((spec.to_string(), text)));
    }
    let all = candidates(env);
    let Some((_, source, text)) = all.iter().find(|(name, _, _)| name == spec) else {
        let mut known: Vec<&str> = all.iter().map(|(n, _, _)| n.as_str()).collect();
        known.dedup();
        return Err(format!(
            "unknown preset \"{spec}\" (known: {}; or a path to a .toml file)",
            known.join(", ")
        ));
    };
    Ok(Some((source.clone(), text.clone())))
}

/// The `--preset` option's check: the preset can be found and is TOML (what `preset::load_spec`
/// refuses; its bad fields are only skipped).
pub fn check_spec(spec: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<(), String> {
    match find_spec(spec.trim(), env)? {
        Some((source, text)) => table(&text, &source).map(|_| ()),
        None => Ok(()),
    }
}
