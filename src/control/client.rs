//! `holoinject ctl`'s end: find the running programs' sockets, send one request, return the
//! reply. Sockets of processes that are gone are removed on the way.

use super::paths;
use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::path::PathBuf;

pub struct Running {
    pub pid: u32,
    pub socket: PathBuf,
    /// `/proc/PID/comm`.
    pub name: String,
}

/// Every process of this user with a control socket, by pid.
pub fn running(env: &dyn Fn(&str) -> Option<String>) -> Result<Vec<Running>, String> {
    let (dir, why) = paths::socket_dir(env);
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(vec![]),
        Err(e) => return Err(format!("{} ({why}): {e}", dir.display())),
    };
    paths::check_private_dir(&dir)?;
    let mut found = vec![];
    for path in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        let Some(pid) = path
            .file_name()
            .and_then(|n| n.to_str()?.strip_suffix(".sock")?.parse::<u32>().ok())
        else {
            continue;
        };
        match std::fs::read_to_string(format!("/proc/{pid}/comm")) {
            Ok(name) => found.push(Running {
                pid,
                socket: path,
                name: name.trim().to_string(),
            }),
            Err(_) => {
                let _ = std::fs::remove_file(&path);
            }
        }
    }
    found.sort_by_key(|r| r.pid);
    Ok(found)
}

/// The process `pid`, or the only one running.
pub fn choose(pid: Option<u32>, env: &dyn Fn(&str) -> Option<String>) -> Result<Running, String> {
    let mut all = running(env)?;
    let (dir, why) = paths::socket_dir(env);
    if let Some(pid) = pid {
        let at = all.iter().position(|r| r.pid == pid).ok_or_else(|| {
            format!(
                "no holoinject process {pid} (no socket {}: {why})",
                paths::socket_path(&dir, pid).display()
            )
        })?;
        return Ok(all.swap_remove(at));
    }
    match all.len() {
        0 => Err(format!(
            "no holoinject process is running (no socket in {}: {why})",
            dir.display()
        )),
        1 => Ok(all.remove(0)),
        _ => {
            let list: Vec<String> = all.iter().map(|r| format!("{} ({})", r.pid, r.name)).collect();
            Err(format!(
                "{} holoinject processes: choose one with --pid: {}",
                all.len(),
                list.join(", ")
            ))
        }
    }
}

/// Sends `request` (one line) and returns the reply; a reply `error: …` is an `Err`.
pub fn send(target: &Running, request: &str) -> Result<String, String> {
    let at = || format!("process {} ({})", target.pid, target.name);
    let mut s = UnixStream::connect(&target.socket).map_err(|e| format!("{}: {e}", at()))?;
    s.write_all(format!("{request}\n").as_bytes())
        .and_then(|_| s.shutdown(std::net::Shutdown::Write))
        .map_err(|e| format!("{}: {e}", at()))?;
    let mut reply = String::new();
    s.read_to_string(&mut reply).map_err(|e| format!("{}: {e}", at()))?;
    match reply.strip_prefix("error: ") {
        Some(e) => Err(e.trim_end().to_string()),
        None if reply.is_empty() => Err(format!("{}: no reply", at())),
        None => Ok(reply),
    }
}

pub const CTL_USAGE: &str =
    "usage: holoinject ctl [--pid P] set KEY VALUE | get [KEY] | dump [DIR] | save-preset | list";

/// `holoinject ctl ARGS…`: what to print on success.
pub fn ctl(args: &[String], env: &dyn Fn(&str) -> Option<String>) -> Result<String, String> {
    let (pid, rest) = match args {
        [flag, p, rest @ ..] if flag == "--pid" => {
            let pid = p
                .parse::<u32>()
                .map_err(|_| format!("--pid {p}: expected a process id"))?;
            (Some(pid), rest)
        }
        [flag] if flag == "--pid" => return Err("--pid needs a process id".into()),
        rest => (None, rest),
    };
    let words: Vec<&str> = rest.iter().map(String::as_str).collect();
    let request = match words.as_slice() {
        ["list"] => return list(env),
        ["--help" | "-h" | "help"] | [] => return Ok(format!("{CTL_USAGE}\n")),
        ["dump", dir] => format!("dump {}", absolute(dir)?),
        [cmd @ ("set" | "get" | "dump" | "save-preset"), more @ ..] => std::iter::once(*cmd)
            .chain(more.iter().copied())
            .collect::<Vec<_>>()
            .join(" "),
        [other, ..] => return Err(format!("unknown ctl command `{other}`; {CTL_USAGE}")),
    };
    send(&choose(pid, env)?, &request)
}

fn absolute(dir: &str) -> Result<String, String> {
    let p = std::path::absolute(dir).map_err(|e| format!("dump {dir}: {e}"))?;
    if p.to_string_lossy().contains(char::is_whitespace) {
        return Err(format!("dump {}: a directory without spaces, please", p.display()));
    }
    Ok(p.to_string_lossy().into_owned())
}

fn list(env: &dyn Fn(&str) -> Option<String>) -> Result<String, String> {
    let all = running(env)?;
    if all.is_empty() {
        let (dir, why) = paths::socket_dir(env);
        return Ok(format!(
            "no holoinject process is running (no socket in {}: {why})\n",
            dir.display()
        ));
    }
    Ok(all.iter().map(|r| format!("{} {}\n", r.pid, r.name)).collect())
}
