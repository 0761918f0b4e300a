//! The minimal text edit that applies `holoinject_shift` to the app's `gl_Position`.
//!
//! Vertex / tessellation-evaluation: `main` is renamed by a `#define` right after `#version`
//! and a wrapper `main` is appended that calls it and shifts `gl_Position`. Geometry: every
//! `EmitVertex()` / `EmitStreamVertex(n)` is routed through a function that shifts first. Every
//! inserted block ends with a `#line` so the app's own line numbers are unchanged.

use super::text::{self, Directive};
use super::{Analysis, RECORD_VARYING, Stage, VIEW_SHIFT_GLSL};

pub fn rewrite(source: &str, analysis: &Analysis) -> Result<String, String> {
    rewrite_recording(source, analysis, false)
}

/// `rewrite`, and with `record` the parallax each vertex's shift gives it passed on to the
/// fragment shader (`holoinject_parallax_w`, see `record`); refused where it cannot be.
pub fn rewrite_recording(source: &str, analysis: &Analysis, record: bool) -> Result<String, String> {
    let blanked = text::blank_comments(source);
    refuse(&blanked, analysis)?;
    let dirs = text::directives(&blanked);
    if !conditionals_balanced(&dirs) {
        return Err("unbalanced #if/#else/#endif".into());
    }
    let record = if record {
        Some(super::record_varying(text::version(&dirs).map(|v| v.0), true).ok_or("no disparity record in GLSL ES")?)
    } else {
        None
    };
    match analysis.stage {
        Stage::Geometry => Ok(rewrite_geometry(source, &blanked, &dirs, record.as_deref())),
        _ => rewrite_main(source, &blanked, &dirs, analysis, record.as_deref()),
    }
}

/// The cases the rewrite must leave alone, with the reason for the log.
fn refuse(blanked: &str, analysis: &Analysis) -> Result<(), String> {
    if !analysis.stage.can_feed_rasterizer() {
        return Err("not a position-writing stage".into());
    }
    if [
        "holoinject_app_main",
        "holoinject_shift",
        "holoinject_view",
        "holoinject_remap",
        "holoinject_comfort",
        RECORD_VARYING,
    ]
    .iter()
    .any(|name| text::has_ident(blanked, name))
    {
        return Err("already rewritten by holoinject".into());
    }
    // Mesa compiles a geometry shader handed over as a vertex shader when the geometry
    // extension is enabled, but not its rewrite (found by the `glsl_compiles` fuzz target);
    // such a program cannot link anyway, so it keeps its own text.
    if analysis.stage != Stage::Geometry
        && ["EmitVertex", "EmitStreamVertex", "EndPrimitive", "EndStreamPrimitive"]
            .iter()
            .any(|name| text::has_ident(blanked, name))
    {
        return Err("geometry-shader built-ins outside a geometry shader".into());
    }
    // Nothing to shift, and Mesa compiles such a "geometry shader" (a vertex shader handed
    // over as one, found by fuzzing) but not with our EmitVertex wrapper added.
    if analysis.stage == Stage::Geometry
        && !["EmitVertex", "EmitStreamVertex"]
            .iter()
            .any(|name| text::has_ident(blanked, name))
    {
        return Err("geometry shader that emits no vertex".into());
    }
    if !analysis.writes_position {
        return Err("does not write gl_Position".into());
    }
    if analysis.writes_layer {
        return Err("writes gl_Layer or gl_ViewportIndex (layered pass)".into());
    }
    Ok(())
}

/// Conditionals that do not pair up (`#else` without `#if`, an `#if` never closed, two
/// `#else`s): Mesa may still compile such a source, but text appended after it would land
/// inside, or trip over, the open block (found by the `glsl_compiles` fuzz target).
pub(super) fn conditionals_balanced(dirs: &[Directive]) -> bool {
    let mut open: Vec<bool> = vec![]; // per open #if: has it had its #else?
    for d in dirs {
        match d.name.as_str() {
            "if" | "ifdef" | "ifndef" => open.push(false),
            "elif" if open.last() == Some(&false) => {}
            "else" if open.last() == Some(&false) => *open.last_mut().unwrap() = true,
            "endif" if open.pop().is_some() => {}
            "elif" | "else" | "endif" => return false,
            _ => {}
        }
    }
    open.is_empty()
}

/// Is every `main (` of the text inside some `#if` block? Then, unless glsl-lang evaluated
/// the conditions, we cannot tell whether the compiler sees a `main` at all.
pub(super) fn main_only_under_conditionals(blanked: &str, dirs: &[Directive]) -> bool {
    let lines = blanked.lines().count() + 1;
    let mut depth_at_line = vec![0usize; lines];
    let mut depth = 0usize;
    let mut next = 0;
    for d in dirs {
        let end = d.line.min(lines - 1);
        if next <= end {
            depth_at_line[next..=end].fill(depth);
        }
        next = d.line + 1;
        match d.name.as_str() {
            "if" | "ifdef" | "ifndef" => depth += 1,
            "endif" => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    if next < depth_at_line.len() {
        depth_at_line[next..].fill(depth);
    }
    let mains: Vec<usize> = blanked
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            text::tokens(l)
                .windows(2)
                .any(|w| w[0].is_ident("main") && w[1].is_punct("("))
        })
        .map(|(i, _)| i)
        .collect();
    !mains.is_empty() && mains.iter().all(|&i| depth_at_line[i] > 0)
}

fn rewrite_main(
    source: &str,
    blanked: &str,
    dirs: &[Directive],
    analysis: &Analysis,
    record: Option<&str>,
) -> Result<String, String> {
    if analysis.has_main.is_none() && main_only_under_conditionals(blanked, dirs) {
        return Err("main() only under #if, and the conditions could not be evaluated".into());
    }
    if dirs.iter().any(|d| d.name == "define" && first_word(&d.rest) == "main") {
        return Err("the shader #defines main itself".into());
    }
    if analysis.has_main == Some(false) || !defines_main(blanked) {
        return Err("no main()".into());
    }
    let version = text::version(dirs);
    let (offset, next_line) = match anchor_line(dirs) {
        Some(line) => text::offset_after_line(source, line).ok_or("no code after #version")?,
        None => (0, 0),
    };
    let head = format!(
        "#define main holoinject_app_main\n{}",
        line_directive(version.map(|v| v.0), next_line + 1)
    );
    let (decl, set) = match record {
        Some(decl) => (
            decl,
            format!("    {RECORD_VARYING} = holoinject_parallax_of(gl_Position);\n"),
        ),
        None => ("", String::new()),
    };
    let tail = format!(
        "#undef main\n{VIEW_SHIFT_GLSL}{decl}void main()\n{{\n    holoinject_app_main();\n{set}    \
         gl_Position = holoinject_shift(gl_Position);\n}}\n"
    );
    Ok(splice(source, offset, &head, &tail))
}

/// The line after which our text goes: the last `#extension` (outside any conditional it is
/// in), else `#version`. No non-preprocessor token may precede an `#extension`, and Mesa also
/// reads a shader differently when a `#define` comes between `#version` and an `#extension`
/// (found by the `glsl_compiles` fuzz target).
fn anchor_line(dirs: &[Directive]) -> Option<usize> {
    let last_extension = dirs
        .iter()
        .filter(|d| d.name == "extension")
        .map(|d| d.line)
        .next_back();
    let anchor = last_extension.or(text::version(dirs).map(|v| v.1));
    anchor.map(|line| text::line_after_conditionals(dirs, line))
}

fn rewrite_geometry(source: &str, blanked: &str, dirs: &[Directive], record: Option<&str>) -> String {
    let version = text::version(dirs);
    let (offset, next_line) = anchor_line(dirs)
        .and_then(|line| text::offset_after_line(source, line))
        .unwrap_or((0, 0));
    let streams = text::has_ident(blanked, "EmitStreamVertex");
    let mut head = String::from(
        "void holoinject_shift_position();\nvoid holoinject_emit();\n\
         #define EmitVertex() holoinject_emit()\n",
    );
    let mut tail = String::from("#undef EmitVertex\n");
    if streams {
        // The stream index must stay a constant expression, so no wrapper function here.
        head += "#define EmitStreamVertex(s) (holoinject_shift_position(), EmitStreamVertex(s))\n";
        tail += "#undef EmitStreamVertex\n";
    }
    head += &line_directive(version.map(|v| v.0), next_line + 1);
    tail += VIEW_SHIFT_GLSL;
    if let Some(decl) = record {
        tail += decl;
        tail += &format!(
            "void holoinject_shift_position()\n{{\n    {RECORD_VARYING} = holoinject_parallax_of(gl_Position);\n    \
             gl_Position = holoinject_shift(gl_Position);\n}}\n"
        );
    } else {
        tail += "void holoinject_shift_position()\n{\n    gl_Position = holoinject_shift(gl_Position);\n}\n";
    }
    tail += "\
             void holoinject_emit()\n{\n    holoinject_shift_position();\n    EmitVertex();\n}\n";
    // Bodies go last: an app redeclaring `out gl_PerVertex` must do so before any use.
    splice(source, offset, &head, &tail)
}

fn splice(source: &str, offset: usize, head: &str, tail: &str) -> String {
    let mut out = String::with_capacity(source.len() + head.len() + tail.len() + 1);
    out.push_str(&source[..offset]);
    out.push_str(head);
    out.push_str(&source[offset..]);
    if !out.ends_with('\n') {
        out.push('\n');
    }
    out.push_str(tail);
    out
}

/// A `#line` that makes the line after it number `next`.
///
/// GLSL < 3.30 (and 1.10 without `#version`) numbers the line after `#line N` as N+1;
/// GLSL 3.30+ and every GLSL ES version (1.00 included) as N (glslang
/// `lineDirectiveShouldSetNextLine`, Mesa `glsl_lexer.ll`). Without `#version` the text cannot
/// tell desktop 1.10 from ES 1.00, so the choice is left to the preprocessor via `GL_ES`.
pub(super) fn line_directive(version: Option<(u32, bool)>, next: usize) -> String {
    match version {
        Some((v, es)) if es || v >= 330 => format!("#line {next}\n"),
        Some(_) => format!("#line {}\n", next - 1),
        None => format!(
            "#ifdef GL_ES\n#define HOLOINJECT_LINE {next}\n#else\n#define HOLOINJECT_LINE {}\n\
             #endif\n#line HOLOINJECT_LINE\n",
            next - 1
        ),
    }
}

/// Whether the code (comments blanked) has a `main (` at the top level: a definition or a
/// prototype; calls to `main` are illegal GLSL.
pub(super) fn defines_main(blanked: &str) -> bool {
    let toks = text::tokens(blanked);
    toks.windows(2).any(|w| w[0].is_ident("main") && w[1].is_punct("("))
}

fn first_word(s: &str) -> &str {
    s.split(|c: char| !c.is_ascii_alphanumeric() && c != '_')
        .next()
        .unwrap_or("")
}
