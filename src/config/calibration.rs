//! Display calibration: a Looking Glass `visual.json`, or one of the device presets embedded
//! from `presets/devices/*.toml`, and the weave parameters derived from it (DESIGN §4).
//!
//! Presets hold nominal factory templates; every real unit is calibrated individually, so a
//! sharp image needs that unit's own `visual.json` (`--device path/to/visual.json`).

mod device_preset;
mod fields;

use fields::{Fields, one_line};
use serde_json::Value;

pub use device_preset::{DevicePreset, QuiltDefaults, preset_names};

/// The most Gen3 sub-pixel cells the weave shader holds (its uniform array size).
pub const MAX_CELLS: usize = 16;

/// One Gen3 sub-pixel cell: where each colour's sub-pixel sits, in pixels from the pixel centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubpixelCell {
    /// `[ROffsetX, ROffsetY, GOffsetX, GOffsetY, BOffsetX, BOffsetY]`
    pub offsets: [f64; 6],
}

/// Everything a `visual.json` says about the optics of one display.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    pub serial: Option<String>,
    pub pitch: f64,
    pub slope: f64,
    pub center: f64,
    pub view_cone: f64,
    pub inv_view: bool,
    pub vertical_angle: f64,
    pub dpi: f64,
    pub screen_w: u32,
    pub screen_h: u32,
    pub flip_image_x: bool,
    /// Kept for completeness: the public HoloPlay/Bridge shaders compute a flipped `y` but never
    /// sample with it, so it does not enter the weave.
    pub flip_image_y: bool,
    pub flip_subp: bool,
    pub fringe: Option<f64>,
    pub cell_pattern_mode: u32,
    pub subpixel_cells: Vec<SubpixelCell>,
}

/// The per-pixel mapping's constants, in the units the weave uses (DESIGN §4).
#[derive(Clone, Debug, PartialEq)]
pub struct WeaveParams {
    /// pitch' = pitch * (screenW/DPI) * cos(atan(1/slope)): lenticules across the screen width.
    pub pitch: f32,
    pub tilt: f32,
    pub subp: f32,
    pub center: f32,
    pub inv_view: bool,
    pub flip_subp: bool,
    pub view_count: u32,
    /// `CellPatternMode`; only used when `cells` is not empty.
    pub cell_pattern: u32,
    /// Gen3 offsets `[Rx, Ry, Gx, Gy, Bx, By]` already divided by screenW (x) and screenH (y).
    pub cells: Vec<[f32; 6]>,
}

impl Calibration {
    /// Parses the text of a `visual.json`; `source` names it in errors.
    pub fn from_visual_json(text: &str, source: &str) -> Result<Calibration, String> {
        let value: Value =
            serde_json::from_str(text).map_err(|e| one_line(format!("{source}: not valid JSON: {e}")))?;
        let Value::Object(obj) = value else {
            return Err(format!("{source}: not a JSON object"));
        };
        Fields {
            obj: &obj,
            source,
            strict: false,
            prefix: "",
        }
        .calibration()
    }

    /// The calibration of a built-in device preset.
    pub fn preset(name: &str) -> Option<Calibration> {
        DevicePreset::get(name).ok().map(|p| p.calibration)
    }

    /// A path when it contains '/' or ends with `.json`, else a preset name.
    pub fn load(name_or_path: &str) -> Result<Calibration, String> {
        if name_or_path.contains('/') || name_or_path.ends_with(".json") {
            let text = std::fs::read_to_string(name_or_path).map_err(|e| format!("{name_or_path}: {e}"))?;
            return Calibration::from_visual_json(&text, name_or_path);
        }
        DevicePreset::get(name_or_path).map(|p| p.calibration)
    }

    pub fn weave_params(&self, view_count: u32) -> WeaveParams {
        let (w, h) = (f64::from(self.screen_w), f64::from(self.screen_h));
        let sign = if self.flip_image_x { -1.0 } else { 1.0 };
        let cells = self.subpixel_cells.iter().map(|c| {
            let o = c.offsets;
            let scale = [w, h, w, h, w, h];
            std::array::from_fn(|i| (o[i] / scale[i]) as f32)
        });
        WeaveParams {
            pitch: (self.pitch * (w / self.dpi) * (1.0 / self.slope).atan().cos()) as f32,
            tilt: (sign * h / (w * self.slope)) as f32,
            subp: (sign / (3.0 * w)) as f32,
            center: self.center as f32,
            inv_view: self.inv_view,
            flip_subp: self.flip_subp,
            view_count,
            cell_pattern: self.cell_pattern_mode,
            cells: cells.collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shape Bridge writes: every value wrapped, plus keys this layer does not use.
    const VISUAL_JSON: &str = r#"{
        "configVersion": "3.0", "serial": "LKG-P00000", "pitch": {"value": 52.0},
        "slope": {"value": -7.0}, "center": {"value": 0.5}, "viewCone": {"value": 40.0},
        "invView": {"value": 1.0}, "verticalAngle": {"value": 0.0}, "DPI": {"value": 324.0},
        "screenW": {"value": 1536.0}, "screenH": {"value": 2048.0}, "flipImageX": {"value": 0.0},
        "flipImageY": {"value": 0.0}, "flipSubp": {"value": 0.0}, "somethingNew": {"value": 3}
    }"#;

    fn err_of(json: &str) -> String {
        Calibration::from_visual_json(json, "visual.json").unwrap_err()
    }

    #[test]
    fn parses_wrapped_and_bare_values() {
        let c = Calibration::from_visual_json(VISUAL_JSON, "visual.json").unwrap();
        assert_eq!((c.pitch, c.slope, c.center, c.dpi), (52.0, -7.0, 0.5, 324.0));
        assert_eq!((c.screen_w, c.screen_h, c.inv_view), (1536, 2048, true));
        assert_eq!(c.serial.as_deref(), Some("LKG-P00000"));
        assert!(c.subpixel_cells.is_empty() && c.fringe.is_none());
        let bare = r#"{"pitch": 52, "slope": -7, "center": 0.5, "DPI": 324,
                       "screenW": 1536, "screenH": 2048, "flipSubp": true}"#;
        let b = Calibration::from_visual_json(bare, "b").unwrap();
        assert_eq!(
            (b.pitch, b.view_cone, b.inv_view, b.flip_subp),
            (52.0, 40.0, true, true)
        );
    }

    #[test]
    fn parses_gen3_cells() {
        let json = VISUAL_JSON.replace(
            r#""somethingNew""#,
            r#""CellPatternMode": {"value": 4}, "subpixelCells": [
                {"ROffsetX": -0.25, "ROffsetY": -0.31, "GOffsetX": -0.25,
                 "GOffsetY": 0.28, "BOffsetX": 0.25, "BOffsetY": 0}], "x""#,
        );
        let c = Calibration::from_visual_json(&json, "v").unwrap();
        assert_eq!(c.cell_pattern_mode, 4);
        assert_eq!(c.subpixel_cells[0].offsets, [-0.25, -0.31, -0.25, 0.28, 0.25, 0.0]);
        let p = c.weave_params(48);
        assert_eq!(p.cells[0][0], (-0.25f64 / 1536.0) as f32);
        assert_eq!(p.cells[0][3], (0.28f64 / 2048.0) as f32);
    }

    #[test]
    fn bad_inputs_give_one_line_errors_naming_source_and_field() {
        let cases = [
            (
                VISUAL_JSON.replace(r#""pitch": {"value": 52.0},"#, ""),
                r#"visual.json: field "pitch": missing"#,
            ),
            (
                VISUAL_JSON.replace("52.0}", "\"NaN\"}"),
                r#"visual.json: field "pitch": NaN is not finite"#,
            ),
            (
                VISUAL_JSON.replace("324.0", "0"),
                r#"visual.json: field "DPI": 0 out of range [1, 10000]"#,
            ),
            (
                VISUAL_JSON.replace("1536.0", "1536.5"),
                r#"visual.json: field "screenW": 1536.5 is not a whole number of pixels"#,
            ),
            (
                VISUAL_JSON.replace("-7.0", "0"),
                r#"visual.json: field "slope": 0 is too close to 0"#,
            ),
            (
                VISUAL_JSON.replace(r#"{"value": 0.5}"#, "[1]"),
                r#"visual.json: field "center": not a number"#,
            ),
            (
                VISUAL_JSON.replace(r#"{"value": 0.5}"#, "{}"),
                r#"visual.json: field "center": object without "value""#,
            ),
            (
                VISUAL_JSON.replace(r#""somethingNew""#, r#""subpixelCells": [{"ROffsetX": 0}], "x""#),
                r#"visual.json: field "subpixelCells[0].ROffsetY": missing"#,
            ),
        ];
        for (json, want) in cases {
            assert_eq!(err_of(&json), want);
        }
        let broken = err_of("{\n \"pitch\": ,\n}");
        assert!(broken.starts_with("visual.json: not valid JSON: "), "{broken}");
        assert!(!broken.contains('\n'));
        assert_eq!(err_of("[1, 2]"), "visual.json: not a JSON object");
    }

    #[test]
    fn derives_weave_params_per_design() {
        let c = Calibration::from_visual_json(VISUAL_JSON, "v").unwrap();
        let p = c.weave_params(48);
        // 52 * (1536/324) * cos(atan(-1/7)) = 246.5185 * 7/sqrt(50) = 244.0409
        assert!((p.pitch - 244.040_88).abs() < 1e-3, "{}", p.pitch);
        // 2048 / (1536 * -7) and 1 / (3 * 1536)
        assert!((p.tilt + 0.190_476_2).abs() < 1e-7);
        assert!((p.subp - 2.170_138_9e-4).abs() < 1e-10);
        assert_eq!(
            (p.center, p.view_count, p.inv_view, p.flip_subp),
            (0.5, 48, true, false)
        );
        let flipped = Calibration {
            flip_image_x: true,
            ..c
        }
        .weave_params(48);
        assert_eq!((flipped.tilt, flipped.subp, flipped.pitch), (-p.tilt, -p.subp, p.pitch));
    }

    #[test]
    fn every_preset_parses_with_sane_params() {
        assert!(preset_names().len() >= 11);
        for name in preset_names() {
            let d = DevicePreset::get(name).unwrap_or_else(|e| panic!("{e}"));
            let c = &d.calibration;
            let q = d.quilt;
            let views = q.columns * q.rows;
            let p = c.weave_params(views);
            let px_per_lens = c.screen_w as f32 / p.pitch;
            assert!((2.0..20.0).contains(&px_per_lens), "{name}: {px_per_lens} px per lens");
            assert!((0.05..0.5).contains(&p.tilt.abs()), "{name}: tilt {}", p.tilt);
            assert!((30..=100).contains(&views), "{name}: {views} views");
            assert!(
                q.columns * q.tile_width <= 8192 && q.rows * q.tile_height <= 8192,
                "{name}"
            );
            let screen_aspect = c.screen_w as f64 / c.screen_h as f64;
            assert!((q.aspect / screen_aspect - 1.0).abs() < 1e-3, "{name}: aspect");
            assert!(d.serial_prefix.starts_with("LKG-") && d.model.contains("Looking Glass"));
            assert_eq!(p.cells.is_empty(), c.cell_pattern_mode == 0, "{name}: cells vs mode");
            assert_eq!(Calibration::preset(name).as_ref(), Some(c));
        }
        let gen3 = Calibration::preset("16-gen3-landscape").unwrap().weave_params(49);
        // 44.72 * 3840/283 * cos(atan(-1/6.9)) = 600.5275; 2160 / (3840 * -6.9) = -0.0815217
        assert!((gen3.pitch - 600.527_45).abs() < 2e-3 && (gen3.tilt + 0.081_521_74).abs() < 1e-7);
        assert_eq!(gen3.cells.len(), 2);
    }

    #[test]
    fn presets_reject_unknown_fields() {
        let text = include_str!("../../presets/devices/portrait.toml");
        let typo = text.replace("pitch =", "ptich =");
        let e = DevicePreset::parse("portrait", &typo).unwrap_err();
        assert_eq!(e, r#"presets/devices/portrait.toml: field "ptich": unknown field"#);
        let extra = format!("colour = 1\n{text}");
        let e = DevicePreset::parse("portrait", &extra).unwrap_err();
        assert!(
            e.starts_with("presets/devices/portrait.toml: ") && e.contains("colour"),
            "{e}"
        );
    }

    #[test]
    fn load_takes_a_path_or_a_preset_name() {
        let dir = std::env::temp_dir().join(format!("holoinject-cal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("visual.json");
        std::fs::write(&path, VISUAL_JSON).unwrap();
        let c = Calibration::load(path.to_str().unwrap()).unwrap();
        assert_eq!(c.screen_w, 1536);
        assert_eq!(Calibration::load("Portrait").unwrap().dpi, 324.0);
        let e = Calibration::load("nope.json").unwrap_err();
        assert!(e.starts_with("nope.json: "), "{e}");
        let e = Calibration::load("hololens").unwrap_err();
        assert!(e.contains("\"hololens\"") && e.contains("portrait, go,") && !e.contains('\n'));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
