//! A per-application preset is a file users write by hand: any bytes give a preset (with one
//! line per skipped field, each naming the file and field) or one line naming the file, and
//! what is accepted builds settings without a complaint. Never a panic.
#![no_main]

use holoinject::config::Settings;
use holoinject::config::preset::parse;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match parse(&text, "presets/fuzz.toml") {
        Ok((preset, skipped)) => {
            for line in &skipped {
                assert!(line.starts_with("presets/fuzz.toml: field \"") && !line.contains('\n'), "{line}");
            }
            let mut complaints = vec![];
            let _ = Settings::from_sources(|_| None, Some(&preset), &mut |e| complaints.push(e));
            assert!(complaints.is_empty(), "accepted values refused later: {complaints:?}");
        }
        Err(e) => assert!(e.starts_with("presets/fuzz.toml") && !e.contains('\n'), "{e}"),
    }
});
