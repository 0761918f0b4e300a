//! Which monitor is the Looking Glass, and where it sits on the X screen.
//!
//! The weave is only right when each of its pixels lands on the panel's own pixel, so the
//! layer must know the panel's rectangle in root-window coordinates. XRandR 1.5 lists the
//! monitors with their geometry and outputs; each output's `EDID` property carries the
//! monitor name the panel reports (the 0xFC display descriptor, at most 13 characters).
//!
//! **How a Looking Glass is recognised.** Looking Glass software names units by a hardware id
//! starting `LKG`: HoloPlay Service's `info` answer shows `"hwid": "LKG030nffpp24"`
//! (docs.lookingglassfactory.com, HoloPlay Core JS, "HoloPlay Service Related"), and the serial
//! prefixes of the models (`LKG-2K`, `LKG-4K`, `LKG-8K`, `LKG-P`, `LKG-A`…`LKG-L`, from
//! LKG-Toolkit's device templates) are kept in `presets/devices/*.toml`. So a monitor whose
//! EDID name starts with `LKG` is a Looking Glass, and the preset whose serial prefix it starts
//! with (longest first) names the model. These names have not been checked against a real
//! unit here: `--monitor NAME|WxH+X+Y` picks the monitor by hand when detection misses.
//!
//! This file is pure (parsing and choosing); its child `xrandr` asks the X server and
//! builds [`Monitor`]s from the answer.

pub mod xrandr;

use crate::config::calibration::{DevicePreset, preset_names};
use crate::config::parse::MonitorSpec;

/// A rectangle of the X screen, in root-window pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: i32,
    pub y: i32,
    pub w: u32,
    pub h: u32,
}

impl std::fmt::Display for Rect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}{:+}{:+}", self.w, self.h, self.x, self.y)
    }
}

/// One XRandR monitor.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Monitor {
    /// The RandR monitor name (usually the output's, e.g. `HDMI-1`).
    pub name: String,
    /// The outputs it shows, by name.
    pub outputs: Vec<String>,
    /// The panel's own name from its EDID (descriptor 0xFC), when it reports one.
    pub edid_name: Option<String>,
    pub geometry: Rect,
    pub primary: bool,
}

impl Monitor {
    /// Whether the panel reports a Looking Glass name.
    pub fn is_looking_glass(&self) -> bool {
        self.edid_name.as_deref().is_some_and(is_looking_glass_name)
    }

    /// The device preset of this unit's model, when its name says which.
    pub fn device_preset(&self) -> Option<DevicePreset> {
        model_preset(self.edid_name.as_deref()?)
    }

    /// One line for logs and `holoinject doctor`: `HDMI-1 "LKG-P" 1536x2048+1920+0`.
    pub fn describe(&self) -> String {
        let edid = self
            .edid_name
            .as_deref()
            .map(|n| format!(" \"{n}\""))
            .unwrap_or_default();
        format!("{}{edid} {}", self.name, self.geometry)
    }
}

pub fn is_looking_glass_name(name: &str) -> bool {
    name.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("LKG"))
}

/// The device preset whose serial prefix `name` starts with (the longest such prefix).
pub fn model_preset(name: &str) -> Option<DevicePreset> {
    preset_names()
        .into_iter()
        .filter_map(|n| DevicePreset::get(n).ok())
        .filter(|p| !p.serial_prefix.is_empty() && name.starts_with(&p.serial_prefix))
        .max_by_key(|p| p.serial_prefix.len())
}

/// The monitor name in an EDID base block: the 0xFC display descriptor's text, up to its
/// line feed, trailing padding removed. `None` for a block too short, with a bad header or
/// checksum, or without a name.
pub fn edid_monitor_name(edid: &[u8]) -> Option<String> {
    const HEADER: [u8; 8] = [0, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0];
    let block = edid.get(..128)?;
    if block[..8] != HEADER || block.iter().fold(0u8, |s, &b| s.wrapping_add(b)) != 0 {
        return None;
    }
    // Four 18-byte descriptors at 54; a display descriptor starts 00 00 00 TAG 00.
    block[54..126].chunks_exact(18).find_map(|d| {
        if d[..3] != [0, 0, 0] || d[3] != 0xfc {
            return None;
        }
        let text = &d[5..18];
        let end = text.iter().position(|&b| b == b'\n').unwrap_or(text.len());
        let name: String = text[..end].iter().map(|&b| b as char).collect();
        Some(name.trim_end().to_string()).filter(|n| !n.is_empty())
    })
}

/// The monitor `--monitor` names (an exact RandR, output or EDID name, case-insensitive), or a
/// rectangle given by hand (`WxH+X+Y`: it need not be a RandR monitor; Xvfb cannot make one).
pub fn select(spec: &MonitorSpec, monitors: &[Monitor]) -> Result<Monitor, String> {
    match spec {
        MonitorSpec::Geometry { w, h, x, y } => Ok(monitors
            .iter()
            .find(|m| {
                m.geometry
                    == Rect {
                        x: *x,
                        y: *y,
                        w: *w,
                        h: *h,
                    }
            })
            .cloned()
            .unwrap_or_else(|| Monitor {
                name: "--monitor".into(),
                outputs: vec![],
                edid_name: None,
                geometry: Rect {
                    x: *x,
                    y: *y,
                    w: *w,
                    h: *h,
                },
                primary: false,
            })),
        MonitorSpec::Name(name) => monitors
            .iter()
            .find(|m| names_of(m).any(|n| n.eq_ignore_ascii_case(name)))
            .cloned()
            .ok_or_else(|| {
                let known: Vec<String> = monitors.iter().map(Monitor::describe).collect();
                format!(
                    "--monitor {name}: no such monitor (connected: {})",
                    list_or_none(&known)
                )
            }),
    }
}

fn names_of(m: &Monitor) -> impl Iterator<Item = &str> {
    std::iter::once(m.name.as_str())
        .chain(m.outputs.iter().map(String::as_str))
        .chain(m.edid_name.as_deref())
}

fn list_or_none(items: &[String]) -> String {
    if items.is_empty() {
        "none".into()
    } else {
        items.join(", ")
    }
}

/// The first monitor that reports a Looking Glass name.
pub fn find_looking_glass(monitors: &[Monitor]) -> Option<&Monitor> {
    monitors.iter().find(|m| m.is_looking_glass())
}

/// The monitors of the X server `$DISPLAY` names (XRandR 1.5).
pub fn detect() -> Result<Vec<Monitor>, String> {
    xrandr::monitors()
}

#[cfg(test)]
mod tests;
