//! `--device NAME|PATH`: a display's calibration and its default quilt. A preset name gives
//! both; a unit's own `visual.json` gives the calibration, and the quilt comes from the preset
//! whose serial prefix matches (else a default fitted to the screen's aspect).

use super::calibration::{Calibration, DevicePreset, QuiltDefaults, preset_names};

#[derive(Clone, Debug, PartialEq)]
pub struct Device {
    pub name: String,
    pub calibration: Calibration,
    pub quilt: QuiltDefaults,
    /// The comfortable range: the preset's, else derived from the calibration and quilt.
    pub comfort: Option<super::comfort::DepthRemap>,
}

fn derived_comfort(c: &Calibration, q: &QuiltDefaults) -> Option<super::comfort::DepthRemap> {
    super::comfort::device_range(
        c.pitch,
        c.dpi,
        c.screen_w,
        c.view_cone,
        q.columns * q.rows,
        q.tile_width,
    )
}

fn quilt_for_serial(serial: Option<&str>) -> Option<QuiltDefaults> {
    let serial = serial?;
    preset_names()
        .into_iter()
        .filter_map(|n| DevicePreset::get(n).ok())
        .find(|p| !p.serial_prefix.is_empty() && serial.starts_with(&p.serial_prefix))
        .map(|p| p.quilt)
}

/// 8x6 views whose tiles have the screen's aspect, 560 px high.
fn fallback_quilt(c: &Calibration) -> QuiltDefaults {
    let aspect = c.screen_w as f64 / c.screen_h.max(1) as f64;
    QuiltDefaults {
        columns: 8,
        rows: 6,
        tile_width: (560.0 * aspect).round() as u32,
        tile_height: 560,
        aspect,
    }
}

pub fn load(spec: &str) -> Result<Device, String> {
    if spec.contains('/') || spec.ends_with(".json") {
        let calibration = Calibration::load(spec)?;
        let quilt = quilt_for_serial(calibration.serial.as_deref()).unwrap_or_else(|| fallback_quilt(&calibration));
        return Ok(Device {
            name: spec.to_string(),
            comfort: derived_comfort(&calibration, &quilt).map(|r| r.of_tile(quilt.tile_width)),
            calibration,
            quilt,
        });
    }
    let p = DevicePreset::get(spec)?;
    Ok(Device {
        name: p.name.to_string(),
        comfort: p
            .comfort
            .or_else(|| derived_comfort(&p.calibration, &p.quilt))
            .map(|r| r.of_tile(p.quilt.tile_width)),
        calibration: p.calibration,
        quilt: p.quilt,
    })
}

#[cfg(test)]
mod tests {
    /// Every preset's `comfort_range` is the derivation of `config::comfort` on its own
    /// calibration and quilt (so a changed calibration cannot leave a stale range).
    #[test]
    fn preset_comfort_ranges_follow_the_derivation() {
        for name in super::preset_names() {
            let p = super::DevicePreset::get(name).unwrap();
            let want = super::derived_comfort(&p.calibration, &p.quilt);
            assert!(p.comfort.is_some(), "{name}: no comfort_range");
            assert_eq!(p.comfort, want, "{name}");
        }
    }

    #[test]
    fn presets_and_paths() {
        let d = super::load("portrait").unwrap();
        assert_eq!((d.quilt.columns, d.quilt.rows), (8, 6));
        let e = super::load("nonexistent-panel").unwrap_err();
        assert!(e.contains("unknown device") && e.contains("portrait"), "{e}");
        assert_eq!(d.comfort, Some(super::super::comfort::DEFAULT_RANGE));
        let e = super::load("/no/such/visual.json").unwrap_err();
        assert!(e.starts_with("/no/such/visual.json:"), "{e}");
    }
}
