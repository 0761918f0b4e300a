//! The device presets embedded from `presets/devices/*.toml`: a model's nominal calibration,
//! its default quilt and its comfortable depth range. Embedded so the layer needs no files at
//! run time; they hold factory templates, which is why a unit's own `visual.json` is still
//! what makes a sharp image.

use super::Calibration;
use super::fields::{Fields, one_line};
use serde::Deserialize;
use serde_json::{Map, Value};

/// A device's nominal calibration and its default quilt.
#[derive(Clone, Debug, PartialEq)]
pub struct DevicePreset {
    pub name: &'static str,
    pub model: String,
    pub serial_prefix: String,
    pub calibration: Calibration,
    pub quilt: QuiltDefaults,
    /// `comfort_range`: the display's comfortable range (`config::comfort` says how it is
    /// derived; a unit test holds the files to that derivation).
    pub comfort: Option<crate::config::comfort::DepthRemap>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuiltDefaults {
    pub columns: u32,
    pub rows: u32,
    pub tile_width: u32,
    pub tile_height: u32,
    /// View width / height.
    pub aspect: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PresetFile {
    model: String,
    serial_prefix: String,
    quilt_columns: u32,
    quilt_rows: u32,
    tile_width: u32,
    tile_height: u32,
    aspect: f64,
    #[serde(default)]
    comfort_range: Option<String>,
    calibration: Map<String, Value>,
}

macro_rules! presets {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_str!(concat!("../../../presets/devices/", $name, ".toml")))),*]
    };
}

/// Embedded so the layer needs no files at run time.
const PRESETS: &[(&str, &str)] = presets![
    "portrait",
    "go",
    "16-gen3-landscape",
    "16-gen3-portrait",
    "32-gen3-landscape",
    "32-gen3-portrait",
    "65-gen2",
    "16-gen2",
    "32-gen2",
    "15.6-gen1",
    "8.9-gen1",
    "32-gen1-8k",
];

pub fn preset_names() -> Vec<&'static str> {
    PRESETS.iter().map(|(name, _)| *name).collect()
}

impl DevicePreset {
    pub fn get(name: &str) -> Result<DevicePreset, String> {
        let Some((name, text)) = PRESETS.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)) else {
            let known = preset_names().join(", ");
            return Err(format!(
                "unknown device \"{name}\" (known: {known}; or a visual.json path)"
            ));
        };
        DevicePreset::parse(name, text)
    }

    pub(super) fn parse(name: &'static str, text: &str) -> Result<DevicePreset, String> {
        let source = format!("presets/devices/{name}.toml");
        let file: PresetFile = toml::from_str(text).map_err(|e| one_line(format!("{source}: {e}")))?;
        let fields = Fields {
            obj: &file.calibration,
            source: &source,
            strict: true,
            prefix: "",
        };
        let comfort = match file.comfort_range.as_deref().map(crate::config::comfort::depth_remap) {
            Some(Ok(r)) => r,
            Some(Err(e)) => return Err(format!("{source}: comfort_range {e}")),
            None => None,
        };
        Ok(DevicePreset {
            name,
            comfort,
            model: file.model,
            serial_prefix: file.serial_prefix,
            calibration: fields.calibration()?,
            quilt: QuiltDefaults {
                columns: file.quilt_columns,
                rows: file.quilt_rows,
                tile_width: file.tile_width,
                tile_height: file.tile_height,
                aspect: file.aspect,
            },
        })
    }
}
