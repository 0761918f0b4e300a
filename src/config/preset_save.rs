//! `holoinject ctl save-preset`: live values written into the program's preset file, so
//! the next run starts where the user left off.
//!
//! Which file: `--preset PATH` when a file was given; else the user's preset that applied;
//! else a new user preset (`~/.config/holoinject/presets/NAME.toml`) named after the
//! bundled preset that applied (starting from its text, so its values carry over: a user
//! preset replaces a bundled one of the same name) or after the program. The file is edited
//! in place (`toml_edit`: comments and other keys stay), written atomically, and read back
//! with the preset loader: what it cannot read is an error, not a surprise next run.

use super::preset;
use std::path::{Path, PathBuf};

/// Writes `values` (option name, value in option syntax) into this process's preset file.
pub fn save(values: &[(&str, String)], env: &dyn Fn(&str) -> Option<String>) -> Result<PathBuf, String> {
    let chosen = preset::for_process(env, &mut |_| {});
    let (path, base) = target(chosen.as_ref(), env, &preset::process_names())?;
    write(&path, &base, values)?;
    Ok(path)
}

/// The file to write and the text to start from.
pub fn target(
    chosen: Option<&preset::Chosen>,
    env: &dyn Fn(&str) -> Option<String>,
    names: &[String],
) -> Result<(PathBuf, String), String> {
    if let Some(c) = chosen {
        let source = Path::new(&c.preset.source);
        if source.is_absolute() {
            let text = std::fs::read_to_string(source).unwrap_or_default();
            return Ok((source.to_path_buf(), text));
        }
    }
    let dir = preset::user_dir(env).ok_or("no preset folder: neither XDG_CONFIG_HOME nor HOME is set")?;
    let bundled = chosen.and_then(|c| {
        let stem = Path::new(&c.preset.source).file_stem()?.to_str()?;
        Some((stem.to_string(), preset::bundled_text(stem)?))
    });
    match bundled {
        Some((name, text)) => Ok((dir.join(format!("{name}.toml")), text.to_string())),
        None => {
            let name = names.first().ok_or("cannot tell this program's name")?;
            Ok((dir.join(format!("{name}.toml")), String::new()))
        }
    }
}

/// `values` set into `base` (TOML) and written to `path`, then read back as a preset.
pub fn write(path: &Path, base: &str, values: &[(&str, String)]) -> Result<(), String> {
    let shown = path.display();
    let mut doc: toml_edit::DocumentMut = base
        .parse()
        .map_err(|e| super::one_line(&format!("{shown}: not valid TOML ({e}); not overwritten")))?;
    for (key, value) in values {
        doc[*key] = toml_edit::value(toml_value(value));
    }
    let text = doc.to_string();
    let (read, skipped) = preset::parse(&text, &shown.to_string())?;
    if let Some(s) = skipped.first() {
        return Err(format!("{s} (not written)"));
    }
    if let Some((k, _)) = values.iter().find(|(k, v)| !same(read.get(k), v)) {
        return Err(format!("{shown}: {k} would not read back; not written"));
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let tmp = path.with_extension("toml.tmp");
    std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{shown}: {e}"))
}

/// The same value, numbers compared as numbers (`1e-5` reads back as `0.00001`).
fn same(read: Option<&str>, v: &str) -> bool {
    match (read.map(str::parse::<f64>), v.parse::<f64>()) {
        (Some(Ok(a)), Ok(b)) => a == b,
        _ => read == Some(v),
    }
}

/// Numbers as TOML numbers (as a user would write them), everything else as strings.
fn toml_value(v: &str) -> toml_edit::Value {
    match v.parse::<f64>() {
        Ok(f) if f.is_finite() && v.parse::<i64>().is_err() => toml_edit::Value::from(f),
        Ok(_) if v.parse::<i64>().is_ok() => toml_edit::Value::from(v.parse::<i64>().unwrap_or(0)),
        _ => toml_edit::Value::from(v),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("holoinject-save-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    /// What save-preset writes, the preset loader reads back, comments and other keys kept.
    #[test]
    fn saved_values_read_back_through_the_loader() {
        let dir = temp("roundtrip");
        let d = dir.display().to_string();
        let env = move |k: &str| (k == "XDG_CONFIG_HOME").then(|| d.clone());
        let (path, base) = target(None, &env, &["cubes".into()]).unwrap();
        assert_eq!(path, dir.join("holoinject/presets/cubes.toml"));
        write(
            &path,
            &base,
            &[("depthiness", "0.25".into()), ("convergence", "auto".into())],
        )
        .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, format!("# mine\nquilt = \"5x9\"\n{text}")).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        write(&path, &text, &[("depthiness", "0.3".into()), ("focus", "-2".into())]).unwrap();
        let c = preset::for_program(&["cubes".into()], &env).unwrap().unwrap();
        assert_eq!(c.skipped, Vec::<String>::new());
        let mut got: Vec<(&str, &str)> = c.preset.values.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        got.sort();
        let want = [
            ("convergence", "auto"),
            ("depthiness", "0.3"),
            ("focus", "-2"),
            ("quilt", "5x9"),
        ];
        assert_eq!(got, want);
        assert!(std::fs::read_to_string(&path).unwrap().starts_with("# mine\n"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_bundled_preset_is_copied_into_a_user_preset_of_its_name() {
        let dir = temp("bundled");
        let d = dir.display().to_string();
        let env = move |k: &str| (k == "XDG_CONFIG_HOME").then(|| d.clone());
        let chosen = preset::for_program(&["glmark2-es2".into()], &env).unwrap();
        let (path, base) = target(chosen.as_ref(), &env, &["glmark2-es2".into()]).unwrap();
        assert_eq!(path, dir.join("holoinject/presets/glmark2.toml"));
        write(&path, &base, &[("focus", "0.01".into())]).unwrap();
        let c = preset::for_program(&["glmark2-es2".into()], &env).unwrap().unwrap();
        assert!(
            c.preset.source.starts_with(&dir.display().to_string()),
            "{}",
            c.preset.source
        );
        assert_eq!(c.preset.get("focus"), Some("0.01"));
        assert!(c.preset.values.len() > 1, "the bundled values carry over");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_that_is_not_toml_is_left_alone() {
        let dir = temp("broken");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.toml");
        std::fs::write(&path, "quilt = [\n").unwrap();
        let e = write(&path, "quilt = [\n", &[("focus", "0.1".into())]).unwrap_err();
        assert!(e.contains("not valid TOML") && !e.contains('\n'), "{e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "quilt = [\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
