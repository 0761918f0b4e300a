//! Mutation robustness (a stable-Rust stand-in for `cargo fuzz`, run in every test pass):
//! every shader of the corpus, cut, spliced and corrupted at random places, goes through
//! analysis, the view-shift rewrite and the `gl_FragCoord` rewrite. None may panic; a
//! rewrite only ever adds text, and one of a shader that parses is refused a second time.

use super::{Stage, analyse, fragcoord, rewrite};
use proptest::prelude::*;

fn corpus() -> Vec<(String, Stage)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/shaders");
    let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let stage = match p.extension().and_then(|e| e.to_str()) {
                Some("geom") => Stage::Geometry,
                Some("tese") => Stage::TessEval,
                Some("frag") => Stage::Fragment,
                _ => Stage::Vertex,
            };
            (std::fs::read_to_string(&p).unwrap(), stage)
        })
        .collect()
}

/// Cuts, duplicates or overwrites a span, or inserts hostile text, at char boundaries.
fn mutate(src: &str, op: u8, at: usize, len: usize, junk: &str) -> String {
    let chars: Vec<char> = src.chars().collect();
    let n = chars.len().max(1);
    let (a, b) = (at % n, (at % n + len % 64).min(chars.len()));
    let (head, mid, tail): (String, String, String) = (
        chars[..a].iter().collect(),
        chars[a..b].iter().collect(),
        chars[b..].iter().collect(),
    );
    match op % 5 {
        0 => head + &tail,
        1 => head + &mid + &mid + &tail,
        2 => head + junk + &tail,
        3 => head + junk + &mid + &tail,
        _ => mid + &head + &tail,
    }
}

const HOSTILE: &[&str] = &[
    "#define main x\n",
    "/*",
    "#version 460\n",
    "#if 0\n",
    "gl_Position",
    "#extension GL_X : enable\n",
    "\u{0}",
    "void main(",
    "}}}",
    "holoinject_view",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]
    #[test]
    fn mutated_shaders_never_panic(file in 0usize..1000, op in any::<u8>(), at in any::<usize>(), len in any::<usize>(), junk in 0usize..HOSTILE.len()) {
        let corpus = corpus();
        let (src, stage) = &corpus[file % corpus.len()];
        let mutated = mutate(src, op, at, len, HOSTILE[junk]);
        let analysis = analyse(&mutated, *stage);
        if let Ok(out) = rewrite(&mutated, &analysis) {
            prop_assert!(out.len() > mutated.len());
            // Refusing a second rewrite is only promised for shaders that parse: in broken
            // ones (an unterminated comment) our own text can end up commented out, and the
            // compile that follows fails anyway, putting the original back.
            if analysis.parsed {
                prop_assert!(rewrite(&out, &analyse(&out, *stage)).is_err(), "rewrote twice");
            }
        }
        if let Ok(out) = fragcoord::rewrite(&mutated) {
            prop_assert!(out.len() > mutated.len() && out.contains(fragcoord::FRAGCOORD_UNIFORM));
        }
    }
}
