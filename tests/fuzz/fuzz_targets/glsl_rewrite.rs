//! Any text, as any stage, through the analysis, the view-shift rewrite and the
//! `gl_FragCoord` rewrite: no panic, a rewrite only adds text, and a parsed shader that was
//! rewritten once is refused a second time (the link path relies on it after relinks).
#![no_main]

use holoinject::shader::{Stage, analyse, fragcoord, rewrite};
use libfuzzer_sys::fuzz_target;

const STAGES: [Stage; 4] = [Stage::Vertex, Stage::Geometry, Stage::TessEval, Stage::Fragment];

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else { return };
    let Ok(source) = std::str::from_utf8(rest) else { return };
    let stage = STAGES[first as usize % STAGES.len()];
    let analysis = analyse(source, stage);
    if let Ok(out) = rewrite(source, &analysis) {
        assert!(out.len() > source.len());
        if analysis.parsed {
            assert!(rewrite(&out, &analyse(&out, stage)).is_err(), "rewrote twice");
        }
    }
    if let Ok(out) = fragcoord::rewrite(source) {
        assert!(out.len() > source.len() && out.contains(fragcoord::FRAGCOORD_UNIFORM));
    }
});
