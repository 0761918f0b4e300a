//! Live controls from outside the app: `holoinject ctl` over a per-process Unix socket
//! ([`server`]) and hotkeys grabbed on the layer's own X connection ([`hotkeys`]).
//!
//! Both run on threads of their own, started at the first frame boundary, and only queue
//! requests in `config::live`; the render thread applies them at a frame boundary. Neither
//! thread can block the app (they share nothing with it but the live store's short-held
//! lock) nor take it down: each request is handled under `catch_unwind`, and a thread that
//! fails ends with one log line while the app goes on.
//!
//! Who may control a process: the socket lives in a directory only its owner can enter
//! (`paths`: `$XDG_RUNTIME_DIR/holoinject`, mode 0700, checked), is itself mode 0600, and
//! every connection's peer uid (`SO_PEERCRED`) must be the process's own: root, who
//! passes the file permissions, is refused too when it is not the owner.

pub mod client;
pub mod commands;
pub mod hotkeys;
pub mod paths;
pub mod server;

use std::sync::atomic::{AtomicBool, Ordering};

static STARTED: AtomicBool = AtomicBool::new(false);

/// Starts the control socket's listener and the hotkey thread, once per process.
pub fn start_once() {
    if STARTED.swap(true, Ordering::AcqRel) {
        return;
    }
    let settings = crate::config::settings();
    spawn("holoinject-ctl", server::run);
    if let Some(mods) = settings.hotkeys.clone() {
        spawn("holoinject-keys", move || hotkeys::run(&mods));
    }
}

fn spawn(name: &str, f: impl FnOnce() + Send + 'static) {
    let run = move || {
        if std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).is_err() {
            crate::log::error(format_args!("live controls: internal failure; this control is off"));
        }
    };
    if let Err(e) = std::thread::Builder::new().name(name.into()).spawn(run) {
        crate::log::warn(format_args!("live controls: cannot start {name}: {e}"));
    }
}
