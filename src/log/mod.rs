//! Logging to stderr at the level in `HOLOINJECT_LOG` (default `warn`); never stdout.
//!
//! The level is read with `getenv` into an atomic on first use: logging can happen inside
//! `dlsym`, before Rust's runtime helpers are safe to initialise.

pub mod costs;
pub mod counts;

use std::fmt::Arguments;
use std::io::Write;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    Off = 1,
    Error,
    Warn,
    Info,
    Debug,
    Trace,
}

impl Level {
    pub fn parse(s: &str) -> Option<Level> {
        Some(match s.trim().to_ascii_lowercase().as_str() {
            "off" | "none" | "quiet" => Level::Off,
            "error" => Level::Error,
            "warn" | "warning" => Level::Warn,
            "info" => Level::Info,
            "debug" => Level::Debug,
            "trace" => Level::Trace,
            _ => return None,
        })
    }
}

static LEVEL: AtomicU8 = AtomicU8::new(0);
static BAD_LEVEL: AtomicBool = AtomicBool::new(false);

pub fn level() -> Level {
    let l = LEVEL.load(Ordering::Relaxed);
    if l != 0 {
        // SAFETY: only valid discriminants are ever stored.
        return unsafe { core::mem::transmute::<u8, Level>(l) };
    }
    // SAFETY: getenv with a valid C string; the result is copied before returning.
    let raw = unsafe { libc::getenv(c"HOLOINJECT_LOG".as_ptr()) };
    let parsed = if raw.is_null() {
        Some(Level::Warn)
    } else {
        // SAFETY: getenv returns a NUL-terminated string, read before anything can change it.
        let s = unsafe { core::ffi::CStr::from_ptr(raw) }.to_str().unwrap_or("");
        Level::parse(s)
    };
    if parsed.is_none() {
        BAD_LEVEL.store(true, Ordering::Relaxed);
    }
    let l = parsed.unwrap_or(Level::Warn);
    LEVEL.store(l as u8, Ordering::Relaxed);
    l
}

pub fn enabled(l: Level) -> bool {
    l <= level()
}

fn emit(l: Level, args: Arguments) {
    if enabled(l) {
        let tag = format!("{l:?}").to_ascii_lowercase();
        let _ = writeln!(std::io::stderr().lock(), "holoinject: {tag}: {args}");
    }
}

/// Logs at a level chosen at run time.
pub fn at(l: Level, args: Arguments) {
    emit(l, args)
}
pub fn error(args: Arguments) {
    emit(Level::Error, args)
}
pub fn warn(args: Arguments) {
    emit(Level::Warn, args)
}
pub fn info(args: Arguments) {
    emit(Level::Info, args)
}
pub fn debug(args: Arguments) {
    emit(Level::Debug, args)
}
pub fn trace(args: Arguments) {
    emit(Level::Trace, args)
}

/// Logs at `l` the first time `flag` is seen, then never again for that flag.
pub fn once(flag: &AtomicBool, l: Level, args: Arguments) {
    if !flag.swap(true, Ordering::Relaxed) {
        emit(l, args)
    }
}

/// Logs at `l` the first time `key` is seen (e.g. a program id and what went wrong with it),
/// so that a condition met on every draw is reported once. Keys are remembered up to a cap;
/// past it, nothing more is logged through here.
pub fn once_for(key: (&'static str, u64), l: Level, args: Arguments) {
    const CAP: usize = 4096;
    type Seen = Option<std::collections::HashSet<(&'static str, u64)>>;
    static SEEN: std::sync::Mutex<Seen> = std::sync::Mutex::new(None);
    if !enabled(l) {
        return;
    }
    let mut seen = SEEN.lock().unwrap_or_else(|p| p.into_inner());
    let seen = seen.get_or_insert_with(Default::default);
    // Called per draw while the condition lasts: one hash lookup, not a scan.
    if seen.len() >= CAP || !seen.insert(key) {
        return;
    }
    emit(l, args)
}

/// How many messages of one kind `limited` lets through before it goes quiet.
pub const LIMIT_PER_KIND: u32 = 20;

/// Logs at `l` unless `LIMIT_PER_KIND` messages of this `kind` were already logged; the last
/// one allowed says that the rest will be suppressed. For conditions that can repeat per
/// object without bound (a program whose rewrite fails, in an app that links thousands).
/// Returns whether the message was written.
pub fn limited(kind: &'static str, l: Level, args: Arguments) -> bool {
    static COUNTS: std::sync::Mutex<Vec<(&'static str, u32)>> = std::sync::Mutex::new(Vec::new());
    if !enabled(l) {
        return false;
    }
    let n = {
        let mut counts = COUNTS.lock().unwrap_or_else(|p| p.into_inner());
        let i = match counts.iter().position(|(k, _)| *k == kind) {
            Some(i) => i,
            None => {
                counts.push((kind, 0));
                counts.len() - 1
            }
        };
        counts[i].1 = counts[i].1.saturating_add(1);
        counts[i].1
    };
    match n {
        n if n < LIMIT_PER_KIND => emit(l, args),
        LIMIT_PER_KIND => emit(l, format_args!("{args} (further messages of this kind suppressed)")),
        _ => return false,
    }
    true
}

static ANNOUNCED: AtomicBool = AtomicBool::new(false);

/// The layer's start-up line (info level), printed on the first GL activity. Tests look for
/// it to tell a loaded layer from a loader warning about a missing one.
pub fn announce() {
    if ANNOUNCED.swap(true, Ordering::Relaxed) {
        return;
    }
    quiet_panics();
    let exe = std::env::current_exe()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    info(format_args!(
        "holoinject {} active in pid {} ({exe})",
        env!("CARGO_PKG_VERSION"),
        std::process::id()
    ));
    if BAD_LEVEL.load(Ordering::Relaxed) {
        warn(format_args!(
            "HOLOINJECT_LOG: unknown level; using `warn` (off|error|warn|info|debug|trace)"
        ));
    }
}

/// Inside someone else's process a panic of ours (caught at the hook, which then falls back to
/// pass-through) must not print Rust's multi-line report, and backtrace, on the app's stderr:
/// it becomes one error line at the asked level. Only when this code lives in its own shared
/// object (the preloaded layer has its own copy of std, hence its own panic hook); linked into
/// a program (tests, fuzz targets) the program's hook is left alone.
fn quiet_panics() {
    // SAFETY: `Dl_info` is plain C data (pointers and integers), valid when zeroed.
    let mut ours = unsafe { std::mem::zeroed::<libc::Dl_info>() };
    // SAFETY: as above.
    let mut exe = unsafe { std::mem::zeroed::<libc::Dl_info>() };
    // SAFETY: dladdr on a function of this object and on the program's program headers
    // (AT_PHDR, inside the executable's mapping); both only fill the out structs.
    let separate = unsafe {
        let phdr = libc::getauxval(libc::AT_PHDR) as *const libc::c_void;
        libc::dladdr(quiet_panics as *const libc::c_void, &mut ours) != 0
            && libc::dladdr(phdr, &mut exe) != 0
            && exe.dli_fbase != ours.dli_fbase
    };
    if separate {
        std::panic::set_hook(Box::new(|info| {
            let at = info
                .location()
                .map(|l| format!(" at {}:{}", l.file(), l.line()))
                .unwrap_or_default();
            let what = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_default();
            error(format_args!("internal panic{at}: {}", what.replace('\n', " ")));
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limited_messages_stop_after_the_limit() {
        let written = (0..100)
            .filter(|i| limited("test-kind", Level::Error, format_args!("message {i}")))
            .count();
        assert_eq!(written, LIMIT_PER_KIND as usize);
        assert!(limited(
            "other-kind",
            Level::Error,
            format_args!("a different kind still logs")
        ));
        // Off levels are not counted.
        assert!(!limited("quiet-kind", Level::Trace, format_args!("not enabled")));
    }
}
