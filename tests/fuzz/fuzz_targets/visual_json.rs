//! A display calibration (`visual.json`) is read from whatever file the user points at:
//! any bytes give a calibration or one line naming the file, never a panic.
#![no_main]

use holoinject::config::calibration::Calibration;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match Calibration::from_visual_json(&text, "visual.json") {
        Ok(c) => {
            for views in [1, 45, 100] {
                let p = c.weave_params(views);
                let _ = format!("{p:?}");
            }
        }
        Err(e) => assert!(e.starts_with("visual.json") && !e.contains('\n'), "{e}"),
    }
});
