//! The requests `holoinject ctl` sends, one line each, and their replies:
//!
//! ```text
//! set KEY VALUE    queue a value (checked as the option checks it); waits for the frame
//!                  boundary that applies it
//! get [KEY]        `KEY = VALUE` lines: the value set, or the one in force (default, auto)
//! dump [DIR]       the next frame dumped as --dump does, into DIR (default: --dump's)
//! save-preset      the live values written into this program's preset file
//! ```

use crate::config::live::{self, Action};
use std::path::PathBuf;
use std::time::Duration;

/// How long a reply waits for the app's next frame boundary.
const FRAME_WAIT: Duration = Duration::from_secs(3);

const USAGE: &str = "expected: set KEY VALUE | get [KEY] | dump [DIR] | save-preset";

/// Runs one request line; `Ok` is the reply (lines), `Err` one line.
pub fn run(line: &str) -> Result<String, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    match words.as_slice() {
        ["set", key, value] => set(key, value),
        ["set", ..] => Err("usage: set KEY VALUE".into()),
        ["get"] => Ok(live::key_names().iter().map(|k| get_line(k)).collect()),
        ["get", key] => live_key(key).map(|k| get_line(k.name)),
        ["dump"] => dump(None),
        ["dump", dir] => dump(Some(PathBuf::from(dir))),
        ["save-preset"] => save_preset(),
        [] => Err(format!("empty request; {USAGE}")),
        [other, ..] => Err(format!("unknown command `{other}`; {USAGE}")),
    }
}

fn live_key(name: &str) -> Result<&'static live::LiveKey, String> {
    live::key(name).ok_or_else(|| {
        format!(
            "`{name}` is not a live setting (live: {})",
            live::key_names().join(", ")
        )
    })
}

fn get_line(name: &str) -> String {
    format!("{name} = {}\n", live::store().shown(name))
}

fn set(name: &str, value: &str) -> Result<String, String> {
    let k = live_key(name)?;
    live::check(k.name, value).map_err(|e| format!("{name} {value}: {e}"))?;
    let frame = live::store().frame;
    live::request(Action::Set(k.name, value.to_string()), "ctl");
    if live::wait(FRAME_WAIT, |s| s.frame > frame) {
        let s = live::store();
        Ok(format!("{name} = {} (from frame {})\n", s.shown(name), s.frame + 1))
    } else {
        Ok(format!(
            "{name} = {value} queued: the program has not ended a frame for 3 s\n"
        ))
    }
}

fn dump(dir: Option<PathBuf>) -> Result<String, String> {
    if dir.as_ref().is_some_and(|d| !d.is_absolute()) {
        return Err("dump DIR: give an absolute path (holoinject ctl sends one)".into());
    }
    if dir.is_none() && crate::config::settings().dump_dir.is_none() {
        return Err("dump: no directory: give one (holoinject ctl dump DIR) or run with --dump DIR".into());
    }
    live::request(Action::Dump(dir), "ctl");
    let asked = live::store().dump.asked;
    if !live::wait(FRAME_WAIT, |s| s.dump.done >= asked) {
        return Err("dump: the program has not ended a frame for 3 s; the dump stays queued".into());
    }
    match live::store().dump.result.clone() {
        Some(Ok(frame)) => Ok(format!("dumped frame {frame}\n")),
        Some(Err(e)) => Err(format!("dump: {e}")),
        None => Err("dump: no result".into()),
    }
}

fn save_preset() -> Result<String, String> {
    let values: Vec<(&str, String)> = {
        let s = live::store();
        s.values.iter().filter_map(|(k, v)| Some((*k, v.clone()?))).collect()
    };
    if values.is_empty() {
        return Err("save-preset: no live value set yet (defaults are not written)".into());
    }
    let env = |k: &str| std::env::var(k).ok();
    let path = crate::config::preset_save::save(&values, &env)?;
    let keys: Vec<&str> = values.iter().map(|(k, _)| *k).collect();
    crate::log::info(format_args!("live: saved {} to {}", keys.join(", "), path.display()));
    Ok(format!("saved {} to {}\n", keys.join(", "), path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_requests_are_one_line_errors() {
        for (line, needle) in [
            ("", "empty request"),
            ("frobnicate 3", "unknown command `frobnicate`"),
            ("set depthiness", "usage: set KEY VALUE"),
            ("set depthines 0.2", "not a live setting"),
            ("set depthiness lots", "expected a number"),
            ("set convergence -1", "convergence -1"),
            ("get nope", "not a live setting"),
            ("dump relative/dir", "absolute path"),
        ] {
            let e = run(line).unwrap_err();
            assert!(e.contains(needle) && !e.contains('\n'), "{line}: {e}");
        }
    }

    #[test]
    fn get_lists_every_live_key() {
        let out = run("get").unwrap();
        for k in live::key_names() {
            assert!(out.contains(&format!("{k} = ")), "{out}");
        }
    }
}
