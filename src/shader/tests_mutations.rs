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

/// The inputs `cargo fuzz` found (tests/fuzz/regressions/glsl: stage byte + source), each
/// checked like the fuzz target does, on a thread so that a hang fails instead of stalling.
#[test]
fn fuzz_regressions_finish_without_panics() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzz/regressions/glsl");
    let mut inputs: Vec<Vec<u8>> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| std::fs::read(e.unwrap().path()).unwrap())
        .collect();
    // Directives ending in `##` at the end of the input, or `##` then a quote, made
    // glsl-lang's preprocessor spin.
    for src in [
        "#if ##",
        "#if a ##",
        "#define X a ##",
        "#if 1\n#elif ##",
        "#if ## \\\n",
        "#if ##/*",
        "#define ####x\"t\n",
        "#define X a ## \"\n",
    ] {
        inputs.push([&[0u8][..], src.as_bytes()].concat());
    }
    assert!(inputs.len() > 6, "no regression files in {dir}");
    for data in inputs {
        let (tx, rx) = std::sync::mpsc::channel();
        let shown = String::from_utf8_lossy(&data).into_owned();
        std::thread::spawn(move || {
            let stages = [Stage::Vertex, Stage::Geometry, Stage::TessEval, Stage::Fragment];
            let stage = stages[data[0] as usize % 4];
            let source = String::from_utf8_lossy(&data[1..]).into_owned();
            let analysis = analyse(&source, stage);
            let _ = rewrite(&source, &analysis);
            let _ = fragcoord::rewrite(&source);
            let _ = super::parse_error(&source);
            tx.send(()).unwrap();
        });
        let done = rx.recv_timeout(std::time::Duration::from_secs(5));
        assert!(done.is_ok(), "analysis did not finish (or panicked) on {shown:?}");
    }
}

#[test]
fn a_final_line_comment_still_parses() {
    let src = "#version 330 core\nuniform mat4 mvp;\nin vec4 p;\nvoid main() { gl_Position = mvp * p; } // end";
    assert!(analyse(src, Stage::Vertex).parsed);
    assert!(!analyse("void main() { gl_Position = vec4(0.0); } /* open", Stage::Vertex).parsed);
}
