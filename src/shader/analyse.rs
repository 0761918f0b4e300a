//! Entry point of the analysis: parse with glsl-lang, fall back to the token scan.

use glsl_lang::ast::TranslationUnit;
use glsl_lang::parse::DefaultParse;

use super::{Analysis, PositionKind, Stage, ast_walk, text, text_scan};

pub fn analyse(source: &str, stage: Stage) -> Analysis {
    let blanked = text::blank_comments(source);
    let version = text::version(&text::directives(&blanked)).map(|(v, _)| v);
    let parsed = parse(source);
    let findings = match &parsed {
        Some(tu) => ast_walk::walk(tu),
        None => text_scan::scan(&blanked),
    };
    Analysis {
        stage,
        version,
        parsed: parsed.is_some(),
        writes_position: findings.writes_position,
        writes_layer: findings.writes_layer,
        position_kind: findings.kind.unwrap_or(PositionKind::Unknown),
        matrix_uniforms: findings.matrices,
        vec4_matrices: parsed.as_ref().map(super::vec4_matrix::find).unwrap_or_default(),
        has_main: parsed.as_ref().map(|tu| {
            tu.0.iter().any(|d| {
                matches!(&**d, glsl_lang::ast::ExternalDeclarationData::FunctionDefinition(f)
                    if f.prototype.name.as_str() == "main")
            })
        }),
    }
}

/// glsl-lang's verdict; it can panic on inputs nobody tested, and no panic may cross FFI.
fn parse(source: &str) -> Option<TranslationUnit> {
    let source = parser_safe(source).ok()?;
    std::panic::catch_unwind(|| TranslationUnit::parse(&source).ok())
        .ok()
        .flatten()
}

/// Why glsl-lang refused the source, for logs (`None` when it parses).
pub fn parse_error(source: &str) -> Option<String> {
    let source = match parser_safe(source) {
        Ok(s) => s,
        Err(e) => return Some(e.to_string()),
    };
    match std::panic::catch_unwind(|| TranslationUnit::parse(&source).err().map(|e| e.to_string())) {
        Ok(err) => err,
        Err(_) => Some("glsl-lang panicked".to_string()),
    }
}

/// The text glsl-lang may be given. Its preprocessor (0.8) loops forever on a directive that
/// ends in `##` at the end of the input, and on `##` followed by a `"` (both found by
/// `cargo fuzz`): a final newline ends every directive; a source with both `##` and `"` (GLSL
/// has no strings; only `#line`/`#include` extensions use quotes) or ending inside a block
/// comment is left to the text analysis. `#extension` lines are dropped (kept as empty
/// lines): its preprocessor refuses every extension it does not know (wined3d enables twenty,
/// `GL_ARB_cull_distance` among them), and none changes what the analysis looks for; the
/// GOOGLE directive extensions it implements stay.
fn parser_safe(source: &str) -> Result<String, &'static str> {
    if text::ends_in_block_comment(source) {
        return Err("unterminated block comment");
    }
    let blanked = text::blank_comments(source);
    if blanked.contains("##") && blanked.contains('"') {
        return Err("token pasting (##) together with a quote");
    }
    // `split`, not `lines`: every newline (and a final `\r`) stays where it was.
    let lines: Vec<&str> = source
        .split('\n')
        .map(|l| {
            let t = l.trim_start();
            let directive = t.strip_prefix('#').map(str::trim_start);
            match directive {
                Some(d) if d.starts_with("extension") && !d.contains("GL_GOOGLE_") => "",
                _ => l,
            }
        })
        .collect();
    Ok(format!("{}\n", lines.join("\n")))
}
