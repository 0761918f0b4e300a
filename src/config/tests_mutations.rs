//! Mutation robustness of the calibration reader and the option value parsers: a
//! real-format `visual.json` and random option values, cut and corrupted at random, must
//! give `Ok` or a one-line error — never a panic.

use super::calibration::Calibration;
use proptest::prelude::*;

const VISUAL_JSON: &str = r#"{"configVersion":"3.0","serial":"LKG-P12345","pitch":{"value":52.58},"slope":{"value":-7.19},"center":{"value":0.24},"viewCone":{"value":40.0},"invView":{"value":1.0},"verticalAngle":{"value":0.0},"DPI":{"value":324.0},"screenW":{"value":1536.0},"screenH":{"value":2048.0},"flipImageX":{"value":0.0},"flipImageY":{"value":0.0},"flipSubp":{"value":0.0},"CellPatternMode":{"value":0},"subpixelCells":[]}"#;

fn corrupt(src: &str, at: usize, len: usize, junk: &str) -> String {
    let chars: Vec<char> = src.chars().collect();
    let a = at % chars.len().max(1);
    let b = (a + len % 32).min(chars.len());
    chars[..a].iter().collect::<String>() + junk + &chars[b..].iter().collect::<String>()
}

const JUNK: &[&str] = &[
    "",
    "\"",
    "{",
    "}",
    ",",
    "-1e999",
    "NaN",
    "null",
    "[[[[",
    "\u{0}",
    "\"value\":",
    "1e308",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]
    #[test]
    fn corrupted_calibrations_give_errors_not_panics(at in any::<usize>(), len in any::<usize>(), j in 0usize..JUNK.len()) {
        let text = corrupt(VISUAL_JSON, at, len, JUNK[j]);
        if let Err(e) = Calibration::from_visual_json(&text, "visual.json") {
            prop_assert!(!e.contains('\n') && e.starts_with("visual.json"), "{e}");
        }
    }

    #[test]
    fn corrupted_values_give_errors_not_panics(s in "\\PC{0,24}") {
        let errors = [
            super::parse::grid(&s).err(),
            super::parse::frames(&s).err(),
            super::parse::mode(&s).err(),
            super::parse::weave_filter(&s).err(),
            super::parse::fbo_scale(&s).err(),
        ];
        for e in errors.into_iter().flatten() {
            prop_assert!(!e.contains('\n'));
        }
    }
}
