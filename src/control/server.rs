//! The layer's end of `holoinject ctl`: one listener thread, one request per connection
//! (a line), one reply (lines; an error is one line starting `error:`). Connections are
//! handled one at a time with short timeouts, so a client that stalls delays other clients
//! by two seconds at most and the app not at all.

use super::{commands, paths};
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::io::AsRawFd;
use std::os::unix::net::{UnixListener, UnixStream};
use std::time::Duration;

/// Longest request line read; longer ones are refused.
const MAX_REQUEST: u64 = 4096;
const IO_TIMEOUT: Duration = Duration::from_secs(2);

/// Binds this process's socket and serves it until the process ends.
pub fn run() {
    let listener = match bind() {
        Ok(l) => l,
        Err(e) => {
            crate::log::warn(format_args!("holoinject ctl: no control socket: {e}"));
            return;
        }
    };
    for conn in listener.incoming() {
        match conn {
            Ok(stream) => {
                if std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| serve(stream))).is_err() {
                    crate::log::error(format_args!("holoinject ctl: internal failure on one request"));
                }
            }
            Err(e) => {
                crate::log::debug(format_args!("holoinject ctl: accept: {e}"));
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

fn bind() -> Result<UnixListener, String> {
    let env = |k: &str| std::env::var(k).ok();
    let (dir, why) = paths::socket_dir(&env);
    paths::ensure_private_dir(&dir)?;
    let path = paths::socket_path(&dir, std::process::id());
    // A socket of our pid is left by an earlier process that had it.
    let _ = std::fs::remove_file(&path);
    let listener = UnixListener::bind(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600))
        .map_err(|e| format!("{}: chmod 600: {e}", path.display()))?;
    crate::log::info(format_args!("holoinject ctl: listening on {} ({why})", path.display()));
    remember_for_exit(&path);
    Ok(listener)
}

static SOCKET: std::sync::OnceLock<std::ffi::CString> = std::sync::OnceLock::new();

/// The socket is removed when the process exits normally (`atexit`) or by `--exit-after`
/// ([`remove_socket`]); after a crash it stays until `holoinject ctl` sees its process gone.
fn remember_for_exit(path: &std::path::Path) {
    let Ok(c) = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()) else {
        return;
    };
    if SOCKET.set(c).is_ok() {
        extern "C" fn at_exit() {
            remove_socket();
        }
        // SAFETY: registers a function of this library that only unlinks a path; the
        // library is never unloaded (LD_PRELOAD).
        unsafe { libc::atexit(at_exit) };
    }
}

/// Unlinks this process's socket, if it made one.
pub fn remove_socket() {
    if let Some(path) = SOCKET.get() {
        // SAFETY: unlinking a NUL-terminated path we own.
        unsafe { libc::unlink(path.as_ptr()) };
    }
}

fn serve(mut stream: UnixStream) {
    let _ = stream.set_read_timeout(Some(IO_TIMEOUT));
    let _ = stream.set_write_timeout(Some(IO_TIMEOUT));
    // Read before answering, also to refuse: closing on unread data resets the connection
    // and the peer would see that instead of the reason.
    let request = read_request(&stream);
    let reply = match peer_uid(&stream) {
        Ok(uid) if uid == paths::uid() => request.and_then(|r| commands::run(&r)),
        Ok(uid) => {
            crate::log::warn(format_args!(
                "holoinject ctl: refused a connection from uid {uid} (this process belongs to uid {})",
                paths::uid()
            ));
            Err(format!("refused: uid {uid} is not this process's owner"))
        }
        Err(e) => Err(format!("refused: cannot tell who is asking ({e})")),
    };
    let text = match reply {
        Ok(lines) => lines,
        Err(e) => format!("error: {}\n", crate::config::one_line(&e)),
    };
    let _ = stream.write_all(text.as_bytes());
    // What is left of an overlong request is read (a bounded amount) before closing, for
    // the same reason as above.
    let _ = stream.shutdown(std::net::Shutdown::Write);
    let _ = std::io::copy(&mut (&stream).take(1 << 16), &mut std::io::sink());
}

fn read_request(stream: &UnixStream) -> Result<String, String> {
    let mut line = String::new();
    let mut reader = BufReader::new(stream.take(MAX_REQUEST + 1));
    reader
        .read_line(&mut line)
        .map_err(|e| format!("reading the request: {e}"))?;
    if line.len() as u64 > MAX_REQUEST {
        return Err(format!("request longer than {MAX_REQUEST} bytes"));
    }
    Ok(line.trim().to_string())
}

/// The uid of the process at the other end (`SO_PEERCRED`).
pub fn peer_uid(stream: &UnixStream) -> Result<u32, String> {
    let mut cred = libc::ucred { pid: 0, uid: 0, gid: 0 };
    let mut len = std::mem::size_of::<libc::ucred>() as libc::socklen_t;
    // SAFETY: SO_PEERCRED fills a `ucred` of the size given, on a socket we own.
    let r = unsafe {
        libc::getsockopt(
            stream.as_raw_fd(),
            libc::SOL_SOCKET,
            libc::SO_PEERCRED,
            (&mut cred as *mut libc::ucred).cast(),
            &mut len,
        )
    };
    if r != 0 {
        return Err(std::io::Error::last_os_error().to_string());
    }
    Ok(cred.uid)
}
