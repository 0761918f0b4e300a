//! Detection against recorded server answers: XRandR monitors as `XRRGetMonitors` lists them
//! and EDID blocks built per known model by `scripts/make-edid.py`.

use super::xrandr::{RawMonitor, from_raw};
use super::*;

macro_rules! edid {
    ($name:literal) => {
        include_bytes!(concat!("../../../tests/data/edid/", $name, ".bin")).as_slice()
    };
}

fn raw(name: &str, edid: Option<&[u8]>, geometry: Rect) -> Monitor {
    from_raw(RawMonitor {
        name: name.into(),
        outputs: vec![(name.into(), edid.map(<[u8]>::to_vec))],
        geometry,
        primary: false,
    })
}

const DESK: Rect = Rect {
    x: 0,
    y: 0,
    w: 1920,
    h: 1080,
};
const SIDE: Rect = Rect {
    x: 1920,
    y: 0,
    w: 1536,
    h: 2048,
};

/// A desk monitor at the origin and a Portrait to its right, as a user's two-head set-up.
fn desk_and_portrait() -> Vec<Monitor> {
    vec![
        raw("DP-1", Some(edid!("ordinary-1920x1080")), DESK),
        raw("HDMI-1", Some(edid!("portrait")), SIDE),
    ]
}

#[test]
fn every_models_edid_names_its_preset() {
    for name in preset_names() {
        let path = format!("{}/tests/data/edid/{name}.bin", env!("CARGO_MANIFEST_DIR"));
        let blob = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e} (run scripts/make-edid.py)"));
        let edid_name = edid_monitor_name(&blob).unwrap_or_else(|| panic!("{path}: no monitor name"));
        assert!(is_looking_glass_name(&edid_name), "{name}: {edid_name}");
        assert_eq!(model_preset(&edid_name).map(|p| p.name), Some(name), "{edid_name}");
    }
}

#[test]
fn the_portrait_is_found_beside_a_desk_monitor() {
    let monitors = desk_and_portrait();
    let lg = find_looking_glass(&monitors).expect("a Looking Glass");
    assert_eq!(lg.name, "HDMI-1");
    assert_eq!(lg.geometry, SIDE);
    assert_eq!(lg.edid_name.as_deref(), Some("LKG-P00123"));
    assert_eq!(lg.device_preset().map(|p| p.name), Some("portrait"));
    assert_eq!(lg.describe(), "HDMI-1 \"LKG-P00123\" 1536x2048+1920+0");
}

#[test]
fn ordinary_monitors_and_missing_edids_are_not_looking_glasses() {
    let monitors = vec![
        raw("DP-1", Some(edid!("ordinary-1920x1080")), DESK),
        raw("VIRTUAL-1", None, SIDE),
    ];
    assert_eq!(monitors[0].edid_name.as_deref(), Some("DELL U2415"));
    assert!(find_looking_glass(&monitors).is_none());
}

#[test]
fn longest_serial_prefix_wins() {
    // `LKG-2K…` (8.9" gen1) must not be taken for a shorter prefix of another model.
    assert_eq!(model_preset("LKG-2K00123").map(|p| p.name), Some("8.9-gen1"));
    assert_eq!(model_preset("LKG-8K00123").map(|p| p.name), Some("32-gen1-8k"));
    assert_eq!(model_preset("LKG-Z0001"), None);
    assert!(is_looking_glass_name("lkg-z0001") && !is_looking_glass_name("LK"));
}

#[test]
fn corrupt_edids_have_no_name() {
    let good = edid!("portrait");
    assert!(edid_monitor_name(&good[..100]).is_none(), "short");
    let mut bad_sum = good.to_vec();
    bad_sum[127] ^= 1;
    assert!(edid_monitor_name(&bad_sum).is_none(), "checksum");
    let mut bad_header = good.to_vec();
    bad_header[0] = 1;
    bad_header[127] = bad_header[127].wrapping_sub(1);
    assert!(edid_monitor_name(&bad_header).is_none(), "header");
}

#[test]
fn monitor_chosen_by_any_of_its_names_or_by_rectangle() {
    let monitors = desk_and_portrait();
    for name in ["HDMI-1", "hdmi-1", "LKG-P00123"] {
        assert_eq!(
            select(&MonitorSpec::Name(name.into()), &monitors).unwrap().geometry,
            SIDE,
            "{name}"
        );
    }
    let e = select(&MonitorSpec::Name("DP-9".into()), &monitors).unwrap_err();
    assert!(
        e.contains("DP-9") && e.contains("HDMI-1 \"LKG-P00123\" 1536x2048+1920+0"),
        "{e}"
    );
    let by_hand = MonitorSpec::Geometry {
        w: 1536,
        h: 2048,
        x: 1920,
        y: 0,
    };
    assert_eq!(select(&by_hand, &monitors).unwrap().name, "HDMI-1");
    let elsewhere = MonitorSpec::Geometry {
        w: 800,
        h: 600,
        x: -800,
        y: 0,
    };
    let m = select(&elsewhere, &monitors).unwrap();
    assert_eq!(
        (m.name.as_str(), m.geometry.to_string()),
        ("--monitor", "800x600-800+0".to_string())
    );
}
