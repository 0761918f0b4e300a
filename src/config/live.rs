//! Live settings: the values a user tunes while looking at the display.
//!
//! `holoinject ctl` and the hotkeys run on threads of their own; the app's render thread
//! must never see a value change in the middle of a frame (half the views with the old
//! depthiness). So those threads only *queue* requests here ([`request`]); the frame
//! boundary drains the queue on the render thread ([`apply_pending`]), turns each request
//! into a new value in option syntax, checks it with the option's own check, logs it at
//! `info` and bumps a generation counter; each context's layer then re-applies every live
//! value to its own `ViewSettings` with the same setter the environment goes through
//! (`ViewSettings::set`). Values are kept as option text, so what `get` shows, what
//! `save-preset` writes and what a preset reads back are one syntax.
//!
//! A key is one entry of [`LIVE_KEYS`]: the option it drives and what a hotkey does to it.
//! The comfort effects are keys like the others (`live("dof", Kind::Switch("on"))`).

use super::options;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// What a hotkey does to a key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// Multiplied (or divided) by this factor per step; `auto` is a valid value when the
    /// option accepts it (convergence).
    Scale(f64),
    /// A step of this fraction of the current depthiness (focus, in the same NDC units).
    StepOfDepthiness(f64),
    /// Cycles through these values.
    Cycle(&'static [&'static str]),
    /// Toggles between `off` and the last other value (this one at first).
    Switch(&'static str),
}

pub struct LiveKey {
    pub name: &'static str,
    pub kind: Kind,
}

const fn live(name: &'static str, kind: Kind) -> LiveKey {
    LiveKey { name, kind }
}

/// Every live key; each name is an option of `options::OPTIONS`.
pub static LIVE_KEYS: &[LiveKey] = &[
    live("depthiness", Kind::Scale(1.25)),
    live("convergence", Kind::Scale(1.1)),
    live("focus", Kind::StepOfDepthiness(0.1)),
    live("output", Kind::Cycle(&["quilt", "native", "sbs", "anaglyph", "mono"])),
    // The comfort effects. A remap switched on without one given uses 20 px of comfortable
    // disparity each side and asymptotes at 60 (outermost view, tile pixels).
    live("depth-remap", Kind::Switch("20,20,60,60")),
    live("dof", Kind::Switch("on")),
    live("edge-fade", Kind::Switch("32")),
];

pub fn key(name: &str) -> Option<&'static LiveKey> {
    LIVE_KEYS.iter().find(|k| k.name == name)
}

pub fn key_names() -> Vec<&'static str> {
    LIVE_KEYS.iter().map(|k| k.name).collect()
}

/// What a thread asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    Set(&'static str, String),
    /// +1 or -1 steps of the key's `Kind`.
    Step(&'static str, i32),
    /// `Switch` on/off, or the next `Cycle` value.
    Next(&'static str),
    /// Dump the next frame into this directory (`None`: the `--dump` directory).
    Dump(Option<PathBuf>),
}

/// A dump asked for and not yet done, or done in frame `frame`.
#[derive(Clone, Debug, Default)]
pub struct DumpState {
    pub wanted: Option<PathBuf>,
    pub asked: u64,
    pub done: u64,
    pub result: Option<Result<u64, String>>,
}

#[derive(Default)]
pub struct Store {
    pending: Vec<(Action, &'static str)>,
    /// Each live key's value in option syntax; `None`: the option's default.
    pub values: BTreeMap<&'static str, Option<String>>,
    /// The numbers in force, published by the render thread (depthiness and convergence,
    /// also when they are defaults or auto).
    pub observed: BTreeMap<&'static str, f64>,
    /// The same for values that are not numbers (the output).
    pub observed_text: BTreeMap<&'static str, String>,
    /// The last `on` value of each `Switch` key.
    switched: BTreeMap<&'static str, String>,
    pub generation: u64,
    pub frame: u64,
    pub dump: DumpState,
    /// When a value last changed and which (the overlay shows it).
    pub changed: Option<(Instant, &'static str)>,
    started: bool,
}

static STORE: Mutex<Store> = Mutex::new(Store {
    pending: Vec::new(),
    values: BTreeMap::new(),
    observed: BTreeMap::new(),
    observed_text: BTreeMap::new(),
    switched: BTreeMap::new(),
    generation: 0,
    frame: 0,
    dump: DumpState {
        wanted: None,
        asked: 0,
        done: 0,
        result: None,
    },
    changed: None,
    started: false,
});
static APPLIED: Condvar = Condvar::new();

/// The store, seeded the first time with the values the process started with.
pub fn store() -> MutexGuard<'static, Store> {
    let mut s = STORE.lock().unwrap_or_else(|e| e.into_inner());
    if !s.started {
        s.started = true;
        let env = |k: &str| std::env::var(k).ok();
        let preset = super::preset::for_process(&env, &mut |_| {});
        for k in LIVE_KEYS {
            let var = options::find(k.name).map(|o| o.env_name()).unwrap_or_default();
            let v = env(&var).or_else(|| preset.as_ref().and_then(|c| c.preset.get(k.name)).map(str::to_string));
            let v = v.filter(|v| check(k.name, v).is_ok());
            s.values.insert(k.name, v);
        }
    }
    s
}

/// The option's own check of `value` for live key `name`, and whether this process can
/// take it now.
pub fn check(name: &str, value: &str) -> Result<(), String> {
    let opt = options::find(name).ok_or_else(|| format!("{name}: not an option of this build"))?;
    (opt.check)(value)?;
    if name == "output" && !possible(value.trim()) {
        return Err("native output needs a display: run with --device".into());
    }
    if name == "output" && !super::settings().multiview() {
        return Err("the program started with --output mono (multiview off): restart without it".into());
    }
    Ok(())
}

/// Queues `action` (from `origin`: "ctl" or "hotkey"); it takes effect at the next frame
/// boundary. Returns the generation that frame will have.
pub fn request(action: Action, origin: &'static str) -> u64 {
    let mut s = store();
    if let Action::Dump(dir) = &action {
        s.dump.wanted = Some(dir.clone().unwrap_or_default());
        s.dump.asked += 1;
        s.dump.result = None;
    }
    s.pending.push((action, origin));
    s.generation + 1
}

/// Waits up to `timeout` for `until` to hold, re-checked at each frame boundary.
pub fn wait(timeout: Duration, until: impl Fn(&Store) -> bool) -> bool {
    let deadline = Instant::now() + timeout;
    let mut s = store();
    while !until(&s) {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return false;
        }
        s = APPLIED.wait_timeout(s, left).unwrap_or_else(|e| e.into_inner()).0;
    }
    true
}

/// At the frame boundary (render thread): applies queued requests. Returns the generation
/// of the values now in force and, when a dump was asked for, its directory.
pub fn apply_pending(frame: u64) -> (u64, Option<PathBuf>) {
    let mut s = store();
    s.frame = frame;
    let pending = std::mem::take(&mut s.pending);
    let mut changed = false;
    for (action, origin) in pending {
        changed |= s.apply(action, origin);
    }
    if changed {
        s.generation += 1;
    }
    let dump = s.dump.wanted.take();
    let generation = s.generation;
    drop(s);
    APPLIED.notify_all();
    (generation, dump)
}

/// Records the outcome of an asked-for dump and wakes whoever waits for it.
pub fn dump_done(frame: u64, result: Result<(), String>) {
    let mut s = store();
    s.dump.done = s.dump.asked;
    s.dump.result = Some(result.map(|()| frame));
    drop(s);
    APPLIED.notify_all();
}

/// Publishes the values in force (render thread, after the rig is updated), numbers and
/// others (the output), under one lock.
pub fn observe(numbers: &[(&'static str, f64)], texts: &[(&'static str, &str)]) {
    let mut s = store();
    for &(name, v) in numbers {
        s.observed.insert(name, v);
    }
    for &(name, v) in texts {
        if s.observed_text.get(name).is_none_or(|t| t != v) {
            s.observed_text.insert(name, v.to_string());
        }
    }
}

impl Store {
    fn apply(&mut self, action: Action, origin: &str) -> bool {
        let name = match &action {
            Action::Set(n, _) | Action::Step(n, _) | Action::Next(n) => *n,
            Action::Dump(_) => return false,
        };
        let Some(k) = key(name) else {
            crate::log::info(format_args!(
                "live ({origin}): {name}: not a live setting in this build"
            ));
            return false;
        };
        let old = self.shown(name);
        let new = match self.next_value(k, &action) {
            Ok(v) => v,
            Err(e) => {
                crate::log::info(format_args!("live ({origin}): {name}: {e}; unchanged"));
                return false;
            }
        };
        if let Err(e) = check(name, &new) {
            crate::log::info(format_args!("live ({origin}): {name} {new}: {e}; unchanged"));
            return false;
        }
        if matches!(k.kind, Kind::Switch(_)) && new != "off" {
            self.switched.insert(name, new.clone());
        }
        self.values.insert(name, Some(new.clone()));
        self.changed = Some((Instant::now(), name));
        crate::log::info(format_args!("live ({origin}): {name} {old} -> {new}"));
        true
    }

    /// The new value `action` gives key `k`.
    fn next_value(&self, k: &LiveKey, action: &Action) -> Result<String, String> {
        let current = self.values.get(k.name).cloned().flatten();
        match (action, k.kind) {
            (Action::Set(_, v), _) => Ok(v.trim().to_string()),
            (Action::Step(_, dir), Kind::Scale(f)) => {
                let now = self.number(k.name).ok_or("no value in force yet")?;
                Ok(format_number(now * f.powi(*dir)))
            }
            (Action::Step(_, dir), Kind::StepOfDepthiness(f)) => {
                let now = self.number(k.name).unwrap_or(0.0);
                let step = f * self.number("depthiness").ok_or("no depthiness in force yet")?.abs();
                Ok(format_number(now + step * f64::from(*dir)))
            }
            (Action::Next(_), Kind::Cycle(values)) => Ok(cycle(values, current.as_deref())),
            (Action::Next(_), Kind::Switch(on)) => Ok(match current.as_deref() {
                Some(v) if v != "off" => "off".to_string(),
                _ => self.switched.get(k.name).cloned().unwrap_or_else(|| on.to_string()),
            }),
            _ => Err("not something this key does".into()),
        }
    }

    /// The number in force: published by the render thread, else the value set.
    pub fn number(&self, name: &str) -> Option<f64> {
        let set = self.values.get(name).cloned().flatten().and_then(|v| v.parse().ok());
        set.or_else(|| self.observed.get(name).copied())
    }

    /// The value as `get` shows it: the text set, with the number in force when it differs
    /// (a default, or auto).
    pub fn shown(&self, name: &str) -> String {
        let set = self.values.get(name).cloned().flatten();
        let seen =
            (self.observed.get(name).map(|v| format_number(*v))).or_else(|| self.observed_text.get(name).cloned());
        match (set, seen) {
            (Some(v), Some(n)) if v.parse::<f64>().is_err() && v != n => format!("{v} ({n})"),
            (Some(v), _) => v,
            (None, Some(n)) => format!("{n} (default)"),
            (None, None) => "default".into(),
        }
    }
}

/// What `--overlay` shows, while the last change is younger than `within`: one line per
/// live key, the changed one marked `>`.
pub fn overlay_lines(within: Duration, frame: u64) -> Option<Vec<String>> {
    let s = store();
    let (at, changed) = s.changed?;
    if at.elapsed() > within {
        return None;
    }
    let width = LIVE_KEYS.iter().map(|k| k.name.len()).max().unwrap_or(0);
    let mut lines = vec![format!("  holoinject {frame}")];
    lines.extend(LIVE_KEYS.iter().map(|k| {
        let mark = if k.name == changed { '>' } else { ' ' };
        format!("{mark} {:width$}  {}", k.name, s.shown(k.name))
    }));
    Some(lines)
}

/// The value after `current` in `values` (options that are not possible here, such as
/// `native` without a device, are skipped by the caller's check failing: see `cycle_from`).
fn cycle(values: &[&str], current: Option<&str>) -> String {
    let mut at = current.and_then(|c| values.iter().position(|v| *v == c));
    for _ in 0..values.len() {
        let next = at.map_or(0, |i| (i + 1) % values.len());
        if possible(values[next]) {
            return values[next].to_string();
        }
        at = Some(next);
    }
    values[0].to_string()
}

/// `native` needs a display's calibration; `mono` is the centre view.
fn possible(value: &str) -> bool {
    value != "native" || super::settings().view.device.is_some()
}

/// Short and exact enough to read back: 4 significant digits.
pub fn format_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return "0".into();
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
#[path = "tests_live.rs"]
mod tests;
