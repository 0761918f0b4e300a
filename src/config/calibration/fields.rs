//! Reading a calibration's fields from JSON, each either `{"value": x}` (as Bridge writes a
//! `visual.json`) or a bare `x` (as our device presets hold them). One reader serves both, so
//! a device preset and a unit's `visual.json` accept the same values with the same one-line
//! errors; only strictness differs: a misspelt key in our own presets is a bug, in a
//! `visual.json` it is a newer format.

use super::{Calibration, MAX_CELLS, SubpixelCell};
use serde_json::{Map, Value};

const CELL_KEYS: [&str; 6] = ["ROffsetX", "ROffsetY", "GOffsetX", "GOffsetY", "BOffsetX", "BOffsetY"];

/// Reads calibration fields from a JSON object, each either `{"value": x}` or a bare `x`.
pub(super) struct Fields<'a> {
    pub obj: &'a Map<String, Value>,
    pub source: &'a str,
    /// Presets are ours: a misspelt key there is a bug, in a `visual.json` it is a newer format.
    pub strict: bool,
    /// Names the enclosing array element in errors, e.g. `subpixelCells[1].`.
    pub prefix: &'a str,
}

const KNOWN_KEYS: [&str; 17] = [
    "configVersion",
    "serial",
    "pitch",
    "slope",
    "center",
    "viewCone",
    "invView",
    "verticalAngle",
    "DPI",
    "screenW",
    "screenH",
    "flipImageX",
    "flipImageY",
    "flipSubp",
    "fringe",
    "CellPatternMode",
    "subpixelCells",
];

impl Fields<'_> {
    pub fn calibration(&self) -> Result<Calibration, String> {
        let unknown = self.obj.keys().find(|k| !KNOWN_KEYS.contains(&k.as_str()));
        if self.strict
            && let Some(k) = unknown
        {
            return Err(self.err(k, "unknown field"));
        }
        let slope = self.required("slope", -1000.0..=1000.0)?;
        if slope.abs() < 1e-3 {
            return Err(self.err("slope", &format!("{slope} is too close to 0")));
        }
        Ok(Calibration {
            serial: self.text("serial"),
            pitch: self.required("pitch", 1e-3..=1000.0)?,
            slope,
            center: self.required("center", -1000.0..=1000.0)?,
            view_cone: self.optional("viewCone", 40.0, 0.0..=180.0)?,
            inv_view: self.flag("invView", true)?,
            vertical_angle: self.optional("verticalAngle", 0.0, -90.0..=90.0)?,
            dpi: self.required("DPI", 1.0..=10000.0)?,
            screen_w: self.pixels("screenW")?,
            screen_h: self.pixels("screenH")?,
            flip_image_x: self.flag("flipImageX", false)?,
            flip_image_y: self.flag("flipImageY", false)?,
            flip_subp: self.flag("flipSubp", false)?,
            fringe: self.number("fringe", -1e6..=1e6)?,
            cell_pattern_mode: self.optional("CellPatternMode", 0.0, 0.0..=4.0)? as u32,
            subpixel_cells: self.cells()?,
        })
    }

    fn err(&self, field: &str, what: &str) -> String {
        let (source, prefix) = (self.source, self.prefix);
        one_line(format!("{source}: field \"{prefix}{field}\": {what}"))
    }

    fn number(&self, key: &str, range: std::ops::RangeInclusive<f64>) -> Result<Option<f64>, String> {
        let Some(v) = self.obj.get(key) else { return Ok(None) };
        let x = scalar(v).map_err(|what| self.err(key, what))?;
        check(x, &range).map(Some).map_err(|what| self.err(key, &what))
    }

    fn required(&self, key: &str, range: std::ops::RangeInclusive<f64>) -> Result<f64, String> {
        self.number(key, range)?.ok_or_else(|| self.err(key, "missing"))
    }

    fn optional(&self, key: &str, default: f64, range: std::ops::RangeInclusive<f64>) -> Result<f64, String> {
        Ok(self.number(key, range)?.unwrap_or(default))
    }

    fn flag(&self, key: &str, default: bool) -> Result<bool, String> {
        let d = if default { 1.0 } else { 0.0 };
        Ok(self.optional(key, d, 0.0..=1.0)? >= 0.5)
    }

    fn pixels(&self, key: &str) -> Result<u32, String> {
        let x = self.required(key, 1.0..=32768.0)?;
        if x.fract() != 0.0 {
            return Err(self.err(key, &format!("{x} is not a whole number of pixels")));
        }
        Ok(x as u32)
    }

    fn text(&self, key: &str) -> Option<String> {
        match self.obj.get(key)? {
            Value::String(s) => Some(s.clone()),
            Value::Object(o) => o.get("value")?.as_str().map(str::to_owned),
            _ => None,
        }
    }

    fn cells(&self) -> Result<Vec<SubpixelCell>, String> {
        let list = match self.obj.get("subpixelCells") {
            None | Some(Value::Null) => return Ok(Vec::new()),
            Some(Value::Array(list)) => list,
            Some(_) => return Err(self.err("subpixelCells", "not an array")),
        };
        if list.len() > MAX_CELLS {
            let what = format!("{} cells, at most {MAX_CELLS} supported", list.len());
            return Err(self.err("subpixelCells", &what));
        }
        list.iter().enumerate().map(|(i, c)| self.cell(i, c)).collect()
    }

    fn cell(&self, index: usize, cell: &Value) -> Result<SubpixelCell, String> {
        let prefix = format!("subpixelCells[{index}].");
        let Value::Object(obj) = cell else {
            return Err(self.err(&format!("subpixelCells[{index}]"), "not an object"));
        };
        let inner = Fields {
            obj,
            source: self.source,
            strict: false,
            prefix: &prefix,
        };
        let mut offsets = [0.0; 6];
        for (slot, key) in offsets.iter_mut().zip(CELL_KEYS) {
            *slot = inner.required(key, -4.0..=4.0)?;
        }
        Ok(SubpixelCell { offsets })
    }
}

/// `{"value": x}` or `x`, where `x` is a number, a boolean or a numeric string.
fn scalar(v: &Value) -> Result<f64, &'static str> {
    let inner = match v {
        Value::Object(o) => o.get("value").ok_or("object without \"value\"")?,
        other => other,
    };
    match inner {
        Value::Number(n) => n.as_f64().ok_or("not a number"),
        Value::Bool(b) => Ok(if *b { 1.0 } else { 0.0 }),
        Value::String(s) => s.trim().parse().map_err(|_| "not a number"),
        _ => Err("not a number"),
    }
}

fn check(x: f64, range: &std::ops::RangeInclusive<f64>) -> Result<f64, String> {
    if !x.is_finite() {
        return Err(format!("{x} is not finite"));
    }
    if !range.contains(&x) {
        return Err(format!("{x} out of range [{}, {}]", range.start(), range.end()));
    }
    Ok(x)
}

pub(super) fn one_line(s: String) -> String {
    crate::config::one_line(&s)
}
